#pragma once
// Inverse kinematics with local optimisation of the kinematic redundancy (thesis section 5.4):
//  - the weighted generalised inverse (eq. 5.47) applied without an explicit inverse (Algorithm
//    5.3), optionally damped (eq. 5.65) with the adaptive damping factor of eq. (5.67);
//  - velocity-level tracking of a reference with Liegeois' null-space term (eq. 5.46), drift
//    compensation (eq. 5.50) and Euler integration (eq. 5.49);
//  - "optimised at a pose": descent of the weighted objective H (eq. 5.51) in the null space while
//    the tool stays on the pose.
// Task rows are rows of the geometric TCP Jacobian (translational velocity, angular velocity), so
// the null space is exact and free of the Cardan representation singularity.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "ik/objectives.hpp"
#include "ik/pose_task.hpp"
#include "kinematics/kinematics.hpp"

namespace armstudy::ik {

using TaskJacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, kMaxDof>;
using TaskVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;

// Task Jacobian rows (m x n) and error e = w_d - f(q) in the same rows (eq. 5.50b): position error,
// and the rotation vector that takes the current tool axis/frame onto the desired one, expressed in
// an orthonormal basis S of the constrained angular directions. Requires tcpJacobian. S (3 x m_rot)
// is returned so desired angular velocities can be mapped the same way. With `pe`, also the
// position and orientation errors (from the rotation computed here once). Tasks of every kind but
// CardanAngles, with all three position components held.
void taskJacobianAndError(const KinematicsWorkspace& ws, const PoseTask& target, TaskJacobian& J,
                          TaskVec& e,
                          Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3>* S = nullptr,
                          PoseError* pe = nullptr);

// Thesis eq. (5.67): lambda = lambda0 (1 - m/m0)^2 for m < m0, else 0. lambda0 = 0 disables.
double adaptiveDamping(double manipulability, double lambda0, double m0);

// Algorithm 5.3 (with eq. 5.65b when lambda > 0):
//   p = wdot + alpha J W^-1 grad^T;  B = J W^-1 J^T + lambda^2 I;  solve B gamma = p (Cholesky);
//   qdot = W^-1 (J^T gamma - alpha grad^T).
// This is the exact minimiser of eq. (5.45) (for lambda = 0); for W != I it equals eq. (5.46)
// with the null-space term N W^-1 grad^T. `w_inv` is the diagonal of W^-1; `grad` may be empty.
// Returns false (qdot untouched) when B is not positive definite (singular J and lambda = 0).
bool redundancyResolution(const Eigen::Ref<const Eigen::MatrixXd>& J,
                          const Eigen::Ref<const Eigen::VectorXd>& w_inv,
                          const Eigen::Ref<const Eigen::VectorXd>& wdot,
                          const Eigen::Ref<const Eigen::VectorXd>& grad, double alpha,
                          double lambda, Eigen::Ref<Eigen::VectorXd> qdot);

struct RedundancyOptions {
  std::vector<double> joint_weights;               // diagonal of W (eq. 5.45a); empty = identity
  double alpha = defaults::kNullspaceGain_per_s;   // null-space gain of eq. (5.46) [1/s]
  double drift_gain = defaults::kDriftGain_per_s;  // K of eq. (5.50a) [1/s]
  double damping_lambda0 = 0;  // eq. (5.67); 0 = undamped generalised inverse (eq. 5.47)
  double damping_m0 = 0;       // manipulability of the task Jacobian below which damping starts
  std::string validate(int dof) const;  // empty when valid
  JointVector weightInverse(int dof) const;
};

// ---- Velocity-level tracking (Fig. 5.10) ----
struct ReferencePoint {
  PoseTask pose;
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();      // desired TCP velocity [m/s]
  Eigen::Vector3d omega_W = Eigen::Vector3d::Zero();  // desired angular velocity [rad/s]
};
using Reference = std::function<ReferencePoint(double t)>;

struct TrackingOptions {
  RedundancyOptions redundancy;
  double dt = defaults::kTrackingStep_s;  // Euler step of eq. (5.49) [s]
  bool stop_at_joint_limit = true;  // abort the motion when a joint leaves its limits (Fig. 5.12b)
  std::string validate(int dof) const;
};

struct TrackingSample {
  double t = 0;
  JointVector q, qdot;
  double position_error_m = 0, orientation_error_rad = 0;
  double lambda = 0, manipulability = 0;  // damping used and sqrt(det(J_w J_w^T)) of the task rows
};

enum class TrackingStatus { Completed, JointLimitReached, SingularJacobian };
const char* toString(TrackingStatus s);

struct TrackingSummary {
  TrackingStatus status = TrackingStatus::Completed;
  int steps = 0;
  int limit_joint = -1;                 // first joint that left its limits
  double limit_q = 0;                   // the limit it crossed (q_min or q_max), rad or m
  double max_joint_speed = 0;           // max |qdot_i| over the run
  std::vector<TrackingSample> samples;  // one per step
  TrackingOptions options_used;
};

// Integrates qdot (Algorithm 5.3 with drift compensation eq. 5.50 and adaptive damping eq. 5.67)
// with explicit Euler (eq. 5.49) from q0 over [0, duration]. With `objective` non-null, its
// gradient drives the null-space term (eq. 5.46); ctx must belong to the same ws.
TrackingSummary trackReference(const Model& model, KinematicsWorkspace& ws,
                               const Reference& reference, const Eigen::VectorXd& q0,
                               double duration, const WeightedObjective* objective,
                               ObjectiveContext* ctx, const TrackingOptions& options);

// ---- Null-space optimisation at a pose ----
inline constexpr int kQuasiNewtonPairs = 5;  // step pairs a quasi-Newton descent remembers
inline constexpr double kQuasiNewtonCurvatureFloor =
    1e-10;  // a pair is kept when s^T y exceeds this times |s| |y|

struct NullspaceOptions {
  int max_iterations = defaults::kNullspaceMaxIterations;
  double relative_improvement = defaults::kNullspaceRelativeImprovement;
  double max_step = defaults::kNullspaceMaxStep;
  int correction_iterations = defaults::kNullspaceCorrectionIterations;
  double pose_tolerance = defaults::kNullspacePoseTolerance;  // [m and rad]
  // Stop once the projected gradient max_i |(N W^-1 grad H)_i| is at most this (the first-order
  // condition of a minimum on the pose); 0 = only the other rules stop.
  double gradient_tolerance = 0;
  // Limited-memory BFGS directions from the last steps' projected gradients (steepest descent
  // when off, when damped, or when a quasi-Newton direction does not descend).
  bool quasi_newton = false;
  // Adaptive damping of the descent direction near singularities (eq. 5.65, 5.67); 0 = off.
  double damping_lambda0 = 0, damping_m0 = 0;
  std::string validate() const;  // empty when valid
};

enum class NullspaceStatus {
  Converged,       // H stopped improving (relative change below the threshold, or stationary)
  IterationLimit,  // still improving when the iteration cap was hit
  NotOnPose,       // the start was not on the pose within tolerance; returned unchanged
};
const char* toString(NullspaceStatus s);

struct NullspaceResult {
  NullspaceStatus status = NullspaceStatus::Converged;
  JointVector q;
  double H_start = 0, H_final = 0;
  int iterations = 0;   // accepted descent steps
  int evaluations = 0;  // objective evaluations (incl. rejected trials)
  // Forward kinematics + TCP Jacobian evaluations (start, every correction of every trial step,
  // the final pose check).
  int kernel_evaluations = 0;
  double step_sum = 0;   // sum over accepted steps of max_i |q_i change| [rad or m]
  double last_step = 0;  // the last accepted step's max_i |q_i change|
  // max_i |(N W^-1 grad H)_i| where the descent stopped (0 when it stopped before computing it).
  double projected_gradient = 0;
  PoseError error;  // at q
};

// Counts of a set of null-space descents (optimiseAtPose calls): summed in a fixed order, they do
// not depend on the thread count or schedule.
struct DescentTally {
  long descents = 0;
  long changed = 0;  // descents whose outcome changed a map cell (set by the map searches)
  long iterations = 0, objective_evaluations = 0, kernel_evaluations = 0;
  double step_sum = 0;          // over all accepted steps
  double last_step_sum = 0;     // over descents, of their last accepted step
  long stopped[3] = {0, 0, 0};  // by NullspaceStatus
  // Starts not descended because they lay on an optimum already proven (set by the map searches).
  long skipped = 0;
  void add(const NullspaceResult& r);   // one descent
  void add(const DescentTally& other);  // another tally
};

// Moves q_start (on the pose) along the projected descent direction -N W^-1 grad H (Algorithm 5.3
// with wdot = 0), with a backtracking line search; after each trial step, Newton corrections with
// the generalised inverse (drift compensation, eq. 5.50) bring the tool back onto the pose. Steps
// that leave the joint limits or the pose are rejected. Stops when H stops improving.
NullspaceResult optimiseAtPose(const Model& model, KinematicsWorkspace& ws, ObjectiveContext& ctx,
                               const PoseTask& target, const Eigen::VectorXd& q_start,
                               const WeightedObjective& objective, const Eigen::VectorXd& w_inv,
                               const NullspaceOptions& options);

// max_i |(N W^-1 grad H)_i| at q (on the pose of `target`): zero at a point that satisfies the
// first-order conditions of a minimum of H on the pose. Leaves FK and J at q in ws.
double projectedGradient(const Model& model, KinematicsWorkspace& ws, ObjectiveContext& ctx,
                         const PoseTask& target, const Eigen::VectorXd& q,
                         const WeightedObjective& objective, const Eigen::VectorXd& w_inv);

// True when every q_i lies within its limits.
bool withinLimits(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q);

}  // namespace armstudy::ik
