// The numbers the docs quote come from the shipped studies' outputs: scripts/doc_numbers.py names
// the studies it needs, whose outputs the suite's fixtures write once (shipped_output.hpp, 2
// threads); the script renders each quoted text from their summary.json and fails when a doc does
// not contain it verbatim.
#include <catch2/catch.hpp>
#include <filesystem>
#include <sstream>
#include <string>

#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy::test;
namespace fs = std::filesystem;

TEST_CASE("the numbers the docs quote match the shipped studies' outputs", "[docs][study]") {
  std::string log;
  REQUIRE(runCommand("python3 " + sourcePath("scripts/doc_numbers.py") + " --studies", log) == 0);
  std::istringstream names(log);
  int studies = 0;
  fs::path out;
  for (std::string name; names >> name; ++studies) {
    INFO(name);
    out = shippedOutput(name).parent_path();  // fails when no fixture wrote the study's outputs
  }
  REQUIRE(studies > 0);  // the script names the studies it reads
  std::string check_log;
  const int st = runCommand(
      "python3 " + sourcePath("scripts/doc_numbers.py") + " --outputs " + out.string(), check_log);
  INFO(check_log);
  CHECK(st == 0);
  CHECK(check_log.find("quoted texts match the outputs") != std::string::npos);
}
