// runUnitBatches (study/stage.hpp): several batches run as one pool give every batch exactly what
// it gets when run alone (the oracle: the same batches through UnitRunner::run one by one), with a
// fresh store, on resume and when unit costs are recorded (one compute call per unit, the earlier
// calls' units handed back through load).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "study/checkpoint.hpp"
#include "study/stage.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

// A stage's view of one batch, kept as UnitBatch's contract says: each compute call replaces the
// previous call's units; load adds units.
struct Job {
  std::vector<std::string> ids;
  std::map<std::size_t, std::string> latest, loaded;
  int calls = 0;
  UnitBatch batch() {
    UnitBatch b;
    b.ids = ids;
    b.load = [this](std::size_t k, const std::string& bytes) {
      if (bytes != "result of " + ids[k]) return false;
      loaded[k] = bytes;
      return true;
    };
    b.compute = [this](const std::vector<std::size_t>& todo, const UnitBatch::Done& done) {
      latest.clear();
      ++calls;
      for (std::size_t k : todo) {
        latest[k] = "result of " + ids[k];
        done(k, latest[k]);
      }
    };
    return b;
  }
  // What the stage ends with: every unit once (computed in the latest call or loaded).
  std::map<std::size_t, std::string> result() const {
    std::map<std::size_t, std::string> all = loaded;
    for (const auto& [k, v] : latest) CHECK(all.emplace(k, v).second);  // never both
    return all;
  }
};

std::vector<Job> jobs() {
  std::vector<Job> j(4);
  j[0].ids = {"reach/g/a/units_0-1", "reach/g/a/units_1-2", "reach/g/a/units_2-3"};
  j[1].ids = {};  // a design without units
  j[2].ids = {"reach/g/b/units_0-1"};
  j[3].ids = {"reach/g/c/units_0-2", "reach/g/c/units_2-4", "reach/g/c/units_4-6",
              "reach/g/c/units_6-7"};
  return j;
}

// Runs the jobs combined and one by one (each with its own store folder, `saved` units stored
// before, as an interrupted run leaves them) and compares what every job ends with.
void compareWithOneByOne(const UnitTimeRecord& times, const std::vector<std::string>& saved) {
  std::vector<std::map<std::size_t, std::string>> expected, got;
  for (int combined = 0; combined < 2; ++combined) {
    const fs::path dir =
        fs::temp_directory_path() / ("armstudy_unit_batches_" + std::to_string(combined));
    fs::remove_all(dir);
    std::string msg;
    CheckpointStore store(dir.string(), "fingerprint\n", msg);
    for (const std::string& id : saved) store.save(id, "result of " + id);
    const UnitRunner runner(store, 1, times);
    std::vector<Job> js = jobs();
    std::vector<UnitBatch> batches;
    for (Job& j : js) batches.push_back(j.batch());
    long loaded = 0;
    if (combined) {
      loaded = runUnitBatches(runner, batches);
    } else {
      for (const UnitBatch& b : batches) loaded += runner.run(b);
    }
    CHECK(loaded == static_cast<long>(saved.size()));
    auto& out = combined ? got : expected;
    for (const Job& j : js) {
      out.push_back(j.result());
      CHECK(out.back().size() == j.ids.size());  // every unit, once
    }
    store.finish();
  }
  CHECK(got == expected);
}

}  // namespace

TEST_CASE("batches run as one pool end as they end run one by one", "[study][units]") {
  SECTION("fresh store") { compareWithOneByOne(UnitTimeRecord{}, {}); }
  SECTION("resuming with some units saved") {
    compareWithOneByOne(UnitTimeRecord{},
                        {"reach/g/a/units_1-2", "reach/g/c/units_0-2", "reach/g/c/units_6-7"});
  }
  SECTION("unit costs recorded: one call per unit, each call replacing every batch's units") {
    const fs::path csv = fs::temp_directory_path() / "armstudy_unit_batches_times.csv";
    fs::remove(csv);
    compareWithOneByOne(UnitTimeRecord{csv.string()}, {"reach/g/b/units_0-1"});
    // One line per computed unit in each of the two runs: 8 units, 1 of them loaded.
    std::ifstream in(csv);
    int lines = 0;
    for (std::string l; std::getline(in, l);) lines += l.rfind("reach/g/", 0) == 0;
    CHECK(lines == 2 * 7);
  }
}

TEST_CASE("a combined compute call gives each batch only its own units, in its own indices",
          "[study][units]") {
  CheckpointStore off;
  const UnitRunner runner(off, 1, UnitTimeRecord{});
  std::vector<Job> js = jobs();
  std::vector<UnitBatch> batches;
  for (Job& j : js) batches.push_back(j.batch());
  CHECK(runUnitBatches(runner, batches) == 0);
  for (const Job& j : js) {
    CHECK(j.calls == 1);  // every batch's compute is called, also with nothing to do
    REQUIRE(j.latest.size() == j.ids.size());
    for (const auto& [k, v] : j.latest) CHECK(v == "result of " + j.ids[k]);
  }
}
