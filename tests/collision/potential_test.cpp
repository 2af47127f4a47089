// Collision potential H_c (thesis eq. 5.53-5.57): boundary and transition conditions of the
// piecewise polynomial, and the witness-point gradient against central finite differences.
#include "collision/potential.hpp"

#include <catch2/catch.hpp>
#include <random>

#include "collision/collision_model.hpp"
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
  const double hm = pairPotential(d1 - kLimitStep_m, o, &gm),
               hp = pairPotential(d1 + kLimitStep_m, o, &gp);
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

namespace {
// Obstacles beside the arm at configuration q (of any design; its base may sit anywhere): a
// sphere beside the middle of the arm and a vertical stem beside the TCP.
std::vector<Obstacle> obstaclesNearArm(const Model& m, KinematicsWorkspace& kin,
                                       const Eigen::VectorXd& q) {
  forwardKinematics(m, kin, q);
  const int mid = m.dof() / 2;
  const Eigen::Vector3d c = 0.5 * (kin.p_WF[mid] + kin.p_WT) + Eigen::Vector3d(0.15, 0.1, 0.0);
  const Eigen::Vector3d s = kin.p_WT + Eigen::Vector3d(0.0, 0.12, 0.0);
  return {sphereObstacle("sphere", c, 0.08), capsuleObstacle("stem", s - Eigen::Vector3d(0, 0, 1),
                                                             s + Eigen::Vector3d(0, 0, 1), 0.02)};
}

// Core of a volume in W, written out from the frames of forward kinematics.
Core coreInWorld(const Model& m, const KinematicsWorkspace& kin, const CollisionVolume& v) {
  const Eigen::Matrix3d R = v.link < 0 ? Eigen::Matrix3d(m.T_WB.linear()) : kin.R_WF[v.link];
  const Eigen::Vector3d p = v.link < 0 ? Eigen::Vector3d(m.T_WB.translation()) : kin.p_WF[v.link];
  Core c;
  c.n = static_cast<int>(v.type);
  for (int i = 0; i < c.n; ++i) c.p[i] = p + R * v.p_L[i];
  return c;
}

// Agreement of the workspace's H_c with the brute-force sum (same distances up to rounding).
constexpr double kBruteForceH = 1e-10;
}  // namespace

TEST_CASE("H_c gradient through witness-point Jacobians matches central differences") {
  for (const auto& design : test::shippedDesigns()) {
    const Model m = loadDesign(test::sourcePath(design));
    KinematicsWorkspace kin(m);
    CollisionWorkspace ws(m);
    CollisionPotentialOptions o;
    o.safety_distance_m = 0.25;  // wide, so many pairs are active
    CollisionQueryOptions qo;
    qo.cutoff_m = o.safety_distance_m;
    for (const bool with_obstacles : {false, true}) {
      std::vector<Obstacle> obstacles;  // placed per sample, fixed while differencing
      auto H = [&](const Eigen::VectorXd& q, Eigen::VectorXd& g) {
        forwardKinematics(m, kin, q);
        collisionDistances(m, kin, obstacles, ws, qo);
        return collisionPotential(m, kin, ws, o, g);
      };
      std::mt19937_64 rng(17);
      Eigen::VectorXd g(m.dof()), dummy(m.dof());
      int active = 0, env_active = 0;
      for (int s = 0; s < 60; ++s) {
        const Eigen::VectorXd q = test::randomConfiguration(m, rng);
        if (with_obstacles) obstacles = obstaclesNearArm(m, kin, q);
        const double h = H(q, g);
        if (h == 0) continue;
        ++active;
        env_active += ws.num_near_env > 0;
        for (int i = 0; i < m.dof(); ++i) {
          Eigen::VectorXd qp = q, qm = q;
          qp[i] += test::kFdStep;
          qm[i] -= test::kFdStep;
          const double fd = (H(qp, dummy) - H(qm, dummy)) / (2 * test::kFdStep);
          INFO(design << (with_obstacles ? " with" : " without") << " obstacles, sample " << s
                      << " joint " << i << " H=" << h);
          CHECK(g[i] == Approx(fd).margin(kArmFdRelative * std::max(1.0, std::abs(g[i]))));
        }
      }
      INFO(design << (with_obstacles ? " with" : " without") << " obstacles");
      CHECK(active > 30);
      if (with_obstacles) CHECK(env_active == active);
    }
  }
}

TEST_CASE("H_c is the sum over every SSV pair closer than d_a (brute force over the volumes)") {
  for (const auto& design : test::shippedDesigns()) {
    const Model m = loadDesign(test::sourcePath(design));
    KinematicsWorkspace kin(m);
    CollisionWorkspace ws(m);
    CollisionPotentialOptions o;
    o.safety_distance_m = 0.2;
    CollisionQueryOptions qo;
    qo.cutoff_m = o.safety_distance_m;
    const auto& vols = m.collision.volumes;
    std::mt19937_64 rng(29);
    Eigen::VectorXd g(m.dof());
    int multi = 0;  // configurations where some body pair has two volume pairs below d_a
    for (int s = 0; s < 100; ++s) {
      const Eigen::VectorXd q = test::randomConfiguration(m, rng);
      const std::vector<Obstacle> obstacles = obstaclesNearArm(m, kin, q);
      collisionDistances(m, kin, obstacles, ws, qo);
      const double h = collisionPotential(m, kin, ws, o, g);
      // Every pair of volumes on two bodies that are checked against each other, and every
      // volume against every obstacle, with the plain SSV distance routine.
      double h_self = 0, h_env = 0;
      int n_self = 0, n_env = 0;
      SsvDistance w;
      for (std::size_t i = 0; i < vols.size(); ++i) {
        for (std::size_t j = i + 1; j < vols.size(); ++j) {
          if (!isCollisionPair(m, std::min(vols[i].link, vols[j].link),
                               std::max(vols[i].link, vols[j].link)))
            continue;
          ssvDistance(coreInWorld(m, kin, vols[i]), vols[i].radius_m, coreInWorld(m, kin, vols[j]),
                      vols[j].radius_m, w);
          if (w.distance_m >= o.safety_distance_m) continue;
          h_self += pairPotential(w.distance_m, o);
          ++n_self;
        }
        for (const Obstacle& ob : obstacles) {
          Core oc;
          oc.n = static_cast<int>(ob.type);
          for (int k = 0; k < oc.n; ++k) oc.p[k] = ob.p_W[k];
          ssvDistance(coreInWorld(m, kin, vols[i]), vols[i].radius_m, oc, ob.radius_m, w);
          if (w.distance_m >= o.safety_distance_m) continue;
          h_env += pairPotential(w.distance_m, o);
          ++n_env;
        }
      }
      INFO(design << " sample " << s);
      CHECK(h == Approx(h_self + h_env).margin(kBruteForceH));
      CHECK(ws.num_near_self == n_self);
      CHECK(ws.num_near_env == n_env);
      CollisionPotentialOptions only_self = o, only_env = o;
      only_self.environment = false;
      only_env.self = false;
      CHECK(collisionPotential(m, kin, ws, only_self, g) == Approx(h_self).margin(kBruteForceH));
      CHECK(collisionPotential(m, kin, ws, only_env, g) == Approx(h_env).margin(kBruteForceH));
      int self_pairs_below = 0;
      for (int i = 0; i < ws.num_self; ++i)
        self_pairs_below += ws.self[i].exact && ws.self[i].distance_m < o.safety_distance_m;
      multi += ws.num_near_self > self_pairs_below;
    }
    INFO(design);
    CHECK(multi > 10);  // the sum over SSV pairs differs from one term per body pair
  }
}
