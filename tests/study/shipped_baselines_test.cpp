// Every shipped study with a recorded baseline (studies/<name>.baseline.json) passes
// `armstudy check studies/<name>.toml` (docs/regression.md): a metric that moved, one that is new
// or one that is missing fails here, so a change of results comes with a re-recorded baseline.
// The check runs once per suite, as the fixture "shipped: <name>" (tests/CMakeLists.txt), whose
// comparison this test reads.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "shipped_output.hpp"
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
  for (const std::string& name : names) {
    INFO("studies/" << name << ".toml");
    REQUIRE(fs::exists(sourcePath("studies/" + name + ".toml")));
    const nlohmann::json check = shippedCheck(name);
    std::string moved;  // the rows outside tolerance, one line each
    for (const auto& row : check.at("rows"))
      if (row.at("verdict") != "ok") moved += row.dump() + "\n";
    INFO(moved);
    CHECK(check.at("passed").get<bool>());
    CHECK(check.at("failures").get<int>() == 0);
    CHECK_FALSE(check.at("rows").empty());
  }
}
