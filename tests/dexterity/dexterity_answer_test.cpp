// The dexterity answer names a winner only outside the map's resolution (the audit's 1 %), and
// gives each design's valley height: checked on facts set by hand, against the rule's closed
// form.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>

#include "common/defaults.hpp"
#include "report/ranking.hpp"
#include "stages/dexterity/dexterity_output.hpp"

using namespace armstudy;
using namespace armstudy::dexterity;

namespace {

// A study of designs named `names` with the given means (all reaching every cell).
std::string answerFor(const std::vector<std::string>& names, const std::vector<double>& means,
                      const std::vector<double>& valleys) {
  std::vector<DesignAnswerFacts> facts;
  Study study;
  StageResult sum;
  for (std::size_t k = 0; k < names.size(); ++k) {
    StudyDesign sd;
    sd.model.name = names[k];
    study.designs.push_back(sd);
    facts.push_back({means[k], 1.0, valleys[k], {}});
  }
  dexterityAnswer(study, DexterityOptions{}, facts, sum);
  REQUIRE(sum.answer.size() == 1);
  return sum.answer[0];
}

}  // namespace

TEST_CASE("levelWithFirst counts the entries within the resolution of the first", "[report]") {
  CHECK(report::levelWithFirst({}, 0.1) == 0);
  CHECK(report::levelWithFirst({1.0}, 0.0) == 1);
  CHECK(report::levelWithFirst({1.0, 0.95, 0.91, 0.5}, 0.09) == 3);
  CHECK(report::levelWithFirst({1.0, 0.95}, 0.04) == 1);
}

TEST_CASE(
    "dexterity answer: means within the audit's tolerance are level, in study order, with "
    "their valleys",
    "[dexterity][report]") {
  // The shipped stem heatmap's three lift offsets: 0.8211 / 0.8214 / 0.8212, a 0.04 % spread.
  const std::string a =
      answerFor({"low", "mid", "high"}, {0.8211, 0.8214, 0.8212}, {0.51, 0.66, 0.81});
  INFO(a);
  CHECK(a.find("level means") != std::string::npos);
  CHECK(a.find("highest") == std::string::npos);
  CHECK(a.find("`low`") < a.find("`mid`"));
  CHECK(a.find("`mid`") < a.find("`high`"));
  CHECK(a.find("valley at z 0.51 m") != std::string::npos);
  CHECK(a.find("valley at z 0.81 m") != std::string::npos);
  CHECK(a.find("0.04 %") != std::string::npos);
}

TEST_CASE("dexterity answer: a difference beyond the tolerance names the highest", "[dexterity]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double top = 0.8;
  const double below = top * (1 - 2 * defaults::kAuditTolerance);
  const std::string a = answerFor({"b", "a"}, {below, top}, {nan, nan});
  INFO(a);
  CHECK(a.find("highest mean `a`") != std::string::npos);
  CHECK(a.find("then `b`") != std::string::npos);
  CHECK(a.find("valley") == std::string::npos);
  CHECK(a.find("level") == std::string::npos);
  // Two level at the top, one below: the two named level, the third after them.
  const std::string b = answerFor({"x", "y", "z"}, {top, below, top * 0.995}, {nan, nan, nan});
  INFO(b);
  CHECK(b.find("level with each other, `x`") != std::string::npos);
  CHECK(b.find("; then `y`") != std::string::npos);
}

TEST_CASE("dexterity answer: a row around the stem answers which half can be approached first",
          "[dexterity][report]") {
  // stem_row's figures: 75 and 27 of 105 cells at 0.192 m; without stems 105 and 81; a sweep.
  Study study;
  StudyDesign sd;
  sd.model.name = "nine";
  study.designs.push_back(sd);
  StageResult sum;
  DesignAnswerFacts f;
  f.manipulability_mean_optimised = 0.553;
  f.reachable_fraction = 0.472;
  f.valley_z_m = std::numeric_limits<double>::quiet_NaN();
  f.row = {{0.192, 75, 105, 27, 105, "neighbouring stems", "neighbouring stems"},
           {0.0, 105, 105, 81, 105, "nothing", "self-collision"},
           {0.13, 69, 105, 33, 105, "a", "b"},
           {0.25, 87, 105, 48, 105, "a", "b"}};
  dexterityAnswer(study, DexterityOptions{}, {f}, sum);
  REQUIRE(sum.answer.size() == 2);
  const std::string& a = sum.answer[0];
  INFO(a);
  CHECK(a.find("near half") != std::string::npos);
  CHECK(a.find("71.4 % (75 of 105 cells)") != std::string::npos);  // 75/105
  CHECK(a.find("far half at 25.7 % (27 of 105 cells)") != std::string::npos);
  CHECK(a.find("without neighbouring stems 100.0 % and 77.1 %") != std::string::npos);
  CHECK(a.find("near half 65.7 %-82.9 %, the far half 31.4 %-45.7 %") != std::string::npos);
}
