#pragma once

#include <numbers>

// Tunables in one place. Every tolerance, cap and default that is not a physical constant lives
// here, with its unit; study files may override the ones marked (study).
namespace armstudy::defaults {

// Command line and inputs (docs/hardening: limits an input may not exceed; exit 2 beyond them)
inline constexpr int kMaxThreads = 256;             // --threads (0 = all cores)
inline constexpr long kMaxUnitItems = 1000000000L;  // --unit-size
inline constexpr int kMaxResidualBins =
    1000;  // --speed-bins, --load-bins, --variable-bins, --workspace-bins
inline constexpr unsigned long long kMaxInputFileBytes =
    256ull << 20;  // any file armstudy reads (256 MiB)
inline constexpr double kMaxTrajectorySamples =
    1e6;  // duration x rate of one trajectory (held in memory: ~200 MB)
inline constexpr double kMaxSampleRate_Hz = 1e5;  // approach and synth --rate, a tracking rate
inline constexpr double kMaxDuration_s = 1e4;     // approach and synth --duration
inline constexpr int kMaxSynthRows = 1000000;     // synth --rows (poses held in memory)
// Weights and gains (joint weights of a weighted pseudo-inverse, objective weights, null-space and
// drift gains, the collision potential's H_0): a positive one lies in this range. A subnormal
// weight passes "> 0" yet its inverse is infinite; the range is orders beyond any shipped study.
inline constexpr double kMinWeight = 1e-6;
inline constexpr double kMaxWeight = 1e6;

// Kinematics
inline constexpr int kMaxDof = 12;  // largest chain the fixed-size workspace holds
inline constexpr double kCardanSingularCosBeta =
    1e-6;  // |cos(beta)| below: representation singular
// |cos(beta)| below: at the rounding of a rotation matrix's entries, where only alpha +- gamma is
// defined by R (printed angles choose gamma = 0 there; kinematics.hpp, cardanForDisplay).
inline constexpr double kCardanRoundingCosBeta = 1e-12;

// Reachability (study): thesis eq. (3.2) acceptance thresholds.
inline constexpr double kPositionTolerance_m = 1e-3;
inline constexpr double kOrientationTolerance_rad = 0.5 * std::numbers::pi / 180.0;

// Task grids (src/tasks)
inline constexpr double kGridRangeSlack = 1e-9;  // relative slack so `to` is kept despite rounding
inline constexpr int kMaxGridAxisValues = 100000;  // values per grid axis
inline constexpr double kMaxGridPoses = 5e8;       // poses per grid (all orientations)

// Per-pose inverse kinematics (src/ik, thesis eq. 3.2). Study files may override the (study) ones.
inline constexpr int kIkMaxStarts = 64;  // starts per cold pose incl. the middle start
inline constexpr int kReachStudyStarts =
    8;  // (study) starts per grid/list pose incl. the warm start
inline constexpr int kIkMaxIterations = 40;       // Levenberg-Marquardt iterations per start
inline constexpr int kIkClassifyStarts = 1;       // (study) starts of the limit-free re-solve
inline constexpr unsigned long long kIkSeed = 1;  // (study) seed of the deterministic restarts
inline constexpr double kIkOrientationWeight_m =
    0.3;  // m/rad: orientation rows' weight in the LM cost
inline constexpr double kIkConvergenceFraction =
    0.05;                                         // stop a start once errors < this x tolerance
inline constexpr double kIkLambdaWarm_m2 = 1e-4;  // LM damping (m^2, on J J^T) at a warm start
inline constexpr double kIkLambdaCold_m2 = 0.3;   // ... at a cold start: short first steps
inline constexpr double kIkLambdaMin_m2 = 1e-12;
inline constexpr double kIkLambdaMax_m2 = 1e3;     // above: the start has stagnated
inline constexpr double kIkLambdaDown = 0.2;       // damping factor after an accepted step
inline constexpr double kIkLambdaUp = 10.0;        // ... after a rejected step
inline constexpr double kIkStagnationRatio = 0.1;  // accepted steps reducing the cost less ...
inline constexpr int kIkStagnationSteps = 2;       // ... this many times in a row end a start
inline constexpr double kIkPolishBand = 50.0;  // SLSQP polish when the best LM miss is < band x tol
inline constexpr int kIkPolishMaxEvaluations = 200;   // NLopt SLSQP evaluations per polish
inline constexpr double kIkReachBoundSlack_m = 1e-6;  // slack of the conservative reach bound
inline constexpr long kPoseListChunk = 32;            // poses per warm-start chain in pose lists
// Work units (checkpoint and distribution grain, docs/regression.md); results do not depend on
// them.
inline constexpr long kReachUnitPoses =
    4096;  // poses per reach unit (whole grid lines / list chunks)
inline constexpr long kDexterityUnitCells = 128;      // map cells per dexterity unit (whole z rows)
inline constexpr long kHarvestUnitFruits = 1;         // approaches per harvest unit
inline constexpr long kHarvestUnitGridPoints = 1024;  // holding-grid points per harvest unit
// Distributed runs (docs/distributed.md, "Rank groups"): a grid's map searches run in groups of at
// least this many ranks (--search-group-ranks; 0 = every rank in every search). Chosen on the
// replay of the million-pose sweep (docs/performance.md); results do not depend on it.
inline constexpr int kSearchGroupRanks = 16;
inline constexpr int kMaxSearchGroupRanks = 1 << 20;
inline constexpr int kMaxPreviewStride = 100;  // --preview: every k-th cell, k at most this
// A map search's predicted cost per reachable pose for an arm of at most six joints, relative to a
// redundant one (groups' sizes only). Assumption from the million-pose sweep's record: the
// six-joint arm's search cost 1/15 (canopy_wall) and 1/3 (workspace_position) of the others' per
// design.
inline constexpr double kSearchWeightNonRedundant = 0.1;

// Model versus measurement (calibration, docs/calibration.md).
inline constexpr double kLeastSquaresRankTolerance = 1e-10;  // relative pivot threshold of QR
inline constexpr int kLeastSquaresMaxEval = 2000;            // SLSQP evaluations per bounded solve
inline constexpr int kCvFolds = 5;                           // k of k-fold cross-validation (study)
inline constexpr unsigned long long kCvSeed = 1;             // fold permutation seed (study)
inline constexpr int kStribeckGridPoints = 48;               // log grid when profiling v_S
inline constexpr int kStribeckRefineIterations = 40;         // golden-section steps after the grid
inline constexpr double kSignificanceZ = 3.0;                // held-out improvement t-statistic
inline constexpr double kMinRelativeImprovement = 0.02;      // and at least 2 % lower held-out RMSE
inline constexpr double kBinFalseAlarm = 0.05;               // family-wise, Bonferroni over bins
inline constexpr int kMinBinSamples = 3;                   // bins with fewer samples are not tested
inline constexpr int kSpeedBins = 8;                       // residual map, signed speed
inline constexpr int kLoadBins = 4;                        // residual map, |load|
inline constexpr double kCollinearR2 = 0.98;               // R^2 above: "cannot be told apart"
inline constexpr double kUnidentifiableR2 = 1.0 - 1e-9;    // R^2 above: not fitted at all
inline constexpr double kMinTemperatureSpan_K = 5.0;       // temperature range below: warning
inline constexpr double kConfidenceZ = 1.959963984540054;  // two-sided 95 % intervals
inline constexpr int kMinResidualDof = 2;                  // rows beyond the parameter count
// Model versus measurement for arms (kinds tcp and trajectory,
// src/calibration/arm_calibration.hpp).
inline constexpr int kArmVariableBins = 4;              // 1-D bins per joint variable
inline constexpr int kArmWorkspaceBins = 4;             // workspace cells per axis
inline constexpr int kGaussNewtonIterations = 8;        // full-data fit iterations
inline constexpr int kArmProfileGridPoints = 12;        // log grid of a profiled parameter
inline constexpr int kArmProfileRefineIterations = 12;  // golden-section steps after the grid
inline constexpr double kParsimonyTolerance =
    0.02;                                         // simpler nested candidate ranks first within 2 %
inline constexpr double kTcpAngleLength_m = 0.1;  // TCP angle residual [rad] -> fit units [m]
inline constexpr int kComplianceFixedPointIterations =
    3;  // sag q = q_m - C g(q): contraction steps
// Unexplained-effect search: residuals of the final model against every operating variable.
inline constexpr int kUnexplainedBins = 10;         // equal-width bins of binned means per variable
inline constexpr int kPeriodogramOversampling = 4;  // frequency grid step = 2 pi / (range * this)
inline constexpr int kPeriodogramRowsPerCycle =
    8;  // highest frequency: rows / this cycles over the range
inline constexpr int kSavitzkyGolayHalfWindow = 4;         // qdd from qd: 9-sample window
inline constexpr int kSavitzkyGolayDegree = 2;             // local quadratic
inline constexpr double kUniformSamplingTolerance = 0.01;  // relative spread of time steps allowed
// Joint-side friction of measured logs: Coulomb term F_c tanh(qd / w) with the width w this
// fraction of the joint's peak speed in the data (rule fixed before any data set was fitted).
inline constexpr double kFrictionWidthFraction = 0.01;
inline constexpr double kMaxLogStepRatio = 2.0;  // a log's time step over this x median: a gap
// A joint log's sample period (sample_period or the median step of its time column) [s]: a log
// sampled faster than 1 MHz or slower than once in 1000 s is a wrong unit, not a robot's log.
inline constexpr double kMinLogSamplePeriod_s = 1e-6;
inline constexpr double kMaxLogSamplePeriod_s = 1e3;
inline constexpr int kMinLogRows = 3;  // a log needs this many rows for its second differences
// Dynamics
inline constexpr double kStandardGravity_mps2 =
    9.81;  // |g|, default gravity (0, 0, -g) in W (study)

// Trajectories (thesis section 5.3.2)
inline constexpr double kApproachExpScale_m =
    1.0;  // length scale of r(s) = L e^{-as} + b, eq. (5.17)
inline constexpr double kTimeScalingNewtonTol = 1e-14;  // |s(t_e) - s_e| when solving for t_e
inline constexpr int kTimeScalingMaxIterations = 100;
// Dexterity measures and redundancy resolution (thesis section 5.4). (study) = [dexterity] may
// override.
inline constexpr double kSingularValueFloor = 1e-12;  // relative to sigma_max: below counts as 0
inline constexpr double kJointLimitActivation =
    0.1;  // (study) H_j threshold, fraction of range inside each limit (eq. 5.52)
inline constexpr double kDriftGain_per_s =
    200.0;  // K in eq. (5.50a) [1/s]; K * dt = 0.2 with the default step
inline constexpr double kNullspaceGain_per_s =
    1.0;  // alpha in eq. (5.46) for trajectory tracking [1/s]
inline constexpr double kTrackingStep_s = 1e-3;  // Euler step of eq. (5.49) [s]
inline constexpr double kOrientationLength_m =
    0.2;  // characteristic length weighting rad against m in pose solves
inline constexpr double kPoseSolveTolerance_m =
    1e-10;  // position-level solve target (then judged against the study tolerance)
inline constexpr double kPoseSolveTolerance_rad = 1e-10;
inline constexpr int kPoseSolveMaxIterations = 60;  // (study) damped Newton iterations per start
inline constexpr double kPoseSolveMaxStep = 0.5;  // largest joint change per Newton step [rad or m]
inline constexpr int kColdStarts = 6;  // (study) deterministic starts when no warm start succeeds
inline constexpr int kNullspaceMaxIterations =
    200;  // (study) null-space descent iterations per pose
inline constexpr double kNullspaceRelativeImprovement =
    1e-6;  // (study) stop when H improves less than this (relative)
inline constexpr double kNullspaceMaxStep =
    0.2;  // largest joint change per null-space step [rad or m]
inline constexpr int kNullspaceCorrectionIterations =
    6;  // Newton steps that bring the tool back onto the pose
inline constexpr double kNullspacePoseTolerance =
    1e-9;  // [m and rad] tool must stay this close to the pose
// Map search (docs/dexterity.md, "How a map value is found"): after the chained row sweeps, seeded
// multi-starts on a sub-grid and neighbour propagation make a cell's value independent of the
// order the grid was traversed in. (study) = [dexterity.search] may override.
inline constexpr int kMapSeedStarts = 24;  // (study) random starts per seeding cell
inline constexpr int kMapSeedStride = 4;   // (study) seeding cells: every n-th gamma and z value
inline constexpr int kMapPropagationRounds = 1000;  // (study) cap on neighbour-propagation rounds
inline constexpr double kMapImprovementRelative =
    1e-7;  // a candidate replaces a cell's value when H drops by more (relative)
inline constexpr unsigned long long kMapSearchSeed = 2;  // (study) seed of the multi-starts
inline constexpr double kMapSameBasin = 0.05;  // [rad | m] a neighbour's optimum this close to a
                                               // cell's (every joint) is not tried there
inline constexpr double kReachManipulabilityImprovement =
    0.01;  // a neighbour's solution replaces a reachable pose's when 1 % better
inline constexpr int kReachCollisionStarts =
    32;  // (study) seeded starts per pose still in collision after propagation
// Map audit (docs/dexterity.md, docs/reachability.md): an independent many-start search on cells
// drawn at random; a study enables it with [dexterity.audit] / [reach.audit].
inline constexpr int kAuditDexterityStarts = 200;  // (study) starts per audited dexterity cell
inline constexpr int kAuditReachStarts = 500;      // (study) starts per audited reach pose
inline constexpr unsigned long long kAuditSeed =
    7;  // (study) draws cells and starts; distinct from the map's seeds
inline constexpr double kAuditTolerance =
    0.01;  // a cell agrees when within 1 % of the audit's best
// Harvest torque stage (docs/dynamics.md). (study) = [harvest] may override.
inline constexpr double kHarvestRate_Hz =
    1000.0;  // (study) tracking and inverse-dynamics rate [Hz]
inline constexpr double kHarvestTemperature_C =
    20.0;  // (study) drive temperature for friction terms [deg C]
inline constexpr double kHarvestToolBeta_rad =
    1.5707963267948966;  // (study) R_tool = Ry(pi/2): TCP z = approach axis
// Self-collision (src/collision, thesis sections 3.4.4 and 5.4.3)
inline constexpr int kMaxCollisionVolumes = 160;        // SSVs per design the workspace holds
inline constexpr int kMaxObstacles = 64;                // environment obstacles per query
inline constexpr double kCollisionParallelSin2 = 1e-4;  // sin^2 of segment angle: treat as parallel
inline constexpr double kCollisionDegenerateRelative =
    1e-14;  // sin^2 of triangle corner: degenerate
inline constexpr double kCollisionTouching_m =
    1e-12;  // core distance below: cores touch, no normal
inline constexpr double kCollisionCoincident_m =
    1e-9;  // SSV points closer than this coincide (input error)
inline constexpr int kCollisionEscapeAttempts =
    8;  // (study) extra IK solves to escape a colliding solution
inline constexpr double kCollisionEscapeSafetyDistance_m =
    0.03;  // (study) d_a of the null-space escape's H_c
inline constexpr int kCollisionEscapeIterations =
    60;  // (study) null-space descent steps per escape
inline constexpr unsigned kSsvFitSeed =
    1;  // CGAL's random generator in fitSsvs (reproducible fits)
inline constexpr double kSsvFitInflation_m =
    1e-9;  // fitted radii: added to the max vertex distance
inline constexpr double kCollisionSafetyDistance_m = 0.05;  // (study) d_a of eq. (5.57)
inline constexpr double kCollisionBlendT = 0.5;  // (study) t of eq. (5.57): cubic for d >= t d_a
inline constexpr double kCollisionPotentialAtContact = 1.0;  // (study) H_0 = H_c,i(0) of eq. (5.57)

}  // namespace armstudy::defaults
