// Dexterity map benchmark (docs/performance.md, "## Dexterity maps"): the thesis Fig. 3.6 map at
// 1 cm x 1 deg (151 x 181 = 27,331 cells, each solved and optimised in the null space) with 1 and
// 2 threads; the same grid without optimisation (plain pose solves only); and, as a peer, the
// plain full-pose solve of every cell by orocos-kdl's ChainIkSolverPos_LMA next to armstudy's
// damped Newton solve and the reachability solver (src/ik/reach_solver, which the map uses for its
// starting solutions) with one start and with the map's starts (same warm starts, roll fixed so all
// solve the same 6-D task).
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>

#include "dexterity/dexterity_map.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "kdl_support.hpp"
#include "study/stage.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::dexterity;
using armstudy::test::toKdl;
using armstudy::test::toKdlChain;

namespace {
constexpr double kSolvedTolerance = 1e-6;  // [m and rad] a peer solve counts below this
double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

int main() {
  const Study study = loadStudy(armstudy::test::sourcePath("studies/stem_heatmap.toml"));
  const Model& m = study.designs.at(0).model;
  const DexterityOptions& opt = *stageSettings<DexterityOptions>(study, "dexterity");
  std::printf(
      "Dexterity map benchmark: %s, grid %d x %d = %d cells (studies/stem_heatmap.toml)\n\n",
      m.name.c_str(), opt.grid.z_m.count, opt.grid.gamma_rad.count, opt.grid.size());
  std::printf(
      "| run | threads | wall [s] | per cell [us] | reachable | mean null-space iterations | ratio "
      "|\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  double base = 0;
  for (int threads : {1, 2}) {
    const DexterityMap map = computeDexterityMap(m, opt, threads);
    long its = 0;
    for (const auto& c : map.cells) its += c.nullspace_iterations;
    if (threads == 1) base = map.seconds;
    std::printf("| optimised map | %d | %.3f | %.1f | %d | %.2f | %.2f |\n", threads, map.seconds,
                1e6 * map.seconds / map.cells.size(), map.reachable(),
                double(its) / std::max(1, map.reachable()), map.seconds / base);
  }
  DexterityOptions plain = opt;
  plain.w_joint_limits = plain.w_manipulability = plain.w_transmission = 0;  // no optimisation
  for (int threads : {1, 2}) {
    const DexterityMap map = computeDexterityMap(m, plain, threads);
    std::printf("| plain map (no optimisation) | %d | %.3f | %.1f | %d | - | %.2f |\n", threads,
                map.seconds, 1e6 * map.seconds / map.cells.size(), map.reachable(),
                map.seconds / base);
  }

  // Peer: full-pose plain solves along each row with warm starts, armstudy vs KDL LMA (1 thread).
  StemGrid g = opt.grid;
  g.task = PoseTaskKind::FullPose;
  const KDL::Chain chain = toKdlChain(m);
  KDL::ChainIkSolverPos_LMA lma(chain, 1e-10, 500, 1e-15);
  IkWorkspace ik_ws(m);
  IkOptions ro1, ro;  // the reach solver with the warm start only, and with the map's starts
  const double tol =
      kSolvedTolerance / defaults::kIkConvergenceFraction;  // converges below kSolved
  ro1.position_tolerance_m = ro.position_tolerance_m = tol;
  ro1.orientation_tolerance_rad = ro.orientation_tolerance_rad = tol;
  ro1.max_starts = 1;
  ro.max_starts = opt.cold_starts;
  ro1.classify_failures = ro.classify_failures = false;
  int ok_a = 0, ok_k = 0, ok_r1 = 0, ok_r = 0;
  double ta = 0, tk = 0, tr1 = 0, tr = 0;
  JointVector q_mid(m.dof());
  for (int i = 0; i < m.dof(); ++i)
    q_mid[i] = 0.5 * (m.joints[i].limits.q_min + m.joints[i].limits.q_max);
  for (int iz = 0; iz < g.z_m.count; iz += 10) {
    JointVector qa = q_mid, qr1 = q_mid, qr = q_mid;
    KDL::JntArray qk(m.dof()), qout(m.dof());
    for (int i = 0; i < m.dof(); ++i) qk(i) = qa[i];
    for (int ig = 0; ig < g.gamma_rad.count; ++ig) {
      const auto cell = g.cell(ig, iz);
      const PoseTask& rt = cell.target;
      const auto id = static_cast<std::uint64_t>(g.index(ig, iz));
      double t0 = now();
      const IkResult r1 = solvePose(m, ik_ws, rt, ro1, id, &qr1);
      tr1 += now() - t0;
      auto solved = [](const IkResult& x) {
        return x.reachable() && x.position_error_m < kSolvedTolerance &&
               x.orientation_error_rad < kSolvedTolerance;
      };
      if (solved(r1)) ++ok_r1, qr1 = r1.q;
      t0 = now();
      const IkResult rr = solvePose(m, ik_ws, rt, ro, id, &qr);
      tr += now() - t0;
      if (solved(rr)) ++ok_r, qr = rr.q;
      t0 = now();
      const IkResult r = solvePose(m, ik_ws, cell.target, IkOptions::exactPose(), id, &qa);
      ta += now() - t0;
      if (r.position_error_m < kSolvedTolerance && r.orientation_error_rad < kSolvedTolerance)
        ++ok_a, qa = r.q;
      const Eigen::Isometry3d T = [&] {
        Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
        X.linear() = cell.target.R_WT;
        X.translation() = cell.target.p_WT;
        return X;
      }();
      t0 = now();
      const int rc = lma.CartToJnt(qk, toKdl(T), qout);
      tk += now() - t0;
      bool in = rc >= 0;
      for (int i = 0; i < m.dof() && in; ++i)
        in = qout(i) >= m.joints[i].limits.q_min && qout(i) <= m.joints[i].limits.q_max;
      if (in) {
        KDL::ChainFkSolverPos_recursive fk(chain);
        KDL::Frame F;
        fk.JntToCart(qout, F);
        if ((Eigen::Vector3d(F.p.x(), F.p.y(), F.p.z()) - cell.target.p_WT).norm() <
            kSolvedTolerance)
          ++ok_k, qk = qout;
      }
    }
  }
  const int n = ((g.z_m.count + 9) / 10) * g.gamma_rad.count;
  std::printf(
      "\nPeer, plain full-pose solves (every 10th row, %d poses, warm starts along the row, 1 "
      "thread):\n\n",
      n);
  std::printf("| solver | solved within limits | per pose [us] | ratio |\n|---|---|---|---|\n");
  std::printf("| armstudy weighted Newton (solvePose, exactPose) | %d | %.1f | 1.00 |\n", ok_a,
              1e6 * ta / n);
  std::printf("| orocos-kdl ChainIkSolverPos_LMA | %d | %.1f | %.2f |\n", ok_k, 1e6 * tk / n,
              tk / ta);
  std::printf("| armstudy reach solver, warm start only | %d | %.1f | %.2f |\n", ok_r1,
              1e6 * tr1 / n, tr1 / ta);
  std::printf("| armstudy reach solver, %d starts (as in the map) | %d | %.1f | %.2f |\n",
              ro.max_starts, ok_r, 1e6 * tr / n, tr / ta);
  return 0;
}
