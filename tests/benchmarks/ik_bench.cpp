// Benchmark of the per-pose reachability solver (src/ik) against orocos-kdl's
// ChainIkSolverPos_LMA, on the same poses in the same run (docs/performance.md,
// "## Reachability (inverse kinematics)"). Not a test.
//
// For each shipped design: 10,000 full poses made by forward kinematics from random joint
// configurations within the limits (known reachable) and 1,000 poses beyond the arm's reach
// (horizontal distance from the lift axis 1.05-1.5 x the summed link lengths; known unreachable).
// Times are per-thread CPU time (the machine is shared). KDL gets the same start sequence (middle
// of the limits, then random configurations, up to the same number of starts); its solution counts
// only when it is within the joint limits (revolute angles wrapped to (-pi, pi]) and meets the same
// tolerances, checked with armstudy's FK.
//
//   cmake --build build --target ik_bench && ./build/tests/benchmarks/ik_bench [poses] [design
//   filter] [quick]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <kdl/chain.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <random>
#include <string>
#include <vector>

#include "ik/reach_solver.hpp"
#include "io/design_io.hpp"
#include "kdl_support.hpp"
#include "kinematics/kinematics.hpp"
#include "test_support.hpp"

using armstudy::test::toKdl;
using armstudy::test::toKdlChain;

using namespace armstudy;
// Per-thread CPU clock: robust against other processes on a shared machine.
struct Clock {
  using time_point = double;
  static double now() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
  }
};

namespace {

struct Row {
  std::string solver;
  int solved = 0, total = 0, false_reach = 0, unreach_total = 0;
  double us_reach = 0, us_unreach = 0;
  double starts = 0;
  double iterations = 0;
};

double seconds(double a, double b) { return b - a; }

}  // namespace

int main(int argc, char** argv) {
  const int n_reach = argc > 1 ? std::atoi(argv[1]) : 10000;
  const int n_unreach = std::max(1, n_reach / 10);
  // "quick" as third argument: only the default armstudy solver, with LM iterations per pose
  // instead of the KDL ratio (for profiling).
  const bool quick = argc > 3 && std::string(argv[3]) == "quick";
  const double kPi = 3.14159265358979323846;
  std::printf(
      "# ik_bench: %d reachable (FK of random q) + %d beyond-reach full poses per design, 1 "
      "thread\n",
      n_reach, n_unreach);
  std::printf(
      "# tolerances 1 mm / 0.5 deg; armstudy max %d starts; KDL LMA same start sequence; CPU time "
      "per thread\n",
      defaults::kIkMaxStarts);
  std::printf("%-22s %-22s %9s %10s %12s %12s %9s %10s\n", "design", "solver", "solved%",
              "unreach_ok", "us/reachable", "us/unreach", "starts", "speedup");
  for (const auto& rel : test::shippedDesigns()) {
    if (argc > 2 && rel.find(argv[2]) == std::string::npos) continue;
    const Model m = loadDesign(test::sourcePath(rel));
    const int n = m.dof();
    std::mt19937_64 rng(2024);
    KinematicsWorkspace kin(m);
    IkWorkspace ws(m);
    std::vector<PoseTask> reach, unreach;
    for (int k = 0; k < n_reach; ++k) {
      const Eigen::VectorXd q = test::randomConfiguration(m, rng);
      forwardKinematics(m, kin, q);
      reach.push_back(fullPoseTask(kin.p_WT, kin.R_WT));
    }
    std::uniform_real_distribution<double> u01(0, 1);
    for (int k = 0; k < n_unreach; ++k) {
      const double r = ws.reach_radius * (1.05 + 0.45 * u01(rng));
      const double phi = 2 * kPi * u01(rng);
      const double t = ws.bound_t_min + (ws.bound_t_max - ws.bound_t_min) * u01(rng);
      Eigen::Vector3d a = ws.bound_axis.unitOrthogonal();
      Eigen::Vector3d b = ws.bound_axis.cross(a);
      const Eigen::Vector3d p =
          ws.bound_p0 + t * ws.bound_axis + r * (std::cos(phi) * a + std::sin(phi) * b);
      const double alpha = kPi * (2 * u01(rng) - 1), beta = 0.5 * kPi * (2 * u01(rng) - 1),
                   gamma = kPi * (2 * u01(rng) - 1);
      unreach.push_back(fullPoseTask(p, rotationFromCardan(alpha, beta, gamma)));
    }

    auto runArmstudy = [&](const std::string& label, IkOptions o) {
      Row row;
      row.solver = label;
      row.total = n_reach;
      row.unreach_total = n_unreach;
      long starts = 0, iterations = 0;
      auto t0 = Clock::now();
      for (int k = 0; k < n_reach; ++k) {
        const IkResult r = solvePose(m, ws, reach[k], o, static_cast<std::uint64_t>(k));
        row.solved += r.reachable();
        starts += r.starts;
        iterations += r.iterations;
      }
      auto t1 = Clock::now();
      for (int k = 0; k < n_unreach; ++k) {
        const IkResult r = solvePose(m, ws, unreach[k], o, static_cast<std::uint64_t>(n_reach + k));
        row.false_reach += r.reachable();
      }
      auto t2 = Clock::now();
      row.us_reach = 1e6 * seconds(t0, t1) / n_reach;
      row.us_unreach = 1e6 * seconds(t1, t2) / n_unreach;
      row.starts = static_cast<double>(starts) / n_reach;
      row.iterations = static_cast<double>(iterations) / n_reach;
      return row;
    };

    std::vector<Row> rows;
    IkOptions def;
    rows.push_back(runArmstudy("armstudy lm+slsqp", def));
    if (quick) {
      const Row& r = rows.back();
      std::printf("%-22s %-22s %8.2f%% %5d/%-4d %12.2f %12.2f %9.2f %10.1f\n", m.name.c_str(),
                  r.solver.c_str(), 100.0 * r.solved / r.total, r.unreach_total - r.false_reach,
                  r.unreach_total, r.us_reach, r.us_unreach, r.starts, r.iterations);
      continue;
    }
    IkOptions nobound = def;
    nobound.use_reach_bound = false;
    {
      Row r = runArmstudy("armstudy (no bound)", nobound);
      rows.push_back(r);
    }
    IkOptions lm = def;
    lm.algorithm = IkAlgorithm::LmOnly;
    rows.push_back(runArmstudy("armstudy lm only", lm));
    IkOptions sq = def;
    sq.algorithm = IkAlgorithm::SlsqpOnly;
    sq.classify_failures = false;
    const int n_sq = std::min(n_reach, 1000);
    {
      // SLSQP alone is slow: a 1,000-pose subset.
      Row row;
      row.solver = "nlopt slsqp only";
      row.total = n_sq;
      row.unreach_total = std::min(n_unreach, 100);
      long starts = 0;
      auto t0 = Clock::now();
      for (int k = 0; k < n_sq; ++k) {
        const IkResult r = solvePose(m, ws, reach[k], sq, static_cast<std::uint64_t>(k));
        row.solved += r.reachable();
        starts += r.starts;
      }
      auto t1 = Clock::now();
      for (int k = 0; k < row.unreach_total; ++k)
        row.false_reach +=
            solvePose(m, ws, unreach[k], sq, static_cast<std::uint64_t>(n_reach + k)).reachable();
      auto t2 = Clock::now();
      row.us_reach = 1e6 * seconds(t0, t1) / n_sq;
      row.us_unreach = 1e6 * seconds(t1, t2) / row.unreach_total;
      row.starts = static_cast<double>(starts) / n_sq;
      rows.push_back(row);
    }

    // orocos-kdl LMA with the same start sequence.
    {
      const KDL::Chain chain = toKdlChain(m);
      KDL::ChainIkSolverPos_LMA lma(chain);
      Row row;
      row.solver = "kdl ChainIkSolverPos_LMA";
      row.total = n_reach;
      row.unreach_total = std::min(n_unreach, 100);  // KDL spends all starts on each: a subset
      KDL::JntArray q_init(n), q_out(n);
      JointVector qs(n);
      auto attempt = [&](const PoseTask& t, std::uint64_t id, long& starts) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = t.R_WT;
        T.translation() = t.p_WT;
        const KDL::Frame F = toKdl(T);
        std::mt19937_64 r2(id * 7919 + 17);
        for (int s = 0; s < def.max_starts; ++s) {
          ++starts;
          for (int i = 0; i < n; ++i) {
            const JointLimits& L = m.joints[i].limits;
            q_init(i) = s == 0 ? 0.5 * (L.q_min + L.q_max)
                               : std::uniform_real_distribution<double>(L.q_min, L.q_max)(r2);
          }
          if (lma.CartToJnt(q_init, F, q_out) < 0) continue;
          bool in_limits = true;
          for (int i = 0; i < n; ++i) {
            double v = q_out(i);
            if (m.joints[i].type == JointType::Revolute) v = std::remainder(v, 2 * kPi);
            qs[i] = v;
            in_limits &= v >= m.joints[i].limits.q_min && v <= m.joints[i].limits.q_max;
          }
          if (!in_limits) continue;
          forwardKinematics(m, kin, qs);
          const PoseError e = poseError(kin, t);
          if (e.position_m <= def.position_tolerance_m &&
              e.orientation_rad <= def.orientation_tolerance_rad)
            return true;
        }
        return false;
      };
      long starts = 0, ustarts = 0;
      auto t0 = Clock::now();
      for (int k = 0; k < n_reach; ++k) row.solved += attempt(reach[k], k, starts);
      auto t1 = Clock::now();
      for (int k = 0; k < row.unreach_total; ++k)
        row.false_reach += attempt(unreach[k], n_reach + k, ustarts);
      auto t2 = Clock::now();
      row.us_reach = 1e6 * seconds(t0, t1) / n_reach;
      row.us_unreach = 1e6 * seconds(t1, t2) / row.unreach_total;
      row.starts = static_cast<double>(starts) / n_reach;
      rows.push_back(row);
    }
    const double kdl_us = rows.back().us_reach;
    for (const Row& r : rows)
      std::printf("%-22s %-22s %8.2f%% %5d/%-4d %12.2f %12.2f %9.2f %9.1fx\n", m.name.c_str(),
                  r.solver.c_str(), 100.0 * r.solved / r.total, r.unreach_total - r.false_reach,
                  r.unreach_total, r.us_reach, r.us_unreach, r.starts, kdl_us / r.us_reach);
    std::fflush(stdout);
  }
  return 0;
}
