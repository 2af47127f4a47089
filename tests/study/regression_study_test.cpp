// End to end through the CLI: the shipped regression study passes its recorded baseline;
// a changed design fails the check with the moved metrics; an interrupted run resumes into
// exactly the files an uninterrupted run writes; results do not depend on the thread count.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "io/files.hpp"
#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

fs::path regressionDir(const std::string& name) { return test::emptyTempDir("reg_" + name); }

// Every result file of a run (all but the manifest, which holds timings and dates) by path.
std::map<std::string, std::string> regressionFiles(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), dir).string();
    if (rel == "manifest.json") continue;
    out[rel] = readFileOrThrow(e.path().string());
  }
  return out;
}

// A study big enough to interrupt: four designs, one grid each (four units).
std::string writeResumeStudy(const fs::path& dir) {
  const fs::path p = dir / "resume.toml";
  std::ofstream f(p);
  f << "[study]\nname = \"resume\"\n";
  for (const auto& d : shippedDesigns()) f << "[[design]]\nfile = \"" << sourcePath(d) << "\"\n";
  f << "[reach]\ntask_space = \"full\"\n[[reach.grid]]\nname = \"wall\"\n"
       "x = { from = \"-0.6 m\", to = \"0.6 m\", step = \"0.02 m\" }\ny = \"0.8 m\"\n"
       "z = { from = \"0.4 m\", to = \"1.6 m\", step = \"0.05 m\" }\n"
       "alpha = \"-90 deg\"\nbeta = \"0 deg\"\ngamma = [\"0 deg\", \"20 deg\"]\n";
  return p.string();
}

}  // namespace

TEST_CASE("the shipped regression study passes `armstudy check` against its baseline",
          "[study][regression][e2e]") {
  // The fixture "shipped: regression" runs the check once per suite (tests/CMakeLists.txt).
  const auto j = shippedCheck("regression");
  CHECK(j["passed"] == true);
  CHECK(j["rows"].size() > 20);
}

TEST_CASE("a changed design table fails the check and names what moved",
          "[study][regression][e2e]") {
  const fs::path dir = regressionDir("moved");
  // Copy the regression study with a shortened link 4 of the final 7-DoF prototype.
  std::string design = readFileOrThrow(sourcePath("designs/final_prototype_7dof.toml"));
  const std::string from = "x = 0.35\n";
  REQUIRE(design.find(from) != std::string::npos);
  design.replace(design.find(from), from.size(), "x = 0.25\n");
  std::ofstream(dir / "final_prototype_7dof.toml") << design;
  std::string study = readFileOrThrow(sourcePath("studies/regression.toml"));
  study = std::regex_replace(study, std::regex("\\.\\./designs/final_prototype_7dof\\.toml"),
                             (dir / "final_prototype_7dof.toml").string());
  study = std::regex_replace(study, std::regex("\\.\\./designs/"), sourcePath("designs/"));
  study = std::regex_replace(
      study, std::regex("\\[regression\\]"),
      "[regression]\nbaseline = \"" + sourcePath("studies/regression.baseline.json") + "\"");
  std::ofstream(dir / "regression.toml") << study;
  std::string log;
  const int st = runCommand(binaryPath() + " check " + (dir / "regression.toml").string() +
                                " --output " + (dir / "out").string(),
                            log);
  INFO(log);
  CHECK(st == 3);
  CHECK(log.find("final_prototype_7dof/reachable_fraction") != std::string::npos);
  CHECK(log.find("MOVED") != std::string::npos);
  CHECK(log.find("check FAILED") != std::string::npos);
}

TEST_CASE("a baseline flag string one entry short is an input error, not moved results",
          "[study][regression][e2e][bad-input]") {
  const fs::path dir = regressionDir("short_flags");
  // The shipped baseline with one per-pose flag string shortened by one character.
  std::string baseline = readFileOrThrow(sourcePath("studies/regression.baseline.json"));
  const std::string key = "\"dexterity/final_prototype_7dof/reachable\": \"";
  const auto at = baseline.find(key);
  REQUIRE(at != std::string::npos);
  baseline.erase(at + key.size(), 1);
  const std::string bad = (dir / "short.baseline.json").string();
  std::ofstream(bad) << baseline;
  std::string study = readFileOrThrow(sourcePath("studies/regression.toml"));
  study = std::regex_replace(study, std::regex("\\.\\./designs/"), sourcePath("designs/"));
  study = std::regex_replace(study, std::regex("\\[regression\\]"),
                             "[regression]\nbaseline = \"" + bad + "\"");
  std::ofstream(dir / "regression.toml") << study;
  std::string log;
  const int st = runCommand(binaryPath() + " check " + (dir / "regression.toml").string() +
                                " --threads 2 --output " + (dir / "out").string(),
                            log);
  INFO(log);
  CHECK(st == 2);
  CHECK(log.find(bad) != std::string::npos);
  CHECK(log.find("dexterity/final_prototype_7dof/reachable") != std::string::npos);
  CHECK(log.find("check FAILED") == std::string::npos);
}

TEST_CASE("results are byte-identical with 1 and 2 threads and from run to run", "[study][e2e]") {
  const fs::path dir = regressionDir("threads");
  const std::string study = writeResumeStudy(dir);
  std::string log;
  REQUIRE(
      runCommand(binaryPath() + " run " + study + " --threads 1 --output " + (dir / "t1").string(),
                 log) == 0);
  REQUIRE(
      runCommand(binaryPath() + " run " + study + " --threads 2 --output " + (dir / "t2").string(),
                 log) == 0);
  const auto a = regressionFiles(dir / "t1/resume"), b = regressionFiles(dir / "t2/resume");
  REQUIRE(a.size() > 5);
  CHECK(a == b);
}

TEST_CASE("a run killed midway resumes into exactly the files of an uninterrupted run",
          "[study][checkpoint][e2e]") {
  const fs::path dir = regressionDir("resume");
  const std::string study = writeResumeStudy(dir);
  std::string log;
  REQUIRE(
      runCommand(binaryPath() + " run " + study + " --threads 1 --output " + (dir / "ref").string(),
                 log) == 0);

  // The same run killed with SIGKILL (no chance to clean up) right after its first unit was saved
  // (the checkpoint store's test hook), then resumed with another thread count.
  const fs::path out = dir / "killed";
  const int killed = runKilledAfterUnits(
      binaryPath() + " run " + study + " --threads 1 --output " + out.string(), 1, log);
  {
    INFO(log);
    REQUIRE(killed == kKilledStatus);
  }
  REQUIRE_FALSE(fs::exists(out / "resume/manifest.json"));
  const int st =
      runCommand(binaryPath() + " run " + study + " --threads 2 --output " + out.string(), log);
  INFO(log);
  REQUIRE(st == 0);
  CHECK(log.find("resuming: 1 completed unit(s)") != std::string::npos);
  CHECK_FALSE(fs::exists(out / "resume/.partial"));
  CHECK(regressionFiles(out / "resume") == regressionFiles(dir / "ref/resume"));
  for (const auto& e : fs::recursive_directory_iterator(out))
    CHECK(e.path().string().find(".tmp") == std::string::npos);
}

TEST_CASE("a resume after a design changed starts fresh and says why", "[study][checkpoint][e2e]") {
  const fs::path dir = regressionDir("changed");
  fs::copy_file(sourcePath("designs/final_prototype_7dof.toml"), dir / "d.toml");
  const fs::path study = dir / "s.toml";
  std::ofstream(study) << "[study]\nname = \"s\"\n[[design]]\nfile = "
                          "\"d.toml\"\n[reach]\ntask_space = \"position\"\n"
                          "[[reach.grid]]\nname = \"g\"\nx = { from = -0.5, to = 0.5, step = 0.25 "
                          "}\ny = 0.7\nz = 1.0\n";
  // Fake an interrupted run of the old inputs: a checkpoint folder with another fingerprint.
  fs::create_directories(dir / "out/s/.partial/units");
  std::ofstream(dir / "out/s/.partial/fingerprint")
      << "armstudy=old\ninput:" << study.string() << "=x\n";
  std::ofstream(dir / "out/s/.partial/units/reach_g_d.00000000.unit") << "stale";
  std::string log;
  const int st = runCommand(
      binaryPath() + " run " + study.string() + " --output " + (dir / "out").string(), log);
  INFO(log);
  CHECK(st == 0);
  CHECK(log.find("starting fresh because 'armstudy' changed") != std::string::npos);
  CHECK(fs::exists(dir / "out/s/manifest.json"));
}
