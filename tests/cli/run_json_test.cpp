// `armstudy run --json`: the run summary on stdout is JSON a script can read, and it agrees with
// the manifest the run wrote (same files, same output folder); the HTML report is among the files.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "io/files.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

TEST_CASE("armstudy run --json prints the run summary, agreeing with the manifest", "[cli]") {
  const fs::path d = fs::temp_directory_path() / ("armstudy_run_json_" + std::to_string(getpid()));
  fs::remove_all(d);
  std::string out;
  // stdout only: progress and messages go to stderr.
  REQUIRE(runCommand(binaryPath() + " run " + sourcePath("studies/regression.toml") +
                         " --overwrite --threads 2 --json --output " + d.string() + " 2>/dev/null",
                     out) == 0);
  const auto j = nlohmann::json::parse(out);
  CHECK(j["study"] == "regression");
  const auto man =
      nlohmann::json::parse(readFileOrThrow(j["output_dir"].get<std::string>() + "/manifest.json"));
  CHECK(j["files"] == man["files"]);
  const auto files = j["files"].get<std::vector<std::string>>();
  CHECK(std::find(files.begin(), files.end(), "report.html") != files.end());
  CHECK(fs::exists(j["report"].get<std::string>()));
  CHECK(j["metrics"].size() > 10);
  CHECK(j["timings"].contains("reachability_s"));
  fs::remove_all(d);
}
