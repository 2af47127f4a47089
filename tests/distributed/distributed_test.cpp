// Studies distributed with MPI (docs/distributed.md): `mpirun -np 1/2/3 armstudy run`
// writes every result file byte for byte as a single process does (the oracle: the same study run
// without mpirun, into the same output path; the two long shipped studies in a coarser copy),
// whatever the thread count per rank; a rank
// killed mid-run ends the job with a clear message and a re-run with another rank count resumes
// from the saved units into the same bytes. The README's commands install MPI
// (scripts/install-deps.sh): in a build without it (ARMSTUDY_MPI=OFF) or without mpirun these tests
// fail.
#include "study/distributed.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "io/files.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

// Fails the calling test unless this build runs MPI jobs and its mpirun exists.
void requireMpi() {
  INFO(
      "MPI is missing (scripts/install-deps.sh installs libopenmpi-dev and openmpi-bin; "
      "ARMSTUDY_MPI=ON)");
  REQUIRE(mpiAvailable());
  INFO("mpirun: '" << ARMSTUDY_MPIEXEC << "'");
  REQUIRE(fs::exists(ARMSTUDY_MPIEXEC));
}

fs::path freshDir(const std::string& name) { return test::emptyTempDir("distributed_" + name); }

std::string designPath(const std::string& name) { return sourcePath("designs/" + name + ".toml"); }

std::string writeStudy(const fs::path& dir, const std::string& name,
                       const std::vector<std::string>& designs, const std::string& sections) {
  const fs::path p = dir / (name + ".toml");
  std::ofstream f(p);
  f << "[study]\nname = \"" << name << "\"\n";
  for (const auto& d : designs) f << "[[design]]\nfile = \"" << designPath(d) << "\"\n";
  f << sections;
  return p.string();
}

// Every file of a study's output folder but the manifest (timings, date, ranks) and the store.
std::map<std::string, std::string> resultFiles(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string rel = fs::relative(e.path(), dir).string();
    if (e.is_regular_file() && rel != "manifest.json" && rel.rfind(".partial", 0) != 0 &&
        rel != ".armstudy.lock")
      out[rel] = readFileOrThrow(e.path().string());
  }
  return out;
}

// The keys of two file maps that differ (for the failure message).
std::string differing(const std::map<std::string, std::string>& a,
                      const std::map<std::string, std::string>& b) {
  std::string d;
  for (const auto& [k, v] : a)
    if (!b.count(k) || b.at(k) != v) d += k + " ";
  for (const auto& [k, v] : b)
    if (!a.count(k)) d += k + "(extra) ";
  return d;
}

// `armstudy run` under mpirun with `ranks` processes (OpenMPI as root needs the two variables).
std::string mpirun(int ranks, const std::string& args) {
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " +
         std::string(ARMSTUDY_MPIEXEC) + " -np " + std::to_string(ranks) + " --oversubscribe " +
         binaryPath() + " run " + args;
}

// `armstudy run` on 2 ranks, rank 1 killed with SIGKILL right after it saved its `units`-th unit:
// the checkpoint store's test hook, set for rank 1 alone (mpirun's form for one executable per
// rank, the second started through env).
std::string mpirunKillingRank1(const std::string& args, long units) {
  const std::string run = binaryPath() + " run " + args;
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " +
         std::string(ARMSTUDY_MPIEXEC) + " --oversubscribe -np 1 " + run +
         " : -np 1 env ARMSTUDY_TEST_ABORT_AFTER_UNITS=" + std::to_string(units) + " " + run;
}

// A fontconfig file that asks for hinted, emboldened glyphs (what a rank's environment on another
// machine or user account may ask for), and the mpirun command whose ranks 1.. run under it.
std::string writeOtherFontconfig(const fs::path& dir) {
  const fs::path p = dir / "fonts.conf";
  std::ofstream(p) << R"(<?xml version="1.0"?>
<!DOCTYPE fontconfig SYSTEM "fonts.dtd">
<fontconfig>
  <include ignore_missing="yes">/etc/fonts/fonts.conf</include>
  <match target="font">
    <edit name="hinting" mode="assign"><bool>true</bool></edit>
    <edit name="hintstyle" mode="assign"><const>hintfull</const></edit>
    <edit name="embolden" mode="assign"><bool>true</bool></edit>
  </match>
</fontconfig>
)";
  return p.string();
}
std::string mpirunOthersUnder(const std::string& fontconfig, int ranks, const std::string& args) {
  const std::string run = binaryPath() + " run " + args;
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " +
         std::string(ARMSTUDY_MPIEXEC) + " --oversubscribe -np 1 " + run + " : -np " +
         std::to_string(ranks - 1) + " env FONTCONFIG_FILE=" + fontconfig + " " + run;
}

const char* kReachSection = R"([reach]
task_space = "full"
[[reach.grid]]
name = "wall"
x = { from = "-0.6 m", to = "0.6 m", step = "0.05 m" }
y = "0.8 m"
z = { from = "0.4 m", to = "1.6 m", step = "0.1 m" }
alpha = "-90 deg"
beta = "0 deg"
gamma = ["0 deg", "20 deg"]
)";

const char* kDexteritySection = R"([dexterity]
stem_x = "0.225 m"
stem_y = "0.7 m"
radius = "0.15 m"
gamma = { min = "-pi/2", max = "pi/2", step = "30 deg" }
z = { min = "0.4 m", max = "1.4 m", step = "0.25 m" }
task = "position_axis"
measure_space = "translational"
[dexterity.objective]
joint_limits = 0.1
manipulability = 1.0
)";

const char* kHarvestSection = R"([harvest]
plot_fruits = 1
[harvest.row]
seed = 3
stems = 2
fruits_per_stem = 2
first_stem_y = "0.7 m"
fruit_z_mean = "0.8 m"
[harvest.approach]
duration = 0.5
[harvest.grid]
x = { from = "0.3 m", to = "0.9 m", step = "0.2 m" }
y = "0.8 m"
z = { from = "0.3 m", to = "1.2 m", step = "0.3 m" }
)";

// Runs `study` under mpirun with each (ranks, threads) into `dir`/out/`name`, comparing every
// result file with `ref`, a single process's.
void requireRanksWrite(const fs::path& dir, const std::string& study, const std::string& name,
                       const std::string& extra, const std::vector<std::pair<int, int>>& runs,
                       const std::map<std::string, std::string>& ref) {
  const fs::path out = dir / "out" / name;
  const std::string args = study + " --output " + (dir / "out").string() + " --overwrite " + extra;
  std::string log;
  REQUIRE(ref.size() > 3);
  for (const auto& [ranks, threads] : runs) {
    INFO(ranks << " rank(s) x " << threads << " thread(s)");
    const int st = runCommand(mpirun(ranks, args + " --threads " + std::to_string(threads)), log);
    INFO(log);
    REQUIRE(st == 0);
    const auto got = resultFiles(out);
    CHECK(differing(ref, got).empty());
    CHECK(got == ref);
    const auto man = nlohmann::json::parse(readFileOrThrow((out / "manifest.json").string()));
    CHECK(man.value("ranks", 1) == ranks);
    CHECK_FALSE(fs::exists(out / ".partial"));
  }
}

// Runs `study` once without mpirun and then under mpirun with each (ranks, threads) into the same
// output path, comparing every result file with the single process's; `expect` (when given)
// checks on the single process's files that the scenario happened.
void requireSameAcrossRanks(
    const fs::path& dir, const std::string& study, const std::string& name,
    const std::string& extra, const std::vector<std::pair<int, int>>& runs,
    const std::function<void(const std::map<std::string, std::string>&)>& expect = nullptr) {
  std::string log;
  INFO("single process");
  REQUIRE(runCommand(binaryPath() + " run " + study + " --output " + (dir / "out").string() +
                         " --overwrite " + extra + " --threads 2",
                     log) == 0);
  const auto ref = resultFiles(dir / "out" / name);
  if (expect) expect(ref);
  requireRanksWrite(dir, study, name, extra, runs, ref);
}

// A coarser copy of the shipped study studies/<name>.toml, written into `dir`: each (from, to)
// text replaced once (each must occur, so a changed shipped file fails the test instead of
// running at full size) and the relative design paths made absolute. Every section, design and
// variant of the shipped file stays; only grid steps and audit sizes change.
std::string coarseCopy(const fs::path& dir, const std::string& name,
                       const std::vector<std::pair<std::string, std::string>>& edits) {
  std::string toml = readFileOrThrow(sourcePath("studies/" + name + ".toml"));
  for (const auto& [from, to] : edits) {
    INFO("studies/" << name << ".toml: " << from);
    const auto at = toml.find(from);
    REQUIRE(at != std::string::npos);
    toml.replace(at, from.size(), to);
  }
  const std::string rel = "\"../designs/", abs = "\"" + sourcePath("designs/");
  for (auto at = toml.find(rel); at != std::string::npos; at = toml.find(rel, at))
    toml.replace(at, rel.size(), abs);
  const fs::path p = dir / (name + ".toml");
  std::ofstream(p) << toml;
  return p.string();
}

}  // namespace

TEST_CASE("a single process is rank 0 of 1", "[distributed]") {
  const Ranks& r = singleProcess();
  CHECK(r.rank() == 0);
  CHECK(r.size() == 1);
  CHECK(r.root());
  CHECK_FALSE(r.distributed());
  CHECK(r.firstFailure(false) == 1);
  CHECK(r.firstFailure(true) == 0);
}

TEST_CASE("reach, dexterity and harvest on 1, 2 and 3 ranks write the bytes of a single process",
          "[distributed][e2e]") {
  requireMpi();
  const fs::path dir = freshDir("stages");
  const std::string study =
      writeStudy(dir, "rdh", {"final_prototype_7dof", "final_prototype_9dof"},
                 std::string(kReachSection) + kDexteritySection + kHarvestSection);
  // Small units: many per batch, so every rank gets some.
  requireSameAcrossRanks(dir, study, "rdh", "--unit-size 16", {{1, 2}, {2, 1}, {3, 1}, {2, 2}});
  fs::remove_all(dir);
}

TEST_CASE(
    "the reach map search, its steps shared among 2 and 3 ranks, writes the bytes of a single "
    "process",
    "[distributed][e2e]") {
  requireMpi();
  // The Fig. 3.8 spraying row at 4 cm with self-collision: every phase of the search has work
  // (neighbour propagation, seeded multi-starts that free a pose and the propagation from it, the
  // wider-neighbourhood round, best-manipulability rounds), each step shared among the ranks, and
  // so are the audit's poses. Two designs: their searches (of different lengths) and audits advance
  // interleaved, one combined loop per step (study/interleave.hpp).
  const fs::path dir = freshDir("search");
  const std::string study =
      writeStudy(dir, "cs", {"first_prototype_6dof", "first_prototype_9dof"}, R"([reach]
task_space = "spraying"
position_tolerance = "1 mm"
orientation_tolerance = "0.5 deg"
[reach.audit]
poses = 40
starts = 20
[[reach.grid]]
name = "row"
x = { from = "-0.78 m", to = "0.78 m", step = "0.04 m" }
y = { from = "0.3 m", to = "1.2 m", step = "0.04 m" }
z = "1.2 m"
alpha = "0 deg"
gamma = ["-40 deg", "40 deg"]
)");
  requireSameAcrossRanks(dir, study, "cs", "--unit-size 400", {{2, 1}, {3, 1}});
  // In rank groups (docs/distributed.md, "Rank groups"): on 2 ranks each searches one design; on 3,
  // ranks 0 and 1 search the first design (their steps shared) and rank 2 the second; then the
  // searches' summaries and changed rows go to every rank.
  requireSameAcrossRanks(dir, study, "cs", "--unit-size 400 --search-group-ranks 1",
                         {{2, 1}, {3, 1}});
  const auto sum = nlohmann::json::parse(readFileOrThrow((dir / "out/cs/summary.json").string()));
  const auto& search = sum["reach"]["grids"][0]["designs"][0]["search"];
  INFO(search.dump());
  CHECK(search["propagation_rounds"].get<int>() >= 2);
  CHECK(search["collision_multistart_freed"].get<int>() >= 1);
  CHECK(search["best_manipulability_updates"].get<int>() > 0);
  CHECK(sum["reach"]["grids"][0]["designs"][0]["audit"]["poses"].get<int>() == 40);
  const auto& search9 = sum["reach"]["grids"][0]["designs"][1]["search"];
  INFO(search9.dump());
  CHECK(search9["best_manipulability_rounds"].get<int>() !=
        search["best_manipulability_rounds"].get<int>());
  CHECK(sum["reach"]["grids"][0]["designs"][1]["audit"]["poses"].get<int>() == 40);
  fs::remove_all(dir);
}

// The explorations' task (a spraying row) and objectives (row coverage, link length).
const char* const kExploreRow = R"([reach]
task_space = "spraying"
position_tolerance = "1 mm"
orientation_tolerance = "0.5 deg"
[[reach.grid]]
name = "row"
x = { from = "-0.6 m", to = "0.6 m", step = "0.1 m" }
y = { from = "0.5 m", to = "1.1 m", step = "0.1 m" }
z = "1.2 m"
alpha = "0 deg"
gamma = "0 deg"
)";
const char* const kExploreObjectives = R"([[explore.objective]]
metric = "reach/row/{design}/reachable_fraction"
goal = "max"
[[explore.objective]]
metric = "cost/link_length"
goal = "min"
)";

TEST_CASE("an exploration on 2 and 3 ranks writes the bytes of a single process",
          "[distributed][e2e][explore]") {
  requireMpi();
  // Grid: candidates are the units (one rank evaluates each, its stages run there alone); the map
  // search of the front designs' outputs runs on every rank.
  const fs::path dir = freshDir("explore");
  const std::string study =
      writeStudy(dir, "ex", {"first_prototype_6dof"}, std::string(kExploreRow) + R"([explore]
design = "first_prototype_6dof"
front_designs = 1
[[explore.parameter]]
key = "joint.j4.x"
values = ["0.13 m", "0.23 m", "0.33 m"]
[[explore.parameter]]
key = "joint.j5.x"
values = ["0.3 m", "0.4 m", "0.5 m"]
)" + kExploreObjectives);
  requireSameAcrossRanks(dir, study, "ex", "", {{2, 1}, {3, 1}});
  fs::remove_all(dir);
  // The optimiser asks for one candidate at a time (each a unit one rank computes while NLopt
  // waits on every rank for its values): the same points, the same bytes on any rank count.
  const fs::path odir = freshDir("explore_optimise");
  const std::string ostudy =
      writeStudy(odir, "exo", {"first_prototype_6dof"}, std::string(kExploreRow) + R"([explore]
design = "first_prototype_6dof"
method = "optimise"
budget = 10
front_designs = 1
[[explore.parameter]]
key = "joint.j4.x"
from = "0.13 m"
to = "0.33 m"
step = "0.05 m"
[[explore.parameter]]
key = "joint.j5.x"
from = "0.3 m"
to = "0.5 m"
step = "0.05 m"
)" + kExploreObjectives);
  requireSameAcrossRanks(odir, ostudy, "exo", "", {{2, 1}, {3, 1}});
  fs::remove_all(odir);
}

TEST_CASE("calibration entries on 1, 2 and 3 ranks write the bytes of a single process",
          "[distributed][e2e]") {
  requireMpi();
  const fs::path dir = freshDir("calibration");
  requireSameAcrossRanks(dir, sourcePath("studies/thesis_drive_friction.toml"),
                         "thesis_drive_friction", "", {{1, 1}, {2, 1}, {3, 1}});
  fs::remove_all(dir);
}

TEST_CASE("per-unit costs are recorded on request, one line per unit, outside the result files",
          "[distributed][e2e]") {
  requireMpi();
  const fs::path dir = freshDir("times");
  const std::string study = writeStudy(dir, "r", {"final_prototype_7dof"}, kReachSection);
  const fs::path csv = dir / "units.csv";
  std::string log;
  REQUIRE(runCommand("ARMSTUDY_UNIT_TIMES=" + csv.string() + " " +
                         mpirun(2, study + " --threads 1 --unit-size 50 --output " +
                                       (dir / "out").string()),
                     log) == 0);
  std::ifstream f(csv);
  std::string line;
  std::getline(f, line);
  CHECK(line == "unit,seconds,cpu_seconds,threads,rank,bytes,part");
  int n = 0;
  while (std::getline(f, line)) {
    CHECK(line.rfind("reach/wall/final_prototype_7dof/units_", 0) == 0);
    CHECK(line.back() == ',');  // a unit belongs to no part
    ++n;
  }
  CHECK(n == 13);  // one unit per grid line (25 x 2 orientations = 50 poses), 13 lines
  CHECK_FALSE(fs::exists(dir / "out/r/units.csv"));
  fs::remove_all(dir);
}

TEST_CASE(
    "a rank killed mid-run ends the job with a clear message, and another rank count resumes into "
    "the same bytes",
    "[distributed][e2e][checkpoint]") {
  requireMpi();
  const fs::path dir = freshDir("kill");
  const std::string study = writeStudy(
      dir, "k", {"final_prototype_7dof"},
      "[reach]\ntask_space = \"full\"\n[[reach.grid]]\nname = \"wall\"\n"
      "x = { from = \"-0.6 m\", to = \"0.6 m\", step = \"0.01 m\" }\ny = \"0.8 m\"\n"
      "z = { from = \"0.4 m\", to = \"1.6 m\", step = \"0.025 m\" }\n"
      "alpha = \"-90 deg\"\nbeta = \"0 deg\"\ngamma = [\"0 deg\", \"20 deg\", \"40 deg\"]\n");
  std::string log;
  REQUIRE(
      runCommand(binaryPath() + " run " + study + " --threads 1 --output " + (dir / "ref").string(),
                 log) == 0);
  const auto ref = resultFiles(dir / "ref/k");
  const fs::path out = dir / "out/k", units = out / ".partial/units";
  const std::string args = study + " --threads 1 --unit-size 1 --output " + (dir / "out").string();
  std::string job;
  const int job_status = runCommand(mpirunKillingRank1(args, 5), job);
  {
    INFO(job);
    REQUIRE(job_status != 0);
    REQUIRE_FALSE(fs::exists(out / "manifest.json"));
    CHECK(job.find("exited on signal 9") != std::string::npos);
    CHECK(job.find("run the same command again, with any number of ranks, to resume") !=
          std::string::npos);
  }
  auto saved = [&] {
    long n = 0;
    for (const auto& e : fs::directory_iterator(units)) n += e.path().extension() == ".unit";
    return n;
  };
  const long kept = saved();
  CHECK(kept >= 5);
  // The re-run, with 3 ranks: resumes every saved unit, ends in the single process's bytes.
  const int st = runCommand(mpirun(3, args), log);
  INFO(log);
  REQUIRE(st == 0);
  CHECK(log.find("resuming: " + std::to_string(kept) + " completed unit(s)") != std::string::npos);
  const auto man = nlohmann::json::parse(readFileOrThrow((out / "manifest.json").string()));
  CHECK(man.value("units_resumed", -1L) == kept);
  const auto got = resultFiles(out);
  CHECK(differing(ref, got).empty());
  CHECK(got == ref);
  fs::remove_all(dir);
}

TEST_CASE(
    "the regression study (design pairs and a variant) on 2 and 3 ranks whose font configuration "
    "differs from rank 0's writes the bytes of a single process",
    "[distributed][e2e][report]") {
  requireMpi();
  const fs::path dir = freshDir("fonts");
  const std::string conf = writeOtherFontconfig(dir);
  // The scenario: fontconfig really answers differently under that file (else this test proves
  // nothing about it).
  std::string plain, other;
  REQUIRE(runCommand("fc-match --format '%{hintstyle} %{embolden}' 'DejaVu Sans'", plain) == 0);
  REQUIRE(runCommand("FONTCONFIG_FILE=" + conf +
                         " fc-match --format '%{hintstyle} %{embolden}' 'DejaVu Sans'",
                     other) == 0);
  INFO("fc-match: '" << plain << "' vs '" << other << "'");
  REQUIRE(plain != other);
  // Every pair of the five designs gets comparison figures, rendered by whichever rank draws the
  // item; small units so that every rank draws some.
  const fs::path out = dir / "out" / "regression";
  const std::string args = sourcePath("studies/regression.toml") + " --output " +
                           (dir / "out").string() + " --overwrite --unit-size 8";
  std::string log;
  REQUIRE(runCommand(binaryPath() + " run " + args + " --threads 2", log) == 0);
  const auto ref = resultFiles(out);
  REQUIRE(ref.size() > 40);
  for (const auto& [ranks, threads] : std::vector<std::pair<int, int>>{{2, 1}, {3, 1}, {2, 2}}) {
    INFO(ranks << " rank(s) x " << threads << " thread(s), ranks 1.. under " << conf);
    const int st = runCommand(
        mpirunOthersUnder(conf, ranks, args + " --threads " + std::to_string(threads)), log);
    INFO(log);
    REQUIRE(st == 0);
    const auto got = resultFiles(out);
    CHECK(differing(ref, got).empty());
  }
  // A single process under that file: the same bytes too.
  REQUIRE(
      runCommand("FONTCONFIG_FILE=" + conf + " " + binaryPath() + " run " + args + " --threads 1",
                 log) == 0);
  CHECK(differing(ref, resultFiles(out)).empty());
  fs::remove_all(dir);
}

// A shipped study, in a coarser copy (coarseCopy), on 2 and 3 ranks and 2 ranks x 2 threads with
// `unit_size` (small, so that every rank computes and renders some of every step) writes the bytes
// of a single process (2 threads, the same unit size); `expect` checks that the scenario happened
// (the files it needs are there).
void shippedStudyOnRanks(
    const std::string& study, const std::vector<std::pair<std::string, std::string>>& coarser,
    int unit_size, const std::function<void(const std::map<std::string, std::string>&)>& expect) {
  requireMpi();
  const fs::path dir = freshDir(study);
  requireSameAcrossRanks(dir, coarseCopy(dir, study, coarser), study,
                         "--unit-size " + std::to_string(unit_size), {{2, 1}, {3, 1}, {2, 2}},
                         expect);
  fs::remove_all(dir);
}

TEST_CASE(
    "the shipped compare_designs study (4 designs, 6 pairs, two grids with map searches and "
    "audits) on 2 and 3 ranks and 2 ranks x 2 threads writes the bytes of a single process",
    "[distributed][e2e][report]") {
  // 17 x 17 wall points x 3 spray angles and 13 x 9 x 11 workspace points per design.
  shippedStudyOnRanks("compare_designs",
                      {{"x = { from = \"-0.8 m\", to = \"0.8 m\", step = \"0.02 m\" }",
                        "x = { from = \"-0.8 m\", to = \"0.8 m\", step = \"0.1 m\" }"},
                       {"z = { from = \"0.2 m\", to = \"1.8 m\", step = \"0.02 m\" }",
                        "z = { from = \"0.2 m\", to = \"1.8 m\", step = \"0.1 m\" }"},
                       {"x = { from = \"-1.2 m\", to = \"1.2 m\", step = \"0.1 m\" }",
                        "x = { from = \"-1.2 m\", to = \"1.2 m\", step = \"0.2 m\" }"},
                       {"y = { from = \"-0.2 m\", to = \"1.4 m\", step = \"0.1 m\" }",
                        "y = { from = \"-0.2 m\", to = \"1.4 m\", step = \"0.2 m\" }"},
                       {"z = { from = \"0 m\", to = \"2 m\", step = \"0.1 m\" }",
                        "z = { from = \"0 m\", to = \"2 m\", step = \"0.2 m\" }"},
                       {"poses = 100", "poses = 12"},
                       {"starts = 200", "starts = 20"}},
                      16, [](const auto& ref) {
                        // The scenario: every design's maps and every pair's comparison figures.
                        REQUIRE(ref.size() > 100);
                        REQUIRE(ref.count("reach/canopy_wall/final_prototype_9dof.vti") == 1);
                      });
}

TEST_CASE(
    "the shipped stem heatmap (three maps with map searches, self-collision and audits) on 2 and 3 "
    "ranks and 2 ranks x 2 threads writes the bytes of a single process",
    "[distributed][e2e][report]") {
  // 31 x 31 cells per map (6 deg x 5 cm) instead of 181 x 151.
  shippedStudyOnRanks(
      "stem_heatmap",
      {{"step = \"1 deg\"", "step = \"6 deg\""},
       {"step = \"1 cm\"", "step = \"5 cm\""},
       {"cells = 50", "cells = 8"},
       {"starts = 200", "starts = 20"}},
      64, [](const auto& ref) {
        // The scenario: the three maps (the design and its two lift offsets) with
        // their audits.
        for (const char* d : {"first_prototype_9dof", "first_prototype_9dof+j1.z=0.6",
                              "first_prototype_9dof+j1.z=0.9"}) {
          REQUIRE(ref.count(std::string("dexterity/") + d + ".vti") == 1);
          REQUIRE(ref.count(std::string("dexterity/") + d + "_audit.csv") == 1);
        }
      });
}

TEST_CASE(
    "on 2 ranks each rank writes the reach grid and stem map files it renders itself (no single "
    "writer), and the files are a single process's bytes",
    "[distributed][e2e]") {
  requireMpi();
  const fs::path dir = freshDir("writers");
  const fs::path out = dir / "out" / "regression";
  const std::string args = sourcePath("studies/regression.toml") + " --output " +
                           (dir / "out").string() + " --overwrite --unit-size 8 --threads 1";
  std::string log;
  REQUIRE(runCommand(binaryPath() + " run " + args, log) == 0);
  const auto ref = resultFiles(out);
  // Rank 1 runs under umask 077, so the files it creates are readable by their owner only: a
  // file's mode says which rank wrote it.
  const std::string run = binaryPath() + " run " + args;
  const std::string cmd = "umask 022; OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " +
                          std::string(ARMSTUDY_MPIEXEC) + " --oversubscribe -np 1 " + run +
                          " : -np 1 sh -c 'umask 077; exec " + run + "'";
  const int st = runCommand(cmd, log);
  INFO(log);
  REQUIRE(st == 0);
  CHECK(differing(ref, resultFiles(out)).empty());
  int by_rank1 = 0, by_rank0 = 0, dexterity_by_rank1 = 0, dexterity_by_rank0 = 0;
  std::string rank1_elsewhere;
  for (const auto& [rel, bytes] : ref) {
    const auto perms = fs::status(out / rel).permissions();
    const bool private_file = (perms & fs::perms::others_read) == fs::perms::none;
    const bool dexterity = rel.rfind("dexterity/", 0) == 0;
    if (private_file)
      ++by_rank1;
    else
      ++by_rank0;
    if (dexterity) ++(private_file ? dexterity_by_rank1 : dexterity_by_rank0);
    if (private_file && rel.rfind("reach/", 0) != 0 && !dexterity) rank1_elsewhere += rel + " ";
  }
  INFO("files written by rank 1 outside reach/ and dexterity/: " << rank1_elsewhere);
  CHECK(by_rank1 > 10);  // rank 1 rendered and wrote pieces of the grids
  CHECK(by_rank0 > 10);  // rank 0 its own pieces and the study's files
  // The four stem maps: rank 1 renders designs 1 and 3, rank 0 designs 0 and 2 and the stage's
  // summary and report.
  CHECK(dexterity_by_rank1 > 4);
  CHECK(dexterity_by_rank0 > 4);
  CHECK(rank1_elsewhere.empty());
  CHECK((fs::status(out / "summary.json").permissions() & fs::perms::others_read) !=
        fs::perms::none);
  fs::remove_all(dir);
}

TEST_CASE(
    "a stem map's search steps and audit are loops the ranks share (several chunks each, owned "
    "round-robin) and give a single process's bytes",
    "[distributed][e2e]") {
  requireMpi();
  const fs::path dir = freshDir("dexterity_shared");
  const std::string study =
      writeStudy(dir, "d", {"first_prototype_9dof"},
                 std::string(kDexteritySection) + "[dexterity.audit]\ncells = 6\nstarts = 20\n");
  requireSameAcrossRanks(dir, study, "d", "--unit-size 2", {{2, 1}, {3, 1}});
  // A single process's unit-cost record lists a shared loop's chunks ("share:<id>", one line per
  // chunk); chunk k is computed by rank k mod N, so a loop of several chunks is spread.
  const fs::path csv = dir / "units.csv";
  std::string log;
  REQUIRE(runCommand("ARMSTUDY_UNIT_TIMES=" + csv.string() + " " + binaryPath() + " run " + study +
                         " --threads 1 --overwrite --output " + (dir / "out").string(),
                     log) == 0);
  std::map<std::string, int> chunks;  // loop id -> chunks
  std::ifstream f(csv);
  std::string line;
  std::getline(f, line);
  while (std::getline(f, line))
    if (line.rfind("share:dexterity-", 0) == 0) ++chunks[line.substr(0, line.find(','))];
  int search_loops = 0, spread = 0;
  for (const auto& [id, n] : chunks) {
    search_loops += id.rfind("share:dexterity-search/first_prototype_9dof/", 0) == 0;
    spread += n > 1;
  }
  CHECK(search_loops >= 2);  // the seeded multi-starts and propagation rounds
  CHECK(spread >= 2);
  CHECK(chunks["share:dexterity-audit/first_prototype_9dof"] == 6);  // a cell per chunk
  fs::remove_all(dir);
}
