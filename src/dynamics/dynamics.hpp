#pragma once
// Rigid-body dynamics of serial arms (thesis section 3.4.2, eq. 3.22-3.28, Appendix B).
//
//   M(q) qdd + h(q, qd) = Q                                   (eq. 3.28)
//
// Q is the generalised joint force (torque for revolute joints in N m, force for prismatic joints
// in N) that the drives must deliver at the joint side; friction and the drive chain
// (eq. 3.27, 3.29) are added on top by src/drive. h contains Coriolis, centrifugal and gravity
// terms.
//
// Usage: build one immutable RigidBodyModel per (design, options) and one DynamicsWorkspace per
// thread. All functions below run without heap allocation.
//
// Frames (docs/conventions.md): link i is the body after joint i, its inertial data are given in
// frame i. The base frame B sits at model.T_WB in W; gravity is given in W (default (0, 0, -g)), so
// a tilted platform is modelled either by a tilted base or by a tilted gravity vector.
#include <Eigen/Core>
#include <array>
#include <string>

#include "common/defaults.hpp"
#include "kinematics/kinematics.hpp"
#include "model/model.hpp"

namespace armstudy {

using MassMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDof, kMaxDof>;

struct DynamicsOptions {
  Eigen::Vector3d g_W{0.0, 0.0, -defaults::kStandardGravity_mps2};  // gravity in W [m/s^2]
  bool include_payload = true;         // model.payload_kg at the TCP (end-effector + fruit)
  bool include_rotor_inertia = false;  // add N^2 * J_rotor (model.drives) to each joint's inertia
  // Returns false (with a message) when a value is unusable, e.g. a non-finite gravity vector.
  bool validate(std::string& error) const;
};

// Immutable dynamic parameters derived from a Model: joint geometry, link inertias about the link
// frame origins (payload merged into the last link), reflected rotor inertias and gravity.
struct RigidBodyModel {
  int n = 0;
  std::array<JointType, kMaxDof> type{};
  std::array<Eigen::Matrix3d, kMaxDof> R_PJ0;  // fixed part of each joint transform
  std::array<Eigen::Vector3d, kMaxDof> p_PJ0;
  std::array<double, kMaxDof> mass{};        // link mass [kg]
  std::array<Eigen::Vector3d, kMaxDof> h;    // first moment m * p_com in the link frame [kg m]
  std::array<Eigen::Matrix3d, kMaxDof> I_O;  // inertia about the link frame origin [kg m^2]
  std::array<double, kMaxDof> armature{};    // reflected rotor inertia N^2 J_rotor [kg m^2 or kg]
  Eigen::Matrix3d R_WB = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();
  Eigen::Vector3d g_B = Eigen::Vector3d::Zero();  // gravity in the base frame
  DynamicsOptions options;                        // the options actually used
};

// Builds the dynamic parameters. Throws InputError (design file, line, key) when the design has no
// [[inertia]] data or, with include_rotor_inertia, a drive lacks a positive gear ratio.
// Links without an [[inertia]] entry are massless.
RigidBodyModel makeRigidBodyModel(const Model& model, const DynamicsOptions& options = {});

// Per-thread scratch space; fixed size, no heap allocation after construction.
struct DynamicsWorkspace {
  explicit DynamicsWorkspace(const RigidBodyModel& rbm);
  int n = 0;
  std::array<Eigen::Matrix3d, kMaxDof> R;   // orientation of frame i in its parent frame
  std::array<Eigen::Vector3d, kMaxDof> p;   // origin of frame i in its parent frame
  std::array<Eigen::Vector3d, kMaxDof> w;   // angular velocity of link i (frame i)
  std::array<Eigen::Vector3d, kMaxDof> wd;  // angular acceleration (frame i)
  std::array<Eigen::Vector3d, kMaxDof> a;   // origin acceleration minus gravity (frame i)
  std::array<Eigen::Vector3d, kMaxDof> f;   // net force on link i (frame i)
  std::array<Eigen::Vector3d, kMaxDof> nm;  // net moment on link i about its origin (frame i)
  std::array<double, kMaxDof> mc{};         // composite (subtree) mass
  std::array<Eigen::Vector3d, kMaxDof> hc;  // composite first moment
  std::array<Eigen::Matrix3d, kMaxDof> Ic;  // composite inertia about the frame origin
  MassMatrix M;
  MassMatrix L;  // Cholesky factor of M (lower triangle), valid after forwardDynamics
  JointVector rhs;
};

// Recursive Newton-Euler (eq. 3.22-3.26 with the forward recursion of Appendix B): the generalised
// joint forces Q that produce the accelerations qdd at (q, qd) under gravity. tau_out has n
// entries.
void inverseDynamics(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                     const Eigen::Ref<const Eigen::VectorXd>& q,
                     const Eigen::Ref<const Eigen::VectorXd>& qd,
                     const Eigen::Ref<const Eigen::VectorXd>& qdd,
                     Eigen::Ref<Eigen::VectorXd> tau_out);

// Bias vector h(q, qd) of eq. (3.28): Coriolis, centrifugal and gravity forces (RNEA with qdd = 0).
void biasForces(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                const Eigen::Ref<const Eigen::VectorXd>& q,
                const Eigen::Ref<const Eigen::VectorXd>& qd, Eigen::Ref<Eigen::VectorXd> h_out);

// Static holding forces g(q) = h(q, 0): gravity and payload only.
void gravityForces(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                   const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Ref<Eigen::VectorXd> g_out);

// Mass matrix M(q) of eq. (3.28), by the composite-rigid-body algorithm on the same link data
// (with the reflected rotor inertias on the diagonal when enabled). Result in ws.M (n x n).
void massMatrix(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                const Eigen::Ref<const Eigen::VectorXd>& q);

enum class ForwardDynamicsStatus { Ok, SingularMassMatrix };
const char* toString(ForwardDynamicsStatus s);

// Forward dynamics: solves M(q) qdd = Q - h(q, qd) with a Cholesky (L L^T) factorisation
// (unblocked, in the workspace; M stays in ws.M, the factor in ws.L).
// A mass matrix that is not positive definite (massless distal links) is a status, not an error.
ForwardDynamicsStatus forwardDynamics(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                                      const Eigen::Ref<const Eigen::VectorXd>& q,
                                      const Eigen::Ref<const Eigen::VectorXd>& qd,
                                      const Eigen::Ref<const Eigen::VectorXd>& Q,
                                      Eigen::Ref<Eigen::VectorXd> qdd_out);

// Kinetic energy (from the link velocities, independent of M) and potential energy in the gravity
// field (zero at the W origin) [J]. Used to check energy conservation of simulations.
struct MechanicalEnergy {
  double kinetic_J = 0;
  double potential_J = 0;
  double total() const { return kinetic_J + potential_J; }
};
MechanicalEnergy mechanicalEnergy(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                                  const Eigen::Ref<const Eigen::VectorXd>& q,
                                  const Eigen::Ref<const Eigen::VectorXd>& qd);

}  // namespace armstudy
