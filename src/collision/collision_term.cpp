#include "collision/collision_term.hpp"

#include "common/errors.hpp"

namespace armstudy::collision {

CollisionTerm::CollisionTerm(CollisionPotentialOptions options, std::vector<Obstacle> obstacles)
    : options_(options), obstacles_(std::move(obstacles)) {
  ARMSTUDY_CHECK(options_.validate().empty(), "CollisionTerm: " + options_.validate());
  ARMSTUDY_CHECK(static_cast<int>(obstacles_.size()) <= kMaxObstacles,
                 "CollisionTerm: too many obstacles");
}

void CollisionTerm::lendWorkspace(ik::ObjectiveContext& ctx, CollisionWorkspace& cws) const {
  ctx.term_scratch[this] = std::shared_ptr<void>(std::shared_ptr<void>{}, &cws);  // not owned
}

double CollisionTerm::evaluate(ik::ObjectiveContext& ctx, JointVector* grad) const {
  std::shared_ptr<void>& slot = ctx.term_scratch[this];
  if (!slot) slot = std::make_shared<CollisionWorkspace>(ctx.model());
  CollisionWorkspace& cws = *static_cast<CollisionWorkspace*>(slot.get());
  CollisionQueryOptions q;
  q.cutoff_m = options_.safety_distance_m;
  q.self = options_.self;
  q.environment = options_.environment;
  collisionDistances(ctx.model(), ctx.ws(), obstacles_, cws, q);
  JointVector local(ctx.dof());
  JointVector& g = grad ? *grad : local;
  g.resize(ctx.dof());
  return collisionPotential(ctx.model(), ctx.ws(), cws, options_, g);
}

}  // namespace armstudy::collision
