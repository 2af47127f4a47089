#pragma once
// The one local pose solver (thesis eq. 3.2):
//   || w_d - f(q) || -> min over q in C (the joint-limit box),
// and the pose is reached when the position and orientation errors are below the tolerances.
// `IkOptions::algorithm` chooses the method; everything else (tolerances, iterations, starts,
// joint weights) is in the same options struct.
//
// Reachability (LmThenSlsqp, LmOnly, SlsqpOnly; docs/reachability.md, benchmark in
// docs/performance.md):
//  1. A conservative reach bound (distance of the target to the set the first revolute joint's
//     origin can occupy, versus the summed link lengths after it) rejects far targets at once.
//  2. Levenberg-Marquardt / damped least squares on the weighted task error, projected onto the
//     joint-limit box with an active set (joints at a bound that the step pushes outward are held),
//     from a sequence of deterministic starts: the warm start (the neighbouring grid cell's
//     solution) if given, the middle of the limits, then seeded random configurations.
//  3. When every start misses narrowly, NLopt SLSQP with analytic gradients and the limits as
//     bounds polishes the best configuration (the constrained fallback).
//  4. For an unreachable pose, the reason: a re-solve without joint limits that succeeds means the
//     limits block the pose; otherwise the pose is out of reach (for a Cardan selection, a best
//     solution at cos(beta) = 0 is reported as the representation's singularity).
//
// Exact pose (WeightedNewton; the dexterity maps, the collision escape): one start (the warm
// start, else the middle of the limits), damped Newton on the geometric task rows weighted by
// W^-1 (IkOptions::joint_weights, eq. 5.45a), iterates projected onto the joint limits, down to
// tight tolerances (IkOptions::exactPose()); no restarts, no polish, no classification.
//
// Orientation error: for the full pose (eq. 5.3) the geodesic angle between R_d and R (the
// solver uses the rotation vector of R_d R^T with the geometric Jacobian); for the tool-axis task
// (spraying, stems) the angle between the design's tool axis and its target direction (rotation
// vector a x a_d scaled to the angle, with the angular Jacobian rows projected perpendicular to
// the tool axis); for a selection of Cardan angles (e.g. "x,y,z,gamma") the Euclidean norm of the
// wrapped differences of the selected angles, with the analytic Jacobian (eq. 5.9-5.11).
#include <cstdint>
#include <string>
#include <vector>

#include "ik/pose_task.hpp"
#include "kinematics/kinematics.hpp"
#include "tasks/task_grid.hpp"

namespace armstudy {

// Why a pose is (not) reachable. Values are stable: they are written into maps and summaries.
enum class ReachStatus : std::uint8_t {
  Reachable = 0,
  OutOfReach = 1,   // no configuration reaches it, even without joint limits
  JointLimits = 2,  // reachable only if the joint limits were lifted
  RepresentationSingularity =
      3,                  // best solution at cos(beta) = 0 (Cardan selections such as
                          // "x,y,z,gamma" only; never for tool-axis, full or position tasks)
  SelfCollision = 4,      // reachable only in self-collision (collision-aware sweeps)
  TorqueLimit = 5,        // reserved for the dynamics stage
  ObstacleCollision = 6,  // reachable only in collision with an environment obstacle
};
inline constexpr int kReachStatusCount = 7;
const char* toString(ReachStatus s);
// What a status means in words, as legends and reports say it ("only in self-collision").
const char* describe(ReachStatus s);
// Per status (index), its describe() text where a map shows its poses as points (a posture on the
// pose: collision-free or only in collision), "" for the others.
std::vector<std::string> statusNamesShownOnMaps();

enum class IkAlgorithm {
  LmThenSlsqp,  // default: LM starts, SLSQP polish of near misses
  LmOnly,
  SlsqpOnly,       // every start solved by NLopt SLSQP (benchmark comparison)
  WeightedNewton,  // one start, damped Newton weighted by W^-1 (tasks of every kind but
                   // CardanAngles); see the header comment
};
const char* toString(IkAlgorithm a);

struct IkOptions {
  // The exact-pose settings (WeightedNewton, tolerances kPoseSolveTolerance_*, at most
  // kPoseSolveMaxIterations Newton iterations).
  static IkOptions exactPose();
  double position_tolerance_m = defaults::kPositionTolerance_m;
  double orientation_tolerance_rad = defaults::kOrientationTolerance_rad;
  int max_starts = defaults::kIkMaxStarts;          // including the warm start
  int max_iterations = defaults::kIkMaxIterations;  // LM (Newton) iterations per start
  std::uint64_t seed = defaults::kIkSeed;
  bool classify_failures = true;  // tell out_of_reach from joint_limits
  int classify_starts = defaults::kIkClassifyStarts;
  bool use_reach_bound = true;
  IkAlgorithm algorithm = IkAlgorithm::LmThenSlsqp;
  double orientation_weight_m = defaults::kIkOrientationWeight_m;
  // Levenberg-Marquardt tuning, chosen with tests/benchmarks/ik_bench (docs/performance.md).
  double lambda_initial_m2 =
      defaults::kIkLambdaCold_m2;                      // damping (m^2, on J J^T) at a cold start:
                                                       // short first steps keep LM in its basin
  double lambda_warm_m2 = defaults::kIkLambdaWarm_m2;  // ... at a warm start (already close)
  double stagnation_ratio =
      defaults::kIkStagnationRatio;  // accepted steps reducing the cost by less (relative), ...
                                     // defaults::kIkStagnationSteps times in a row, end a start
  int max_rejected_steps = 5;        // rejected LM steps in a row end a start
  int seed_candidates = 8;           // a random start is the best (lowest task error) of this many
                                     // seeded configurations
  // Sweeps (src/reach/reach_sweep): chain each line from both ends and keep the better result per
  // pose (results then do not depend on the traversal direction); false: one chain per line,
  // in the direction below (without the map search's symmetry; benchmarks and tests only).
  bool sweep_both_directions = true;
  // Traverse each line from its last pose first (a check that results do not depend on the
  // traversal order; not a solver setting).
  bool sweep_descending = false;
  // WeightedNewton: the diagonal of W (eq. 5.45a; empty = identity) and the largest joint change
  // per Newton step [rad or m].
  std::vector<double> joint_weights;
  double max_step = defaults::kPoseSolveMaxStep;
  std::string validate() const;  // empty when valid
};

struct IkResult {
  ReachStatus status = ReachStatus::OutOfReach;
  bool reachable() const { return status == ReachStatus::Reachable; }
  double position_error_m = 0;  // of the best configuration found (within the limits)
  double orientation_error_rad = 0;
  JointVector q;                  // best configuration found (the solution when reachable)
  int starts = 0;                 // starts used (within limits)
  int iterations = 0;             // LM iterations over all starts (incl. classification)
  bool polished = false;          // the SLSQP polish produced the solution
  bool bound_rejected = false;    // certainly unreachable by the reach bound (one local solve only)
  double manipulability = 0;      // sqrt(det(J_t J_t^T)) of the task Jacobian (eq. 5.59): the
                                  // geometric rows the task constrains (taskJacobianRows)
  double joint_limit_margin = 0;  // min over joints of distance to a limit / limit range
};

// Per-thread scratch; constructed once per thread from the model. The hot path does not allocate
// (the SLSQP polish, a rare fallback, does).
class IkWorkspace {
 public:
  explicit IkWorkspace(const Model& model);
  KinematicsWorkspace kin;
  // Conservative reach bound: the TCP lies within `reach_radius` of the origin of the first
  // revolute joint, which moves on the segment p0 + t * axis, t in [t_min, t_max] (leading lift).
  bool has_bound = false;
  Eigen::Vector3d bound_p0 = Eigen::Vector3d::Zero(), bound_axis = Eigen::Vector3d::Zero();
  double bound_t_min = 0, bound_t_max = 0, reach_radius = 0;
};

// Solves one pose with options.algorithm. `pose_id` seeds the random starts (deterministic: the
// same id gives the same starts on any thread). `warm_start` (may be null) is tried first (the one
// start of WeightedNewton, whose result is its last iterate, status Reachable when within the
// tolerances, else OutOfReach).
IkResult solvePose(const Model& model, IkWorkspace& ws, const PoseTask& target,
                   const IkOptions& options, std::uint64_t pose_id,
                   const JointVector* warm_start = nullptr);

// The smooth objective the SLSQP polish minimises and its analytic gradient (grad may be null):
// 0.5 |e_p|^2 + orientation term (0.5 w^2 |e_Cardan|^2, or w^2 (1 - cos(angle)) for the full
// pose). Runs forwardKinematics at q. Exposed for the finite-difference test.
double ikObjective(const Model& model, KinematicsWorkspace& kin, const PoseTask& target,
                   double orientation_weight_m, const Eigen::VectorXd& q, Eigen::VectorXd* grad);

// Thesis eq. (5.59): the manipulability (metrics::computeMeasures) at the configuration in kin
// (requires tcpJacobian) of the task rows ik::taskJacobianAndError builds: the selected position
// rows, then 3 angular rows (full pose), the 2 angular rows perpendicular to the tool axis
// (tool-axis tasks) or none (position). Units: m^k for k position rows (rad^-1 folded in);
// the angular rows are dimensionless, so the value weighs them with a characteristic length of
// 1 m. For a Cardan selection, its analytic rows (eq. 5.11); 0 at that representation's
// singularity.
double taskManipulability(const KinematicsWorkspace& kin, const PoseTask& target);
// The rows of the task Jacobian whose Yoshikawa value taskManipulability reports, into J_out
// (rows beyond the returned count are zero): the geometric rows the target constrains, or for a
// Cardan selection its analytic rows (eq. 5.11). Returns the number of rows; 0 at that
// representation's singularity. Requires tcpJacobian.
int taskJacobianRows(const KinematicsWorkspace& kin, const PoseTask& target, Jacobian6& J_out);
// The thesis' Cardan value of a task space (analytic rows eq. 5.11, e.g. spraying's alpha and
// gamma rows): depends on the angle representation (it equals the tool-axis value divided by
// |cos beta|), so it is only for reproducing the thesis' figures, never for comparisons.
double cardanManipulability(const KinematicsWorkspace& kin, const TaskSpace& task_space);

// The translational and rotational parts of the task manipulability: sqrt(det) of the position
// rows alone (m^k) and of the angular rows alone (dimensionless); 0 for a part the task lacks.
struct ManipulabilityParts {
  double translation = 0, rotation = 0;
};
ManipulabilityParts taskManipulabilityParts(const KinematicsWorkspace& kin, const PoseTask& target);

// The result solvePose would report for configuration q (errors, manipulability, joint-limit
// margin at q; status Reachable when q is within the joint limits and the tolerances, else
// `otherwise`). For solutions found by other means (the collision escape's null-space descent).
IkResult evaluateSolution(const Model& model, IkWorkspace& ws, const PoseTask& target,
                          const IkOptions& options, const JointVector& q, ReachStatus otherwise);

// The k-th seeded random configuration of `id`, uniform within the joint limits (counter-based
// splitmix64: the same on any thread and platform). The solver's random starts and every
// multi-start search (dexterity refinement, map audits) draw from it.
void randomConfiguration(const Model& model, std::uint64_t seed, std::uint64_t id, int k,
                         JointVector& q);
// The k-th uniform number in [0, 1) of stream `id` from the same generator.
double uniformDraw(std::uint64_t seed, std::uint64_t id, std::uint64_t k);
// `count` distinct indices of [0, n) drawn with `seed` from the same generator (partial
// Fisher-Yates), ascending; all of them when count >= n. The map audits draw their cells with it.
std::vector<long> drawIndices(long n, long count, std::uint64_t seed);

// Smallest distance to a joint limit as a fraction of that joint's range (0 at a limit, 0.5 in
// the middle).
double jointLimitMargin(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q);

}  // namespace armstudy
