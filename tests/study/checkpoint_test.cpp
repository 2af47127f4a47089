// Checkpoints: units saved by an interrupted run are found by a resume with the same inputs and
// discarded, with the reason, when the inputs changed.
#include <catch2/catch.hpp>
#include <filesystem>

#include "study/checkpoint.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

TEST_CASE("checkpoint store resumes with the same fingerprint", "[study][checkpoint]") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_ckpt_same";
  fs::remove_all(dir);
  std::string msg;
  {
    CheckpointStore s(dir.string(), "armstudy=1\ninput:a.toml=h1\n", msg);
    CHECK(msg.empty());
    s.save("reach/design+x=0.1/grid0/chunk3", std::string("bytes\0with nul", 14));
    s.save("reach/design/grid0/chunk0", "other");
  }  // interrupted: finish() never called
  CHECK(CheckpointStore::hasPartialRun(dir.string()));
  CheckpointStore s(dir.string(), "armstudy=1\ninput:a.toml=h1\n", msg);
  CHECK(msg.find("resuming: 2") != std::string::npos);
  std::string b;
  REQUIRE(s.load("reach/design+x=0.1/grid0/chunk3", b));
  CHECK(b == std::string("bytes\0with nul", 14));
  CHECK_FALSE(s.load("reach/design/grid0/chunk1", b));
  s.finish();
  CHECK_FALSE(CheckpointStore::hasPartialRun(dir.string()));
}

TEST_CASE("checkpoint store starts fresh, saying why, when an input changed", "[study][checkpoint]") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_ckpt_changed";
  fs::remove_all(dir);
  std::string msg;
  {
    CheckpointStore s(dir.string(), "armstudy=1\ninput:designs/a.toml=h1\n", msg);
    s.save("unit0", "old");
  }
  CheckpointStore s(dir.string(), "armstudy=1\ninput:designs/a.toml=h2\n", msg);
  CHECK(msg.find("starting fresh because 'input:designs/a.toml' changed") != std::string::npos);
  std::string b;
  CHECK_FALSE(s.load("unit0", b));
  CHECK(s.completedUnits() == 0);
}
