#pragma once
// The dexterity stage (thesis section 3.2.1, Fig. 3.5, 3.6, 5.15): for each cell of a stem-centric
// grid, solve the pose ("plain" configuration), then optimise the redundancy in the null space
// ("optimised" configuration), and evaluate manipulability, transmission towards the stem,
// condition and ellipsoids for both.
//
// Work split: one z row (a circle around the stem) is one independent unit, solved in gamma order
// with warm starts from the previous cell; rows run in parallel (OpenMP) and their results do not
// depend on the thread count or schedule.
//
// A map value describes the design, not the solver's path (docs/dexterity.md, "How a map value is
// found"): the chained rows alone stay on the solution branch they started in, so after them
// searchDexterityMap (1) runs seeded multi-starts on a sub-grid of cells and (2) propagates
// better solutions to neighbouring cells (all eight directions, Jacobi rounds: every cell of a
// round reads only the previous round) until no cell improves; in collision maps (3) cells still
// reached only in collision get further random starts. Both steps are order-independent and
// bit-identical for any thread count.
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "collision/collision.hpp"
#include "dexterity/stem_grid.hpp"
#include "ik/nullspace.hpp"
#include "ik/objectives.hpp"
#include "ik/reach_solver.hpp"
#include "metrics/dexterity_measures.hpp"
#include "study/checkpoint.hpp"
#include "study/stage_designs.hpp"

namespace armstudy {
class UnitRunner;
}

namespace armstudy::dexterity {

// (study) Random starts per stem cell still reached only in collision after the map search
// ([dexterity.search] collision_starts; kept beside the stem-map settings it belongs to). Off by
// default: 8 per cell freed none of the cells in collision of the shipped stem maps (docs/
// dexterity.md "Known limits") and cost the row map 0.8x of a map without collisions.
inline constexpr int kMapCollisionStarts = 0;

// What a stem map checks at every posture it keeps (docs/dexterity.md, "Collisions"): the
// design's self-collision pairs and/or obstacles fixed in W (the stems of the row, the study's
// [[obstacle]]s). A posture collides when a checked distance is <= clearance_m.
struct StemCollision {
  bool self = false;
  std::vector<collision::Obstacle> obstacles;
  double clearance_m = 0;
  bool enabled() const { return self || !obstacles.empty(); }
};

// The null-space descent of the maps (docs/dexterity.md, "What is computed"): limited-memory BFGS
// directions in the null space (projected steepest descent with [dexterity.solver] quasi_newton =
// false, and for a descent that ended in contact), stopped by the projected gradient
// (kMapStationaryGradient) or the relative improvement.
ik::NullspaceOptions mapDescentOptions();

struct DexterityOptions {
  StemGrid grid;
  StageDesigns designs;  // [dexterity] designs and [dexterity.tool_axis] (study/stage_designs.hpp)
  // Collisions checked for designs with a collision model (collisionFor); a design without
  // volumes is evaluated without them.
  StemCollision collision;
  StemCollision collisionFor(const Model& model) const {
    return model.collision.empty() ? StemCollision{} : collision;
  }
  // The row sweep (docs/dexterity.md, "The row around the stem"): the map again with each entry's
  // collisions instead of `collision`, the neighbouring stems at row_sweep_spacing_m[k] (0: none).
  std::vector<StemCollision> row_sweep;
  std::vector<double> row_sweep_spacing_m;
  double row_spacing_m = -1;  // [dexterity.row]'s spacing (0: no neighbours; -1: no row)
  metrics::MeasureSpace measure_space = metrics::MeasureSpace::Translational;
  // Weights of eq. (5.51); finite and >= 0.
  double w_joint_limits = 0.0;
  double w_manipulability = 1.0;  // H_m1
  double w_transmission = 0.0;    // H_m2 along u
  // w_c H_c (eq. 5.53-5.57) over the checked pairs (collisionFor) with safety distance d_a; 0 or
  // a design without volumes: no term.
  double w_collision = 0.0;
  double collision_safety_distance_m = defaults::kCollisionSafetyDistance_m;
  double joint_limit_activation = defaults::kJointLimitActivation;
  bool fixed_direction = false;  // u from the study instead of TCP -> stem
  Eigen::Vector3d direction_W = Eigen::Vector3d::UnitY();
  std::vector<double> joint_weights;  // W of eq. (5.45a), empty = identity
  double position_tolerance_m = defaults::kPositionTolerance_m;
  double orientation_tolerance_rad = defaults::kOrientationTolerance_rad;
  int cold_starts = defaults::kColdStarts;
  // The exact pose solve (solvePose, WeightedNewton) of every start; its joint_weights are
  // `joint_weights` above (exactSolveOptions).
  IkOptions solve = IkOptions::exactPose();
  IkOptions exactSolveOptions() const;
  ik::NullspaceOptions nullspace = mapDescentOptions();
  bool ellipsoids = true;  // write .vtp ellipsoid glyph data
  // The map search after the chained rows (searchDexterityMap); seed_starts = 0 and
  // propagation_rounds = 0 give the chained sweep alone.
  int seed_starts = defaults::kMapSeedStarts;
  int seed_stride = defaults::kMapSeedStride;
  int propagation_rounds = defaults::kMapPropagationRounds;
  // Collision maps: random starts for every cell still reached only in collision after the
  // propagation (then propagation again from the cells they freed); 0: none.
  int collision_starts = kMapCollisionStarts;
  std::uint64_t search_seed = defaults::kMapSearchSeed;
  bool descending =
      false;  // chained rows from the largest gamma down (a check of path independence)
  // The audit (dexterity_audit.hpp): cells drawn at random, each searched from audit_starts
  // random configurations independently of the map's path; audit_cells = 0: no audit.
  int audit_cells = 0;
  int audit_starts = defaults::kAuditDexterityStarts;
  std::uint64_t audit_seed = defaults::kAuditSeed;
  // Validation independent of the design (weights, tolerances, grid) and per design (weights size).
  std::string validate() const;
  std::string validateFor(const Model& model) const;
  ik::WeightedObjective buildObjective(const Model& model) const;
};

struct CellResult {
  // Reachable: a collision-free posture on the pose was found (the quantities below are its);
  // SelfCollision / ObstacleCollision: the pose is reached only in collision (colliding_pair
  // indexes collision::collisionPairNames); OutOfReach / JointLimits: no posture on the pose.
  ReachStatus status = ReachStatus::OutOfReach;
  bool reachable = false;  // status == Reachable
  bool optimised = false;  // null-space optimisation ran (reachable and redundant)
  JointVector q_plain, q_opt;
  metrics::DexterityMeasures plain, opt;  // in options.measure_space, transmission along u
  metrics::Ellipsoid ellipsoid_plain, ellipsoid_opt;
  double H_plain = 0, H_opt = 0;
  double position_error_m = 0, orientation_error_rad = 0;  // of the plain solution
  int starts = 0;  // starts tried (1 = the warm start sufficed)
  int nullspace_iterations = 0;
  ik::NullspaceStatus nullspace_status = ik::NullspaceStatus::Converged;
  // The null-space descents run to find this cell's result (the search's candidates carry their
  // own; the chain's stay with the cell until the search counts them).
  ik::DescentTally descent;
  // Where the optimised configuration came from (values written into the .vti field found_by).
  enum class Source : std::uint8_t { Chain = 0, MultiStart = 1, Neighbour = 2 };
  Source found_by = Source::Chain;
  int colliding_pair = -1;  // the closest pair at the colliding posture (in collision only)
  double min_distance_m = std::numeric_limits<double>::quiet_NaN();  // at q_opt, collision maps
};

// One cell as bytes (the units' and the shared search steps' format; found_by is not part of it)
// and back; getCell marks `r` failed on a value out of range.
void putCell(UnitWriter& w, const CellResult& c);
void getCell(UnitReader& r, CellResult& c);
// A descent tally as bytes (in a cell's and a search step's bytes) and back.
void putTally(UnitWriter& w, const ik::DescentTally& t);
void getTally(UnitReader& r, ik::DescentTally& t);

// What the map search did (searchDexterityMap).
struct MapSearchSummary {
  int seeding_cells = 0;        // cells that got seeded multi-starts
  long multistart_tries = 0;    // random starts solved onto a pose
  int multistart_improved = 0;  // cells the multi-starts improved (or made reachable)
  int rounds = 0;               // neighbour-propagation rounds until no cell changed
  long neighbour_tries = 0;     // neighbour seeds tried
  int neighbour_improved =
      0;                  // cell updates by neighbour seeds (a cell may improve in several rounds)
  bool converged = true;  // false when the round cap stopped the propagation
  // Collision maps: cells still in collision after the propagation, their extra random starts,
  // and the cells those freed.
  int collision_cells = 0;
  long collision_tries = 0;
  int collision_freed = 0;
  // The null-space descents by kind: the chained rows', the seeded starts', the neighbour tries',
  // the collision starts' (changed: candidates adopted by a cell).
  ik::DescentTally chain, seed, neighbour, collision;
  double seed_seconds = 0, neighbour_seconds = 0, collision_seconds = 0;  // wall time per kind
  double seconds = 0;
};

struct DexterityMap {
  std::string design;
  int dof = 0;
  StemGrid grid;
  std::vector<CellResult> cells;  // index = grid.index(i_gamma, i_z)
  double seconds = 0;
  int threads = 1;
  MapSearchSummary search;
  bool collision = false;               // cells were checked for collisions
  std::vector<std::string> pair_names;  // collision::collisionPairNames of the checked pairs
  int reachable() const;
};

// Computes the map: the chained rows, then searchDexterityMap. threads = 0: OpenMP default.
// Preconditions: options.validateFor(model) empty.
DexterityMap computeDexterityMap(const Model& model, const DexterityOptions& options, int threads);

// Computes only the z rows of the given ranges (each within [0, z count), non-empty), in one
// parallel loop over all their rows; the map has every cell, those of other rows stay default.
// Each computed cell equals computeDexterityMap's (rows are independent). `on_done` (may be
// empty) is called once per range as soon as its last row is done, from the thread that did it
// (concurrently for distinct ranges), with the range's index and the map, whose cells of that
// range are final. An exception thrown by on_done is rethrown after the loop.
using RowsDone = std::function<void(std::size_t range, const DexterityMap& map)>;
DexterityMap computeDexterityRows(const Model& model, const DexterityOptions& options,
                                  const std::vector<ItemRange>& row_ranges, int threads,
                                  const RowsDone& on_done = {});

// The map search after the chained rows (see the header comment): seeded multi-starts on every
// options.seed_stride-th gamma and z value (options.seed_starts random configurations within the
// limits, each solved onto the cell's pose and optimised in the null space), then neighbour
// propagation: a cell retries from the optimised configuration of each neighbour that is better
// (lower H) or reachable where it is not, keeping a candidate that lowers H by more than
// defaults::kMapImprovementRelative; rounds repeat, retrying only from neighbours that changed,
// until no cell changes (at most options.propagation_rounds in all). Collision maps: then every
// cell still reached only in collision gets options.collision_starts further random starts, and
// the propagation resumes from the cells they freed. Updates map.cells and map.search. Each step
// is a loop the processes of `runner` share (null: this process alone); the result does not depend
// on who computed a cell (a step reads only the map before it).
void searchDexterityMap(const Model& model, const DexterityOptions& options, DexterityMap& map,
                        int threads, const UnitRunner* runner = nullptr);

// One candidate for a cell from the configuration `seed`: solved onto the cell's pose by the
// exact solve (options.exactSolveOptions(), in ik_ws), then optimised in the null space (redundant
// designs) and checked for collisions (settleCollision, with `cws` non-null for collision maps).
// False when the seed does not lead onto the pose; a candidate in collision returns true with
// out.reachable false. `out` holds the candidate's plain (the solved pose) and optimised results;
// without `measure`, their measures (out.plain, out.opt and the ellipsoids) are left for
// measureCell, so that a search pays them only for the candidates it adopts. With `proven` (the
// cell's own optimum, whose projected gradient is at most kMapStationaryGradient), a start whose
// pose solution lies within kMapProofRadius of it (every joint) is not descended: false, with
// out.descent.skipped = 1.
bool cellFromSeed(const Model& model, KinematicsWorkspace& ws, IkWorkspace& ik_ws,
                  ik::ObjectiveContext& ctx, const ik::WeightedObjective& objective,
                  const DexterityOptions& options, const StemGrid::Cell& cell,
                  const JointVector& seed, CellResult& out,
                  collision::CollisionWorkspace* cws = nullptr, bool measure = true,
                  const JointVector* proven = nullptr);

// A map cell's optimum is proven when its projected gradient is at most kMapStationaryGradient
// (the first-order conditions on the pose, ik::projectedGradient); a start within kMapProofRadius
// of it (every joint) descends back to it and is not tried.
extern const double kMapStationaryGradient, kMapProofRadius;
bool provenOptimum(const Model& model, KinematicsWorkspace& ws, ik::ObjectiveContext& ctx,
                   const ik::WeightedObjective& objective, const DexterityOptions& options,
                   const StemGrid::Cell& cell, const CellResult& c);

// The measures of a cell's plain and optimised postures (r.plain, r.opt, the ellipsoids) from
// r.q_plain and r.q_opt.
void measureCell(const Model& model, KinematicsWorkspace& ws, const DexterityOptions& options,
                 const StemGrid::Cell& cell, CellResult& r);

// Solves and optimises one cell. The plain configuration: a local damped Newton solve from
// `warm_plain` (the previous cell's plain solution, may be null) when that lands on the pose (so
// along a row the plain configuration follows the TCP), else the reachability solver (src/ik/
// reach_solver: multi-start Levenberg-Marquardt within the limits, deterministic by `cell_id`,
// options.cold_starts starts including the warm start), polished by the local solve to the tight
// tolerance the null-space stage needs. The null-space descent starts from the pose solution
// nearest `warm_opt` (the previous cell's optimised configuration, may be null) when that solve
// lands on the pose, else from the plain configuration. Uses the per-thread ws, ik_ws and ctx.
// Collision maps (`cws` non-null): a plain posture in collision is replaced by the collision-aware
// solve's (collision::solvePoseCollisionAware: H_c descended in the null space, then restarts);
// the cell is then settled (settleCollision). An unreachable cell's status tells joint limits
// from out of reach (the reach solver's classification).
CellResult solveCell(const Model& model, KinematicsWorkspace& ws, IkWorkspace& ik_ws,
                     ik::ObjectiveContext& ctx, const ik::WeightedObjective& objective,
                     const DexterityOptions& options, const StemGrid::Cell& cell,
                     std::uint64_t cell_id, const JointVector* warm_plain,
                     const JointVector* warm_opt, collision::CollisionWorkspace* cws = nullptr);

}  // namespace armstudy::dexterity
