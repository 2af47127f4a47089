#include "dexterity/stem_collision.hpp"

#include <algorithm>
#include <limits>

#include "collision/reach_collision.hpp"

namespace armstudy::dexterity {

namespace {

// The smallest checked distance at q and the pair attaining it (indexed like
// collision::collisionPairNames(model, col.obstacles, col.self)).
struct Contact {
  double d_min = std::numeric_limits<double>::infinity();
  int pair = -1;
  bool obstacle = false;
};
Contact contactAt(const Model& model, KinematicsWorkspace& ws, collision::CollisionWorkspace& cws,
                  const StemCollision& col, const JointVector& q) {
  forwardKinematics(model, ws, q);
  collision::CollisionQueryOptions query;
  query.self = col.self;
  query.environment = !col.obstacles.empty();
  collision::collisionDistances(model, ws, col.obstacles, cws, query);
  const double ds =
      col.self ? collision::minSelfDistance(cws) : std::numeric_limits<double>::infinity();
  const double de = collision::minEnvironmentDistance(cws);
  Contact c;
  c.d_min = std::min(ds, de);
  if (ds <= de && cws.closest_self >= 0) {
    c.pair = cws.closest_self;
  } else if (cws.closest_env >= 0) {
    c.pair = (col.self ? cws.num_self : 0) + cws.closest_env;
    c.obstacle = true;
  }
  return c;
}

}  // namespace

void settleCollision(const Model& model, KinematicsWorkspace& ws,
                     collision::CollisionWorkspace* cws, const StemCollision& col, CellResult& r) {
  if (!r.reachable) return;
  r.status = ReachStatus::Reachable;
  if (!cws || !col.enabled()) return;
  Contact c = contactAt(model, ws, *cws, col, r.q_opt);
  r.min_distance_m = c.d_min;
  if (c.d_min > col.clearance_m) return;
  if (r.q_opt != r.q_plain) {
    const Contact p = contactAt(model, ws, *cws, col, r.q_plain);
    if (p.d_min > col.clearance_m) {  // the descent ended in contact: keep its start
      r.q_opt = r.q_plain;            // (its measures follow it: measureCell)
      r.H_opt = r.H_plain;
      r.optimised = false;
      r.min_distance_m = p.d_min;
      return;
    }
    c = p;
  }
  r.reachable = false;
  r.status = c.obstacle ? ReachStatus::ObstacleCollision : ReachStatus::SelfCollision;
  r.colliding_pair = c.pair;
  r.min_distance_m = c.d_min;
}

void escapeCollision(const Model& model, KinematicsWorkspace& ws, IkWorkspace& ik_ws,
                     collision::CollisionWorkspace& cws, const DexterityOptions& options,
                     const StemGrid::Cell& cell, std::uint64_t cell_id, CellResult& r) {
  const StemCollision& col = options.collision;
  if (contactAt(model, ws, cws, col, r.q_plain).d_min > col.clearance_m) return;
  IkOptions io;
  io.position_tolerance_m = options.position_tolerance_m;
  io.orientation_tolerance_rad = options.orientation_tolerance_rad;
  io.max_starts = options.cold_starts;
  io.classify_failures = false;
  collision::CollisionReachOptions co;
  co.clearance_m = col.clearance_m;
  co.self = col.self;
  const collision::CollisionReachResult cr = collision::solvePoseCollisionAware(
      model, ik_ws, cws, cell.target, io, co, cell_id, col.obstacles, &r.q_plain);
  r.starts += cr.attempts;
  if (!cr.ik.reachable()) return;
  const IkResult s =
      solvePose(model, ik_ws, cell.target, options.exactSolveOptions(), cell_id, &cr.ik.q);
  if (!(s.position_error_m <= options.position_tolerance_m &&
        s.orientation_error_rad <= options.orientation_tolerance_rad))
    return;
  r.q_plain = s.q;
  r.position_error_m = s.position_error_m;
  r.orientation_error_rad = s.orientation_error_rad;
}

}  // namespace armstudy::dexterity
