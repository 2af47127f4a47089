// Dexterity map benchmark (docs/performance.md, "## Dexterity maps"): the thesis Fig. 3.6 map at
// 1 cm x 1 deg (151 x 181 = 27,331 cells, each solved and optimised in the null space) with 1 and
// 2 threads; the same grid without optimisation (plain pose solves only); and, as a peer, the
// plain full-pose solve of every cell by orocos-kdl's ChainIkSolverPos_LMA next to armstudy's
// damped Newton solve (same warm starts, roll fixed so both solve the same 6-D task).
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>

#include <chrono>
#include <cstdio>

#include "dexterity/dexterity_map.hpp"
#include "io/design_io.hpp"
#include "io/study_io.hpp"

using namespace armstudy;
using namespace armstudy::dexterity;

namespace {
double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
KDL::Frame toKdl(const Eigen::Isometry3d& T) {
  const Eigen::Matrix3d R = T.linear();
  return KDL::Frame(KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)),
                    KDL::Vector(T.translation().x(), T.translation().y(), T.translation().z()));
}
KDL::Chain toKdlChain(const Model& m) {
  KDL::Chain c;
  c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(m.T_WB)));
  for (const Joint& j : m.joints) {
    c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(j.T_PJ0)));
    c.addSegment(KDL::Segment(KDL::Joint(j.type == JointType::Revolute ? KDL::Joint::RotZ : KDL::Joint::TransZ),
                              KDL::Frame::Identity()));
  }
  c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(m.T_NT)));
  return c;
}
}  // namespace

int main() {
  const Study study = loadStudy(std::string(ARMSTUDY_SOURCE_DIR) + "/studies/stem_heatmap.toml");
  const Model& m = study.designs.at(0).model;
  const DexterityOptions& opt = *study.dexterity;
  std::printf("Dexterity map benchmark: %s, grid %d x %d = %d cells (studies/stem_heatmap.toml)\n\n",
              m.name.c_str(), opt.grid.z_m.count, opt.grid.gamma_rad.count, opt.grid.size());
  std::printf("| run | threads | wall [s] | per cell [us] | reachable | mean null-space iterations | ratio |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  double base = 0;
  for (int threads : {1, 2}) {
    const DexterityMap map = computeDexterityMap(m, opt, threads);
    long its = 0;
    for (const auto& c : map.cells) its += c.nullspace_iterations;
    if (threads == 1) base = map.seconds;
    std::printf("| optimised map | %d | %.3f | %.1f | %d | %.2f | %.2f |\n", threads, map.seconds,
                1e6 * map.seconds / map.cells.size(), map.reachable(), double(its) / std::max(1, map.reachable()),
                map.seconds / base);
  }
  DexterityOptions plain = opt;
  plain.w_joint_limits = plain.w_manipulability = plain.w_transmission = 0;  // no optimisation
  for (int threads : {1, 2}) {
    const DexterityMap map = computeDexterityMap(m, plain, threads);
    std::printf("| plain map (no optimisation) | %d | %.3f | %.1f | %d | - | %.2f |\n", threads, map.seconds,
                1e6 * map.seconds / map.cells.size(), map.reachable(), map.seconds / base);
  }

  // Peer: full-pose plain solves along each row with warm starts, armstudy vs KDL LMA (1 thread).
  StemGrid g = opt.grid;
  g.task = ik::PoseTaskKind::FullPose;
  KinematicsWorkspace ws(m);
  const JointVector w_inv = JointVector::Ones(m.dof());
  const KDL::Chain chain = toKdlChain(m);
  KDL::ChainIkSolverPos_LMA lma(chain, 1e-10, 500, 1e-15);
  int ok_a = 0, ok_k = 0;
  double ta = 0, tk = 0;
  for (int iz = 0; iz < g.z_m.count; iz += 10) {
    JointVector qa = coldStart(m, 0);
    KDL::JntArray qk(m.dof()), qout(m.dof());
    for (int i = 0; i < m.dof(); ++i) qk(i) = qa[i];
    for (int ig = 0; ig < g.gamma_rad.count; ++ig) {
      const auto cell = g.cell(ig, iz);
      double t0 = now();
      const auto r = ik::solvePose(m, ws, cell.target, qa, w_inv, {});
      ta += now() - t0;
      if (r.error.position_m < 1e-6 && r.error.orientation_rad < 1e-6) ++ok_a, qa = r.q;
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
        if ((Eigen::Vector3d(F.p.x(), F.p.y(), F.p.z()) - cell.target.p_WT).norm() < 1e-6) ++ok_k, qk = qout;
      }
    }
  }
  const int n = ((g.z_m.count + 9) / 10) * g.gamma_rad.count;
  std::printf("\nPeer, plain full-pose solves (every 10th row, %d poses, warm starts along the row, 1 thread):\n\n", n);
  std::printf("| solver | solved within limits | per pose [us] | ratio |\n|---|---|---|---|\n");
  std::printf("| armstudy damped Newton (solvePose) | %d | %.1f | 1.00 |\n", ok_a, 1e6 * ta / n);
  std::printf("| orocos-kdl ChainIkSolverPos_LMA | %d | %.1f | %.2f |\n", ok_k, 1e6 * tk / n, tk / ta);
  return 0;
}
