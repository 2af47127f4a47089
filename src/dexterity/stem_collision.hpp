#pragma once
// The collision checks of a stem map's cells (docs/dexterity.md, "Collisions"), with the
// collision model and the collision-aware solve of src/collision (the reach stage's).
#include "collision/collision.hpp"
#include "dexterity/dexterity_map.hpp"

namespace armstudy::dexterity {

// The collision check of a cell's postures (collision maps): the optimised posture when it is
// clear, else the plain one as the optimised (a descent that ended in contact falls back to its
// start), else the cell is reached only in collision: status SelfCollision / ObstacleCollision
// and the closest pair at the plain posture. Without collisions: status Reachable.
void settleCollision(const Model& model, KinematicsWorkspace& ws,
                     collision::CollisionWorkspace* cws, const StemCollision& col, CellResult& r);

// A chained cell's plain posture (r.q_plain, on the pose) in collision is replaced by the
// collision-aware solve's (collision::solvePoseCollisionAware: H_c descended in the null space
// with the tool on the pose, then seeded restarts), polished onto the pose by the exact solve
// (options.exactSolveOptions()); unchanged when that finds no collision-free posture
// (settleCollision then gives the verdict). Requires options.collisionFor(model).enabled().
void escapeCollision(const Model& model, KinematicsWorkspace& ws, IkWorkspace& ik_ws,
                     collision::CollisionWorkspace& cws, const DexterityOptions& options,
                     const StemGrid::Cell& cell, std::uint64_t cell_id, CellResult& r);

}  // namespace armstudy::dexterity
