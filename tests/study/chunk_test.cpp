// Work units as the checkpoint (and later distribution) grain: a stage's result assembled from
// units, in any order and after any interruption, is bit for bit the result of one uninterrupted
// run. Oracles: the whole-grid sweep / whole map / whole design evaluation of the same inputs (the
// code path without units), and the result files of a run without checkpoints.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>

#include "collision/collision.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "reach/reach_sweep.hpp"
#include "stages/dexterity/dexterity_output.hpp"
#include "stages/harvest/harvest_stage.hpp"
#include "stages/reach/reach_stage.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

// Options of a stage run in these tests: threads, items per unit (0 = stage default), no progress.
RunOptions runOpts(int threads, long unit_items) {
  RunOptions o;
  o.threads = threads;
  o.unit_items = unit_items;
  o.progress = false;
  return o;
}

}  // namespace

namespace {

fs::path freshDir(const std::string& name) { return test::emptyTempDir("chunk_" + name); }

// Bitwise equality (NaN == NaN, -0 != +0).
template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void requireSameSweep(const PoseSweep& a, const PoseSweep& b) {
  REQUIRE(a.size == b.size);
  CHECK(a.offset == b.offset);
  CHECK(a.dof == b.dof);
  CHECK(sameBits(a.status, b.status));
  CHECK(sameBits(a.starts, b.starts));
  CHECK(sameBits(a.position_error_m, b.position_error_m));
  CHECK(sameBits(a.orientation_error_rad, b.orientation_error_rad));
  CHECK(sameBits(a.manipulability, b.manipulability));
  CHECK(sameBits(a.joint_limit_margin, b.joint_limit_margin));
  CHECK(sameBits(a.q, b.q));
  CHECK(a.collision == b.collision);
  CHECK(a.obstacles == b.obstacles);
  CHECK(sameBits(a.min_distance_m, b.min_distance_m));
  CHECK(sameBits(a.colliding_pair, b.colliding_pair));
  CHECK(sameBits(a.obstacle_distance_m, b.obstacle_distance_m));
  CHECK(a.pair_names == b.pair_names);
}

// Files below `dir` (relative path -> content), without the manifest (timings, dates) and the
// checkpoint folder.
std::map<std::string, std::string> resultFiles(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), dir).string();
    if (rel == "manifest.json" || rel.rfind(".partial", 0) == 0) continue;
    out[rel] = readFileOrThrow(e.path().string());
  }
  return out;
}

// The units saved in a run's checkpoint folder whose file name starts with `prefix` (a running
// process may remove the folder meanwhile: then none).
std::vector<fs::path> unitFiles(const fs::path& output_dir, const std::string& prefix = "") {
  std::vector<fs::path> out;
  try {
    for (const auto& e : fs::directory_iterator(output_dir / ".partial/units"))
      if (e.path().extension() == ".unit" && e.path().filename().string().rfind(prefix, 0) == 0)
        out.push_back(e.path());
  } catch (const fs::filesystem_error&) {
    return {};
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Simulates a run killed midway: removes every second saved unit and truncates one more, so the
// resume must solve some units again and ignore a damaged one. Returns the units left intact.
long damageStore(const fs::path& output_dir, const std::string& prefix) {
  std::vector<fs::path> units = unitFiles(output_dir, prefix);
  long intact = 0;
  for (std::size_t k = 0; k < units.size(); ++k) {
    if (k % 2 == 1) {
      fs::remove(units[k]);
    } else if (k == 2) {
      const std::string b = readFileOrThrow(units[k].string());
      std::ofstream(units[k], std::ios::binary | std::ios::trunc) << b.substr(0, b.size() / 2);
    } else {
      ++intact;
    }
  }
  return intact;
}

std::string designPath(const std::string& name) { return sourcePath("designs/" + name + ".toml"); }

// A study file in `dir` with the given designs and sections.
std::string writeStudy(const fs::path& dir, const std::string& name,
                       const std::vector<std::string>& designs, const std::string& sections) {
  const fs::path p = dir / (name + ".toml");
  std::ofstream f(p);
  f << "[study]\nname = \"" << name << "\"\n";
  for (const auto& d : designs) f << "[[design]]\nfile = \"" << designPath(d) << "\"\n";
  f << sections;
  return p.string();
}

const char* kDexteritySection = R"([dexterity]
stem_x = "0.225 m"
stem_y = "0.7 m"
radius = "0.15 m"
gamma = { min = "-pi/2", max = "pi/2", step = "15 deg" }
z = { min = "0.4 m", max = "1.4 m", step = "0.125 m" }
task = "position_axis"
measure_space = "translational"
ellipsoids = true
[dexterity.objective]
joint_limits = 0.1
manipulability = 1.0
)";

const char* kHarvestSection = R"([harvest]
plot_fruits = 2
[harvest.row]
seed = 3
stems = 3
fruits_per_stem = 2
first_stem_y = "0.7 m"
fruit_z_mean = "0.8 m"
[harvest.approach]
duration = 0.5
[harvest.grid]
x = { from = "0.3 m", to = "0.9 m", step = "0.1 m" }
y = "0.8 m"
z = { from = "0.3 m", to = "1.2 m", step = "0.15 m" }
)";

}  // namespace

TEST_CASE(
    "a grid swept in chunks of 1 line, 7 lines or whole, with 1 or 2 threads, assembles in any "
    "order "
    "into the whole sweep",
    "[study][chunk][reach]") {
  const Model m = loadDesign(designPath("first_prototype_6dof"));
  TaskGrid g;
  g.name = "g";
  g.task_space = TaskSpace::spraying();
  g.axes = {AxisRange{-0.78, 0.78, 0.08}, AxisRange{0.3, 1.2, 0.1}, AxisRange{1.2, 1.2, 1}};
  g.orientations = {{0, 0, -0.7}, {0, 0, 0.7}};
  REQUIRE(g.validate().empty());
  const IkOptions o = ReachConfig::studyDefaults();
  const PoseSweep whole = sweepGrid(m, g, o, 1, nullptr);
  REQUIRE(whole.countReachable() > 0);
  REQUIRE(whole.countReachable() < whole.size);  // warm-start chains break inside lines
  const long units = sweepUnitCount(g);
  REQUIRE(units == g.lines());
  std::mt19937 rng(7);
  for (long lines : {1L, 7L, units})
    for (int threads : {1, 2}) {
      INFO(lines << " line(s) per chunk, " << threads << " thread(s)");
      const std::vector<ItemRange> ranges = splitRange(units, lines);
      std::vector<int> reported(ranges.size(), 0);
      std::vector<PoseSweep> done(ranges.size());
      std::vector<PoseSweep> chunks = sweepGridRanges(m, g, ranges, o, threads, nullptr, {},
                                                      [&](std::size_t k, const PoseSweep& c) {
                                                        ++reported[k];  // distinct k: no race
                                                        done[k] = c;
                                                      });
      REQUIRE(chunks.size() == ranges.size());
      for (std::size_t k = 0; k < ranges.size(); ++k) {
        CHECK(reported[k] == 1);
        CHECK(chunks[k].offset == ranges[k].begin * g.lineLength());
        requireSameSweep(done[k], chunks[k]);  // the chunk handed to on_done was final
      }
      std::shuffle(chunks.begin(), chunks.end(), rng);
      requireSameSweep(assembleSweep(chunks, g.size()), whole);
    }
  // A chunk swept alone equals the same poses of the whole sweep.
  const std::vector<PoseSweep> alone = sweepGridRanges(m, g, {{3, 5}}, o, 2, nullptr);
  const long b = 3 * g.lineLength(), e = 5 * g.lineLength();
  REQUIRE(alone.front().size == e - b);
  CHECK(std::equal(alone.front().status.begin(), alone.front().status.end(),
                   whole.status.begin() + b));
  CHECK(std::memcmp(alone.front().q.data(), whole.q.data() + b * whole.dof,
                    (e - b) * whole.dof * sizeof(double)) == 0);
}

TEST_CASE("collision-aware sweeps of pose-list chunks assemble into the whole sweep",
          "[study][chunk][reach]") {
  const Model m = loadDesign(designPath("first_prototype_6dof"));
  PoseList l;
  l.name = "l";
  l.task_space = TaskSpace::position();
  for (int i = 0; i < 150; ++i) {  // a helix through the workspace: 5 chunks of 32 poses
    TaskVector6 w = TaskVector6::Zero();
    w.head<3>() << 0.6 * std::cos(0.15 * i), 0.3 + 0.5 * std::abs(std::sin(0.05 * i)),
        0.6 + 0.006 * i;
    l.poses.push_back(w);
    l.lines.push_back(i + 2);
  }
  SweepCollision col{true,
                     {collision::sphereObstacle("stem", Eigen::Vector3d(0.3, 0.6, 1.0), 0.05)}};
  const IkOptions o = ReachConfig::studyDefaults();
  const PoseSweep whole = sweepPoseList(m, l, o, 1, nullptr, col);
  REQUIRE(whole.collision);
  REQUIRE(whole.obstacles);
  REQUIRE(whole.countReachable() > 0);
  const long units = sweepUnitCount(l);
  REQUIRE(units == 5);
  std::vector<PoseSweep> chunks =
      sweepPoseListRanges(m, l, splitRange(units, 2), o, 2, nullptr, col);
  std::reverse(chunks.begin(), chunks.end());
  requireSameSweep(assembleSweep(chunks, whole.size), whole);
}

TEST_CASE("the reach stage resumes from saved chunks into the files of an uninterrupted run",
          "[study][chunk][checkpoint]") {
  const fs::path dir = freshDir("reach_stage");
  const Study s = loadStudy(writeStudy(
      dir, "r", {"final_prototype_7dof", "first_prototype_6dof"},
      "[reach]\ntask_space = \"full\"\nself_collision = true\n[[reach.grid]]\nname = \"wall\"\n"
      "x = { from = \"-0.6 m\", to = \"0.6 m\", step = \"0.05 m\" }\ny = \"0.8 m\"\n"
      "z = { from = \"0.5 m\", to = \"1.5 m\", step = \"0.1 m\" }\n"
      "alpha = \"-90 deg\"\nbeta = \"0 deg\"\ngamma = \"10 deg\"\n"));
  // Reference: no checkpoints, default unit size, one thread.
  const StageResult ref = runStage(s, "reach", (dir / "ref").string(), runOpts(1, 0));
  const auto ref_files = resultFiles(dir / "ref");
  REQUIRE(ref_files.size() >= 4);
  REQUIRE(ref_files.at("summary.json").find("colliding_pairs") !=
          std::string::npos);  // collision columns

  // One grid line per unit; the run "dies" before finish(), then loses some units.
  const fs::path out = dir / "out";
  std::string msg;
  {
    CheckpointStore store(out.string(), "fp\n", msg);
    const StageResult first = runStage(s, "reach", out.string(), runOpts(2, 1), &store);
    CHECK(first.units_resumed == 0);
  }
  const long lines = stageSettings<ReachConfig>(s, "reach")->grids[0].lines();
  REQUIRE(static_cast<long>(unitFiles(out).size()) == 2 * lines);
  const long intact = damageStore(out, "");
  fs::remove_all(out / "reach");
  CheckpointStore store(out.string(), "fp\n", msg);
  CHECK(msg.find("resuming") != std::string::npos);
  const StageResult resumed = runStage(s, "reach", out.string(), runOpts(2, 1), &store);
  CHECK(resumed.units_resumed == intact);
  CHECK(resultFiles(out) == ref_files);
  CHECK(resumed.metrics.scalars == ref.metrics.scalars);
  CHECK(resumed.metrics.flags == ref.metrics.flags);
  // Everything saved now: a third run solves nothing.
  const StageResult third = runStage(s, "reach", out.string(), runOpts(1, 1), &store);
  CHECK(third.units_resumed == 2 * lines);
  CHECK(resultFiles(out) == ref_files);
}

TEST_CASE(
    "dexterity rows computed in ranges and units deserialised in any order give the whole map",
    "[study][chunk][dexterity]") {
  const fs::path dir = freshDir("dexterity_rows");
  const Study s = loadStudy(writeStudy(dir, "d", {"final_prototype_7dof"}, kDexteritySection));
  REQUIRE(stageSettings<dexterity::DexterityOptions>(s, "dexterity"));
  const Model& m = s.designs[0].model;
  const long rows = stageSettings<dexterity::DexterityOptions>(s, "dexterity")->grid.z_m.count;
  // The chained rows of the whole grid (the units hold these; the map search runs after them).
  const dexterity::DexterityMap whole = dexterity::computeDexterityRows(
      m, *stageSettings<dexterity::DexterityOptions>(s, "dexterity"), {{0, rows}}, 1);
  REQUIRE(whole.reachable() > 0);
  REQUIRE(rows >= 5);
  const ItemRange all{0, rows};
  const std::string whole_bytes = dexterity::serializeRows(whole, all);

  const std::vector<ItemRange> ranges = splitRange(rows, 3);
  std::vector<std::string> units(ranges.size());
  const dexterity::DexterityMap parts = dexterity::computeDexterityRows(
      m, *stageSettings<dexterity::DexterityOptions>(s, "dexterity"), ranges, 2,
      [&](std::size_t k, const dexterity::DexterityMap& p) {
        units[k] = dexterity::serializeRows(p, ranges[k]);
      });
  CHECK(dexterity::serializeRows(parts, all) == whole_bytes);

  std::vector<std::size_t> order(ranges.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::shuffle(order.begin(), order.end(), std::mt19937(3));
  dexterity::DexterityMap joined;
  joined.dof = m.dof();
  joined.grid = stageSettings<dexterity::DexterityOptions>(s, "dexterity")->grid;
  joined.cells.resize(joined.grid.size());
  for (std::size_t k : order) {
    ItemRange got;
    REQUIRE(dexterity::deserializeRows(units[k], joined, got));
    CHECK(got.begin == ranges[k].begin);
    CHECK(got.end == ranges[k].end);
  }
  CHECK(dexterity::serializeRows(joined, all) == whole_bytes);
  // The search over the joined units gives computeDexterityMap's map.
  dexterity::DexterityMap searched = joined;
  dexterity::searchDexterityMap(m, *stageSettings<dexterity::DexterityOptions>(s, "dexterity"),
                                searched, 2);
  CHECK(dexterity::serializeRows(searched, all) ==
        dexterity::serializeRows(
            dexterity::computeDexterityMap(
                m, *stageSettings<dexterity::DexterityOptions>(s, "dexterity"), 1),
            all));
  // Bytes of another kind or a map of another shape are refused, leaving the map unchanged.
  ItemRange got;
  CHECK_FALSE(dexterity::deserializeRows("armstudy-reach-unit-v4", joined, got));
  CHECK_FALSE(dexterity::deserializeRows(units[0].substr(0, units[0].size() - 1), joined, got));
  dexterity::DexterityMap other = joined;
  other.dof = m.dof() + 2;
  CHECK_FALSE(dexterity::deserializeRows(units[0], other, got));
  CHECK(dexterity::serializeRows(joined, all) == whole_bytes);
}

TEST_CASE("the dexterity stage resumes from saved rows into the files of an uninterrupted run",
          "[study][chunk][checkpoint][dexterity]") {
  const fs::path dir = freshDir("dexterity_stage");
  const Study s = loadStudy(
      writeStudy(dir, "d", {"final_prototype_7dof", "first_prototype_9dof"}, kDexteritySection));
  runStage(s, "dexterity", (dir / "ref").string(), runOpts(1, 0));
  const auto ref_files = resultFiles(dir / "ref");
  const fs::path out = dir / "out";
  std::string msg;
  {
    CheckpointStore store(out.string(), "fp\n", msg);
    CHECK(runStage(s, "dexterity", out.string(), runOpts(2, 1), &store).units_resumed == 0);
  }
  REQUIRE(static_cast<long>(unitFiles(out, "dexterity_").size()) ==
          2 * stageSettings<dexterity::DexterityOptions>(s, "dexterity")->grid.z_m.count);
  const long intact = damageStore(out, "dexterity_");
  fs::remove_all(out / "dexterity");
  CheckpointStore store(out.string(), "fp\n", msg);
  const StageResult ds = runStage(s, "dexterity", out.string(), runOpts(2, 1), &store);
  CHECK(ds.units_resumed == intact);
  CHECK(resultFiles(out) == ref_files);
}

TEST_CASE("tracking units: runs resume into the files of an uninterrupted run",
          "[study][chunk][checkpoint][tracking]") {
  const fs::path dir = freshDir("tracking_stage");
  const Study s = loadStudy(test::sourcePath("studies/fig5_13_obstacle.toml"));
  runStage(s, "tracking", (dir / "ref").string(), runOpts(1, 0));
  const auto ref_files = resultFiles(dir / "ref");
  REQUIRE(ref_files.count("tracking/summary.json"));
  const fs::path out = dir / "out";
  std::string msg;
  {
    CheckpointStore store(out.string(), "fp\n", msg);
    CHECK(runStage(s, "tracking", out.string(), runOpts(2, 0), &store).units_resumed == 0);
  }
  REQUIRE(unitFiles(out, "tracking_").size() ==
          2);  // one entry: the plain run and the run with H_c
  const long intact = damageStore(out, "tracking_");
  REQUIRE(intact == 1);
  fs::remove_all(out / "tracking");
  CheckpointStore store(out.string(), "fp\n", msg);
  CHECK(runStage(s, "tracking", out.string(), runOpts(2, 0), &store).units_resumed == intact);
  CHECK(resultFiles(out) == ref_files);
  CHECK(runStage(s, "tracking", out.string(), runOpts(1, 0), &store).units_resumed == 2);
  CHECK(resultFiles(out) == ref_files);
}

TEST_CASE("harvest units: fruits and grid points resume into the files of an uninterrupted run",
          "[study][chunk][checkpoint][harvest]") {
  const fs::path dir = freshDir("harvest_stage");
  const Study s = loadStudy(writeStudy(dir, "h", {"final_prototype_9dof"}, kHarvestSection));
  REQUIRE(stageSettings<harvest::HarvestOptions>(s, "harvest"));
  const Model& m = s.designs[0].model;
  const GreenhouseRow row =
      sampleGreenhouseRow(stageSettings<harvest::HarvestOptions>(s, "harvest")->row);
  REQUIRE(row.fruits.size() == 6);

  // Units in shuffled order give the whole design result, profiles included.
  const harvest::DesignResult whole = harvest::evaluateHarvestDesign(
      m, *stageSettings<harvest::HarvestOptions>(s, "harvest"), row, 1);
  int evaluated = 0;
  for (const auto& f : whole.fruits) evaluated += f.evaluated();
  REQUIRE(evaluated > 0);
  const ItemRange all_fruits{0, 6}, all_points{0, static_cast<long>(whole.grid.size())};
  harvest::HarvestWork work;
  work.fruits = splitRange(6, 4);
  work.grid = splitRange(all_points.end, 5);
  std::vector<std::string> fruit_units(work.fruits.size()), grid_units(work.grid.size());
  work.fruits_done = [&](std::size_t k, const harvest::DesignResult& d) {
    fruit_units[k] = harvest::serializeFruits(d, work.fruits[k]);
  };
  work.grid_done = [&](std::size_t k, const harvest::DesignResult& d) {
    grid_units[k] = harvest::serializeGridPoints(d, work.grid[k]);
  };
  const harvest::DesignResult parts = harvest::evaluateHarvestDesign(
      m, *stageSettings<harvest::HarvestOptions>(s, "harvest"), row, 2, &work);
  CHECK(harvest::serializeFruits(parts, all_fruits) == harvest::serializeFruits(whole, all_fruits));
  CHECK(harvest::serializeGridPoints(parts, all_points) ==
        harvest::serializeGridPoints(whole, all_points));
  harvest::DesignResult joined;
  joined.fruits.resize(6);
  joined.grid.resize(whole.grid.size());
  std::mt19937 rng(5);
  std::shuffle(fruit_units.begin(), fruit_units.end(), rng);
  std::shuffle(grid_units.begin(), grid_units.end(), rng);
  ItemRange got;
  for (const auto& u : fruit_units) REQUIRE(harvest::deserializeFruits(u, joined, got));
  for (const auto& u : grid_units) REQUIRE(harvest::deserializeGridPoints(u, joined, got));
  CHECK(harvest::serializeFruits(joined, all_fruits) ==
        harvest::serializeFruits(whole, all_fruits));
  CHECK(harvest::serializeGridPoints(joined, all_points) ==
        harvest::serializeGridPoints(whole, all_points));
  CHECK_FALSE(harvest::deserializeFruits(grid_units[0], joined, got));  // another unit kind

  // The stage: killed (no finish), units lost, resumed -> the files of a run without checkpoints.
  const RunOptions opt = runOpts(0, 2);
  const std::string ref_dir = (dir / "ref").string();
  runStage(s, "harvest", ref_dir, RunOptions{});
  const auto ref_files = resultFiles(dir / "ref");
  const std::string out = (dir / "out").string();
  std::string msg;
  {
    CheckpointStore store(out, "fp\n", msg);
    CHECK(runStage(s, "harvest", out, opt, &store).units_resumed == 0);
  }
  const long n_units = static_cast<long>(unitFiles(out, "harvest_").size());
  CHECK(n_units == 3 + (all_points.end + 1) / 2);
  const long intact = damageStore(out, "harvest_");
  fs::remove_all(fs::path(out) / "harvest");
  CheckpointStore store(out, "fp\n", msg);
  CHECK(runStage(s, "harvest", out, opt, &store).units_resumed == intact);
  CHECK(resultFiles(out) == ref_files);
}

namespace {

// Runs `armstudy run args` with the checkpoint store's test hook: killed with SIGKILL right after
// its `units`-th saved unit. Requires that the hook killed it, i.e. that the run was interrupted.
void runKilledAfter(const std::string& args, long units, const fs::path& study_out) {
  std::string log;
  const int st = runKilledAfterUnits(binaryPath() + " run " + args, units, log);
  INFO(log);
  REQUIRE(st == kKilledStatus);
  REQUIRE_FALSE(fs::exists(study_out / "manifest.json"));
}

// Resumes, checks that every saved unit was used, and compares with the reference files.
void resumeAndCompare(const std::string& args, const fs::path& study_out, const fs::path& ref_out) {
  const long saved = static_cast<long>(unitFiles(study_out).size());
  std::string log;
  const int st = runCommand(binaryPath() + " run " + args, log);
  INFO(log);
  REQUIRE(st == 0);
  CHECK(log.find("resuming: " + std::to_string(saved) + " completed unit(s)") != std::string::npos);
  const auto man = nlohmann::json::parse(readFileOrThrow((study_out / "manifest.json").string()));
  CHECK(man.value("units_resumed", -1L) == saved);
  CHECK_FALSE(fs::exists(study_out / ".partial"));
  CHECK(resultFiles(study_out) == resultFiles(ref_out));
}

}  // namespace

TEST_CASE("a run killed in the middle of a grid resumes from the saved chunks",
          "[study][chunk][checkpoint][e2e]") {
  const fs::path dir = freshDir("kill_grid");
  const std::string study =
      writeStudy(dir, "g", {"final_prototype_7dof"},
                 "[reach]\ntask_space = \"full\"\n[[reach.grid]]\nname = \"wall\"\n"
                 "x = { from = \"-0.6 m\", to = \"0.6 m\", step = \"0.02 m\" }\ny = \"0.8 m\"\n"
                 "z = { from = \"0.4 m\", to = \"1.6 m\", step = \"0.05 m\" }\n"
                 "alpha = \"-90 deg\"\nbeta = \"0 deg\"\ngamma = [\"0 deg\", \"20 deg\"]\n");
  std::string log;
  REQUIRE(
      runCommand(binaryPath() + " run " + study + " --threads 1 --output " + (dir / "ref").string(),
                 log) == 0);
  const fs::path out = dir / "out/g";
  const std::string args = study + " --threads 1 --unit-size 1 --output " + (dir / "out").string();
  // One grid line per unit: 50 units; killed right after the third is saved.
  runKilledAfter(args, 3, out);
  CHECK(unitFiles(out).size() == 3);
  resumeAndCompare(study + " --threads 2 --unit-size 1 --output " + (dir / "out").string(), out,
                   dir / "ref/g");
}

TEST_CASE("a run killed in its harvest stage resumes its dexterity and harvest units",
          "[study][chunk][checkpoint][e2e]") {
  const fs::path dir = freshDir("kill_stages");
  const std::string study = writeStudy(dir, "dh", {"final_prototype_9dof"},
                                       std::string(kDexteritySection) + kHarvestSection);
  std::string log;
  REQUIRE(
      runCommand(binaryPath() + " run " + study + " --threads 1 --output " + (dir / "ref").string(),
                 log) == 0);
  const fs::path out = dir / "out/dh";
  const std::string args = study + " --threads 1 --unit-size 2 --output " + (dir / "out").string();
  // The dexterity stage saves one unit per height (9), then the harvest stage its units: killed
  // right after the first harvest unit.
  const long dexterity_units = 9;
  runKilledAfter(args, dexterity_units + 1, out);
  CHECK(static_cast<long>(unitFiles(out, "dexterity_").size()) == dexterity_units);
  CHECK(unitFiles(out, "harvest_").size() == 1);
  resumeAndCompare(study + " --threads 2 --unit-size 2 --output " + (dir / "out").string(), out,
                   dir / "ref/dh");
}
