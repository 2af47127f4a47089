// Kinematics against independent oracles: central finite differences for every Jacobian and
// dJ/dq, orocos-kdl for forward kinematics and the geometric Jacobian, and hand-computed poses.
#include "kinematics/kinematics.hpp"

#include <catch2/catch.hpp>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "io/design_io.hpp"
#include "kdl_support.hpp"
#include "test_support.hpp"

using armstudy::test::toKdl;
using armstudy::test::toKdlChain;

using namespace armstudy;
using namespace armstudy::test;

namespace {

Eigen::Matrix<double, 6, 1> poseError(const KinematicsWorkspace& a, const KinematicsWorkspace& b) {
  // translation difference and rotation difference as angle-axis vector (R_b^T R_a)
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = a.p_WT - b.p_WT;
  const Eigen::AngleAxisd aa(a.R_WT * b.R_WT.transpose());
  e.tail<3>() = aa.angle() * aa.axis();
  return e;
}

}  // namespace

TEST_CASE("forward kinematics and Jacobian agree with orocos-kdl on random configurations",
          "[kinematics][oracle]") {
  std::mt19937_64 rng(42);
  for (const auto& rel : shippedDesigns()) {
    Model m = loadDesign(sourcePath(rel));
    m.base = PoseXYZABG{0.1, -0.2, 0.05, 0.1, -0.2, 0.3};  // a non-trivial base placement too
    m.finalize();
    KinematicsWorkspace ws(m);
    const KDL::Chain chain = toKdlChain(m);
    KDL::ChainFkSolverPos_recursive fk(chain);
    KDL::ChainJntToJacSolver jac(chain);
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::VectorXd q = randomConfiguration(m, rng);
      forwardKinematicsAndJacobian(m, ws, q);
      KDL::JntArray qk(m.dof());
      for (int i = 0; i < m.dof(); ++i) qk(i) = q[i];
      KDL::Frame F;
      REQUIRE(fk.JntToCart(qk, F) >= 0);
      KDL::Jacobian Jk(m.dof());
      REQUIRE(jac.JntToJac(qk, Jk) >= 0);
      for (int r = 0; r < 3; ++r) {
        CHECK(std::abs(ws.p_WT[r] - F.p(r)) < kOracleTolerance);
        for (int c = 0; c < 3; ++c) CHECK(std::abs(ws.R_WT(r, c) - F.M(r, c)) < kOracleTolerance);
      }
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < m.dof(); ++c)
          CHECK(std::abs(ws.J_W_tcp(r, c) - Jk(r, c)) < kOracleTolerance);
    }
  }
}

TEST_CASE("geometric TCP Jacobian matches central finite differences", "[kinematics][fd]") {
  std::mt19937_64 rng(7);
  for (const auto& rel : shippedDesigns()) {
    const Model m = loadDesign(sourcePath(rel));
    KinematicsWorkspace ws(m), wp(m), wm(m);
    for (int trial = 0; trial < 50; ++trial) {
      const Eigen::VectorXd q = randomConfiguration(m, rng);
      forwardKinematicsAndJacobian(m, ws, q);
      for (int i = 0; i < m.dof(); ++i) {
        Eigen::VectorXd qp = q, qm = q;
        qp[i] += kFdStep;
        qm[i] -= kFdStep;
        forwardKinematics(m, wp, qp);
        forwardKinematics(m, wm, qm);
        const Eigen::Matrix<double, 6, 1> fd = poseError(wp, wm) / (2 * kFdStep);
        CHECK((fd - ws.J_W_tcp.col(i)).norm() < kFdTolerance);
      }
    }
  }
}

TEST_CASE("dJ/dq_i matches central finite differences of the Jacobian", "[kinematics][fd]") {
  std::mt19937_64 rng(11);
  for (const auto& rel : shippedDesigns()) {
    const Model m = loadDesign(sourcePath(rel));
    const int n = m.dof();
    KinematicsWorkspace ws(m), wp(m), wm(m);
    Eigen::MatrixXd dJ(6, n);
    for (int trial = 0; trial < 30; ++trial) {
      const Eigen::VectorXd q = randomConfiguration(m, rng);
      forwardKinematicsAndJacobian(m, ws, q);
      for (int i = 0; i < n; ++i) {
        tcpJacobianDerivative(m, ws, i, dJ);
        Eigen::VectorXd qp = q, qm = q;
        qp[i] += kFdStep;
        qm[i] -= kFdStep;
        forwardKinematicsAndJacobian(m, wp, qp);
        forwardKinematicsAndJacobian(m, wm, qm);
        const Eigen::MatrixXd fd = (wp.J_W_tcp - wm.J_W_tcp) / (2 * kFdStep);
        CHECK((fd - dJ).cwiseAbs().maxCoeff() < kFdTolerance);
      }
    }
  }
}

TEST_CASE("point Jacobian of a point on a link matches finite differences", "[kinematics][fd]") {
  std::mt19937_64 rng(5);
  const Model m = loadDesign(sourcePath("designs/final_prototype_9dof.toml"));
  KinematicsWorkspace ws(m), wp(m), wm(m);
  Eigen::MatrixXd J(6, m.dof());
  const Eigen::Vector3d p_link(0.05, -0.02, 0.1);  // a point fixed in link 4's frame
  const int link = 4;
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd q = randomConfiguration(m, rng);
    forwardKinematics(m, ws, q);
    pointJacobian(m, ws, link, ws.p_WF[link] + ws.R_WF[link] * p_link, J);
    for (int i = 0; i < m.dof(); ++i) {
      Eigen::VectorXd qp = q, qm = q;
      qp[i] += kFdStep;
      qm[i] -= kFdStep;
      forwardKinematics(m, wp, qp);
      forwardKinematics(m, wm, qm);
      const Eigen::Vector3d fd =
          ((wp.p_WF[link] + wp.R_WF[link] * p_link) - (wm.p_WF[link] + wm.R_WF[link] * p_link)) /
          (2 * kFdStep);
      CHECK((fd - J.col(i).head<3>()).norm() < kFdTolerance);
    }
  }
}

TEST_CASE("analytic Jacobian (eq. 5.9-5.11) matches finite differences of Cardan angles",
          "[kinematics][fd]") {
  std::mt19937_64 rng(3);
  for (const auto& rel : shippedDesigns()) {
    const Model m = loadDesign(sourcePath(rel));
    KinematicsWorkspace ws(m), wp(m), wm(m);
    const TaskSpace task = TaskSpace::fullPose();
    Eigen::MatrixXd Jw(6, m.dof());
    int checked = 0;
    for (int trial = 0; trial < 40; ++trial) {
      const Eigen::VectorXd q = randomConfiguration(m, rng);
      forwardKinematicsAndJacobian(m, ws, q);
      const TaskVector w = tcpTaskVector(ws);
      if (std::abs(std::cos(w.w[4])) < 0.05 || std::abs(w.w[3]) > 3.0 || std::abs(w.w[5]) > 3.0)
        continue;  // stay clear of the singularity and the +/-pi wrap for differencing
      REQUIRE(analyticJacobian(ws, task, Jw));
      for (int i = 0; i < m.dof(); ++i) {
        Eigen::VectorXd qp = q, qm = q;
        qp[i] += kFdStep;
        qm[i] -= kFdStep;
        forwardKinematics(m, wp, qp);
        forwardKinematics(m, wm, qm);
        const Eigen::Matrix<double, 6, 1> fd =
            (tcpTaskVector(wp).w - tcpTaskVector(wm).w) / (2 * kFdStep);
        CHECK((fd - Jw.col(i)).norm() < kFdTolerance * (1 + fd.norm()));
      }
      ++checked;
    }
    CHECK(checked > 10);
  }
}

TEST_CASE("hand-checked poses of the first prototype (Table 3.1)", "[kinematics]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_6dof.toml"));
  KinematicsWorkspace ws(m);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
  forwardKinematics(m, ws, q);
  // q = 0: frame 2 at (0, 0.1, 0.65) rotated Rz(pi/2); links 4, 5, 6 point along +y; the TCP
  // (0.2 m along x6, an assumption of the design file) at (0, 1.03, 1.0); frame 6 has R = Rz(pi/2)
  // and the TCP axes are turned by gamma = -pi/2 (spray axis = TCP y), so R_WT = I.
  CHECK((ws.p_WF[1] - Eigen::Vector3d(0, 0.1, 0.65)).norm() < kHandCheckTolerance);
  CHECK((ws.p_WF[3] - Eigen::Vector3d(0, 0.33, 0.80)).norm() < kHandCheckTolerance);
  CHECK((ws.p_WF[4] - Eigen::Vector3d(0, 0.73, 1.0)).norm() < kHandCheckTolerance);
  CHECK((ws.p_WT - Eigen::Vector3d(0, 1.03, 1.0)).norm() < kHandCheckTolerance);
  const Eigen::Matrix3d Rz90 = rotationFromCardan(0, 0, M_PI / 2);
  CHECK((ws.R_WF[5] - Rz90).norm() < kHandCheckTolerance);
  CHECK((ws.R_WT - Eigen::Matrix3d::Identity()).norm() < kHandCheckTolerance);
  // Lift up 0.2 m and turn joint 2 by +90 deg: everything after frame 2 turns about the world z.
  q[0] = 0.2;
  q[1] = M_PI / 2;
  forwardKinematics(m, ws, q);
  CHECK((ws.p_WT - Eigen::Vector3d(-0.93, 0.1, 1.2)).norm() < kHandCheckTolerance);
}

TEST_CASE("printed Cardan angles give the rotation back inside the singular band", "[kinematics]") {
  // |cos(beta)| from just inside the band (1e-6) down to the rounding of the entries, both signs
  // of beta: cardanForDisplay reproduces R to rounding; cardanFromRotation's gamma = 0 is off by
  // about |cos(beta)|.
  for (const double sign : {1.0, -1.0})
    for (const double cb : {5e-7, 4.4e-8, 1e-9, 1e-11, 1e-13, 0.0}) {
      const double a = 0.7, g = -1.1, b = sign * (M_PI / 2 - cb);
      const Eigen::Matrix3d R = rotationFromCardan(a, b, g);
      const CardanAngles c = cardanForDisplay(R);
      INFO("beta " << b << ", |cos beta| about " << cb);
      CHECK(c.singular);
      CHECK((rotationFromCardan(c.alpha, c.beta, c.gamma) - R).cwiseAbs().maxCoeff() <
            kHandCheckTolerance);
      if (cb >= 1e-9) {
        CHECK(std::abs(c.alpha - a) < 1e-6);  // the split of R's own angles, to cond. 1/cos(beta)
        CHECK(std::abs(c.gamma - g) < 1e-6);
      }
    }
}

TEST_CASE("Cardan angles round-trip and report the representation singularity", "[kinematics]") {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-3.0, 3.0), ub(-1.5, 1.5);
  for (int k = 0; k < 1000; ++k) {
    const double a = u(rng), b = ub(rng), g = u(rng);
    const CardanAngles c = cardanFromRotation(rotationFromCardan(a, b, g));
    CHECK_FALSE(c.singular);
    CHECK(std::abs(c.alpha - a) < 1e-9);
    CHECK(std::abs(c.beta - b) < 1e-9);
    CHECK(std::abs(c.gamma - g) < 1e-9);
  }
  const CardanAngles s = cardanFromRotation(rotationFromCardan(0.3, M_PI / 2, 0.2));
  CHECK(s.singular);
  CHECK(std::isfinite(s.alpha));
  CHECK(std::isfinite(s.gamma));
  Eigen::Matrix3d T;
  CHECK_FALSE(cardanRateMatrix(0.1, M_PI / 2, T));

  // analyticJacobian refuses at the singularity rather than returning Inf/NaN.
  const Model m = loadDesign(sourcePath("designs/final_prototype_9dof.toml"));
  KinematicsWorkspace ws(m);
  ws.R_WT = rotationFromCardan(0.3, M_PI / 2, 0.2);
  ws.J_W_tcp.setOnes(6, m.dof());
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, m.dof());
  CHECK_FALSE(analyticJacobian(ws, TaskSpace::fullPose(), J));
  CHECK(J.isZero());
  Eigen::MatrixXd Jp(3, m.dof());
  CHECK(analyticJacobian(ws, TaskSpace::position(), Jp));  // position-only never singular
}

TEST_CASE("task spaces parse and reject unknown components", "[kinematics]") {
  TaskSpace t;
  std::string err;
  REQUIRE(parseTaskSpace("x,y,z,alpha,gamma", t, err));
  CHECK(t.dim() == 5);
  CHECK(t.toString() == TaskSpace::spraying().toString());
  CHECK(parseTaskSpace("full", t, err));
  CHECK(t.dim() == 6);
  CHECK_FALSE(parseTaskSpace("x,y,roll", t, err));
  CHECK(err.find("roll") != std::string::npos);
  CHECK_FALSE(parseTaskSpace("x,x", t, err));
}
