// Redundancy resolution (thesis section 5.4): Algorithm 5.3 against the explicit formulas
// (eq. 5.46, 5.47, 5.65), null-space motion invariants, the thesis scenarios of Fig. 5.12
// (joint-limit avoidance) and Fig. 5.16 (adaptive damping at the workspace boundary).
#include "ik/nullspace.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>

#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::ik;
using namespace armstudy::test;

namespace {
constexpr double kNullspaceDriftTolerance = 1e-6;  // [m and rad] tool drift over a long run
constexpr double kLinearAlgebraTolerance = 1e-9;   // Algorithm 5.3 vs explicit inverse
constexpr double kTrackingTolerance_m = 1e-4;      // tracking error far from singularities

PoseTask targetAt(const KinematicsWorkspace& ws, PoseTaskKind kind) {
  PoseTask t;
  t.kind = kind;
  t.p_WT = ws.p_WT;
  t.R_WT = ws.R_WT;
  t.axis_W = ws.a_WT;
  return t;
}
}  // namespace

TEST_CASE("Algorithm 5.3 equals the explicit weighted generalised inverse (eq. 5.46, 5.47, 5.65)",
          "[ik][nullspace][oracle]") {
  std::mt19937_64 rng(21);
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  KinematicsWorkspace ws(m);
  const int n = m.dof();
  for (int trial = 0; trial < 50; ++trial) {
    forwardKinematicsAndJacobian(m, ws, randomConfiguration(m, rng));
    for (auto kind : {PoseTaskKind::Position, PoseTaskKind::PositionAxis, PoseTaskKind::FullPose}) {
      TaskJacobian Jt;
      TaskVec e;
      taskJacobianAndError(ws, targetAt(ws, kind), Jt, e);
      const Eigen::MatrixXd J = Jt;
      const int mm = static_cast<int>(J.rows());
      const Eigen::VectorXd w = Eigen::VectorXd::Random(n).cwiseAbs().array() + 0.5;
      const Eigen::VectorXd w_inv = w.cwiseInverse();
      const Eigen::VectorXd wdot = Eigen::VectorXd::Random(mm);
      const Eigen::VectorXd grad = Eigen::VectorXd::Random(n);
      const double alpha = 0.7;
      for (double lambda : {0.0, 0.05}) {
        Eigen::VectorXd qdot(n);
        REQUIRE(redundancyResolution(J, w_inv, wdot, grad, alpha, lambda, qdot));
        // Explicit: J# = W^-1 J^T (J W^-1 J^T + lambda^2 I)^-1; qdot = J# wdot - alpha (I - J# J)
        // W^-1 grad.
        const Eigen::MatrixXd Winv = w_inv.asDiagonal();
        const Eigen::MatrixXd B =
            J * Winv * J.transpose() + lambda * lambda * Eigen::MatrixXd::Identity(mm, mm);
        const Eigen::MatrixXd Jsharp = Winv * J.transpose() * B.inverse();
        const Eigen::MatrixXd N = Eigen::MatrixXd::Identity(n, n) - Jsharp * J;
        const Eigen::VectorXd expect = Jsharp * wdot - alpha * N * Winv * grad;
        CHECK((qdot - expect).norm() < kLinearAlgebraTolerance * std::max(1.0, expect.norm()));
        if (lambda == 0) {
          // Constraint (5.45b) holds exactly; the null-space part produces no task velocity (5.48).
          CHECK((J * qdot - wdot).norm() < kLinearAlgebraTolerance);
          CHECK((J * N * grad).norm() < kLinearAlgebraTolerance);
        }
      }
    }
  }
}

TEST_CASE("adaptive damping follows eq. 5.67", "[ik][nullspace]") {
  CHECK(adaptiveDamping(0.3, 0.2, 0.1) == 0.0);
  CHECK(std::abs(adaptiveDamping(0.05, 0.2, 0.1) - 0.2 * 0.25) < kHandCheckTolerance);
  CHECK(std::abs(adaptiveDamping(0.0, 0.2, 0.1) - 0.2) < kHandCheckTolerance);
  CHECK(adaptiveDamping(0.0, 0.0, 0.1) == 0.0);
}

TEST_CASE("null-space motion keeps the tool still over a long run", "[ik][nullspace][invariant]") {
  std::mt19937_64 rng(33);
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  KinematicsWorkspace ws(m);
  ObjectiveContext ctx(m, ws);
  WeightedObjective obj;
  obj.add(1.0, std::make_shared<ManipulabilityTerm>(metrics::MeasureSpace::Translational));
  obj.add(0.1, std::make_shared<JointLimitTerm>(m, 0.1));
  // Start inside the limits, away from them.
  Eigen::VectorXd q0 = 0.5 * randomConfiguration(m, rng);
  forwardKinematicsAndJacobian(m, ws, q0);
  for (auto kind : {PoseTaskKind::PositionAxis, PoseTaskKind::FullPose}) {
    forwardKinematicsAndJacobian(m, ws, q0);
    const PoseTask target = targetAt(ws, kind);
    const double h0 = [&] {
      ctx.prepare(q0);
      return obj.evaluate(ctx, nullptr);
    }();
    // Velocity level: 10 s of pure null-space motion (wdot_d = 0), 10,000 Euler steps.
    TrackingOptions o;
    o.redundancy.alpha = 2.0;
    o.stop_at_joint_limit = false;
    const auto sum = trackReference(
        m, ws,
        [&](double) {
          ReferencePoint r;
          r.pose = target;
          return r;
        },
        q0, 10.0, &obj, &ctx, o);
    double worst_p = 0, worst_o = 0;
    for (const auto& s : sum.samples) {
      worst_p = std::max(worst_p, s.position_error_m);
      worst_o = std::max(worst_o, s.orientation_error_rad);
    }
    INFO(toString(kind) << ": worst drift " << worst_p << " m, " << worst_o << " rad");
    CHECK(sum.samples.size() == 10001);
    CHECK(worst_p < kNullspaceDriftTolerance);
    CHECK(worst_o < kNullspaceDriftTolerance);
    const Eigen::VectorXd q_end = sum.samples.back().q;
    CHECK((q_end - q0).norm() > 0.1);  // the joints really moved
    ctx.prepare(q_end);
    forwardKinematicsAndJacobian(m, ws, q_end);
    ctx.prepare(q_end);
    CHECK(obj.evaluate(ctx, nullptr) < h0);  // and the objective improved

    // Position level: optimisation at the pose keeps the tool on it and does not worsen H.
    const auto res = optimiseAtPose(m, ws, ctx, target, q0, obj, JointVector::Ones(m.dof()), {});
    CHECK(res.status != NullspaceStatus::NotOnPose);
    CHECK(res.error.position_m < kNullspaceDriftTolerance);
    CHECK(res.error.orientation_rad < kNullspaceDriftTolerance);
    CHECK(res.H_final < res.H_start);
    CHECK(withinLimits(m, res.q));
    // The optimum is stationary in the null space: a further run barely improves it.
    const auto again =
        optimiseAtPose(m, ws, ctx, target, res.q, obj, JointVector::Ones(m.dof()), {});
    CHECK(again.H_start - again.H_final <= 1e-3 * std::abs(res.H_final));
  }
}

TEST_CASE("thesis Fig. 5.12: joint-limit avoidance keeps the lift inside its limit",
          "[ik][nullspace][thesis]") {
  // 7-DoF final prototype, position task (m = 3, redundancy 4). The TCP follows a straight line
  // 1.2 m upwards in 3 s, from z = -0.16 m to z = 1.04 m in the base frame, starting with the lift
  // at q1 = -0.4 m. With the assumed lift range [-0.5, 0.5] m, the minimum-norm solution drives
  // the lift into its upper limit; with H_j (eq. 5.52, thresholds 10 % inside) the redundancy
  // takes the motion into the arm joints instead.
  const Model m = loadDesign(sourcePath("designs/final_prototype_7dof.toml"));
  KinematicsWorkspace ws(m);
  ObjectiveContext ctx(m, ws);
  Eigen::VectorXd q0(7);
  q0 << -0.4, 0.2, 0.3, 1.2, 0.0, 0.6, 0.0;
  forwardKinematics(m, ws, q0);
  const Eigen::Vector3d p0 = ws.p_WT, p1 = p0 + Eigen::Vector3d(0, 0, 1.2);
  const double T = 3.0;
  const Reference line = [&](double t) {
    ReferencePoint r;
    r.pose.kind = PoseTaskKind::Position;
    r.pose.p_WT = p0 + (p1 - p0) * (t / T);
    r.v_W = (p1 - p0) / T;
    return r;
  };
  WeightedObjective hj;
  hj.add(1.0, std::make_shared<JointLimitTerm>(m, defaults::kJointLimitActivation));
  TrackingOptions o;
  o.redundancy.alpha = 10.0;

  const auto off = trackReference(m, ws, line, q0, T, nullptr, nullptr, o);
  CHECK(off.status == TrackingStatus::JointLimitReached);
  CHECK(off.limit_joint == 0);

  const auto on = trackReference(m, ws, line, q0, T, &hj, &ctx, o);
  CHECK(on.status == TrackingStatus::Completed);
  double max_q1 = -1e9, max_err = 0;
  for (const auto& s : on.samples) {
    max_q1 = std::max(max_q1, s.q[0]);
    max_err = std::max(max_err, s.position_error_m);
  }
  CHECK(max_q1 < m.joints[0].limits.q_max);
  CHECK(max_err < kTrackingTolerance_m);  // the line is still tracked
}

TEST_CASE("thesis Fig. 5.16: adaptive damping keeps joint speeds bounded beyond the workspace",
          "[ik][nullspace][thesis]") {
  // 7-DoF, position task; the line runs 1 m along +y in 2 s and ends outside the reachable
  // workspace. Damping eq. (5.67) with lambda0 = 0.3, m0 = 0.15 (manipulability of J_T).
  const Model m = loadDesign(sourcePath("designs/final_prototype_7dof.toml"));
  KinematicsWorkspace ws(m);
  Eigen::VectorXd q0(7);
  q0 << 0.0, 0.2, 0.3, 1.2, 0.0, 0.6, 0.0;
  forwardKinematics(m, ws, q0);
  const Eigen::Vector3d p0 = ws.p_WT, p1 = p0 + Eigen::Vector3d(0, 1.0, 0);
  const double T = 2.0;
  const Reference line = [&](double t) {
    ReferencePoint r;
    r.pose.kind = PoseTaskKind::Position;
    r.pose.p_WT = p0 + (p1 - p0) * (t / T);
    r.v_W = (p1 - p0) / T;
    return r;
  };
  TrackingOptions damped;
  damped.stop_at_joint_limit = false;
  damped.redundancy.damping_lambda0 = 0.3;
  damped.redundancy.damping_m0 = 0.15;
  const auto sd = trackReference(m, ws, line, q0, T, nullptr, nullptr, damped);
  TrackingOptions plain = damped;
  plain.redundancy.damping_lambda0 = 0;
  const auto sp = trackReference(m, ws, line, q0, T, nullptr, nullptr, plain);

  const double path_speed = (p1 - p0).norm() / T;  // 0.5 m/s
  INFO("max joint speed damped " << sd.max_joint_speed << ", undamped " << sp.max_joint_speed);
  CHECK(sd.max_joint_speed < 20 * path_speed);   // bounded (10 rad/s)
  CHECK(sp.max_joint_speed > 200 * path_speed);  // without damping it explodes near the singularity
  // Error stays at the drift level while the arm is far from the singularity (m > m0); it grows
  // only once the manipulability has dropped, and the goal is indeed out of reach.
  bool left_far_region = false;
  for (const auto& s : sd.samples) {
    if (s.manipulability < damped.redundancy.damping_m0) left_far_region = true;
    if (!left_far_region) CHECK(s.position_error_m < kTrackingTolerance_m);
    if (s.position_error_m > 1e-3) CHECK(left_far_region);
  }
  CHECK(sd.samples.back().position_error_m > 0.3);
}
