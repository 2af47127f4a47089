#pragma once
// Shared helpers for tests: named tolerances, paths to shipped files, random configurations.
#include <sys/wait.h>

#include <Eigen/Core>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "model/model.hpp"

namespace armstudy::test {

// Named tolerances (never bare literals in assertions).
inline constexpr double kFdStep = 1e-6;            // central-difference step [m or rad]
inline constexpr double kFdTolerance = 1e-7;       // agreement of analytic vs central differences
inline constexpr double kOracleTolerance = 1e-12;  // agreement with an independent library
inline constexpr double kHandCheckTolerance = 1e-12;

// The source folder and the armstudy program the tests were built with (tests/test_paths.cpp).
std::string sourceDir();
std::string binaryPath();
inline std::string sourcePath(const std::string& rel) { return sourceDir() + "/" + rel; }

// An empty folder <temp>/armstudy_<name>, made anew (whatever was there is removed first).
inline std::filesystem::path emptyTempDir(const std::string& name) {
  const std::filesystem::path d = std::filesystem::temp_directory_path() / ("armstudy_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// Every regular file under `root`, as paths relative to it.
inline std::set<std::string> filesUnder(const std::filesystem::path& root) {
  std::set<std::string> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(root))
    if (e.is_regular_file()) out.insert(std::filesystem::relative(e.path(), root).string());
  return out;
}

inline const std::vector<std::string>& shippedDesigns() {
  static const std::vector<std::string> d = {
      "designs/first_prototype_6dof.toml", "designs/first_prototype_9dof.toml",
      "designs/final_prototype_9dof.toml", "designs/final_prototype_7dof.toml"};
  return d;
}

// Uniform random configuration within the joint limits (deterministic for a given engine).
inline Eigen::VectorXd randomConfiguration(const Model& m, std::mt19937_64& rng) {
  Eigen::VectorXd q(m.dof());
  for (int i = 0; i < m.dof(); ++i) {
    std::uniform_real_distribution<double> u(m.joints[i].limits.q_min, m.joints[i].limits.q_max);
    q[i] = u(rng);
  }
  return q;
}

// Runs a shell command, returns exit status; stdout+stderr captured into `out`.
inline int runCommand(const std::string& cmd, std::string& out) {
  out.clear();
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return -1;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  const int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The status a shell reports for a command killed with SIGKILL.
inline constexpr int kKilledStatus = 128 + SIGKILL;

// Runs `command` (an `armstudy run ...`) with the checkpoint store's test hook
// (src/study/checkpoint.hpp), which kills it with SIGKILL right after it saved its `units`-th unit.
// Returns the command's status: kKilledStatus when the hook killed it, 0 when the run ended first.
inline int runKilledAfterUnits(const std::string& command, long units, std::string& out) {
  return runCommand(
      "ARMSTUDY_TEST_ABORT_AFTER_UNITS=" + std::to_string(units) + " " + command + " 2>&1; exit $?",
      out);
}

}  // namespace armstudy::test
