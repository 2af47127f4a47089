#pragma once
// The outputs of shipped studies that several tests read, written once per suite by ctest
// fixtures (tests/CMakeLists.txt, "shipped: <study>"; tests/shipped_fixtures.cmake.in names the
// tests that require each).
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "io/files.hpp"
#include "test_support.hpp"

namespace armstudy::test {

// The output folder of the shipped study `name` (studies/<name>.toml): $ARMSTUDY_SHIPPED_OUTPUT/
// <name>. Throws (the test fails) when the test did not run through ctest with the fixture, or when
// the folder is missing or older than the armstudy program. `fixture_test`: the test that writes
// the folder, where it is not "shipped: <name>".
inline std::filesystem::path shippedOutput(const std::string& name,
                                           const std::string& fixture_test = "") {
  namespace fs = std::filesystem;
  const std::string fixture =
      "the fixture \"" + (fixture_test.empty() ? "shipped: " + name : fixture_test) + "\"";
  const char* root = std::getenv("ARMSTUDY_SHIPPED_OUTPUT");
  if (!root)
    throw std::runtime_error("ARMSTUDY_SHIPPED_OUTPUT is not set: run this test through ctest (" +
                             fixture + " writes the study's outputs first)");
  const fs::path dir = fs::path(root) / name, manifest = dir / "manifest.json";
  if (!fs::exists(manifest))
    throw std::runtime_error(manifest.string() + " is missing: " + fixture +
                             " did not run or failed");
  if (fs::last_write_time(manifest) < fs::last_write_time(binaryPath()))
    throw std::runtime_error(dir.string() + " is older than " + binaryPath() + ": " + fixture +
                             " did not run after the program was built");
  return dir;
}

// The comparison with its committed baseline that the fixture of the shipped study `name` wrote
// (`armstudy check --json`, $ARMSTUDY_SHIPPED_OUTPUT/<name>.check.json). Throws when the fixture
// did not run the check after the study's outputs were written.
inline nlohmann::json shippedCheck(const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path dir = shippedOutput(name);
  const fs::path json = dir.parent_path() / (name + ".check.json");
  if (!fs::exists(json))
    throw std::runtime_error(json.string() + " is missing: the fixture \"shipped: " + name +
                             "\" did not run `armstudy check` to the end");
  if (fs::last_write_time(json) < fs::last_write_time(dir / "manifest.json"))
    throw std::runtime_error(json.string() + " is older than the study's outputs");
  return nlohmann::json::parse(readFileOrThrow(json.string()));
}

}  // namespace armstudy::test
