// Inverse dynamics, mass matrix and forward dynamics of the 9-DoF final prototype against
// orocos-kdl in the same run (docs/performance.md, "## Inverse dynamics").
//   cmake --build build --target dynamics_bench && ./build/tests/benchmarks/dynamics_bench
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <random>
#include <vector>

#include "bench_util.hpp"
#include "dynamics/dynamics.hpp"
#include "io/design_io.hpp"
#include "kdl_support.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;

namespace {

// The leanest KDL chain for the same arm: one segment per joint whose tip is the next joint's
// fixed transform, the link inertia moved into that tip frame, the payload merged into the last
// segment. This is the fair peer (the tests' chain has two segments per joint).
KDL::Chain minimalKdlChain(const Model& m) {
  KDL::Chain c;
  c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(m.T_WB * m.joints[0].T_PJ0)));
  for (int i = 0; i < m.dof(); ++i) {
    const bool last = i + 1 == m.dof();
    const KDL::Frame tip = toKdl(last ? m.T_NT : m.joints[i + 1].T_PJ0);
    KDL::RigidBodyInertia I = toKdl(m.inertias[i]);
    if (last)
      I = I + toKdl(m.T_NT) *
                  KDL::RigidBodyInertia(m.payload_kg,
                                        KDL::Vector(m.p_payload_com_T.x(), m.p_payload_com_T.y(),
                                                    m.p_payload_com_T.z()));
    c.addSegment(KDL::Segment(
        KDL::Joint(m.joints[i].type == JointType::Revolute ? KDL::Joint::RotZ : KDL::Joint::TransZ),
        tip, tip.Inverse() * I));
  }
  return c;
}

// Median of 7 batches (bench_util.hpp), in ns per call; fn(i) runs call i of the batch.
template <class Fn>
double nsPerCall(int calls, Fn fn) {
  return 1e9 * bench::timePerCall(fn, calls, 7);
}

}  // namespace

int main() {
  const Model m = loadDesign(sourcePath("designs/final_prototype_9dof.toml"));
  const int n = m.dof();
  const RigidBodyModel rbm = makeRigidBodyModel(m);
  DynamicsWorkspace ws(rbm);
  const KDL::Chain kdl_full = toKdlDynamicChain(m, true, false);
  const KDL::Chain kdl_min = minimalKdlChain(m);
  KDL::ChainIdSolver_RNE rne_full(kdl_full, KDL::Vector(0, 0, -9.81));
  KDL::ChainIdSolver_RNE rne_min(kdl_min, KDL::Vector(0, 0, -9.81));
  KDL::ChainDynParam dyn_min(kdl_min, KDL::Vector(0, 0, -9.81));

  const int N = 1000;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::VectorXd> q(N), qd(N), qdd(N);
  std::vector<KDL::JntArray> kq(N, KDL::JntArray(n)), kqd(N, KDL::JntArray(n)),
      kqdd(N, KDL::JntArray(n));
  for (int k = 0; k < N; ++k) {
    q[k] = randomConfiguration(m, rng);
    qd[k].resize(n);
    qdd[k].resize(n);
    for (int i = 0; i < n; ++i) {
      qd[k][i] = u(rng);
      qdd[k][i] = 3 * u(rng);
      kq[k](i) = q[k][i];
      kqd[k](i) = qd[k][i];
      kqdd[k](i) = qdd[k][i];
    }
  }
  KDL::Wrenches f_full(kdl_full.getNrOfSegments(), KDL::Wrench::Zero());
  KDL::Wrenches f_min(kdl_min.getNrOfSegments(), KDL::Wrench::Zero());
  KDL::JntArray kt(n);
  KDL::JntSpaceInertiaMatrix kM(n);
  Eigen::VectorXd tau(n), out(n);

  // Agreement check before timing (the peers compute the same numbers).
  double max_rel_full = 0, max_rel_min = 0;
  for (int k = 0; k < N; ++k) {
    inverseDynamics(rbm, ws, q[k], qd[k], qdd[k], tau);
    const double scale = std::max(1.0, tau.cwiseAbs().maxCoeff());
    rne_full.CartToJnt(kq[k], kqd[k], kqdd[k], f_full, kt);
    for (int i = 0; i < n; ++i)
      max_rel_full = std::max(max_rel_full, std::abs(kt(i) - tau[i]) / scale);
    rne_min.CartToJnt(kq[k], kqd[k], kqdd[k], f_min, kt);
    for (int i = 0; i < n; ++i)
      max_rel_min = std::max(max_rel_min, std::abs(kt(i) - tau[i]) / scale);
  }

  const int R = 20;  // passes over the N states per repetition
  const double t_id = nsPerCall(N * R, [&](int i) {
    const int k = i % N;
    inverseDynamics(rbm, ws, q[k], qd[k], qdd[k], tau);
    bench::doNotOptimize(tau[0]);
  });
  const double t_kdl_min = nsPerCall(N * R, [&](int i) {
    const int k = i % N;
    rne_min.CartToJnt(kq[k], kqd[k], kqdd[k], f_min, kt);
    bench::doNotOptimize(kt(0));
  });
  const double t_kdl_full = nsPerCall(N * R, [&](int i) {
    const int k = i % N;
    rne_full.CartToJnt(kq[k], kqd[k], kqdd[k], f_full, kt);
    bench::doNotOptimize(kt(0));
  });
  const double t_grav = nsPerCall(N * R, [&](int i) {
    const int k = i % N;
    gravityForces(rbm, ws, q[k], out);
    bench::doNotOptimize(out[0]);
  });
  const double t_M = nsPerCall(N * R, [&](int i) {
    const int k = i % N;
    massMatrix(rbm, ws, q[k]);
    bench::doNotOptimize(ws.M(0, 0));
  });
  const double t_kdl_M = nsPerCall(N * R, [&](int i) {
    const int k = i % N;
    dyn_min.JntToMass(kq[k], kM);
    bench::doNotOptimize(kM(0, 0));
  });
  const double t_fd = nsPerCall(N * R, [&](int i) {
    const int k = i % N;
    forwardDynamics(rbm, ws, q[k], qd[k], qdd[k], out);
    bench::doNotOptimize(out[0]);
  });

  std::printf(
      "Dynamics of final_prototype_9dof (n = %d), %d random states, median of 7 batches of %d "
      "calls\n",
      n, N, N * R);
  std::printf(
      "KDL agreement (max relative torque difference): full chain %.1e, minimal chain %.1e\n",
      max_rel_full, max_rel_min);
  std::printf("| operation | armstudy [ns/call] | peer | peer [ns/call] | speed-up |\n");
  std::printf("|---|---:|---|---:|---:|\n");
  std::printf(
      "| inverse dynamics (RNEA) | %.0f | KDL ChainIdSolver_RNE, minimal chain (%u segments) | "
      "%.0f | %.1fx |\n",
      t_id, kdl_min.getNrOfSegments(), t_kdl_min, t_kdl_min / t_id);
  std::printf(
      "| inverse dynamics (RNEA) | %.0f | KDL ChainIdSolver_RNE, test chain (%u segments) | %.0f | "
      "%.1fx |\n",
      t_id, kdl_full.getNrOfSegments(), t_kdl_full, t_kdl_full / t_id);
  std::printf(
      "| mass matrix (CRBA) | %.0f | KDL ChainDynParam::JntToMass, minimal chain | %.0f | %.1fx "
      "|\n",
      t_M, t_kdl_M, t_kdl_M / t_M);
  std::printf("| gravity vector g(q) | %.0f | - | - | - |\n", t_grav);
  std::printf("| forward dynamics (h + CRBA + Cholesky) | %.0f | - | - | - |\n", t_fd);
  const bool ok =
      t_id < 1000.0 && t_kdl_min / t_id >= 3.0 && max_rel_min < 1e-9 && max_rel_full < 1e-9;
  std::printf("targets (RNEA < 1 us, >= 3x KDL minimal chain, agreement 1e-9): %s\n",
              ok ? "met" : "NOT met");
  return 0;
}
