// Collision pairs and distances of whole arm models: against a brute-force evaluation over all
// volume pairs, the shipped models' enclosure of the kinematic skeleton, obstacles, cutoff bounds
// and the no-heap guarantee of the per-configuration path.
#include "collision/collision.hpp"

#include <atomic>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <new>
#include <random>

#include "alloc_counter.hpp"
#include "collision/collision_model.hpp"
#include "collision/potential.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using armstudy::test::g_allocations;  // tests/alloc_counter.hpp replaces the allocation functions

using namespace armstudy;
using namespace armstudy::collision;
using Eigen::Vector3d;

namespace {

// Brute force and workspace evaluate the same formulas on the same volumes: rounding only.
constexpr double kSameFormula_m = 1e-12;
// A witness point on an SSV surface: |distance to core - radius| up to rounding.
constexpr double kOnSurface_m = 1e-9;
constexpr int kConfigurations = 300;

Core worldCore(const Model& m, const KinematicsWorkspace& kin, const CollisionVolume& v) {
  Eigen::Matrix3d R = v.link < 0 ? Eigen::Matrix3d(m.T_WB.linear()) : kin.R_WF[v.link];
  Vector3d p = v.link < 0 ? Vector3d(m.T_WB.translation()) : kin.p_WF[v.link];
  Core c;
  c.n = static_cast<int>(v.type);
  for (int i = 0; i < c.n; ++i) c.p[i] = p + R * v.p_L[i];
  return c;
}

// Minimum over every volume pair of two bodies, no culling.
double bruteForce(const Model& m, const KinematicsWorkspace& kin, int a, int b) {
  double best = std::numeric_limits<double>::infinity();
  SsvDistance w;
  for (const auto& va : m.collision.volumes)
    for (const auto& vb : m.collision.volumes) {
      if (va.link != a || vb.link != b) continue;
      ssvDistance(worldCore(m, kin, va), va.radius_m, worldCore(m, kin, vb), vb.radius_m, w);
      best = std::min(best, w.distance_m);
    }
  return best;
}

double pointToCore(const Vector3d& x, const Core& c) {
  Core p;
  p.n = 1;
  p.p[0] = x;
  Vector3d a, b;
  return std::sqrt(squaredDistanceCores(p, c, a, b));
}

}  // namespace

TEST_CASE("collision pairs are all body pairs except neighbours and the allowed pairs") {
  for (const auto& path : test::shippedDesigns()) {
    const Model m = loadDesign(test::sourcePath(path));
    INFO(m.name);
    REQUIRE_FALSE(m.collision.empty());
    CollisionWorkspace ws(m);
    int expected = 0;
    for (int a = -1; a < m.dof(); ++a)
      for (int b = a + 1; b < m.dof(); ++b) {
        bool allowed = false;
        for (const auto& p : m.collision.allowed_pairs) allowed |= (p[0] == a && p[1] == b);
        const bool checked = b - a > 1 && !allowed;
        CHECK(isCollisionPair(m, a, b) == checked);
        CHECK(isCollisionPair(m, b, a) == checked);
        expected += checked ? 1 : 0;  // every body of the shipped models carries volumes
      }
    CHECK(ws.num_self == expected);
  }
}

TEST_CASE("pair distances equal a brute-force minimum over all volume pairs") {
  std::mt19937_64 rng(7);
  for (const auto& path : test::shippedDesigns()) {
    const Model m = loadDesign(test::sourcePath(path));
    INFO(m.name);
    KinematicsWorkspace kin(m);
    CollisionWorkspace ws(m);
    for (int s = 0; s < kConfigurations; ++s) {
      forwardKinematics(m, kin, test::randomConfiguration(m, rng));
      collisionDistances(m, kin, {}, ws);
      double min_d = std::numeric_limits<double>::infinity();
      for (int i = 0; i < ws.num_self; ++i) {
        const PairDistance& p = ws.self[i];
        REQUIRE(p.exact);
        REQUIRE(p.distance_m ==
                Approx(bruteForce(m, kin, p.link_a, p.link_b)).margin(kSameFormula_m));
        min_d = std::min(min_d, p.distance_m);
        // Witnesses lie on the surfaces of the reported volumes.
        const auto& va = m.collision.volumes[p.volume_a];
        const auto& vb = m.collision.volumes[p.volume_b];
        REQUIRE(va.link == p.link_a);
        REQUIRE(vb.link == p.link_b);
        if (!p.w.n.isZero()) {
          REQUIRE(std::abs(pointToCore(p.w.p_a, worldCore(m, kin, va)) - va.radius_m) <=
                  kOnSurface_m);
          REQUIRE(std::abs(pointToCore(p.w.p_b, worldCore(m, kin, vb)) - vb.radius_m) <=
                  kOnSurface_m);
          REQUIRE((p.w.p_b - p.w.p_a).dot(p.w.n) == Approx(p.distance_m).margin(kSameFormula_m));
        }
      }
      REQUIRE(minSelfDistance(ws) == min_d);
    }
  }
}

TEST_CASE("a cutoff reports exact distances below it and valid lower bounds above it") {
  const Model m = loadDesign(test::sourcePath("designs/final_prototype_9dof.toml"));
  KinematicsWorkspace kin(m);
  CollisionWorkspace ws(m), ref(m);
  std::mt19937_64 rng(11);
  CollisionQueryOptions o;
  o.cutoff_m = 0.1;
  int bounded = 0;
  for (int s = 0; s < kConfigurations; ++s) {
    forwardKinematics(m, kin, test::randomConfiguration(m, rng));
    collisionDistances(m, kin, {}, ws, o);
    collisionDistances(m, kin, {}, ref);
    for (int i = 0; i < ws.num_self; ++i) {
      const double truth = ref.self[i].distance_m;
      if (truth < o.cutoff_m) {
        REQUIRE(ws.self[i].exact);
      }
      if (ws.self[i].exact) {
        REQUIRE(ws.self[i].distance_m == truth);
      } else {
        ++bounded;
        REQUIRE(ws.self[i].distance_m >= o.cutoff_m);
        REQUIRE(ws.self[i].distance_m <= truth);
      }
    }
  }
  CHECK(bounded > 0);
}

TEST_CASE(
    "the shipped collision models enclose the kinematic skeleton and have no permanent contacts") {
  std::mt19937_64 rng(3);
  for (const auto& path : test::shippedDesigns()) {
    const Model m = loadDesign(test::sourcePath(path));
    INFO(m.name);
    // Skeleton of body i in frame i: from its origin to the next joint's origin (or the TCP).
    for (int i = 0; i < m.dof(); ++i) {
      const Vector3d end = i + 1 < m.dof() ? Vector3d(m.joints[i + 1].T_PJ0.translation())
                                           : Vector3d(m.T_NT.translation());
      for (int k = 0; k <= 20; ++k) {
        const Vector3d x = end * (k / 20.0);
        bool inside = false;
        for (const auto& v : m.collision.volumes) {
          if (v.link != i) continue;
          Core c;
          c.n = static_cast<int>(v.type);
          for (int j = 0; j < c.n; ++j) c.p[j] = v.p_L[j];
          inside |= pointToCore(x, c) <= v.radius_m;
        }
        // Or inside the housing of its own joint, a volume of the parent body (the 6-DoF nozzle
        // starts at the j6 housing's surface): inside it at every joint angle sampled.
        if (!inside && i > 0 && m.joints[i].type == JointType::Revolute) {
          bool all = true;
          for (double q : {-M_PI, -1.0, 0.0, 1.0, 2.0}) {
            const Vector3d xp = m.joints[i].T_PJ0 * (Eigen::AngleAxisd(q, Vector3d::UnitZ()) * x);
            bool in = false;
            for (const auto& v : m.collision.volumes) {
              if (v.link != i - 1) continue;
              Core c;
              c.n = static_cast<int>(v.type);
              for (int j = 0; j < c.n; ++j) c.p[j] = v.p_L[j];
              in |= pointToCore(xp, c) <= v.radius_m;
            }
            all &= in;
          }
          inside = all;
        }
        INFO("body " << m.joints[i].name << " skeleton point " << x.transpose());
        CHECK(inside);
      }
    }
    // Every checked pair is free somewhere: structural contacts must be [[collision_allowed]].
    KinematicsWorkspace kin(m);
    CollisionWorkspace ws(m);
    std::vector<bool> free(ws.num_self, false);
    for (int s = 0; s < 2000; ++s) {
      forwardKinematics(
          m, kin, s == 0 ? Eigen::VectorXd::Zero(m.dof()) : test::randomConfiguration(m, rng));
      collisionDistances(m, kin, {}, ws);
      if (s == 0) {
        INFO("home configuration q = 0");
        CHECK(minSelfDistance(ws) > 0);
      }
      for (int i = 0; i < ws.num_self; ++i)
        if (ws.self[i].distance_m > 0) free[i] = true;
    }
    for (int i = 0; i < ws.num_self; ++i) {
      INFO(pairName(m, ws.self[i], false));
      CHECK(free[i]);
    }
  }
}

TEST_CASE("environment obstacles are checked against every body in the task frame") {
  const Model m = loadDesign(test::sourcePath("designs/final_prototype_7dof.toml"));
  KinematicsWorkspace kin(m);
  CollisionWorkspace ws(m);
  forwardKinematics(m, kin, Eigen::VectorXd::Zero(m.dof()));
  // A sphere of radius 0.1 m centred on the TCP overlaps the end-effector (radius 0.07 m around
  // the segment ending at the TCP): distance -0.17 m. A capsule stem 1 m away in x is clear.
  const std::vector<Obstacle> obstacles = {
      sphereObstacle("fruit", kin.p_WT, 0.1),
      capsuleObstacle("stem", kin.p_WT + Vector3d(1, 0, -1), kin.p_WT + Vector3d(1, 0, 1), 0.02)};
  collisionDistances(m, kin, obstacles, ws);
  REQUIRE(ws.num_env == 2 * (m.dof() + 1));
  const PairDistance& c = ws.env[ws.closest_env];
  CHECK(c.link_a == m.dof() - 1);
  CHECK(c.link_b == 0);
  CHECK(c.distance_m == Approx(-0.17).margin(kSameFormula_m));
  CHECK(pairName(m, c, true, obstacles) == "j9-obstacle:fruit");
  // Brute force for every body-obstacle pair.
  for (int i = 0; i < ws.num_env; ++i) {
    const PairDistance& p = ws.env[i];
    const Obstacle& o = obstacles[p.link_b];
    Core oc;
    oc.n = static_cast<int>(o.type);
    for (int k = 0; k < 3; ++k) oc.p[k] = o.p_W[k];
    double best = std::numeric_limits<double>::infinity();
    SsvDistance w;
    for (const auto& v : m.collision.volumes)
      if (v.link == p.link_a) {
        ssvDistance(worldCore(m, kin, v), v.radius_m, oc, o.radius_m, w);
        best = std::min(best, w.distance_m);
      }
    CHECK(p.distance_m == Approx(best).margin(kSameFormula_m));
  }
  // Self pairs are unaffected by obstacles.
  CollisionWorkspace ws2(m);
  collisionDistances(m, kin, {}, ws2);
  CHECK(minSelfDistance(ws2) == minSelfDistance(ws));
}

TEST_CASE("the per-configuration path does not allocate") {
  const Model m = loadDesign(test::sourcePath("designs/final_prototype_9dof.toml"));
  KinematicsWorkspace kin(m);
  CollisionWorkspace ws(m);
  const std::vector<Obstacle> obstacles = {sphereObstacle("s", Vector3d(0.3, 1.0, 0.6), 0.1)};
  CollisionPotentialOptions po;
  po.safety_distance_m = 0.3;
  CollisionQueryOptions qo;
  qo.cutoff_m = po.safety_distance_m;
  Eigen::VectorXd grad(m.dof());
  std::mt19937_64 rng(5);
  std::vector<Eigen::VectorXd> qs;
  for (int s = 0; s < 50; ++s) qs.push_back(test::randomConfiguration(m, rng));
  const long before = g_allocations.load();
  double sum = 0;
  for (const auto& q : qs) {
    forwardKinematics(m, kin, q);
    collisionDistances(m, kin, obstacles, ws, qo);
    sum += collisionPotential(m, kin, ws, po, grad);
  }
  const long after = g_allocations.load();
  CHECK(after == before);
  CHECK(sum > 0);  // the potential was active, so the gradient path ran
}
