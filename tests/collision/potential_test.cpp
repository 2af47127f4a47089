// Collision potential H_c (thesis eq. 5.53-5.57): boundary and transition conditions of the
// piecewise polynomial, and the witness-point gradient against central finite differences.
#include <catch2/catch.hpp>
#include <random>

#include "collision/potential.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::collision;

namespace {
// One-sided limits at a breakpoint, evaluated this far from it [m].
constexpr double kLimitStep_m = 1e-9;
// Value/slope/curvature limits agree to this (the polynomials are O(1) on a 0.1 m scale).
constexpr double kContinuity = 1e-6;
// Gradient vs central differences on the arm (relative to max(1, |g|)).
constexpr double kArmFdRelative = 1e-6;

double curvature(double d, const CollisionPotentialOptions& o) {
  const double h = 1e-5;
  double g1, g0;
  pairPotential(d + h, o, &g1);
  pairPotential(d - h, o, &g0);
  return (g1 - g0) / (2 * h);
}
}  // namespace

TEST_CASE("pair potential meets the boundary and transition conditions of eq. (5.57)") {
  CollisionPotentialOptions o;
  o.safety_distance_m = 0.1;
  o.blend_t = 0.4;
  o.h0 = 2.5;
  REQUIRE(o.validate().empty());
  const double da = o.safety_distance_m, d1 = o.blend_t * da;
  double g = 0;
  CHECK(pairPotential(0, o) == Approx(o.h0).epsilon(1e-14));
  CHECK(pairPotential(da, o, &g) == 0);
  CHECK(g == 0);
  CHECK(pairPotential(2 * da, o) == 0);
  // Zero value, slope and curvature approaching d_a from below.
  double gl = 0;
  CHECK(std::abs(pairPotential(da - kLimitStep_m, o, &gl)) <= kContinuity);
  CHECK(std::abs(gl) <= kContinuity);
  CHECK(std::abs(curvature(da - 2e-5, o)) <= 1e-3 * std::abs(curvature(d1, o)));
  // Continuous value, slope and curvature at t d_a.
  double gm = 0, gp = 0;
  const double hm = pairPotential(d1 - kLimitStep_m, o, &gm), hp = pairPotential(d1 + kLimitStep_m, o, &gp);
  CHECK(hm == Approx(hp).margin(kContinuity));
  CHECK(gm == Approx(gp).margin(kContinuity));
  CHECK(curvature(d1 - 2e-5, o) == Approx(curvature(d1 + 2e-5, o)).epsilon(1e-3));
  // Monotone: decreasing in d everywhere below d_a, including penetration d < 0.
  double prev = pairPotential(-0.05, o);
  for (double d = -0.05; d < da; d += 1e-3) {
    const double h = pairPotential(d, o);
    CHECK(h <= prev);
    prev = h;
  }
  // dH/dd against central differences across all three pieces.
  for (double d : {-0.03, 0.01, 0.039, 0.041, 0.07, 0.099}) {
    pairPotential(d, o, &g);
    const double fd = (pairPotential(d + test::kFdStep, o) - pairPotential(d - test::kFdStep, o)) /
                      (2 * test::kFdStep);
    CHECK(g == Approx(fd).margin(test::kFdTolerance * std::max(1.0, std::abs(g))));
  }
  CollisionPotentialOptions bad = o;
  bad.blend_t = 1;
  CHECK_FALSE(bad.validate().empty());
}

TEST_CASE("H_c gradient through witness-point Jacobians matches central differences") {
  const Model m = loadDesign(test::sourcePath("designs/final_prototype_9dof.toml"));
  KinematicsWorkspace kin(m);
  CollisionWorkspace ws(m);
  CollisionPotentialOptions o;
  o.safety_distance_m = 0.25;  // wide, so many pairs are active
  CollisionQueryOptions qo;
  qo.cutoff_m = o.safety_distance_m;
  const std::vector<Obstacle> obstacles = {
      sphereObstacle("sphere", Eigen::Vector3d(0.2, 1.0, 0.5), 0.12),
      capsuleObstacle("stem", Eigen::Vector3d(0.4, 1.2, 0), Eigen::Vector3d(0.4, 1.2, 2), 0.02)};
  auto H = [&](const Eigen::VectorXd& q, Eigen::VectorXd& g) {
    forwardKinematics(m, kin, q);
    collisionDistances(m, kin, obstacles, ws, qo);
    return collisionPotential(m, kin, ws, o, g);
  };
  std::mt19937_64 rng(17);
  Eigen::VectorXd g(m.dof()), dummy(m.dof());
  int active = 0;
  for (int s = 0; s < 60; ++s) {
    const Eigen::VectorXd q = test::randomConfiguration(m, rng);
    const double h = H(q, g);
    if (h == 0) continue;
    ++active;
    for (int i = 0; i < m.dof(); ++i) {
      Eigen::VectorXd qp = q, qm = q;
      qp[i] += test::kFdStep;
      qm[i] -= test::kFdStep;
      const double fd = (H(qp, dummy) - H(qm, dummy)) / (2 * test::kFdStep);
      INFO("sample " << s << " joint " << i << " H=" << h);
      CHECK(g[i] == Approx(fd).margin(kArmFdRelative * std::max(1.0, std::abs(g[i]))));
    }
  }
  CHECK(active > 30);
}
