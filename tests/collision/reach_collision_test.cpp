// Collision-aware reachability: reachable and collision-free (escaping a colliding first solution
// through the redundancy), reachable only in collision (with the pair), unreachable.
#include "collision/reach_collision.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "ik/nullspace.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::collision;

TEST_CASE(
    "collision-aware reachability classifies poses and escapes collisions through the redundancy") {
  const Model m = loadDesign(test::sourcePath("designs/final_prototype_7dof.toml"));
  IkWorkspace ws(m);
  CollisionWorkspace cws(m);
  IkOptions ik;
  CollisionReachOptions co;
  REQUIRE(co.validate().empty());
  // A position target (redundancy 4) at the TCP of a known collision-free configuration.
  Eigen::VectorXd q_true(7);
  q_true << 0.0, 0.2, 0.3, 1.2, 0.0, 0.6, 0.0;
  forwardKinematics(m, ws.kin, q_true);
  const PoseTask target = positionTask(ws.kin.p_WT);
  const Eigen::Vector3d p_elbow = 0.5 * (ws.kin.p_WF[2] + ws.kin.p_WF[3]);

  // No obstacles: reachable and collision-free.
  const auto free = solvePoseCollisionAware(m, ws, cws, target, ik, co, 1);
  REQUIRE(free.ik.status == ReachStatus::Reachable);
  CHECK(free.min_distance_m > 0);

  // A sphere on the first solution's upper arm: the solver finds another arm posture.
  forwardKinematics(m, ws.kin, free.ik.q);
  const std::vector<Obstacle> on_arm = {
      sphereObstacle("ball", 0.5 * (ws.kin.p_WF[2] + ws.kin.p_WF[3]), 0.05)};
  const auto escaped = solvePoseCollisionAware(m, ws, cws, target, ik, co, 1, on_arm);
  INFO("attempts " << escaped.attempts << ", distance " << escaped.min_distance_m);
  CHECK(escaped.ik.status == ReachStatus::Reachable);
  CHECK(escaped.nullspace_escape);  // H_c descended in the null space: no further IK solve
  CHECK(escaped.attempts == 1);
  CHECK(escaped.min_distance_m > 0);
  // Without the null-space descent, other IK starts find another posture.
  CollisionReachOptions restarts_only = co;
  restarts_only.escape_safety_distance_m = 0;
  const auto restarted = solvePoseCollisionAware(m, ws, cws, target, ik, restarts_only, 1, on_arm);
  CHECK(restarted.ik.status == ReachStatus::Reachable);
  CHECK_FALSE(restarted.nullspace_escape);
  CHECK(restarted.attempts > 1);
  for (const auto* r : {&escaped, &restarted}) {
    forwardKinematics(m, ws.kin, r->ik.q);
    CHECK((ws.kin.p_WT - target.p_WT).norm() <= ik.position_tolerance_m);
    CHECK(ik::withinLimits(m, r->ik.q));
    collisionDistances(m, ws.kin, on_arm, cws);  // independent re-check of the returned q
    CHECK(minEnvironmentDistance(cws) > 0);
    CHECK(minSelfDistance(cws) > 0);
    CHECK(std::min(minEnvironmentDistance(cws), minSelfDistance(cws)) == r->min_distance_m);
  }
  (void)p_elbow;

  // A sphere around the target itself: reachable only in collision, and the pair is named.
  const std::vector<Obstacle> at_tcp = {sphereObstacle("fruit", target.p_WT, 0.04)};
  const auto hit = solvePoseCollisionAware(m, ws, cws, target, ik, co, 1, at_tcp);
  CHECK(hit.ik.status == ReachStatus::ObstacleCollision);
  CHECK(hit.min_distance_m < 0);
  CHECK(hit.colliding_pair == "j9-obstacle:fruit");
  CHECK(hit.attempts == 1 + co.escape_attempts);
  // Deterministic for a pose id.
  const auto again = solvePoseCollisionAware(m, ws, cws, target, ik, co, 1, at_tcp);
  CHECK(again.ik.q == hit.ik.q);

  // Far away: unreachable, no collision check.
  PoseTask far = target;
  far.p_WT = Eigen::Vector3d(5, 5, 5);
  const auto out = solvePoseCollisionAware(m, ws, cws, far, ik, co, 1);
  CHECK(out.ik.status == ReachStatus::OutOfReach);
  CHECK(out.attempts == 1);
}

TEST_CASE(
    "a collision-aware solve given the solution the caller already has returns what the whole "
    "solve returns, on poses that are free, escaped and in collision",
    "[collision]") {
  const Model m = loadDesign(test::sourcePath("designs/final_prototype_7dof.toml"));
  IkWorkspace ws(m);
  CollisionWorkspace cws(m);
  IkOptions ik;
  ik.max_starts = 1;
  CollisionReachOptions co;
  co.escape_attempts = 0;
  std::mt19937_64 rng(7);
  int kinds[3] = {0, 0, 0};  // reachable without escape, reachable by the descent, in collision
  for (int t = 0; t < 60; ++t) {
    // A pose the arm reaches, an obstacle on its upper arm or around the tool for some of them.
    const Eigen::VectorXd q_true = test::randomConfiguration(m, rng);
    forwardKinematics(m, ws.kin, q_true);
    const PoseTask target = positionTask(ws.kin.p_WT);
    std::vector<Obstacle> obstacles;
    if (t % 3 == 1)
      obstacles.push_back(sphereObstacle("arm", 0.5 * (ws.kin.p_WF[2] + ws.kin.p_WF[3]), 0.05));
    if (t % 3 == 2) obstacles.push_back(sphereObstacle("tool", ws.kin.p_WT, 0.04));
    const JointVector start = test::randomConfiguration(m, rng);
    const auto whole = solvePoseCollisionAware(m, ws, cws, target, ik, co, t, obstacles, &start);
    const IkResult solved = solvePose(m, ws, target, ik, t, &start);
    const auto given =
        solvePoseCollisionAware(m, ws, cws, target, ik, co, t, obstacles, &start, &solved);
    INFO("pose " << t);
    CHECK(given.ik.status == whole.ik.status);
    CHECK(given.ik.q == whole.ik.q);
    CHECK(given.ik.manipulability == whole.ik.manipulability);
    CHECK(given.nullspace_escape == whole.nullspace_escape);
    CHECK(given.colliding_pair_index == whole.colliding_pair_index);
    CHECK((given.min_distance_m == whole.min_distance_m ||
           (std::isnan(given.min_distance_m) && std::isnan(whole.min_distance_m))));
    if (whole.ik.reachable()) ++kinds[whole.nullspace_escape ? 1 : 0];
    if (whole.ik.status == ReachStatus::ObstacleCollision ||
        whole.ik.status == ReachStatus::SelfCollision)
      ++kinds[2];
  }
  // The scenario: each kind of outcome happened.
  INFO("free " << kinds[0] << ", escaped " << kinds[1] << ", in collision " << kinds[2]);
  CHECK(kinds[0] > 0);
  CHECK(kinds[1] > 0);
  CHECK(kinds[2] > 0);
}
