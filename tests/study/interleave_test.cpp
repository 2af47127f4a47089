// Interleaved programs (study/interleave.hpp, issue 16): programs whose shared loops are grouped
// into combined loops give the results of the same programs run one after another (the oracle),
// whatever chunks the runner cuts the combined loops into; the steps are the longest program's, not
// the sum; a program's failure reaches the caller after the others ended.
#include <catch2/catch.hpp>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "study/interleave.hpp"

using namespace armstudy;

namespace {

// Program p: `steps` Jacobi steps over n items; a step sets v[i] = f(previous v of i and its
// neighbours, step) (reads only the previous step), packs a chunk's new values as bytes.
struct Jacobi {
  long n;
  int steps;
  long chunk;  // items per chunk of its loops
  std::vector<std::int64_t> v;
  void run(const UnitRunner* runner) {
    v.assign(n, 0);
    for (long i = 0; i < n; ++i) v[i] = (i * 7919 + n) % 101;
    for (int s = 0; s < steps; ++s) {
      std::vector<std::int64_t> next = v;
      SharedLoop loop;
      loop.id = "jacobi/" + std::to_string(n) + "/" + std::to_string(s);
      loop.items = n;
      loop.chunk = chunk;
      loop.compute = [&](const std::vector<SharedLoop::Chunk>& mine) {
        for (const long i : SharedLoop::itemsOf(mine)) {
          const std::int64_t l = i > 0 ? v[i - 1] : 0, r = i + 1 < n ? v[i + 1] : 0;
          // Blocks of 5 items of odd index stay as they are (chunks of 5 with nothing to send).
          next[i] = (i / 5) % 2 ? v[i] : (3 * v[i] + l + 2 * r + s) % 1009;
        }
      };
      loop.finish = [&](const std::vector<SharedLoop::Chunk>& mine) {
        for (const long i : SharedLoop::itemsOf(mine)) v[i] = next[i];
      };
      // "i=value," for the items that changed; empty when none did.
      loop.pack = [&](std::size_t, const ItemRange& r) {
        std::string b;
        for (long i = r.begin; i < r.end; ++i)
          if (next[i] != v[i]) b += std::to_string(i) + "=" + std::to_string(next[i]) + ",";
        return b;
      };
      loop.unpack = [&](std::size_t, const ItemRange& r, const std::string& bytes) {
        REQUIRE(!bytes.empty());
        for (std::size_t pos = 0; pos < bytes.size();) {
          const std::size_t eq = bytes.find('=', pos), comma = bytes.find(',', pos);
          REQUIRE((eq != std::string::npos && comma != std::string::npos && eq < comma));
          const long i = std::stol(bytes.substr(pos, eq - pos));
          REQUIRE((i >= r.begin && i < r.end));
          v[i] = std::stoll(bytes.substr(eq + 1, comma - eq - 1));
          pos = comma + 1;
        }
      };
      runSharedLoop(runner, loop);
    }
  }
};

// A runner that plays a distributed run of two processes inside one: the chunks of even index are
// "this process's" (computed and finished here), those of odd index arrive as bytes from a second
// copy of the same loop state computed separately (the other process), through pack and unpack.
// Counts the loops it ran and their sizes.
class TwoProcesses final : public UnitRunner {
 public:
  TwoProcesses() : UnitRunner(off_, 1, UnitTimeRecord{}) {}
  mutable std::vector<long> loop_items;
  mutable std::vector<std::vector<ItemRange>> loop_chunks;
  mutable long empty_packs = 0;  // chunks with nothing to send
  void share(const SharedLoop& loop) const override {
    loop_items.push_back(loop.items);
    const std::vector<ItemRange> chunks = loop.chunks();
    loop_chunks.push_back(chunks);
    std::vector<SharedLoop::Chunk> even, odd;
    for (std::size_t k = 0; k < chunks.size(); ++k) (k % 2 ? odd : even).push_back({k, chunks[k]});
    // The other process's chunks first: computed (its compute writes only its items' candidates),
    // packed, then this process computes and finishes its own, and takes the others' bytes.
    if (!odd.empty()) loop.compute(odd);
    std::vector<std::string> bytes;
    for (const SharedLoop::Chunk& c : odd) {
      bytes.push_back(loop.pack(c.first, c.second));
      empty_packs += bytes.back().empty();
    }
    loop.computeAll(even);
    for (std::size_t j = 0; j < odd.size(); ++j)
      if (!bytes[j].empty()) loop.unpack(odd[j].first, odd[j].second, bytes[j]);
  }

 private:
  CheckpointStore off_;
};

std::vector<Jacobi> programs() { return {{23, 4, 5, {}}, {7, 9, 2, {}}, {40, 1, 16, {}}, {12, 6, 5, {}}}; }

}  // namespace

TEST_CASE("interleaved programs give the results of the same programs run one after another", "[interleave]") {
  std::vector<Jacobi> seq = programs();
  for (Jacobi& j : seq) j.run(nullptr);

  for (const bool two : {false, true}) {
    INFO((two ? "two processes played in one" : "this process alone"));
    std::vector<Jacobi> il = programs();
    std::vector<InterleavedProgram> progs;
    for (Jacobi& j : il) progs.push_back([&j](const UnitRunner* r) { j.run(r); });
    TwoProcesses runner;
    runInterleaved(two ? &runner : nullptr, progs);
    for (std::size_t p = 0; p < il.size(); ++p) CHECK(il[p].v == seq[p].v);
    if (two) {
      // One combined loop per step of the longest program (9), not one per program step (20);
      // step s holds the programs that still have a step s.
      REQUIRE(runner.loop_items.size() == 9);
      CHECK(runner.loop_items[0] == 23 + 7 + 40 + 12);
      CHECK(runner.loop_items[1] == 23 + 7 + 12);
      CHECK(runner.loop_items[8] == 7);
      CHECK(runner.empty_packs > 0);
      // A combined loop keeps each program's own chunks: step 0 is the programs' chunks, in program
      // order, shifted by the items before them (none spans two programs).
      std::vector<ItemRange> expected;
      long off = 0;
      for (const Jacobi& j : il) {
        for (const ItemRange& r : splitRange(j.n, j.chunk)) expected.push_back({off + r.begin, off + r.end});
        off += j.n;
      }
      REQUIRE(runner.loop_chunks[0].size() == expected.size());
      for (std::size_t k = 0; k < expected.size(); ++k) {
        CHECK(runner.loop_chunks[0][k].begin == expected[k].begin);
        CHECK(runner.loop_chunks[0][k].end == expected[k].end);
      }
    }
  }
}

TEST_CASE("a failing interleaved program fails the call after the others ended", "[interleave]") {
  std::vector<Jacobi> il = programs();
  std::vector<Jacobi> seq = programs();
  for (Jacobi& j : seq) j.run(nullptr);
  std::vector<InterleavedProgram> progs;
  for (Jacobi& j : il) progs.push_back([&j](const UnitRunner* r) { j.run(r); });
  progs.insert(progs.begin() + 1, [](const UnitRunner* r) {
    SharedLoop loop;
    loop.items = 3;
    loop.compute = [](const std::vector<SharedLoop::Chunk>&) {};
    loop.pack = [](std::size_t, const ItemRange&) { return std::string(); };
    loop.unpack = [](std::size_t, const ItemRange&, const std::string&) {};
    runSharedLoop(r, loop);
    throw std::runtime_error("program 1 failed");
  });
  TwoProcesses runner;
  CHECK_THROWS_WITH(runInterleaved(&runner, progs), "program 1 failed");
  for (std::size_t p = 0; p < il.size(); ++p) CHECK(il[p].v == seq[p].v);
}

TEST_CASE("a loop that fails while combined stops every program and reaches the caller", "[interleave]") {
  std::vector<Jacobi> il = programs();
  std::vector<InterleavedProgram> progs;
  for (Jacobi& j : il) progs.push_back([&j](const UnitRunner* r) { j.run(r); });
  progs.push_back([](const UnitRunner* r) {
    SharedLoop loop;
    loop.items = 4;
    loop.compute = [](const std::vector<SharedLoop::Chunk>&) { throw std::runtime_error("compute failed"); };
    runSharedLoop(r, loop);
    FAIL("a program goes on after its loop failed");
  });
  CHECK_THROWS_WITH(runInterleaved(nullptr, progs), "compute failed");
}
