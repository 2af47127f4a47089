#pragma once
// The outputs of shipped studies that several tests read, written once per suite by ctest
// fixtures (tests/CMakeLists.txt, "shipped: <study>"; tests/shipped_fixtures.cmake.in names the
// tests that require each).
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "test_support.hpp"

namespace armstudy::test {

// The output folder of the shipped study `name` (studies/<name>.toml): $ARMSTUDY_SHIPPED_OUTPUT/
// <name>. Throws (the test fails) when the test did not run through ctest with the fixture, or when
// the folder is missing or older than the armstudy program.
inline std::filesystem::path shippedOutput(const std::string& name) {
  namespace fs = std::filesystem;
  const std::string fixture = "the fixture \"shipped: " + name + "\"";
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

}  // namespace armstudy::test
