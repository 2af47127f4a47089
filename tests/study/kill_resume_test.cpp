// A run killed with SIGKILL mid-way resumes into the bytes of an uninterrupted run. Small
// enough (one design, 14 units of 13 poses) for the ASan/UBSan subset
// (scripts/sanitizer-subset.sh), where armstudy itself runs under the sanitizers; the larger
// kill/resume tests are in chunk_test.cpp and regression_study_test.cpp.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>

#include "io/files.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

// Every file of a run but the manifest (timings, dates) by relative path.
std::map<std::string, std::string> outputFiles(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename() != "manifest.json")
      out[fs::relative(e.path(), dir).string()] = readFileOrThrow(e.path().string());
  return out;
}

long savedUnits(const fs::path& study_out) {
  long n = 0;
  std::error_code ec;
  for (auto it = fs::directory_iterator(study_out / ".partial/units", ec);
       !ec && it != fs::directory_iterator(); it.increment(ec))
    n += it->path().extension() == ".unit";
  return n;
}

}  // namespace

TEST_CASE("a run killed with SIGKILL mid-way resumes into the bytes of an uninterrupted run",
          "[study][checkpoint][kill]") {
  const fs::path dir =
      fs::temp_directory_path() / ("armstudy_kill_resume." + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path study = dir / "k.toml";
  // One grid line of 13 poses per unit (--unit-size 1): 7 heights x 2 tool angles = 14 units.
  std::ofstream(study)
      << "[study]\nname = \"k\"\n[[design]]\nfile = \""
      << sourcePath("designs/final_prototype_7dof.toml")
      << "\"\n[reach]\ntask_space = \"full\"\n[[reach.grid]]\nname = \"wall\"\n"
         "x = { from = \"-0.6 m\", to = \"0.6 m\", step = \"0.1 m\" }\ny = \"0.8 m\"\n"
         "z = { from = \"0.4 m\", to = \"1.6 m\", step = \"0.2 m\" }\n"
         "alpha = \"-90 deg\"\nbeta = \"0 deg\"\ngamma = [\"0 deg\", \"20 deg\"]\n";
  const std::string run = binaryPath() + " run " + study.string() + " --unit-size 1 ";
  std::string log;
  REQUIRE(runCommand(run + "--threads 1 --output " + (dir / "ref").string(), log) == 0);

  // The same run killed with SIGKILL (no chance to clean up) right after its second unit was
  // saved: the checkpoint store's test hook picks the moment, so the kill always lands mid-run.
  const fs::path out = dir / "killed" / "k";
  const int killed =
      runKilledAfterUnits(run + "--threads 1 --output " + (dir / "killed").string(), 2, log);
  INFO(log);
  REQUIRE(killed == kKilledStatus);
  REQUIRE_FALSE(fs::exists(out / "manifest.json"));
  const long before = savedUnits(out);
  CHECK(before == 2);

  // Resumed with another thread count: the saved units are used, the files are the reference's.
  const int st = runCommand(run + "--threads 2 --output " + (dir / "killed").string(), log);
  INFO(log);
  REQUIRE(st == 0);
  CHECK(log.find("resuming: " + std::to_string(before) + " completed unit(s)") !=
        std::string::npos);
  CHECK_FALSE(fs::exists(out / ".partial"));
  CHECK(outputFiles(out) == outputFiles(dir / "ref" / "k"));
  for (const auto& e : fs::recursive_directory_iterator(dir / "killed"))
    CHECK(e.path().filename().string().find(".tmp.") == std::string::npos);
  fs::remove_all(dir);
}
