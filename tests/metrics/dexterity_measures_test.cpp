// Dexterity measures against closed forms (planar 2R arm of thesis Fig. 5.14) and against a second
// computation (determinant, explicit inverse) on the shipped designs.
#include "metrics/dexterity_measures.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>

#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::metrics;
using namespace armstudy::test;

namespace {
constexpr double kMeasureTolerance = 1e-10;
}

TEST_CASE("planar 2R arm: manipulability l1 l2 |sin q2| (Yoshikawa closed form)",
          "[metrics][closed_form]") {
  const double l1 = 0.7, l2 = 0.4;
  for (double q1 : {0.0, 0.3, -1.2})
    for (double q2 : {0.2, 1.0, 2.5, -0.7}) {
      Eigen::Matrix2d J;
      J << -l1 * std::sin(q1) - l2 * std::sin(q1 + q2), -l2 * std::sin(q1 + q2),
          l1 * std::cos(q1) + l2 * std::cos(q1 + q2), l2 * std::cos(q1 + q2);
      const auto d = computeMeasures(J, Eigen::Vector2d(1, 0));
      CHECK(std::abs(d.manipulability - l1 * l2 * std::abs(std::sin(q2))) < kMeasureTolerance);
      // beta along x: (e_x^T (J J^T)^-1 e_x)^-1/2, eq. (5.60), via the explicit inverse.
      const Eigen::Matrix2d Ainv = (J * J.transpose()).inverse();
      CHECK(std::abs(d.transmission - 1.0 / std::sqrt(Ainv(0, 0))) < kMeasureTolerance);
      CHECK(std::abs(d.condition * d.inverse_condition - 1.0) < kMeasureTolerance);
    }
  // Stretched arm: singular, motion along the arm impossible (Fig. 5.14a).
  Eigen::Matrix2d J;
  J << 0, 0, l1 + l2, l2;
  const auto d = computeMeasures(J, Eigen::Vector2d(1, 0));
  CHECK(d.manipulability == 0.0);
  CHECK(d.transmission == 0.0);
  CHECK(std::isinf(d.condition));
  CHECK(d.inverse_condition < kMeasureTolerance);
}

TEST_CASE("measures of the shipped designs agree with determinant and inverse",
          "[metrics][oracle]") {
  std::mt19937_64 rng(17);
  for (const auto& rel : shippedDesigns()) {
    const Model m = loadDesign(sourcePath(rel));
    KinematicsWorkspace ws(m);
    for (int trial = 0; trial < 30; ++trial) {
      forwardKinematicsAndJacobian(m, ws, randomConfiguration(m, rng));
      const Eigen::Vector3d u = Eigen::Vector3d::Random().normalized();
      const Eigen::MatrixXd JT = ws.J_W_tcp.topRows<3>();
      const Eigen::Matrix3d A = JT * JT.transpose();
      const auto d = tcpMeasures(ws, MeasureSpace::Translational, u, true);
      CHECK(std::abs(d.manipulability - std::sqrt(A.determinant())) < kMeasureTolerance);
      CHECK(std::abs(d.transmission - 1.0 / std::sqrt(u.dot(A.inverse() * u))) <
            1e-8 * std::max(1.0, d.transmission));
      // Ellipsoid: axes diag(lengths^2) axes^T = J_T J_T^T, axes orthonormal and right-handed.
      const Ellipsoid e = translationalEllipsoid(ws);
      const Eigen::Matrix3d T =
          e.axes_W * e.lengths.array().square().matrix().asDiagonal() * e.axes_W.transpose();
      CHECK((T - A).norm() < kMeasureTolerance);
      CHECK((e.axes_W.transpose() * e.axes_W - Eigen::Matrix3d::Identity()).norm() <
            kMeasureTolerance);
      CHECK(e.axes_W.determinant() > 0);
      CHECK(std::abs(e.lengths.prod() - d.manipulability) < kMeasureTolerance);
      CHECK(std::abs(e.lengths.minCoeff() - d.sigma_min) < kMeasureTolerance);
    }
  }
}

TEST_CASE("normalisation across a map makes the best value 1", "[metrics]") {
  std::vector<double> v = {0.2, 0.5, 0.9, 0.4};
  const std::vector<unsigned char> valid = {1, 1, 0, 1};
  const double best = normaliseToBest(v, valid, -1.0);
  CHECK(best == 0.5);
  CHECK(v[0] == 0.4);
  CHECK(v[1] == 1.0);
  CHECK(v[2] == -1.0);
  CHECK(v[3] == 0.8);
}
