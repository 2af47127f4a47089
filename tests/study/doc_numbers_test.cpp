// The numbers the docs quote come from the shipped studies' outputs: the studies
// scripts/doc_numbers.py needs are run here (2 threads), then the script renders each quoted text
// from their summary.json and fails when a doc does not contain it verbatim.
#include <catch2/catch.hpp>
#include <filesystem>
#include <sstream>
#include <string>

#include "test_support.hpp"

using namespace armstudy::test;
namespace fs = std::filesystem;

TEST_CASE("the numbers the docs quote match the shipped studies' outputs", "[docs][study]") {
  const fs::path out = fs::temp_directory_path() / "armstudy_doc_numbers_test";
  fs::remove_all(out);
  std::string log;
  REQUIRE(runCommand("python3 " + sourcePath("scripts/doc_numbers.py") + " --studies", log) == 0);
  std::istringstream names(log);
  int studies = 0;
  for (std::string name; names >> name; ++studies) {
    INFO(name);
    std::string run_log;
    const int st = runCommand(binaryPath() + " run " + sourcePath("studies/" + name + ".toml") +
                                  " --threads 2 --output " + out.string(),
                              run_log);
    INFO(run_log);
    REQUIRE(st == 0);
  }
  REQUIRE(studies > 0);  // the script names the studies it reads
  std::string check_log;
  const int st = runCommand(
      "python3 " + sourcePath("scripts/doc_numbers.py") + " --outputs " + out.string(), check_log);
  INFO(check_log);
  CHECK(st == 0);
  CHECK(check_log.find("quoted texts match the outputs") != std::string::npos);
}
