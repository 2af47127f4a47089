// Regression checks: tolerance rules, flips of per-pose flags, baseline round trip and the bad
// inputs (baseline of another study, unknown format version, negative tolerance).
#include "study/regression.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/errors.hpp"
#include "engine/study_file.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;

namespace {
Baseline sampleBaseline() {
  Baseline b;
  b.study = "s";
  b.metrics.scalars["reach/a/grid0/reachable_fraction"] = 0.5;
  b.metrics.scalars["reach/a/grid0/manipulability_mean"] = 0.02;
  b.metrics.flags["reach/a/grid0/reachable"] = {1, 0, 1, 1, 0};
  return b;
}
RegressionSpec sampleSpec() {
  RegressionSpec spec;
  spec.rules.push_back({"*/reachable_fraction", 0.001, 0, 0, 1});
  spec.rules.push_back({"*/manipulability_*", 0, 0.01, 0, 2});
  spec.rules.push_back({"*/reachable", 0, 0, 1, 3});
  return spec;
}
const CheckRow& row(const CheckResult& r, const std::string& metric) {
  for (const auto& x : r.rows)
    if (x.metric == metric) return x;
  FAIL("no row " << metric);
  return r.rows.front();
}
}  // namespace

TEST_CASE("baselines round-trip through JSON exactly", "[study][regression]") {
  const Baseline b = sampleBaseline();
  const Baseline c = parseBaseline(baselineToJson(b), "b.json", "s");
  CHECK(c.metrics.scalars == b.metrics.scalars);
  CHECK(c.metrics.flags == b.metrics.flags);
  const CheckResult r = compareToBaseline(b, c.metrics, sampleSpec());
  CHECK(r.passed());
  CHECK(r.rows.size() == 3);
}

TEST_CASE("tolerances decide the verdict per metric, the first matching rule wins",
          "[study][regression]") {
  const Baseline b = sampleBaseline();
  StudyMetrics now = b.metrics;
  now.scalars["reach/a/grid0/reachable_fraction"] = 0.5009;   // within 0.001 absolute
  now.scalars["reach/a/grid0/manipulability_mean"] = 0.0202;  // 1 % relative: exactly at the limit
  CHECK(compareToBaseline(b, now, sampleSpec()).passed());
  now.scalars["reach/a/grid0/reachable_fraction"] = 0.5011;
  CheckResult r = compareToBaseline(b, now, sampleSpec());
  CHECK_FALSE(r.passed());
  CHECK(row(r, "reach/a/grid0/reachable_fraction").verdict == Verdict::Fail);
  CHECK(row(r, "reach/a/grid0/manipulability_mean").verdict == Verdict::Pass);
  // A metric without a rule falls back to a tight default.
  RegressionSpec bare;
  now = b.metrics;
  now.scalars["reach/a/grid0/manipulability_mean"] = 0.0200001;
  CHECK_FALSE(compareToBaseline(b, now, bare).passed());
}

TEST_CASE("per-pose flips are counted against the allowed number", "[study][regression]") {
  const Baseline b = sampleBaseline();
  StudyMetrics now = b.metrics;
  now.flags["reach/a/grid0/reachable"] = {1, 1, 1, 1, 0};  // one flip: allowed by the rule
  CheckResult r = compareToBaseline(b, now, sampleSpec());
  CHECK(r.passed());
  CHECK(row(r, "reach/a/grid0/reachable").flips == 1);
  now.flags["reach/a/grid0/reachable"] = {0, 1, 1, 1, 0};  // two flips
  r = compareToBaseline(b, now, sampleSpec());
  CHECK_FALSE(r.passed());
  CHECK(row(r, "reach/a/grid0/reachable").flipped == std::vector<std::size_t>{0, 1});
}

TEST_CASE("a flag string of another length than the run's is an error naming baseline and key",
          "[study][regression][bad-input]") {
  const Baseline b = sampleBaseline();
  StudyMetrics now = b.metrics;
  now.flags["reach/a/grid0/reachable"] = {1, 0, 1};  // the baseline's string is longer
  RegressionSpec spec = sampleSpec();
  spec.baseline_path = "studies/s.baseline.json";
  try {
    compareToBaseline(b, now, spec);
    FAIL("expected an InputError");
  } catch (const InputError& e) {
    CHECK(e.file() == "studies/s.baseline.json");
    CHECK(e.key() == "flags.reach/a/grid0/reachable");
    CHECK_THAT(e.message(), Catch::Contains("5 per-pose flags") && Catch::Contains("gives 3"));
  }
}

TEST_CASE("missing and new metrics fail the check", "[study][regression]") {
  const Baseline b = sampleBaseline();
  StudyMetrics now = b.metrics;
  now.scalars.erase("reach/a/grid0/manipulability_mean");
  now.scalars["reach/b/grid0/reachable_fraction"] = 1.0;
  const CheckResult r = compareToBaseline(b, now, sampleSpec());
  CHECK(row(r, "reach/a/grid0/manipulability_mean").verdict == Verdict::Missing);
  CHECK(row(r, "reach/b/grid0/reachable_fraction").verdict == Verdict::New);
  CHECK(r.failures() == 2);
  CHECK(checkTable(r, true).find("MISSING") != std::string::npos);
  CHECK(checkJson(r).find("\"passed\": false") != std::string::npos);
}

TEST_CASE("bad baselines are clear errors", "[study][regression][bad-input]") {
  const std::string good = baselineToJson(sampleBaseline());
  CHECK_THROWS_WITH(parseBaseline(good, "b.json", "other"),
                    Catch::Contains("belongs to study 's'"));
  std::string v2 = good;
  v2.replace(v2.find("\"format_version\": 1"), 19, "\"format_version\": 7");
  CHECK_THROWS_WITH(parseBaseline(v2, "b.json", "s"),
                    Catch::Contains("unknown baseline format version 7"));
  CHECK_THROWS_AS(parseBaseline("{not json", "b.json", "s"), InputError);
  CHECK_THROWS_WITH(parseBaseline("{\"a\": 1}", "b.json", "s"),
                    Catch::Contains("not an armstudy baseline"));
}

TEST_CASE("a negative tolerance in the study is an error with line and key",
          "[study][regression][bad-input]") {
  const auto dir = std::filesystem::temp_directory_path() / "armstudy_regression_test";
  std::filesystem::create_directories(dir);
  const auto p = dir / "neg.toml";
  std::ofstream(p) << "[study]\nname = \"neg\"\n[[design]]\nfile = \""
                   << sourcePath("designs/final_prototype_7dof.toml")
                   << "\"\n[[regression.tolerance]]\nmetric = \"*\"\nabs = -0.1\n";
  try {
    loadStudy(p.string());
    FAIL("expected an InputError");
  } catch (const InputError& e) {
    CHECK(e.key() == "regression.tolerance[0].abs");
    CHECK(e.line() == 7);
  }
}

TEST_CASE("every metric a shipped stage names begins with the stage's name",
          "[study][regression]") {
  StudyMetrics m;
  m.scalars["harvest/d/feasible_fraction"] = 1;
  m.scalars["harvestx/d/a"] = 1;  // a prefix of the name is not the stage
  m.flags["dynamics/d/fruit_feasible"] = {1};
  CHECK(metricsOutside(m, "harvest") ==
        std::vector<std::string>{"harvestx/d/a", "dynamics/d/fruit_feasible"});
  CHECK(metricsOutside(m, "dynamics") ==
        std::vector<std::string>{"harvest/d/feasible_fraction", "harvestx/d/a"});
  // The shipped harvest study's baseline: all under harvest/ (the engine refuses others).
  const std::string file = sourcePath("studies/harvest_torque.baseline.json");
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const StudyMetrics shipped = parseBaseline(text.str(), file, "harvest_torque").metrics;
  REQUIRE(shipped.scalars.size() > 10);
  CHECK(metricsOutside(shipped, "harvest").empty());
}
