// Every shipped study with a recorded baseline (studies/<name>.baseline.json) passes
// `armstudy check studies/<name>.toml` (docs/regression.md): a metric that moved, one that is new
// or one that is missing fails here, so a change of results comes with a re-recorded baseline.
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "test_support.hpp"

using namespace armstudy::test;
namespace fs = std::filesystem;

TEST_CASE("armstudy check passes for every shipped study with a baseline",
          "[study][regression][e2e]") {
  const std::string suffix = ".baseline.json";
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(sourcePath("studies"))) {
    const std::string f = e.path().filename().string();
    if (f.size() > suffix.size() && f.ends_with(suffix))
      names.push_back(f.substr(0, f.size() - suffix.size()));
  }
  std::sort(names.begin(), names.end());
  {
    INFO("no *.baseline.json in " << sourcePath("studies"));
    REQUIRE_FALSE(names.empty());
  }
  const fs::path out =
      fs::temp_directory_path() / ("armstudy_shipped_baselines." + std::to_string(::getpid()));
  fs::remove_all(out);
  for (const std::string& name : names) {
    INFO("studies/" << name << ".toml");
    REQUIRE(fs::exists(sourcePath("studies/" + name + ".toml")));
    std::string log;
    const auto t0 = std::chrono::steady_clock::now();
    const int st = runCommand(binaryPath() + " check " + sourcePath("studies/" + name + ".toml") +
                                  " --output " + out.string(),
                              log);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    INFO(log);
    CHECK(st == 0);
    // The time of each check, for the suite's time budget (ctest --verbose shows it).
    std::cout << "armstudy check studies/" << name << ".toml: exit " << st << " in " << seconds
              << " s\n";
  }
  fs::remove_all(out);
}
