// H_c as a null-space objective term (thesis section 5.4.3): its gradient through the objective
// interface against central differences, and thesis Fig. 5.13 (a straight TCP line past a sphere).
#include <catch2/catch.hpp>
#include <random>

#include "collision/collision_term.hpp"
#include "ik/nullspace.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::collision;
using namespace armstudy::ik;

namespace {
// Fig. 5.13 acceptance: explicit Euler at 1 ms with a strong null-space motion keeps the TCP
// within 1.5 mm of the line (the undisturbed run tracks to 1e-6 m).
constexpr double kFig513Tracking_m = 1.5e-3;
constexpr double kTermFdRelative = 1e-6;
}  // namespace

TEST_CASE(
    "the collision term's gradient through the objective interface matches central differences") {
  const Model m = loadDesign(test::sourcePath("designs/final_prototype_7dof.toml"));
  KinematicsWorkspace ws(m);
  ObjectiveContext ctx(m, ws);
  CollisionPotentialOptions o;
  o.safety_distance_m = 0.3;
  WeightedObjective h;
  h.add(2.0, std::make_shared<CollisionTerm>(o, std::vector<Obstacle>{sphereObstacle(
                                                    "s", Eigen::Vector3d(0.1, 0.9, 0.5), 0.1)}));
  auto eval = [&](const Eigen::VectorXd& q, JointVector* g) {
    forwardKinematicsAndJacobian(m, ws, q);
    ctx.prepare(q);
    return h.evaluate(ctx, g);
  };
  std::mt19937_64 rng(23);
  int active = 0;
  for (int s = 0; s < 40; ++s) {
    const Eigen::VectorXd q = test::randomConfiguration(m, rng);
    JointVector g(m.dof());
    if (eval(q, &g) == 0) continue;
    ++active;
    for (int i = 0; i < m.dof(); ++i) {
      Eigen::VectorXd qp = q, qm = q;
      qp[i] += test::kFdStep;
      qm[i] -= test::kFdStep;
      const double fd = (eval(qp, nullptr) - eval(qm, nullptr)) / (2 * test::kFdStep);
      CHECK(g[i] == Approx(fd).margin(kTermFdRelative * std::max(1.0, std::abs(g[i]))));
    }
  }
  CHECK(active > 20);
}

TEST_CASE(
    "thesis Fig. 5.13: with H_c the arm passes a spherical obstacle while the TCP tracks the line",
    "[collision][nullspace][thesis]") {
  // 7-DoF final prototype, position task (redundancy 4). The TCP moves 0.6 m along +x in 4 s.
  // The sphere (radius 0.06 m) sits beside the upper arm's mid-motion position of the
  // undisturbed run (minimum-norm joint velocities), 0.16 m ahead in x and 0.08 m out in y from
  // the middle of link j3, far from the TCP path.
  const Model m = loadDesign(test::sourcePath("designs/final_prototype_7dof.toml"));
  KinematicsWorkspace ws(m);
  ObjectiveContext ctx(m, ws);
  Eigen::VectorXd q0(7);
  q0 << 0.0, 0.2, 0.3, 1.2, 0.0, 0.6, 0.0;
  forwardKinematics(m, ws, q0);
  const Eigen::Vector3d p0 = ws.p_WT, p1 = p0 + Eigen::Vector3d(0.6, 0, 0);
  const double T = 4.0;
  const Reference line = [&](double t) {
    ReferencePoint r;
    r.pose.kind = PoseTaskKind::Position;
    r.pose.p_WT = p0 + (p1 - p0) * (t / T);
    r.v_W = (p1 - p0) / T;
    return r;
  };
  TrackingOptions o;
  o.redundancy.alpha = 10.0;
  const auto off = trackReference(m, ws, line, q0, T, nullptr, nullptr, o);
  REQUIRE(off.status == TrackingStatus::Completed);
  forwardKinematics(m, ws, off.samples[off.samples.size() / 2].q);
  const Eigen::Vector3d centre = 0.5 * (ws.p_WF[2] + ws.p_WF[3]) + Eigen::Vector3d(0.16, 0.08, 0.0);
  const std::vector<Obstacle> obstacles = {sphereObstacle("sphere", centre, 0.06)};

  CollisionWorkspace cws(m);
  struct Run {
    double min_distance = 1e9, max_error = 0, start_distance = 0;
    std::string closest;
  };
  auto examine = [&](const TrackingSummary& s) {
    Run r;
    for (std::size_t k = 0; k < s.samples.size(); ++k) {
      forwardKinematics(m, ws, s.samples[k].q);
      collisionDistances(m, ws, obstacles, cws);
      const double d = minEnvironmentDistance(cws);
      if (k == 0) r.start_distance = d;
      if (d < r.min_distance) {
        r.min_distance = d;
        r.closest = pairName(m, cws.env[cws.closest_env], true, obstacles);
      }
      r.max_error = std::max(r.max_error, s.samples[k].position_error_m);
    }
    return r;
  };
  const Run without = examine(off);
  INFO("without H_c: min distance " << without.min_distance << " (" << without.closest << ")");
  CHECK(without.start_distance > 0.1);  // the sphere is clear at the start ...
  CHECK(without.min_distance < -0.05);  // ... and the upper arm runs into it
  CHECK(without.closest == "j3-obstacle:sphere");

  CollisionPotentialOptions po;
  po.safety_distance_m = 0.15;
  WeightedObjective hc;
  hc.add(3.0, std::make_shared<CollisionTerm>(po, obstacles));
  const auto on = trackReference(m, ws, line, q0, T, &hc, &ctx, o);
  REQUIRE(on.status == TrackingStatus::Completed);
  const Run with = examine(on);
  INFO("with H_c: min distance " << with.min_distance << " (" << with.closest << "), max TCP error "
                                 << with.max_error);
  CHECK(with.min_distance > 0);               // clear of the sphere throughout
  CHECK(with.max_error < kFig513Tracking_m);  // while the TCP stays on the line
  forwardKinematics(m, ws, on.samples.back().q);
  CHECK((ws.p_WT - p1).norm() < kFig513Tracking_m);
}
