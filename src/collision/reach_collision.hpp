#pragma once
// Collision-aware reachability of one pose: reachable and collision-free, reachable
// only in collision (and which pair: self-collision or an environment obstacle), or unreachable.
// The redundancy is used to escape a collision: when the first solution collides,
//  1. (position, full-pose and tool-axis tasks) the collision potential H_c (eq. 5.53-5.57) is
//     descended in the null space of the task from that solution, the tool held on the pose
//     (ik::optimiseAtPose, thesis section 5.4.3), which moves the links apart without leaving
//     the pose;
//  2. if that does not clear it, further IK solves from deterministic random starts (seeded by
//     pose id and attempt) look for another posture.
#include <span>
#include <string>
#include <vector>

#include "collision/collision.hpp"
#include "ik/nullspace.hpp"
#include "ik/reach_solver.hpp"

namespace armstudy::collision {

struct CollisionReachOptions {
  double clearance_m = 0;  // a configuration is collision-free when every distance > clearance
  int escape_attempts = defaults::kCollisionEscapeAttempts;  // extra IK solves after a collision
  bool self = true;  // check the design's self-collision pairs (obstacles: when given)
  // Null-space escape: H_c with this safety distance d_a (eq. 5.57); 0 disables step 1.
  double escape_safety_distance_m = defaults::kCollisionEscapeSafetyDistance_m;
  std::string validate() const;
};

struct CollisionReachResult {
  IkResult ik;  // status SelfCollision / ObstacleCollision when reachable only in collision
  double min_distance_m = 0;  // smallest checked distance at ik.q (reachable poses)
  double obstacle_distance_m =
      0;                       // smallest body-obstacle distance at ik.q (+inf without obstacles)
  std::string colliding_pair;  // e.g. "j3-j7" or "j4-obstacle:stem" (in collision)
  // Index of the colliding pair in collisionPairNames(model, obstacles): self pairs first
  // (cws.self order), then body-obstacle pairs (cws.env order); -1 when not in collision.
  int colliding_pair_index = -1;
  int attempts = 0;               // IK solves used (1 + escapes)
  bool nullspace_escape = false;  // the collision-free solution came from the null-space descent
  // The work behind it: the iterations of every pose solve it ran (the first one's unless the
  // caller passed it as `solved`, the escape's exact-pose solve, the restarts), and the H_c
  // null-space descent (one at most; `changed` when its posture was taken).
  int iterations = 0;
  ik::DescentTally escape;
};

// Requires cws built from the same model. Deterministic for a given pose_id. `solved`: the result
// of solvePose(model, ws, target, ik_options, pose_id, warm_start) when the caller has it already
// (then it is not solved again).
CollisionReachResult solvePoseCollisionAware(
    const Model& model, IkWorkspace& ws, CollisionWorkspace& cws, const PoseTask& target,
    const IkOptions& ik_options, const CollisionReachOptions& options, std::uint64_t pose_id,
    std::span<const Obstacle> obstacles = {}, const JointVector* warm_start = nullptr,
    const IkResult* solved = nullptr);

// Names of every pair a collision-aware solve can report, indexed like
// CollisionReachResult::colliding_pair_index: the self pairs (when `self`) then, for each
// obstacle, every body with volumes ("j4-obstacle:stem").
std::vector<std::string> collisionPairNames(const Model& model, std::span<const Obstacle> obstacles,
                                            bool self);

}  // namespace armstudy::collision
