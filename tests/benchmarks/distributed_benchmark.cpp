// Distributed runs on one machine (docs/performance.md "Distributed runs"): the same study as 1
// process x 1 thread, as 2 and 3 MPI ranks x 1 thread, 2 ranks x 2 threads and 1 process x 2
// threads: wall time, CPU time of the processes, parallel efficiency T1 / (cores T), a byte
// comparison of every run's results with the first's, and the serial part s = 2 T(2) - T(1).
// Optionally records per-unit costs (ARMSTUDY_UNIT_TIMES) of the 1 x 1 run for
// tests/benchmarks/simulate_distribution.py.
//
//   cmake --build build --target distributed_bench
//   build/tests/benchmarks/distributed_bench [study.toml] [unit-times.csv] ["more run options"]
// (default study: studies/compare_designs.toml; needs a build with ARMSTUDY_MPI)
#include <sys/resource.h>
#include <sys/time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "io/files.hpp"

namespace fs = std::filesystem;

namespace {

double childCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

std::string loadAverage() {
  std::ifstream f("/proc/loadavg");
  std::string a;
  f >> a;
  return a;
}

struct Timing {
  double wall = 0, cpu = 0;
};

Timing run(const std::string& cmd) {
  const double c0 = childCpuSeconds();
  const auto t0 = std::chrono::steady_clock::now();
  if (std::system((cmd + " > /dev/null").c_str()) != 0) {
    std::fprintf(stderr, "failed: %s\n", cmd.c_str());
    std::exit(1);
  }
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
          childCpuSeconds() - c0};
}

std::map<std::string, std::string> resultFiles(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string rel = fs::relative(e.path(), dir).string();
    if (e.is_regular_file() && rel != "manifest.json" && rel != ".armstudy.lock")
      out[rel] = armstudy::readFileOrThrow(e.path().string());
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string study =
      argc > 1 ? argv[1] : std::string(ARMSTUDY_SOURCE_DIR) + "/studies/compare_designs.toml";
  const std::string times = argc > 2 ? argv[2] : "";
  const std::string more = argc > 3 ? std::string(" ") + argv[3] : "";
  if (std::string(ARMSTUDY_MPIEXEC).empty()) {
    std::fprintf(stderr, "distributed_bench needs a build with MPI (ARMSTUDY_MPI=ON)\n");
    return 1;
  }
  const fs::path out = fs::temp_directory_path() / "armstudy_distributed_bench";
  fs::remove_all(out);
  const std::string bin = ARMSTUDY_BINARY,
                    args = " run " + study + " --overwrite --output " + out.string() + more;
  const std::string mpi =
      std::string("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ") + ARMSTUDY_MPIEXEC +
      " --oversubscribe -np ";
  std::printf("study %s%s, load average before: %s\n", study.c_str(), more.c_str(),
              loadAverage().c_str());
  const std::string env1 = times.empty() ? "" : "ARMSTUDY_UNIT_TIMES=" + times + " ";
  if (!times.empty()) fs::remove(times);
  const Timing t1 = run(env1 + bin + args + " --threads 1");
  std::string name;
  for (const auto& e : fs::directory_iterator(out)) name = e.path().filename().string();
  const auto ref = resultFiles(out / name);
  struct Row {
    const char* label;
    std::string cmd;
    int cores;
    Timing t;
    bool same = false;
  };
  std::vector<Row> rows = {{"2 MPI ranks x 1 thread", mpi + "2 " + bin + args + " --threads 1", 2},
                           {"3 MPI ranks x 1 thread", mpi + "3 " + bin + args + " --threads 1", 3},
                           {"2 MPI ranks x 2 threads", mpi + "2 " + bin + args + " --threads 2", 4},
                           {"1 process x 2 threads", bin + args + " --threads 2", 2}};
  for (Row& r : rows) {
    r.t = run(r.cmd);
    r.same = resultFiles(out / name) == ref;
  }
  std::printf(
      "| run | wall [s] | CPU [s] | speed-up | efficiency | result files "
      "|\n|---|---:|---:|---:|---:|---|\n");
  std::printf("| 1 process x 1 thread | %.1f | %.1f | 1.00 | 100 %% | reference |\n", t1.wall,
              t1.cpu);
  bool all_same = true;
  for (const Row& r : rows) {
    std::printf("| %s | %.1f | %.1f | %.2f | %.0f %% | %s |\n", r.label, r.t.wall, r.t.cpu,
                t1.wall / r.t.wall, 100 * t1.wall / (r.cores * r.t.wall),
                r.same ? "identical" : "DIFFER");
    all_same = all_same && r.same;
  }
  // Amdahl with T(N) = s + p / N: s = 2 T(2) - T(1) from the 2-thread run (no phase labels).
  const double s2 = 2 * rows.back().t.wall - t1.wall;
  std::printf("serial part s = 2 T(2 threads) - T(1) = %.2f s, %.1f %% of T(1)\n", s2,
              100 * s2 / t1.wall);
  std::printf("load average after: %s\n", loadAverage().c_str());
  fs::remove_all(out);
  return all_same ? 0 : 1;
}
