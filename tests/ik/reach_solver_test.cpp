// Per-pose IK (thesis eq. 3.2) against independent oracles: poses made by forward kinematics
// (known reachable; the solution is re-checked with an independent pose comparison), closed-form
// arms for out_of_reach vs joint_limits, central finite differences for the SLSQP gradient, and a
// finite-difference Jacobian for the manipulability (eq. 5.59).
#include "ik/reach_solver.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;

namespace {

constexpr double kGradientTolerance = 1e-6;
constexpr double kManipulabilityTolerance = 1e-6;
constexpr double kSameRowsTolerance = 1e-12;  // the same rows built two ways
constexpr double kRelativeTolerance = 1e-9;   // determinant vs singular values
constexpr double kSolveRateRequired = 0.99;   // tests use few poses; the benchmark checks 99.9 %

PoseTask fullPoseOf(const KinematicsWorkspace& kin) { return fullPoseTask(kin.p_WT, kin.R_WT); }

// Independent check of a solution: FK at q, then position distance and the geodesic angle.
void checkSolution(const Model& m, const PoseTask& t, const IkResult& r, const IkOptions& o) {
  KinematicsWorkspace kin(m);
  forwardKinematics(m, kin, r.q);
  CHECK((kin.p_WT - t.p_WT).norm() <= o.position_tolerance_m);
  CHECK(Eigen::AngleAxisd(t.R_WT.transpose() * kin.R_WT).angle() <= o.orientation_tolerance_rad);
  for (int i = 0; i < m.dof(); ++i) {
    CHECK(r.q[i] >= m.joints[i].limits.q_min);
    CHECK(r.q[i] <= m.joints[i].limits.q_max);
  }
}

// Two joints: a lift along z in [0, 0.1] m, then a revolute joint about z with a 0.5 m link.
Model liftArm() {
  return parseDesign(R"(
[design]
name = "lift_arm"
[[joint]]
name = "lift"
type = "prismatic"
x = 0
y = 0
z = 0
alpha = 0
beta = 0
gamma = 0
min = 0
max = 0.1
[[joint]]
name = "turn"
type = "revolute"
x = 0
y = 0
z = 0
alpha = 0
beta = 0
gamma = 0
min = "-170 deg"
max = "170 deg"
[tcp]
x = 0.5
)",
                     "lift_arm.toml");
}

}  // namespace

TEST_CASE("poses made by forward kinematics are found reachable on every shipped design",
          "[ik][oracle]") {
  std::mt19937_64 rng(7);
  IkOptions o;
  for (const auto& rel : shippedDesigns()) {
    const Model m = loadDesign(sourcePath(rel));
    KinematicsWorkspace kin(m);
    IkWorkspace ws(m);
    const int n = 150;
    int solved = 0;
    for (int k = 0; k < n; ++k) {
      forwardKinematics(m, kin, randomConfiguration(m, rng));
      const PoseTask t = fullPoseOf(kin);
      const IkResult r = solvePose(m, ws, t, o, static_cast<std::uint64_t>(k));
      if (!r.reachable()) continue;
      ++solved;
      checkSolution(m, t, r, o);
      CHECK(r.position_error_m <= o.position_tolerance_m);
      CHECK(r.joint_limit_margin >= 0);
      CHECK(r.joint_limit_margin <= 0.5);
    }
    INFO(m.name);
    CHECK(solved >= kSolveRateRequired * n);
  }
}

TEST_CASE("poses beyond the summed link lengths are out of reach", "[ik][oracle]") {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  for (const auto& rel : shippedDesigns()) {
    const Model m = loadDesign(sourcePath(rel));
    IkWorkspace ws(m);
    for (bool bound : {true, false}) {
      IkOptions o;
      o.use_reach_bound = bound;
      o.max_starts = 4;
      for (int k = 0; k < 20; ++k) {
        const Eigen::Vector3d a = ws.bound_axis.unitOrthogonal(), b = ws.bound_axis.cross(a);
        const double phi = 6.283185307 * u(rng);
        PoseTask t = positionTask(Eigen::Vector3d::Zero());
        t.p_WT = ws.bound_p0 + 0.05 * ws.bound_axis +
                 ws.reach_radius * 1.1 * (std::cos(phi) * a + std::sin(phi) * b);
        const IkResult r = solvePose(m, ws, t, o, k);
        CHECK(r.status == ReachStatus::OutOfReach);
        CHECK(r.bound_rejected == bound);
      }
    }
  }
}

TEST_CASE("closed-form arm: lift limits block, distance puts out of reach", "[ik][oracle]") {
  const Model m = liftArm();
  IkWorkspace ws(m);
  IkOptions o;
  PoseTask t = positionTask(
      Eigen::Vector3d(0.3, 0.4, 0.05));  // |(x, y)| = 0.5 at a height inside the stroke
  IkResult r = solvePose(m, ws, t, o, 1);
  REQUIRE(r.reachable());
  CHECK(r.q[0] == Approx(0.05).margin(o.position_tolerance_m));
  CHECK(r.q[1] == Approx(std::atan2(0.4, 0.3)).margin(1e-2));
  t.p_WT = Eigen::Vector3d(0.3, 0.4, 0.5);  // needs a 0.5 m lift, the stroke ends at 0.1 m
  r = solvePose(m, ws, t, o, 2);
  CHECK(r.status == ReachStatus::JointLimits);
  CHECK(r.position_error_m == Approx(0.4).margin(o.position_tolerance_m));
  t.p_WT = Eigen::Vector3d(0.3, 0.2, 0.05);  // |(x, y)| = 0.36 != 0.5: no lift height helps
  r = solvePose(m, ws, t, o, 3);
  CHECK(r.status == ReachStatus::OutOfReach);
  t.p_WT = Eigen::Vector3d(-0.5, 0.0, 0.05);  // needs q2 = 180 deg, the limit is 170 deg
  r = solvePose(m, ws, t, o, 4);
  CHECK(r.status == ReachStatus::JointLimits);
}

TEST_CASE("the SLSQP objective gradient matches central finite differences", "[ik][oracle]") {
  std::mt19937_64 rng(11);
  for (const auto& rel : shippedDesigns()) {
    const Model m = loadDesign(sourcePath(rel));
    KinematicsWorkspace kin(m);
    for (const TaskSpace& ts :
         {TaskSpace::fullPose(), TaskSpace::spraying(), TaskSpace::position()}) {
      for (int trial = 0; trial < 10; ++trial) {
        forwardKinematics(m, kin, randomConfiguration(m, rng));
        const PoseTask t = taskTarget(ts, tcpTaskVector(kin).w);
        const Eigen::VectorXd q = randomConfiguration(m, rng);
        Eigen::VectorXd g;
        ikObjective(m, kin, t, 0.3, q, &g);
        for (int i = 0; i < m.dof(); ++i) {
          Eigen::VectorXd qp = q, qm = q;
          qp[i] += kFdStep;
          qm[i] -= kFdStep;
          const double fd = (ikObjective(m, kin, t, 0.3, qp, nullptr) -
                             ikObjective(m, kin, t, 0.3, qm, nullptr)) /
                            (2 * kFdStep);
          CHECK(g[i] == Approx(fd).margin(kGradientTolerance));
        }
      }
    }
  }
}

TEST_CASE("manipulability equals sqrt(det(J J^T)) of a finite-difference position Jacobian",
          "[ik][oracle]") {
  std::mt19937_64 rng(13);
  const Model m = loadDesign(sourcePath("designs/final_prototype_7dof.toml"));
  KinematicsWorkspace kin(m), k2(m);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::VectorXd q = randomConfiguration(m, rng);
    forwardKinematicsAndJacobian(m, kin, q);
    Eigen::MatrixXd J(3, m.dof());
    for (int i = 0; i < m.dof(); ++i) {
      Eigen::VectorXd qp = q, qm = q;
      qp[i] += kFdStep;
      qm[i] -= kFdStep;
      forwardKinematics(m, k2, qp);
      const Eigen::Vector3d pp = k2.p_WT;
      forwardKinematics(m, k2, qm);
      J.col(i) = (pp - k2.p_WT) / (2 * kFdStep);
    }
    const double expected = std::sqrt((J * J.transpose()).determinant());
    const PoseTask position = positionTask(kin.p_WT);
    CHECK(taskManipulability(kin, position) == Approx(expected).margin(kManipulabilityTolerance));
  }
}

TEST_CASE("task rows of part of the position and the tool axis, and their manipulability",
          "[ik][oracle]") {
  // Oracle: for the task space "x,z,alpha,gamma" (the tool axis with y free) the rows are the
  // x and z rows of the geometric Jacobian, then two angular rows whose Gram matrix is
  // J_R^T (I - a a^T) J_R (the projection perpendicular to the tool axis a, any basis); the
  // manipulability and its parts equal sqrt(det(J J^T)) of those rows, by determinant here and by
  // the singular values in metrics.
  std::mt19937_64 rng(33);
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  KinematicsWorkspace kin(m);
  TaskSpace space;
  std::string error;
  REQUIRE(parseTaskSpace("x,z,alpha,gamma", space, error));
  for (int trial = 0; trial < 10; ++trial) {
    forwardKinematicsAndJacobian(m, kin, randomConfiguration(m, rng));
    const PoseTask t = taskTarget(space, TaskVector6::Zero());
    REQUIRE(t.kind == PoseTaskKind::PositionAxis);
    Jacobian6 J(6, m.dof());
    REQUIRE(taskJacobianRows(kin, t, J) == 4);
    CHECK((J.row(0) - kin.J_W_tcp.row(0)).norm() < kSameRowsTolerance);
    CHECK((J.row(1) - kin.J_W_tcp.row(2)).norm() < kSameRowsTolerance);
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - kin.a_WT * kin.a_WT.transpose();
    const Eigen::MatrixXd J_R = kin.J_W_tcp.bottomRows<3>();
    const Eigen::MatrixXd B = J.middleRows(2, 2);
    CHECK((B.transpose() * B - J_R.transpose() * P * J_R).norm() < kSameRowsTolerance);
    const Eigen::MatrixXd rows = J.topRows(4);
    const double expected = std::sqrt((rows * rows.transpose()).determinant());
    CHECK(taskManipulability(kin, t) == Approx(expected).epsilon(kRelativeTolerance));
    const ManipulabilityParts parts = taskManipulabilityParts(kin, t);
    const Eigen::MatrixXd Jp = rows.topRows(2);
    CHECK(parts.translation ==
          Approx(std::sqrt((Jp * Jp.transpose()).determinant())).epsilon(kRelativeTolerance));
    CHECK(parts.rotation ==
          Approx(std::sqrt((B * B.transpose()).determinant())).epsilon(kRelativeTolerance));
  }
}

TEST_CASE("the same pose id gives the same result, options are validated", "[ik]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  IkWorkspace a(m), b(m);
  TaskVector6 w_d;
  w_d << 0.2, 0.7, 1.1, 0, 0, 0.5;
  const PoseTask t = taskTarget(TaskSpace::spraying(), w_d);
  IkOptions o;
  const IkResult r1 = solvePose(m, a, t, o, 42), r2 = solvePose(m, b, t, o, 42);
  CHECK(r1.status == r2.status);
  CHECK(r1.q == r2.q);
  CHECK(r1.position_error_m == r2.position_error_m);
  o.position_tolerance_m = 0;
  CHECK_FALSE(o.validate().empty());
  o = IkOptions{};
  o.orientation_tolerance_rad = -1;
  CHECK_FALSE(o.validate().empty());
}

TEST_CASE("tool-axis task: FK-made targets are solved with the axis on target and the roll free",
          "[ik][oracle]") {
  // Oracle: targets from FK of random configurations (known reachable); the solution is checked
  // with an independent FK (position distance, angle between tool axes); the SLSQP objective's
  // gradient against central differences.
  std::mt19937_64 rng(21);
  IkOptions o;
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  KinematicsWorkspace kin(m), k2(m);
  IkWorkspace ws(m);
  const int n = 100;
  int solved = 0;
  for (int k = 0; k < n; ++k) {
    forwardKinematics(m, kin, randomConfiguration(m, rng));
    const PoseTask t = positionAxisTask(kin.p_WT, kin.a_WT);
    const IkResult r = solvePose(m, ws, t, o, static_cast<std::uint64_t>(k));
    if (!r.reachable()) continue;
    ++solved;
    forwardKinematics(m, k2, r.q);
    CHECK((k2.p_WT - t.p_WT).norm() <= o.position_tolerance_m);
    CHECK(std::acos(std::clamp(k2.R_WT.col(2).dot(t.axis_W), -1.0, 1.0)) <=
          o.orientation_tolerance_rad);
    CHECK(r.manipulability > 0);
    if (k < 5) {
      const Eigen::VectorXd q = randomConfiguration(m, rng);
      Eigen::VectorXd g;
      ikObjective(m, k2, t, 0.3, q, &g);
      for (int i = 0; i < m.dof(); ++i) {
        Eigen::VectorXd qp = q, qm = q;
        qp[i] += kFdStep;
        qm[i] -= kFdStep;
        const double fd =
            (ikObjective(m, k2, t, 0.3, qp, nullptr) - ikObjective(m, k2, t, 0.3, qm, nullptr)) /
            (2 * kFdStep);
        CHECK(g[i] == Approx(fd).margin(kGradientTolerance));
      }
    }
  }
  CHECK(solved >= kSolveRateRequired * n);
}

TEST_CASE(
    "a verdict agrees with the posture stored beside it: a pose reached within the "
    "tolerance just outside the reach bound is reachable",
    "[ik][oracle]") {
  // Closed form: the lift arm's TCP sweeps the cylinder of radius 0.5 m, so a target at radius
  // 0.5 m + d is missed by exactly d. With d inside the position tolerance the pose is reached
  // (eq. 3.2 with the tolerance), although the exact point lies beyond the reach bound.
  const Model m = liftArm();
  IkWorkspace ws(m);
  IkOptions o;
  REQUIRE(ws.reach_radius == Approx(0.5));
  for (const double d : {0.3e-3, 0.65e-3, 0.95e-3, 1.2e-3}) {
    const PoseTask t = positionTask(Eigen::Vector3d((0.5 + d) * 0.6, (0.5 + d) * 0.8, 0.05));
    const IkResult r = solvePose(m, ws, t, o, 7);
    INFO("d = " << d);
    CHECK(r.position_error_m == Approx(d).margin(1e-6));
    CHECK(r.reachable() == (d <= o.position_tolerance_m));
  }
  // Shipped designs, targets around the outer shell: the status is reachable exactly when the
  // stored posture is within the limits and its errors within the tolerances.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  for (const auto& rel : shippedDesigns()) {
    const Model dm = loadDesign(sourcePath(rel));
    IkWorkspace dws(dm);
    if (!dws.has_bound) continue;
    IkOptions po;
    po.max_starts = 8;
    for (int k = 0; k < 30; ++k) {
      const Eigen::Vector3d a = dws.bound_axis.unitOrthogonal(), b = dws.bound_axis.cross(a);
      const double phi = 6.283185307 * u(rng);
      PoseTask t = positionTask(Eigen::Vector3d::Zero());
      t.p_WT = dws.bound_p0 + 0.05 * dws.bound_axis +
               (dws.reach_radius + 1.5e-3 * u(rng)) * (std::cos(phi) * a + std::sin(phi) * b);
      const IkResult r = solvePose(dm, dws, t, po, k);
      bool within_limits = true;
      for (int i = 0; i < dm.dof(); ++i)
        within_limits &= r.q[i] >= dm.joints[i].limits.q_min && r.q[i] <= dm.joints[i].limits.q_max;
      const bool within = within_limits && r.position_error_m <= po.position_tolerance_m &&
                          r.orientation_error_rad <= po.orientation_tolerance_rad;
      INFO(dm.name << " target " << k);
      CHECK(r.reachable() == within);
    }
  }
}
