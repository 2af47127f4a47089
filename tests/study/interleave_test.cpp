// Interleaved programs (study/interleave.hpp): programs whose shared loops are grouped
// into combined loops give the results of the same programs run one after another (the oracle),
// whatever chunks the runner cuts the combined loops into; the steps are the longest program's, not
// the sum; a program's failure reaches the caller after the others ended.
#include "study/interleave.hpp"

#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "test_support.hpp"

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

std::vector<Jacobi> programs() {
  return {{23, 4, 5, {}}, {7, 9, 2, {}}, {40, 1, 16, {}}, {12, 6, 5, {}}};
}

}  // namespace

TEST_CASE("interleaved programs give the results of the same programs run one after another",
          "[interleave]") {
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
        for (const ItemRange& r : splitRange(j.n, j.chunk))
          expected.push_back({off + r.begin, off + r.end});
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

TEST_CASE("a loop that fails while combined stops every program and reaches the caller",
          "[interleave]") {
  std::vector<Jacobi> il = programs();
  std::vector<InterleavedProgram> progs;
  for (Jacobi& j : il) progs.push_back([&j](const UnitRunner* r) { j.run(r); });
  progs.push_back([](const UnitRunner* r) {
    SharedLoop loop;
    loop.items = 4;
    loop.compute = [](const std::vector<SharedLoop::Chunk>&) {
      throw std::runtime_error("compute failed");
    };
    runSharedLoop(r, loop);
    FAIL("a program goes on after its loop failed");
  });
  CHECK_THROWS_WITH(runInterleaved(nullptr, progs), "compute failed");
}

TEST_CASE(
    "rank groups: programs dealt out costliest first, ranks in proportion to the groups' cost",
    "[interleave]") {
  // Fewer than two groups of at least min_ranks ranks: every rank runs every program.
  CHECK(planRankGroups({1, 1, 1}, 3, 2).ranks.empty());
  CHECK(planRankGroups({1}, 64, 1).ranks.empty());
  // One program per group, ranks in proportion 3:1:1:1.
  RankGroupPlan a = planRankGroups({3, 1, 1, 1}, 12, 1);
  CHECK(a.group_of == std::vector<std::size_t>{0, 1, 2, 3});
  CHECK(a.ranks == std::vector<int>{6, 2, 2, 2});
  // Two groups: the costly program alone, the five cheap ones together (a tie goes to the lower
  // group index only after the second group caught up), two ranks each.
  RankGroupPlan b = planRankGroups({5, 1, 1, 1, 1, 1}, 4, 2);
  CHECK(b.group_of == std::vector<std::size_t>{0, 1, 1, 1, 1, 1});
  CHECK(b.ranks == std::vector<int>{2, 2});
  // Every group keeps at least one rank, and the ranks add up.
  RankGroupPlan c = planRankGroups({100, 1, 1}, 3, 1);
  CHECK(c.ranks == std::vector<int>{1, 1, 1});
  for (int n : {8, 64, 256, 1000}) {
    std::vector<double> w;
    for (int p = 0; p < 35; ++p) w.push_back(1 + (p * 37) % 11);
    const RankGroupPlan d = planRankGroups(w, n, 4);
    int sum = 0;
    for (int r : d.ranks) {
      CHECK(r >= 1);
      sum += r;
    }
    CHECK(sum == n);
    CHECK(d.ranks.size() == static_cast<std::size_t>(std::min(35, n / 4)));
  }
}

namespace {

// A process of a run in two rank groups, played in one: it is in group 0 (whose two processes the
// TwoProcesses runner plays), and the exchange brings the results of group 1's programs, computed
// here by separate copies of those programs (the other group's processes).
class GroupedProcess final : public UnitRunner {
 public:
  GroupedProcess() : UnitRunner(off_, 1, UnitTimeRecord{}) {}
  mutable TwoProcesses group_runner;
  mutable std::vector<std::string> sent;  // what this process sent in the exchange
  std::function<std::string(std::size_t)>
      other_group;  // program p's result bytes, computed elsewhere
  std::unique_ptr<RankGroups> groups(const std::vector<double>& weights) const override {
    struct Fake final : RankGroups {
      const GroupedProcess* self = nullptr;
      const UnitRunner& runner() const override { return self->group_runner; }
      std::vector<std::string> exchange(const std::vector<std::string>& mine) const override {
        self->sent = mine;
        std::vector<std::string> all(mine.size());
        for (std::size_t p = 0; p < all.size(); ++p)
          all[p] = group_of[p] == 0 ? mine[p] : self->other_group(p);
        return all;
      }
    };
    auto g = std::make_unique<Fake>();
    g->self = this;
    g->group_of = planRankGroups(weights, 4, 2).group_of;
    g->mine = 0;
    return g;
  }
  void share(const SharedLoop&) const override { FAIL("the programs run in the group's runner"); }

 private:
  CheckpointStore off_;
};

std::string packValues(const std::vector<std::int64_t>& v) {
  std::string b;
  for (const std::int64_t x : v) b += std::to_string(x) + ",";
  return b;
}

}  // namespace

TEST_CASE("in rank groups, a process runs its group's programs and takes the others' results",
          "[interleave]") {
  std::vector<Jacobi> seq = programs();
  for (Jacobi& j : seq) j.run(nullptr);
  // Weights n x steps: 92, 63, 40, 72 -> group 0 runs programs 0 and 2, group 1 programs 1 and 3.
  std::vector<Jacobi> il = programs();
  std::vector<InterleavedProgram> progs;
  for (Jacobi& j : il) progs.push_back([&j](const UnitRunner* r) { j.run(r); });
  GroupedProcess runner;
  runner.other_group = [](std::size_t p) {
    Jacobi j = programs()[p];
    j.run(nullptr);
    return packValues(j.v);
  };
  ProgramResults results;
  results.pack = [&](std::size_t p) { return packValues(il[p].v); };
  results.unpack = [&](std::size_t p, const std::string& bytes) {
    il[p].v.clear();
    for (std::size_t pos = 0; pos < bytes.size();) {
      const std::size_t comma = bytes.find(',', pos);
      il[p].v.push_back(std::stoll(bytes.substr(pos, comma - pos)));
      pos = comma + 1;
    }
  };
  results.weight = [&](std::size_t p) { return double(il[p].n * il[p].steps); };
  runInterleaved(&runner, progs, &results);
  for (std::size_t p = 0; p < il.size(); ++p) CHECK(il[p].v == seq[p].v);
  // The group ran only its programs (0: 23 items x 4 steps, 2: 40 items x 1 step), combined.
  REQUIRE(runner.group_runner.loop_items.size() == 4);
  CHECK(runner.group_runner.loop_items[0] == 23 + 40);
  CHECK(runner.group_runner.loop_items[1] == 23);
  // It sent its programs' results and nothing for the others'.
  REQUIRE(runner.sent.size() == 4);
  CHECK(runner.sent[0] == packValues(seq[0].v));
  CHECK(runner.sent[2] == packValues(seq[2].v));
  CHECK(runner.sent[1].empty());
  CHECK(runner.sent[3].empty());
}

namespace {

// The distribution simulator runs on python3, which scripts/install-deps.sh installs: missing, the
// calling test fails.
void requirePython3() {
  INFO("python3 is missing (scripts/install-deps.sh installs it)");
  REQUIRE(std::system("python3 -c 'pass' > /dev/null 2>&1") == 0);
}

}  // namespace

TEST_CASE("the distribution simulator forms rank groups as planRankGroups does",
          "[interleave][benchmarks]") {
  // tests/benchmarks/simulate_distribution.py --groups replays the searches in the groups armstudy
  // would form: its assign_groups must agree with planRankGroups.
  requirePython3();
  const std::vector<std::tuple<std::vector<double>, int, int>> cases = {
      {{1, 1, 1}, 3, 2},
      {{3, 1, 1, 1}, 12, 1},
      {{5, 1, 1, 1, 1, 1}, 4, 2},
      {{100, 1, 1}, 3, 1},
      {{2, 2, 2, 2}, 64, 16},
      {{0.5, 8, 8.2, 0.6, 11, 10.4, 9}, 256, 16},
      {{0.5, 8, 8.2, 0.6, 11, 10.4, 9}, 37, 4},
      {{0, 0, 0, 5}, 8, 2}};
  for (const auto& [w, n, r] : cases) {
    const RankGroupPlan plan = planRankGroups(w, n, r);
    std::string expected = "None";
    if (!plan.ranks.empty()) {
      expected = "([";
      for (std::size_t p = 0; p < plan.group_of.size(); ++p)
        expected += (p ? ", " : "") + std::to_string(plan.group_of[p]);
      expected += "], [";
      for (std::size_t j = 0; j < plan.ranks.size(); ++j)
        expected += (j ? ", " : "") + std::to_string(plan.ranks[j]);
      expected += "])";
    }
    std::string list;
    for (const double x : w) list += (list.empty() ? "" : ", ") + std::to_string(x);
    const std::string cmd = "python3 -c \"import sys; sys.path.insert(0, '" +
                            test::sourcePath("tests/benchmarks") +
                            "'); import simulate_distribution as sd; print(sd.assign_groups([" +
                            list + "], " + std::to_string(n) + ", " + std::to_string(r) + "))\"";
    std::string got;
    REQUIRE(test::runCommand(cmd, got) == 0);
    while (!got.empty() && got.back() == '\n') got.pop_back();
    INFO("weights " << list << ", " << n << " ranks, groups of >= " << r);
    CHECK(got == expected);
  }
}

TEST_CASE(
    "the distribution simulator's ceiling: the longest chain of a record, the bound of any "
    "schedule",
    "[interleave][benchmarks]") {
  // tests/benchmarks/simulate_distribution.py --ceiling: a lower bound on the makespan of any
  // schedule, the serial rest plus the larger of work / N and the longest chain of pieces that must
  // run one after another. A hand-made record: design a's costliest unit 0.03 s, its search steps'
  // costliest chunks 0.05 and 0.04 s (design b's 0.01 s chunk in the same combined step does not
  // count for a), its audit step 0.01 s: a chain of 0.13 s; b's: 0.10 + 0.01 s; the files'
  // costliest piece 0.05 s. Work 0.34 s.
  requirePython3();
  const std::string dir = std::filesystem::temp_directory_path().string() + "/armstudy-ceiling-" +
                          std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  const std::string csv = dir + "/units.csv";
  {
    std::ofstream f(csv);
    f << "unit,seconds,cpu_seconds,threads,rank,bytes,part\n"
         "reach/g/a/units_0-1,0.01,0.01,1,0,10,\n"
         "reach/g/a/units_1-2,0.03,0.03,1,0,10,\n"
         "reach/g/b/units_0-1,0.10,0.10,1,0,10,\n"
         "share:interleaved/2/search/a/0_propagate,0.02,0.02,1,0,5,0\n"
         "share:interleaved/2/search/a/0_propagate,0.05,0.05,1,0,5,0\n"
         "share:interleaved/2/search/a/0_propagate,0.01,0.01,1,0,5,1\n"
         "share:interleaved/2/search/a/1_best,0.04,0.04,1,0,5,0\n"
         "share:interleaved/2/audit/a,0.01,0.01,1,0,5,0\n"
         "share:files/g,0.05,0.05,1,0,100,\n"
         "share:files/g,0.02,0.02,1,0,100,\n";
  }
  const std::string script = test::sourcePath("tests/benchmarks/simulate_distribution.py");
  std::string out;
  REQUIRE(test::runCommand("python3 -c \"import sys; sys.path.insert(0, '" +
                               test::sourcePath("tests/benchmarks") +
                               "'); import simulate_distribution as sd; c, n = sd.load_chains('" +
                               csv + "', 1.0); print('%.4f %s' % (c, n.split(':')[0]))\"",
                           out) == 0);
  CHECK(out == "0.1300 g/a\n");
  // On 4 ranks the chain binds (0.34 / 4 < 0.13): bound 0.1 + 0.13 s, efficiency at most
  // (0.34 + 0.1) / (4 x 0.23) = 48 %; with 80 % out of reach, no serial rest allows it.
  REQUIRE(test::runCommand(
              "python3 " + script + " " + csv + " --ceiling --serial-total 0.1 --ranks 4,2", out) ==
          0);
  INFO(out);
  CHECK(out.find("| 4 | 0.085 | 0.230 | 48 % | none |") != std::string::npos);
  // On 2 ranks the work binds (0.17 s): 80 % allows a serial rest of (0.34 - 0.8 x 2 x 0.17) / (0.8
  // x 2 - 1).
  CHECK(out.find("| 2 | 0.170 | 0.270 | 81 % | 0.113 |") != std::string::npos);
  std::filesystem::remove_all(dir);
}
