#pragma once
// Forward kinematics, Jacobians and their derivatives (thesis section 3.4.1, Appendix B,
// eq. 5.3-5.11).
//
// All quantities are expressed in the world/task frame W. The robot base frame B sits at
// model.T_WB in W (identity unless a design or study places the base), so with the default base
// W = B. Frame i is the body frame after joint i; the TCP frame T is model.T_NT after the last
// frame. Geometric Jacobians stack translational velocity over angular velocity: J = [J_T; J_R].
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "common/defaults.hpp"
#include "model/model.hpp"

namespace armstudy {

inline constexpr int kMaxDof = defaults::kMaxDof;
using JointVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxDof, 1>;
using Jacobian6 = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxDof>;
using Jacobian3 = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxDof>;

// Per-thread scratch space. Construct once per thread from the model; no heap allocation after.
struct KinematicsWorkspace {
  explicit KinematicsWorkspace(const Model& model);
  int n = 0;
  std::array<Eigen::Matrix3d, kMaxDof> R_WF;  // orientation of frame i in W
  std::array<Eigen::Vector3d, kMaxDof> p_WF;  // origin of frame i in W [m]
  Eigen::Matrix3d R_WT;                       // TCP orientation in W
  Eigen::Vector3d p_WT;                       // TCP position in W [m]
  Eigen::Vector3d a_WT;                       // the design's tool axis in W (R_WT * tool_axis_T)
  Jacobian6 J_W_tcp;  // geometric TCP Jacobian in W (valid after tcpJacobian)
};

// Pose of every joint frame and the TCP (Appendix B, eq. B.2 and B.16 in closed recursive form).
void forwardKinematics(const Model& model, KinematicsWorkspace& ws,
                       const Eigen::Ref<const Eigen::VectorXd>& q);

// Geometric TCP Jacobian J_W_tcp = [J_T; J_R] (eq. B.7, B.8, B.14, B.15, B.21 evaluated in W).
// Requires forwardKinematics at the same q.
void tcpJacobian(const Model& model, KinematicsWorkspace& ws);

// Convenience: forwardKinematics + tcpJacobian.
void forwardKinematicsAndJacobian(const Model& model, KinematicsWorkspace& ws,
                                  const Eigen::Ref<const Eigen::VectorXd>& q);

// Geometric Jacobian (6 x n) of a point p_W (given in W) rigidly attached to link `link`
// (0-based joint index; -1 = the fixed base). Columns of joints after `link` are zero.
// Used for witness points of collision volumes and centres of mass.
void pointJacobian(const Model& model, const KinematicsWorkspace& ws, int link,
                   const Eigen::Vector3d& p_W, Eigen::Ref<Eigen::MatrixXd> J_out);

// Derivative dJ_W_tcp / dq_i of the geometric TCP Jacobian (6 x n), needed by the
// manipulability and transmission gradients (thesis eq. 5.62, 5.64). Requires forwardKinematics.
void tcpJacobianDerivative(const Model& model, const KinematicsWorkspace& ws, int i,
                           Eigen::Ref<Eigen::MatrixXd> dJ_out);

// ---- Orientation representation: Cardan (fixed x-y-z) angles, R = Rx(alpha) Ry(beta) Rz(gamma)
// ----
struct CardanAngles {
  double alpha = 0, beta = 0, gamma = 0;
  bool singular = false;  // |cos(beta)| < defaults::kCardanSingularCosBeta (eq. 5.10)
};
CardanAngles cardanFromRotation(const Eigen::Matrix3d& R);
// The same angles for printing: exact (rotationFromCardan gives R back to rounding) also within the
// singular band where cardanFromRotation sets gamma = 0, down to |cos(beta)| of
// defaults::kCardanRoundingCosBeta (below it, gamma = 0 too); `singular` as there.
CardanAngles cardanForDisplay(const Eigen::Matrix3d& R);
Eigen::Matrix3d rotationFromCardan(double alpha, double beta, double gamma);

// Thesis eq. (5.10): T_A^{-1}, mapping angular velocity omega to Cardan rates. Returns false (and
// leaves out untouched) at the representation singularity cos(beta) = 0; never NaN or Inf.
bool cardanRateMatrix(double alpha, double beta, Eigen::Matrix3d& T_A_inv);

// ---- Task spaces: a selection of the components of w = (x, y, z, alpha, beta, gamma) (eq. 5.3)
// ----
enum class TaskComponent : int { X = 0, Y, Z, Alpha, Beta, Gamma };

struct TaskSpace {
  std::array<bool, 6> selected{};  // which of x, y, z, alpha, beta, gamma are constrained
  int dim() const;
  bool hasOrientation() const { return selected[3] || selected[4] || selected[5]; }
  static TaskSpace fullPose();   // eq. 5.3
  static TaskSpace spraying();   // eq. 3.1: (x, y, z, alpha, gamma)
  static TaskSpace position();   // (x, y, z)
  std::string toString() const;  // e.g. "x,y,z,alpha,gamma"
};
// Parses "full", "spraying", "position" or a comma list such as "x,y,z,alpha,gamma".
// Returns false (and sets `error`) for unknown components.
bool parseTaskSpace(const std::string& text, TaskSpace& out, std::string& error);

// Task-space vector w = f(q) of the current TCP pose (all six components), eq. 5.5.
struct TaskVector {
  Eigen::Matrix<double, 6, 1> w;
  bool singular = false;
};
TaskVector tcpTaskVector(const KinematicsWorkspace& ws);

// Analytic task-space Jacobian J_w = [J_T; T_A^{-1} J_R] (eq. 5.9, 5.11), rows restricted to the
// task space's selected components (m x n). Requires tcpJacobian. Returns false at the
// representation singularity when an orientation row is selected; J_out is then left unchanged.
bool analyticJacobian(const KinematicsWorkspace& ws, const TaskSpace& task,
                      Eigen::Ref<Eigen::MatrixXd> J_out);

}  // namespace armstudy
