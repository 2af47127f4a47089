// The Catch2 main of every test executable. Each test process gets a temporary folder of its own
// (TMPDIR, which std::filesystem::temp_directory_path() and the armstudy processes a test starts
// both use), so tests that name fixed folders under the temporary directory never collide with
// the same test running at the same time in another process or work tree. Removed at exit.
#define CATCH_CONFIG_RUNNER
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

int main(int argc, char* argv[]) {
  namespace fs = std::filesystem;
  const char* base = std::getenv("TMPDIR");
  const fs::path dir =
      fs::path(base && *base ? base : "/tmp") / ("armstudy_test_" + std::to_string(getpid()));
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!ec) setenv("TMPDIR", dir.c_str(), 1);
  const int rc = Catch::Session().run(argc, argv);
  if (!ec) fs::remove_all(dir, ec);
  return rc;
}
