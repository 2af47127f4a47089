#pragma once
// Tunables in one place. Every tolerance, cap and default that is not a physical constant lives
// here, with its unit; study files may override the ones marked (study).
namespace armstudy::defaults {

// Kinematics
inline constexpr int kMaxDof = 12;                     // largest chain the fixed-size workspace holds
inline constexpr double kCardanSingularCosBeta = 1e-6;  // |cos(beta)| below: representation singular

// Reachability (study): thesis eq. (3.2) acceptance thresholds.
inline constexpr double kPositionTolerance_m = 1e-3;
inline constexpr double kOrientationTolerance_rad = 0.5 * 3.14159265358979323846 / 180.0;

// Dexterity measures and redundancy resolution (thesis section 5.4). (study) = [dexterity] may override.
inline constexpr double kSingularValueFloor = 1e-12;      // relative to sigma_max: below counts as 0
inline constexpr double kJointLimitActivation = 0.1;      // (study) H_j threshold, fraction of range inside each limit (eq. 5.52)
inline constexpr double kDriftGain_per_s = 200.0;         // K in eq. (5.50a) [1/s]; K * dt = 0.2 with the default step
inline constexpr double kNullspaceGain_per_s = 1.0;       // alpha in eq. (5.46) for trajectory tracking [1/s]
inline constexpr double kTrackingStep_s = 1e-3;           // Euler step of eq. (5.49) [s]
inline constexpr double kOrientationLength_m = 0.2;       // characteristic length weighting rad against m in pose solves
inline constexpr double kPoseSolveTolerance_m = 1e-10;    // position-level solve target (then judged against the study tolerance)
inline constexpr double kPoseSolveTolerance_rad = 1e-10;
inline constexpr int kPoseSolveMaxIterations = 60;        // (study) damped Newton iterations per start
inline constexpr double kPoseSolveMaxStep = 0.5;          // largest joint change per Newton step [rad or m]
inline constexpr int kColdStarts = 6;                     // (study) deterministic starts when no warm start succeeds
inline constexpr int kNullspaceMaxIterations = 200;       // (study) null-space descent iterations per pose
inline constexpr double kNullspaceRelativeImprovement = 1e-6;  // (study) stop when H improves less than this (relative)
inline constexpr double kNullspaceMaxStep = 0.2;          // largest joint change per null-space step [rad or m]
inline constexpr int kNullspaceCorrectionIterations = 6;  // Newton steps that bring the tool back onto the pose
inline constexpr double kNullspacePoseTolerance = 1e-9;   // [m and rad] tool must stay this close to the pose

}  // namespace armstudy::defaults
