// The one local pose solver (solvePose) with IkAlgorithm::WeightedNewton: poses made by forward
// kinematics are recovered from nearby starts, and the joint weights W of eq. (5.45a) shape the
// solution as the closed-form W-weighted minimum-norm step does.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>

#include "ik/reach_solver.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;

namespace {
constexpr double kExactPose = 1e-9;             // [m and rad] what the exact solve reaches
constexpr double kFirstOrderRelative = 2e-2;    // |dq - dq*| / |dq*| for a 1 mm displacement
constexpr double kWeightsMatterRelative = 0.2;  // the weighted and unweighted steps differ by more
constexpr double kStep_m = 1e-3;

PoseTask poseTaskAt(const KinematicsWorkspace& ws, PoseTaskKind kind) {
  PoseTask t;
  t.kind = kind;
  t.p_WT = ws.p_WT;
  t.R_WT = ws.R_WT;
  t.axis_W = ws.a_WT;
  return t;
}

// Closed form of the W-weighted minimum-norm joint step for the position change dp at the
// configuration in ws: dq* = W^-1 J^T (J W^-1 J^T)^-1 dp (J: the 3 position rows).
Eigen::VectorXd weightedMinimumNorm(const KinematicsWorkspace& ws, const Eigen::VectorXd& w_inv,
                                    const Eigen::Vector3d& dp) {
  const Eigen::MatrixXd J = ws.J_W_tcp.topRows<3>();
  const Eigen::MatrixXd JWinv = J * w_inv.asDiagonal();
  const Eigen::Matrix3d B = JWinv * J.transpose();
  return JWinv.transpose() * B.inverse() * dp;
}
}  // namespace

TEST_CASE("solvePose WeightedNewton recovers poses made by forward kinematics", "[ik][solver]") {
  std::mt19937_64 rng(44);
  for (const auto& rel : shippedDesigns()) {
    const Model m = loadDesign(sourcePath(rel));
    IkWorkspace ws(m);
    int solved = 0;
    const int trials = 100;
    for (int trial = 0; trial < trials; ++trial) {
      const Eigen::VectorXd q_true = randomConfiguration(m, rng);
      forwardKinematics(m, ws.kin, q_true);
      const PoseTask t =
          poseTaskAt(ws.kin, m.dof() >= 6 ? PoseTaskKind::FullPose : PoseTaskKind::Position);
      // Start from a configuration perturbed by up to 0.3 rad / 0.3 m per joint.
      const JointVector q0 = q_true + 0.3 * Eigen::VectorXd::Random(m.dof());
      const IkResult r = solvePose(m, ws, t, IkOptions::exactPose(), 0, &q0);
      if (r.position_error_m < kExactPose && r.orientation_error_rad < kExactPose) ++solved;
      CHECK(r.reachable() == (r.position_error_m <= defaults::kPoseSolveTolerance_m &&
                              r.orientation_error_rad <= defaults::kPoseSolveTolerance_rad));
      for (int i = 0; i < m.dof(); ++i) {
        CHECK(r.q[i] >= m.joints[i].limits.q_min);
        CHECK(r.q[i] <= m.joints[i].limits.q_max);
      }
    }
    INFO(rel << ": solved " << solved << " of " << trials);
    CHECK(solved >=
          90);  // local solver from a nearby start; the multi-start methods cover the rest
  }
}

TEST_CASE("solvePose WeightedNewton takes the W-weighted minimum-norm step (eq. 5.45a)",
          "[ik][solver][oracle]") {
  // 7-DoF final prototype, position task (redundancy 4): a 1 mm displacement of the TCP from a
  // configuration inside the limits. To first order the solver's joint change is the closed-form
  // weighted minimum-norm step; a heavy weight on the lift moves the motion into the other joints.
  const Model m = loadDesign(sourcePath("designs/final_prototype_7dof.toml"));
  const int n = m.dof();
  IkWorkspace ws(m);
  std::mt19937_64 rng(45);
  int compared = 0;
  for (int trial = 0; trial < 20; ++trial) {
    JointVector q0(n);
    for (int i = 0; i < n; ++i) {  // keep 20 % of each range away from the limits
      const JointLimits& L = m.joints[i].limits;
      q0[i] = L.q_min +
              (0.2 + 0.6 * std::uniform_real_distribution<double>(0, 1)(rng)) * (L.q_max - L.q_min);
    }
    forwardKinematicsAndJacobian(m, ws.kin, q0);
    const Eigen::Vector3d dp = kStep_m * Eigen::Vector3d(1, -2, 2) / 3.0;
    const PoseTask t = positionTask(ws.kin.p_WT + dp);
    std::vector<double> weights(n, 1.0);
    weights[0] = 100.0;  // the lift
    Eigen::VectorXd w_inv = Eigen::VectorXd::Ones(n);
    w_inv[0] = 1.0 / weights[0];
    const Eigen::VectorXd dq_weighted = weightedMinimumNorm(ws.kin, w_inv, dp);
    const Eigen::VectorXd dq_plain = weightedMinimumNorm(ws.kin, Eigen::VectorXd::Ones(n), dp);
    if (!((dq_weighted - dq_plain).norm() > kWeightsMatterRelative * dq_plain.norm())) continue;
    ++compared;
    IkOptions o = IkOptions::exactPose();
    o.joint_weights = weights;
    const IkResult rw = solvePose(m, ws, t, o, 0, &q0);
    REQUIRE(rw.reachable());
    CHECK((rw.q - q0 - dq_weighted).norm() < kFirstOrderRelative * dq_weighted.norm());
    const IkResult rp = solvePose(m, ws, t, IkOptions::exactPose(), 0, &q0);
    REQUIRE(rp.reachable());
    CHECK((rp.q - q0 - dq_plain).norm() < kFirstOrderRelative * dq_plain.norm());
  }
  INFO("configurations where the weights change the step");
  CHECK(compared >= 10);
}
