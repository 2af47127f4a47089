// Checkpoints: units saved by an interrupted run are found by a resume with the same inputs and
// discarded, with the reason, when the inputs changed; unit bytes round-trip exactly; the range
// countdown reports each range's completion once.
#include "study/checkpoint.hpp"

#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <thread>

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

TEST_CASE("each rank's store removes the units it saved, finish removes the rest",
          "[study][checkpoint]") {
  // A distributed run: every rank opens the store in the same folder and saves the units it
  // computes; at the end each removes its own (in parallel), rank 0 then the folder with what is
  // left (units an interrupted run saved, which nobody of this run saved again).
  const fs::path dir = fs::temp_directory_path() / "armstudy_ckpt_ranks";
  fs::remove_all(dir);
  std::string msg;
  const std::string fp = "armstudy=1\n";
  {
    CheckpointStore earlier(dir.string(), fp, msg);
    earlier.save("unit/old", "from an interrupted run");
  }
  CheckpointStore rank0(dir.string(), fp, msg), rank1(dir.string(), fp, msg);
  rank0.save("unit/a", "a");
  rank0.save("unit/b", "b");
  rank1.save("unit/c", "c");
  auto count = [&] {
    long n = 0;
    for (const auto& e : fs::directory_iterator(dir / ".partial/units"))
      n += e.path().extension() == ".unit";
    return n;
  };
  REQUIRE(count() == 4);
  rank0.removeSaved();
  std::string b;
  CHECK_FALSE(rank1.load("unit/a", b));
  CHECK_FALSE(rank1.load("unit/b", b));
  CHECK(rank1.load("unit/c", b));
  CHECK(rank1.load("unit/old", b));
  rank1.removeSaved();
  CHECK(count() == 1);  // the interrupted run's unit
  CHECK(rank0.load("unit/old", b));
  rank0.finish();
  CHECK_FALSE(fs::exists(dir / ".partial"));
  fs::remove_all(dir);
}

TEST_CASE("checkpoint store starts fresh, saying why, when an input changed",
          "[study][checkpoint]") {
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

TEST_CASE("unit bytes round-trip bit for bit, other formats and damaged bytes are refused",
          "[study][checkpoint]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 12, 1> q(7);
  q << 1, -0.0, 3e-300, nan, 5, 6, 7;
  const Eigen::Matrix3d R = (Eigen::Matrix3d() << 1, 2, 3, 4, 5, 6, 7, 8, 9).finished();
  UnitWriter w("fmt-v1");
  w.put<std::int32_t>(-5);
  w.put<double>(-0.0);
  w.putVector(std::vector<std::uint8_t>{1, 0, 255});
  w.putVector(std::vector<double>{});
  w.putString(std::string("a\0b\nc", 5));
  w.putMatrix(q);
  w.putMatrix(R);
  const std::string b = w.bytes();

  UnitReader r(b, "fmt-v1");
  CHECK(r.get<std::int32_t>() == -5);
  const double z = r.get<double>();
  CHECK(std::signbit(z));
  std::vector<std::uint8_t> v;
  r.getVector(v);
  CHECK(v == std::vector<std::uint8_t>{1, 0, 255});
  std::vector<double> e{1.0};
  r.getVector(e);
  CHECK(e.empty());
  CHECK(r.getString() == std::string("a\0b\nc", 5));
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 12, 1> q2;
  r.getMatrix(q2);
  REQUIRE(q2.size() == 7);
  CHECK(std::memcmp(q2.data(), q.data(), 7 * sizeof(double)) == 0);  // NaN and -0 included
  Eigen::Matrix3d R2;
  r.getMatrix(R2);
  CHECK(R2 == R);
  CHECK(r.finished());

  CHECK_FALSE(UnitReader(b, "fmt-v2").ok());  // another format version
  const std::string too_short = "fmt";
  CHECK_FALSE(UnitReader(too_short, "fmt-v1").ok());  // shorter than the magic
  // Cut anywhere: some read fails, nothing is read past the end.
  for (std::size_t cut : {b.size() - 1, b.size() / 2, std::size_t(10)}) {
    const std::string cut_bytes = b.substr(0, cut);
    UnitReader t(cut_bytes, "fmt-v1");
    t.get<std::int32_t>();
    t.get<double>();
    t.getVector(v);
    t.getVector(e);
    t.getString();
    t.getMatrix(q2);
    t.getMatrix(R2);
    CHECK_FALSE(t.finished());
  }
  // A fixed-size target of another shape is refused.
  UnitReader s(b, "fmt-v1");
  s.get<std::int32_t>();
  s.get<double>();
  s.getVector(v);
  s.getVector(e);
  s.getString();
  Eigen::Vector3d wrong;
  s.getMatrix(wrong);
  CHECK_FALSE(s.ok());
}

TEST_CASE("ranges split items evenly, the countdown reports each range's completion exactly once",
          "[study][checkpoint]") {
  const std::vector<ItemRange> r = splitRange(10, 4);
  REQUIRE(r.size() == 3);
  CHECK((r[0].begin == 0 && r[0].end == 4 && r[1].begin == 4 && r[1].end == 8 && r[2].begin == 8 &&
         r[2].end == 10));
  CHECK(r[2].text() == "8-10");
  CHECK(splitRange(0, 4).empty());
  CHECK(splitRange(3, 0).size() == 3);  // at least one item per range
  // Many threads finishing items of the same ranges in any order: one completion per range, by
  // the last item.
  const std::vector<ItemRange> ranges = splitRange(20000, 7);
  RangeCountdown countdown(ranges);
  std::vector<std::atomic<int>> completions(ranges.size());
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (long i = t; i < 20000; i += 4)
        if (countdown.itemDone(static_cast<std::size_t>(i / 7))) ++completions[i / 7];
    });
  for (auto& th : threads) th.join();
  for (const auto& c : completions) CHECK(c.load() == 1);
}
