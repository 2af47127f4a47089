#include "collision/reach_collision.hpp"

#include <cmath>
#include <memory>
#include <random>

#include "collision/collision_term.hpp"
#include "ik/nullspace.hpp"

namespace armstudy::collision {

std::string CollisionReachOptions::validate() const {
  if (!(clearance_m >= 0) || !std::isfinite(clearance_m))
    return "clearance must be a finite length >= 0";
  if (escape_attempts < 0 || escape_attempts > 1000) return "escape_attempts must lie in 0..1000";
  if (!(escape_safety_distance_m >= 0) || !std::isfinite(escape_safety_distance_m))
    return "escape safety distance must be a finite length >= 0";
  return "";
}

std::vector<std::string> collisionPairNames(const Model& model, std::span<const Obstacle> obstacles,
                                            bool self) {
  const CollisionWorkspace cws(model);
  std::vector<std::string> names;
  if (self)
    for (int p = 0; p < cws.num_self; ++p) names.push_back(pairName(model, cws.self[p], false));
  // The order of collisionDistances' environment pairs: per obstacle, every body with volumes.
  for (int o = 0; o < static_cast<int>(obstacles.size()); ++o)
    for (int b = 0; b <= model.dof(); ++b) {
      if (cws.body_begin[b] == cws.body_begin[b + 1]) continue;
      PairDistance p;
      p.link_a = b - 1;
      p.link_b = o;
      names.push_back(pairName(model, p, true, obstacles));
    }
  return names;
}

namespace {

// The smallest checked distance at a configuration and the pair attaining it.
struct Check {
  double d_min = 0, d_obstacle = 0;
  PairDistance pair;  // the closest pair (named only when the pose ends in collision)
  int pair_index = -1;
  bool obstacle = false;  // the closest pair is a body-obstacle pair
};

// The task the null-space descent holds: the reach task itself (the tool axis normalised) for a
// position, tool-axis or full-pose task. A literal selection of Cardan angles (e.g. "x,y,z,gamma")
// has no exact null space of its own; there the full pose of the colliding solution q is held (its
// orientation already meets the selected angles), so the descent explores the redundancy that
// remains with the free angle fixed. False when the position is not fully selected.
bool nullspaceTask(const Model& model, KinematicsWorkspace& kin, const PoseTask& t,
                   const JointVector& q, PoseTask& out) {
  if (!t.allPositionSelected()) return false;
  out = t;
  if (t.kind == PoseTaskKind::PositionAxis) {
    out.axis_W = t.axis_W.normalized();
  } else if (t.kind == PoseTaskKind::CardanAngles) {
    forwardKinematics(model, kin, q);
    out = fullPoseTask(t.p_WT, kin.R_WT);
  }
  return true;
}

// From a colliding solution q: put the tool exactly on the pose, then descend H_c (safety
// distance escape_safety_distance_m + clearance) in the null space of the task with the tool held
// there (ik::optimiseAtPose). The result judged by the reach solver's tolerances and limits
// (status Reachable or OutOfReach; its collision distances are the caller's to check).
// The descent and the exact-pose solve's iterations count into `out`.
IkResult nullspaceEscape(const Model& model, IkWorkspace& ws, CollisionWorkspace& cws,
                         const PoseTask& target, const IkOptions& ik_options,
                         const CollisionReachOptions& options, std::span<const Obstacle> obstacles,
                         const JointVector& q, CollisionReachResult& out) {
  PoseTask pose_task;
  if (!nullspaceTask(model, ws.kin, target, q, pose_task)) return IkResult{};
  CollisionPotentialOptions po;
  po.safety_distance_m = options.escape_safety_distance_m + options.clearance_m;
  po.self = options.self;
  po.environment = !obstacles.empty();
  ik::WeightedObjective h_c;
  const auto term = std::make_shared<CollisionTerm>(
      po, std::vector<Obstacle>(obstacles.begin(), obstacles.end()));
  h_c.add(1.0, term);
  ik::ObjectiveContext ctx(model, ws.kin);
  term->lendWorkspace(ctx, cws);
  const Eigen::VectorXd w_inv = Eigen::VectorXd::Ones(model.dof());
  // The reach solution meets the tolerances; the null-space descent needs the pose exactly.
  const IkResult on = solvePose(model, ws, pose_task, IkOptions::exactPose(), 0, &q);
  out.iterations += on.iterations;
  ik::NullspaceOptions no;
  no.max_iterations = defaults::kCollisionEscapeIterations;
  const ik::NullspaceResult r =
      ik::optimiseAtPose(model, ws.kin, ctx, pose_task, on.q, h_c, w_inv, no);
  out.escape.add(r);
  if (r.status == ik::NullspaceStatus::NotOnPose) return IkResult{};
  IkResult found = evaluateSolution(model, ws, target, ik_options, r.q, ReachStatus::OutOfReach);
  found.starts = 0;
  return found;
}

}  // namespace

CollisionReachResult solvePoseCollisionAware(
    const Model& model, IkWorkspace& ws, CollisionWorkspace& cws, const PoseTask& target,
    const IkOptions& ik_options, const CollisionReachOptions& options, std::uint64_t pose_id,
    std::span<const Obstacle> obstacles, const JointVector* warm_start, const IkResult* solved) {
  CollisionReachResult out;
  CollisionQueryOptions query;
  query.self = options.self;
  query.environment = !obstacles.empty();
  auto check = [&](const JointVector& q) {
    forwardKinematics(model, ws.kin, q);
    collisionDistances(model, ws.kin, obstacles, cws, query);
    Check c;
    const double ds = options.self ? minSelfDistance(cws) : std::numeric_limits<double>::infinity();
    const double de = minEnvironmentDistance(cws);
    c.d_min = std::min(ds, de);
    c.d_obstacle = de;
    if (ds <= de && cws.closest_self >= 0) {
      c.pair = cws.self[cws.closest_self];
      c.pair_index = cws.closest_self;
    } else if (cws.closest_env >= 0) {
      c.pair = cws.env[cws.closest_env];
      c.pair_index = (options.self ? cws.num_self : 0) + cws.closest_env;
      c.obstacle = true;
    }
    return c;
  };
  out.ik = solved ? *solved : solvePose(model, ws, target, ik_options, pose_id, warm_start);
  out.attempts = 1;
  out.iterations = solved ? 0 : out.ik.iterations;
  if (!out.ik.reachable()) return out;
  const Check first_check = check(out.ik.q);
  out.min_distance_m = first_check.d_min;
  out.obstacle_distance_m = first_check.d_obstacle;
  if (first_check.d_min > options.clearance_m) return out;
  const IkResult first = out.ik;
  auto accept = [&](IkResult r, const Check& c, bool by_descent) {
    r.starts += first.starts;
    out.ik = r;
    out.min_distance_m = c.d_min;
    out.obstacle_distance_m = c.d_obstacle;
    out.nullspace_escape = by_descent;
    out.escape.changed += by_descent ? 1 : 0;
    return out;
  };
  // Step 1: descend H_c in the null space from the colliding solution (thesis section 5.4.3).
  if (options.escape_safety_distance_m > 0) {
    const IkResult found =
        nullspaceEscape(model, ws, cws, target, ik_options, options, obstacles, first.q, out);
    if (found.reachable()) {
      const Check c = check(found.q);
      if (c.d_min > options.clearance_m) return accept(found, c, true);
    }
  }
  // Step 2: other solutions of the same pose (the redundancy), from other deterministic seeds.
  for (int k = 1; k <= options.escape_attempts; ++k) {
    // Each escape starts from its own random configuration (deterministic per pose and attempt);
    // the solver's own start sequence begins at the middle of the limits and would find the
    // same posture again.
    const std::uint64_t id = pose_id ^ (0x9E3779B97F4A7C15ull * static_cast<std::uint64_t>(k));
    std::mt19937_64 rng(id);
    JointVector start(model.dof());
    for (int i = 0; i < model.dof(); ++i)
      start[i] = std::uniform_real_distribution<double>(model.joints[i].limits.q_min,
                                                        model.joints[i].limits.q_max)(rng);
    IkResult r = solvePose(model, ws, target, ik_options, id, &start);
    ++out.attempts;
    out.iterations += r.iterations;
    if (!r.reachable()) continue;
    const Check c = check(r.q);
    if (c.d_min > options.clearance_m) return accept(r, c, false);
  }
  out.ik = first;
  out.ik.status =
      first_check.obstacle ? ReachStatus::ObstacleCollision : ReachStatus::SelfCollision;
  out.colliding_pair = pairName(model, first_check.pair, first_check.obstacle, obstacles);
  out.colliding_pair_index = first_check.pair_index;
  return out;
}

}  // namespace armstudy::collision
