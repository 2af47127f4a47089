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

// Self-collision (src/collision, thesis sections 3.4.4 and 5.4.3)
inline constexpr int kMaxCollisionVolumes = 160;          // SSVs per design the workspace holds
inline constexpr int kMaxObstacles = 64;                  // environment obstacles per query
inline constexpr double kCollisionParallelSin2 = 1e-4;    // sin^2 of segment angle: treat as parallel
inline constexpr double kCollisionDegenerateRelative = 1e-14;  // sin^2 of triangle corner: degenerate
inline constexpr double kCollisionTouching_m = 1e-12;     // core distance below: cores touch, no normal
inline constexpr double kCollisionCoincident_m = 1e-9;    // SSV points closer than this coincide (input error)
inline constexpr double kSsvFitInflation_m = 1e-9;        // fitted radii: added to the max vertex distance
inline constexpr double kCollisionSafetyDistance_m = 0.05;  // (study) d_a of eq. (5.57)
inline constexpr double kCollisionBlendT = 0.5;           // (study) t of eq. (5.57): cubic for d >= t d_a
inline constexpr double kCollisionPotentialAtContact = 1.0;  // (study) H_0 = H_c,i(0) of eq. (5.57)

}  // namespace armstudy::defaults
