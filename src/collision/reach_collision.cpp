#include "collision/reach_collision.hpp"

#include <cmath>
#include <random>

namespace armstudy::collision {

std::string CollisionReachOptions::validate() const {
  if (!(clearance_m >= 0) || !std::isfinite(clearance_m)) return "clearance must be a finite length >= 0";
  if (escape_attempts < 0 || escape_attempts > 1000) return "escape_attempts must lie in 0..1000";
  return "";
}

CollisionReachResult solvePoseCollisionAware(const Model& model, IkWorkspace& ws, CollisionWorkspace& cws,
                                             const IkTarget& target, const IkOptions& ik_options,
                                             const CollisionReachOptions& options, std::uint64_t pose_id,
                                             std::span<const Obstacle> obstacles,
                                             const JointVector* warm_start) {
  CollisionReachResult out;
  // The smallest distance at q and the pair attaining it.
  auto check = [&](const JointVector& q, double& d_min, std::string& pair, int& self_index) {
    forwardKinematics(model, ws.kin, q);
    collisionDistances(model, ws.kin, obstacles, cws);
    const double ds = minSelfDistance(cws), de = minEnvironmentDistance(cws);
    d_min = std::min(ds, de);
    self_index = -1;
    if (ds <= de && cws.closest_self >= 0) {
      pair = pairName(model, cws.self[cws.closest_self], false);
      self_index = cws.closest_self;
    } else if (cws.closest_env >= 0)
      pair = pairName(model, cws.env[cws.closest_env], true, obstacles);
  };
  out.ik = solvePose(model, ws, target, ik_options, pose_id, warm_start);
  out.attempts = 1;
  if (!out.ik.reachable()) return out;
  std::string pair;
  int self_index = -1;
  check(out.ik.q, out.min_distance_m, pair, self_index);
  if (out.min_distance_m > options.clearance_m) return out;
  // Escape: other solutions of the same pose (the redundancy), from other deterministic seeds.
  const IkResult first = out.ik;
  const double first_d = out.min_distance_m;
  const std::string first_pair = pair;
  const int first_self_index = self_index;
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
    if (!r.reachable()) continue;
    double d = 0;
    std::string p;
    int pi = -1;
    check(r.q, d, p, pi);
    if (d > options.clearance_m) {
      out.ik = r;
      out.min_distance_m = d;
      return out;
    }
  }
  out.ik = first;
  out.ik.status = ReachStatus::SelfCollision;
  out.min_distance_m = first_d;
  out.colliding_pair = first_pair;
  out.colliding_self_pair = first_self_index;
  return out;
}

}  // namespace armstudy::collision
