#pragma once
// Collision-aware reachability of one pose (issue 5): reachable and collision-free, reachable
// only in collision (and which pair), or unreachable. The redundancy is used to escape a
// collision: when the first solution collides, further IK solves from deterministic random
// starts (seeded by pose id and attempt) look for a collision-free configuration of the same pose
// before giving up.
#include <span>
#include <string>

#include "collision/collision.hpp"
#include "ik/reach_solver.hpp"

namespace armstudy::collision {

struct CollisionReachOptions {
  double clearance_m = 0;   // a configuration is collision-free when every distance > clearance
  int escape_attempts = defaults::kCollisionEscapeAttempts;  // extra IK solves after a collision
  std::string validate() const;
};

struct CollisionReachResult {
  IkResult ik;                     // status SelfCollision when reachable only in collision
  double min_distance_m = 0;       // smallest self/obstacle distance at ik.q (reachable poses)
  std::string colliding_pair;      // e.g. "j3-j7" or "j4-obstacle:stem" (status SelfCollision)
  int colliding_self_pair = -1;    // index into cws.self when the colliding pair is a self pair
  int attempts = 0;                // IK solves used (1 + escapes)
};

// Requires cws built from the same model. Deterministic for a given pose_id.
CollisionReachResult solvePoseCollisionAware(const Model& model, IkWorkspace& ws, CollisionWorkspace& cws,
                                             const IkTarget& target, const IkOptions& ik_options,
                                             const CollisionReachOptions& options, std::uint64_t pose_id,
                                             std::span<const Obstacle> obstacles = {},
                                             const JointVector* warm_start = nullptr);

}  // namespace armstudy::collision
