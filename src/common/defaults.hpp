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

// Dynamics
inline constexpr double kStandardGravity_mps2 = 9.81;    // |g|, default gravity (0, 0, -g) in W (study)

// Trajectories (thesis section 5.3.2)
inline constexpr double kApproachExpScale_m = 1.0;       // length scale of r(s) = L e^{-as} + b, eq. (5.17)
inline constexpr double kTimeScalingNewtonTol = 1e-14;   // |s(t_e) - s_e| when solving for t_e
inline constexpr int kTimeScalingMaxIterations = 100;

}  // namespace armstudy::defaults
