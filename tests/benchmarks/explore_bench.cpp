// Design-space exploration benchmark (docs/performance.md "Design-space exploration"):
// 200 variants of the first prototype (6-DoF) on a spraying row plus a stem map, exhaustive grid,
// 2 threads. Peer: the same kind of variants as an ordinary [[variant]] sweep through the reach
// and dexterity stages (no exploration around them), on the first 20 variants, per variant.
//   cmake -S . -B build -DARMSTUDY_BUILD_BENCHMARKS=ON && cmake --build build --target
//   explore_bench
//   ./build/tests/benchmarks/explore_bench [threads=2] [j4 values=10]
// The explore grid is (j4 values) x 10 (j5.x) x 2 (tcp.x): 200 variants by default. Wall time and
// process CPU time are both printed (on a loaded shared machine the CPU time is the stable part).
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

// The spraying row of thesis Fig. 3.8 (eq. 3.3) at 4 cm instead of 1 cm, and the Fig. 3.6 stem
// map at 10 deg x 5 cm: coarser than the shipped studies so that 200 variants are a design
// exploration, not a night's run.
const char* kTasks = R"(
[reach]
task_space = "spraying"
position_tolerance = "1 mm"
orientation_tolerance = "0.5 deg"
[[reach.grid]]
name = "row"
x = { from = "-0.78 m", to = "0.78 m", step = "0.04 m" }
y = { from = "0.3 m", to = "1.2 m", step = "0.04 m" }
z = "1.2 m"
alpha = "0 deg"
gamma = ["-40 deg", "40 deg"]

[dexterity]
stem_x = "0.225 m"
stem_y = "0.7 m"
radius = "0.15 m"
gamma = { min = "-pi/2", max = "pi/2", step = "10 deg" }
z = { min = "0.2 m", max = "1.4 m", step = "5 cm" }
task = "position_axis"
measure_space = "translational"
ellipsoids = false
[dexterity.objective]
joint_limits = 0.1
manipulability = 1.0
)";

double cpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  const int threads = argc > 1 ? std::atoi(argv[1]) : 2;
  const int n_j4 = argc > 2 ? std::atoi(argv[2]) : 10;
  std::string j4_values;  // 0.14, 0.16, ... m
  for (int k = 0; k < n_j4; ++k) j4_values += (k ? ", " : "") + std::to_string(0.14 + 0.02 * k);
  const fs::path dir =
      fs::temp_directory_path() / ("armstudy_explore_bench_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string design = armstudy::test::sourcePath("designs/first_prototype_6dof.toml");
  const std::string head = "[study]\nname = \"bench\"\n[[design]]\nfile = \"" + design + "\"\n";
  {
    std::ofstream f(dir / "explore.toml");
    f << head << kTasks << R"(
[explore]
design = "first_prototype_6dof"
method = "grid"
front_designs = 0
[[explore.parameter]]
key = "joint.j4.x"
values = [)" + j4_values + R"(]
[[explore.parameter]]
key = "joint.j5.x"
from = "0.30 m"
to = "0.48 m"
step = "0.02 m"
[[explore.parameter]]
key = "tcp.x"
values = ["0.2 m", "0.25 m"]
[[explore.objective]]
label = "row coverage"
metric = "reach/row/{design}/reachable_fraction"
goal = "max"
[[explore.objective]]
label = "stem map coverage"
metric = "dexterity/{design}/reachable_fraction"
goal = "max"
[[explore.objective]]
label = "link length"
metric = "cost/link_length"
goal = "min"
)";
  }
  {
    std::ofstream f(dir / "sweep.toml");
    f << head << kTasks << R"(
[[variant]]
of = "first_prototype_6dof"
sweep = { "joint.j4.x" = [0.14], "joint.j5.x" = [0.30, 0.34, 0.38, 0.42, 0.46], "tcp.x" = [0.2] }
)";
  }
  RunOptions opt;
  opt.threads = threads;
  opt.progress = false;
  const Study ex = loadStudy((dir / "explore.toml").string());
  auto t0 = std::chrono::steady_clock::now();
  double c0 = cpuSeconds();
  const StageResult r = runStage(ex, "explore", (dir / "ex").string(), opt);
  const double t_explore = seconds(t0), c_explore = cpuSeconds() - c0;
  const double n = r.metrics.scalars.at("explore/evaluations");

  const Study sw = loadStudy((dir / "sweep.toml").string());
  t0 = std::chrono::steady_clock::now();
  c0 = cpuSeconds();
  runStage(sw, "reach", (dir / "sw").string(), opt);
  runStage(sw, "dexterity", (dir / "sw").string(), opt);
  const double t_sweep = seconds(t0), c_sweep = cpuSeconds() - c0;
  const double n_sweep = static_cast<double>(sw.designs.size());

  std::printf(
      "explore_bench: %d thread(s); spraying row 40 x 23 x 2 poses + stem map 19 x 25 cells per "
      "variant\n",
      threads);
  std::printf(
      "| run | variants | wall [s] | CPU [s] | wall per variant [s] | CPU per variant [s] | CPU "
      "ratio |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  std::printf("| explore (grid + base) | %.0f | %.1f | %.1f | %.3f | %.3f | %.2f |\n", n, t_explore,
              c_explore, t_explore / n, c_explore / n, (c_explore / n) / (c_sweep / n_sweep));
  std::printf(
      "| [[variant]] sweep, reach + dexterity stages (peer) | %.0f | %.1f | %.1f | %.3f | %.3f | "
      "1.00 |\n",
      n_sweep, t_sweep, c_sweep, t_sweep / n_sweep, c_sweep / n_sweep);
  std::printf(
      "front size: %.0f; 200 variants at the measured CPU per variant on %d fully available cores: "
      "%.0f s "
      "(target 600 s)\n",
      r.metrics.scalars.at("explore/front_size"), threads, 200 * (c_explore / n) / threads);
  fs::remove_all(dir);
  return 0;
}
