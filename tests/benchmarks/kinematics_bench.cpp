// Benchmark (not a test): forward kinematics + full TCP Jacobian per call, armstudy vs
// orocos-kdl (ChainFkSolverPos_recursive + ChainJntToJacSolver) on the same random configurations.
// Run: cmake --build build --target kinematics_bench && ./build/tests/benchmarks/kinematics_bench
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <random>

#include "bench_util.hpp"
#include "io/design_io.hpp"
#include "kdl_support.hpp"
#include "kinematics/kinematics.hpp"
#include "test_support.hpp"

using armstudy::test::toKdl;

using namespace armstudy;

int main() {
  std::printf("Forward kinematics + full TCP Jacobian, time per call (median of 7 batches)\n\n");
  std::printf("%-24s %5s %14s %14s %10s\n", "design", "DoF", "armstudy [us]", "KDL [us]",
              "KDL/armstudy");
  for (const auto& rel : test::shippedDesigns()) {
    const Model m = loadDesign(test::sourcePath(rel));
    std::mt19937_64 rng(1);
    const int N = 4096;
    std::vector<Eigen::VectorXd> qs;
    for (int i = 0; i < N; ++i) qs.push_back(test::randomConfiguration(m, rng));
    KinematicsWorkspace ws(m);
    const double t_ours = bench::timePerCall(
        [&](int i) {
          forwardKinematicsAndJacobian(m, ws, qs[i % N]);
          bench::doNotOptimize(ws.J_W_tcp(0, 0) + ws.p_WT.x());
        },
        200000);
    // KDL: the same chain, one segment per table row plus the joint.
    KDL::Chain c;
    for (const Joint& j : m.joints) {
      c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(j.T_PJ0)));
      c.addSegment(KDL::Segment(
          KDL::Joint(j.type == JointType::Revolute ? KDL::Joint::RotZ : KDL::Joint::TransZ),
          KDL::Frame::Identity()));
    }
    c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(m.T_NT)));
    KDL::ChainFkSolverPos_recursive fk(c);
    KDL::ChainJntToJacSolver jac(c);
    std::vector<KDL::JntArray> qk;
    for (const auto& q : qs) {
      KDL::JntArray a(m.dof());
      for (int i = 0; i < m.dof(); ++i) a(i) = q[i];
      qk.push_back(a);
    }
    KDL::Frame F;
    KDL::Jacobian J(m.dof());
    const double t_kdl = bench::timePerCall(
        [&](int i) {
          fk.JntToCart(qk[i % N], F);
          jac.JntToJac(qk[i % N], J);
          bench::doNotOptimize(J(0, 0) + F.p.x());
        },
        50000);
    std::printf("%-24s %5d %14.3f %14.3f %10.1f\n", m.name.c_str(), m.dof(), t_ours * 1e6,
                t_kdl * 1e6, t_kdl / t_ours);
  }
  return 0;
}
