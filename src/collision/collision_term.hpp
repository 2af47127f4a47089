#pragma once
// H_c (thesis eq. 5.53-5.57) as a term of the null-space IK's weighted objective (eq. 5.51):
// self-collision pairs and, optionally, environment obstacles fixed in the task frame.
#include <vector>

#include "collision/collision.hpp"
#include "collision/potential.hpp"
#include "ik/objectives.hpp"

namespace armstudy::collision {

class CollisionTerm final : public ik::ObjectiveTerm {
 public:
  // `options` must validate; the obstacles are copied (the term is immutable and shared).
  CollisionTerm(CollisionPotentialOptions options, std::vector<Obstacle> obstacles = {});
  std::string name() const override { return "collision"; }
  // H_c and dH_c/dq at the prepared configuration. The per-thread CollisionWorkspace lives in
  // ctx.term_scratch (allocated on the first evaluation in a context, never after).
  double evaluate(ik::ObjectiveContext& ctx, JointVector* grad) const override;
  // Lets the term evaluate in the caller's per-thread workspace `cws` (of the same model; it must
  // outlive ctx) instead of allocating its own in a fresh context. Every query recomputes all
  // of the workspace's per-query fields, so sharing it never changes a result.
  void lendWorkspace(ik::ObjectiveContext& ctx, CollisionWorkspace& cws) const;
  const std::vector<Obstacle>& obstacles() const { return obstacles_; }

 private:
  CollisionPotentialOptions options_;
  std::vector<Obstacle> obstacles_;
};

}  // namespace armstudy::collision
