#pragma once
// Inside the trajectory kind (trajectory_calibration.cpp): what its catalogue entries are and the
// parts of its problem that the calibrated design writer (trajectory_design.cpp) reads.
#include <string>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "drive/friction.hpp"
#include "dynamics/dynamics.hpp"
#include "model/model.hpp"

namespace armstudy::calibration::trajectory_detail {

enum class TrajEffect { Payload, RotorInertia, GravityTilt, LinkMass, Friction, JointSide, Motor };
// Terms of the joint-side catalogue of measured logs (joints without a [[drive]]) and of a coupled
// motor (a row of the coupling matrix with more than one joint).
enum class SideTerm { Coulomb, Viscous, Offset, Inertia };
// Where the joint's own dynamics ([[joint]] coulomb, viscous, effort_offset, armature) holds a
// term.
double JointDynamics::*sideField(SideTerm term);
struct Tag {
  TrajEffect type;
  int joint = -1;  // the motor (row of the coupling matrix) for TrajEffect::Motor
  drive::Effect friction = drive::Effect::Coulomb;
  SideTerm term = SideTerm::Coulomb;
};

// Adds d to the friction parameter named by its [drive.friction] key (src/drive maps keys to
// fields).
void addFriction(drive::FrictionParams& p, const std::string& key, double d);
double frictionValue(const drive::FrictionParams& p, const std::string& key);

// Adds an extra body at the TCP, given by its linear inertial parameters x = (m, h_T = m c_T,
// I_T: xx yy zz xy xz yz about the TCP origin in TCP axes), to the last link (frame N) of the
// rigid-body model: with p = p_NT, R = R_NT, h = R h_T,
//   mass += m,  h_N += h + m p,  I_N += R I_T R^T + m (|p|^2 1 - p p^T) + 2 (p.h) 1 - p h^T - h p^T
// (parallel-axis theorem for a body known about the TCP origin), linear in x.
void addPayloadParameters(const Model& m, const Eigen::VectorXd& x, RigidBodyModel& rbm);

// What the calibrated design writer reads of a trajectory problem: each catalogue entry's tag and,
// per joint, the design's friction and its drive (null without one).
struct TrajectoryTerms {
  const std::vector<Tag>& tags;
  const std::vector<drive::FrictionParams>& friction;
  const std::vector<const Drive*>& drives;
};
TrajectoryTerms trajectoryTerms(const ArmProblem& problem);  // problem: of the trajectory kind

}  // namespace armstudy::calibration::trajectory_detail
