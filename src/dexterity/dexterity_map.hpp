#pragma once
// The dexterity stage (thesis section 3.2.1, Fig. 3.5, 3.6, 5.15): for each cell of a stem-centric
// grid, solve the pose ("plain" configuration), then optimise the redundancy in the null space
// ("optimised" configuration), and evaluate manipulability, transmission towards the stem,
// condition and ellipsoids for both.
//
// Work split: one z row (a circle around the stem) is one independent unit, solved in gamma order
// with warm starts from the previous cell; rows run in parallel (OpenMP) and their results do not
// depend on the thread count or schedule.
#include <string>
#include <vector>

#include "dexterity/stem_grid.hpp"
#include "ik/nullspace.hpp"
#include "ik/objectives.hpp"
#include "metrics/dexterity_measures.hpp"

namespace armstudy::dexterity {

struct DexterityOptions {
  StemGrid grid;
  metrics::MeasureSpace measure_space = metrics::MeasureSpace::Translational;
  // Weights of eq. (5.51); finite and >= 0.
  double w_joint_limits = 0.0;
  double w_manipulability = 1.0;  // H_m1
  double w_transmission = 0.0;    // H_m2 along u
  double joint_limit_activation = defaults::kJointLimitActivation;
  bool fixed_direction = false;                         // u from the study instead of TCP -> stem
  Eigen::Vector3d direction_W = Eigen::Vector3d::UnitY();
  std::vector<double> joint_weights;                    // W of eq. (5.45a), empty = identity
  double position_tolerance_m = defaults::kPositionTolerance_m;
  double orientation_tolerance_rad = defaults::kOrientationTolerance_rad;
  int cold_starts = defaults::kColdStarts;
  ik::PoseSolveOptions solve;
  ik::NullspaceOptions nullspace;
  bool ellipsoids = true;  // write .vtp ellipsoid glyph data
  // Validation independent of the design (weights, tolerances, grid) and per design (weights size).
  std::string validate() const;
  std::string validateFor(const Model& model) const;
  ik::WeightedObjective buildObjective(const Model& model) const;
};

struct CellResult {
  bool reachable = false;
  bool optimised = false;  // null-space optimisation ran (reachable and redundant)
  JointVector q_plain, q_opt;
  metrics::DexterityMeasures plain, opt;  // in options.measure_space, transmission along u
  metrics::Ellipsoid ellipsoid_plain, ellipsoid_opt;
  double H_plain = 0, H_opt = 0;
  double position_error_m = 0, orientation_error_rad = 0;  // of the plain solution
  int starts = 0;                // pose solves tried (1 = the warm start sufficed)
  int nullspace_iterations = 0;
  ik::NullspaceStatus nullspace_status = ik::NullspaceStatus::Converged;
};

struct DexterityMap {
  std::string design;
  int dof = 0;
  StemGrid grid;
  std::vector<CellResult> cells;  // index = grid.index(i_gamma, i_z)
  double seconds = 0;
  int threads = 1;
  int reachable() const;
};

// Computes the map. threads = 0: OpenMP default. Preconditions: options.validateFor(model) empty.
DexterityMap computeDexterityMap(const Model& model, const DexterityOptions& options, int threads);

// Solves and optimises one cell. `warm_plain` (may be null) seeds the pose solve (else cold starts);
// the plain configuration is that solve's result. The null-space descent starts from the pose
// solution nearest `warm_opt` (the previous cell's optimised configuration, may be null) when that
// solve lands on the pose, else from the plain configuration; so along a row the optimisation
// follows the TCP like the thesis' velocity-level IK does. Uses the per-thread ws and ctx.
CellResult solveCell(const Model& model, KinematicsWorkspace& ws, ik::ObjectiveContext& ctx,
                     const ik::WeightedObjective& objective, const DexterityOptions& options,
                     const StemGrid::Cell& cell, const JointVector* warm_plain,
                     const JointVector* warm_opt);

// Deterministic cold-start configuration k (k = 0: mid-range; k > 0: a fixed pseudo-random
// sequence within the limits), the same on every thread and run.
JointVector coldStart(const Model& model, int k);

}  // namespace armstudy::dexterity
