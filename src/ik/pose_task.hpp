#pragma once
// What the tool must do at one pose (docs/conventions.md, "Tasks"), and how far it is from doing
// it. Every solver, measure and stage takes this one description of a task:
//  - Position: the TCP at p_WT (the components in position_selected), orientation free;
//  - PositionAxis: also the design's tool axis (Model::tool_axis_T, in W KinematicsWorkspace::a_WT)
//    along axis_W, the roll about it free (spraying, eq. 3.1 as a physical task; harvesting,
//    thesis Fig. 3.4; the dexterity stage's "position_axis");
//  - FullPose: also the TCP orientation R_WT (eq. 5.3);
//  - CardanAngles: a literal selection of Cardan angles (a task space such as "x,y,z,gamma"), the
//    only kind that uses an angle representation (and can meet its singularity, cos(beta) = 0).
#include <array>
#include <cstdint>

#include "kinematics/kinematics.hpp"
#include "tasks/task_grid.hpp"

namespace armstudy {

enum class PoseTaskKind : std::uint8_t { Position, PositionAxis, FullPose, CardanAngles };
// "position", "position_axis", "full", "cardan_angles".
const char* toString(PoseTaskKind k);

struct PoseTask {
  PoseTaskKind kind = PoseTaskKind::FullPose;
  std::array<bool, 3> position_selected{true, true, true};  // which of x, y, z are held
  Eigen::Vector3d p_WT = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_WT = Eigen::Matrix3d::Identity();  // FullPose: the TCP orientation
  Eigen::Vector3d axis_W = Eigen::Vector3d::UnitZ();   // PositionAxis: the tool axis's direction
  std::array<bool, 3> angle_selected{false, false, false};  // CardanAngles: alpha, beta, gamma
  Eigen::Vector3d angles = Eigen::Vector3d::Zero();         // CardanAngles: their values [rad]
  bool allPositionSelected() const {
    return position_selected[0] && position_selected[1] && position_selected[2];
  }
  int positionRows() const;
  // Rows of the task the orientation adds: 0, 2 (tool axis), 3 (full pose) or the selected angles.
  int orientationRows() const;
  int rows() const { return positionRows() + orientationRows(); }
};

// Rows of a task of kind k holding the whole position (k not CardanAngles): 3, 5 or 6.
int taskDim(PoseTaskKind k);

// A task of every kind but CardanAngles with all three position components held.
PoseTask positionTask(const Eigen::Vector3d& p_WT);
PoseTask positionAxisTask(const Eigen::Vector3d& p_WT, const Eigen::Vector3d& axis_W);
PoseTask fullPoseTask(const Eigen::Vector3d& p_WT, const Eigen::Matrix3d& R_WT);

// How far the tool is from a task.
struct PoseError {
  double position_m = 0;       // distance of the held position components
  double orientation_rad = 0;  // angle between the tool axes (PositionAxis), the frames
                               // (FullPose), or the norm of the wrapped angle differences
  bool singular = false;       // CardanAngles only: the representation is singular at the pose
};
// Errors of the TCP pose currently in kin (after forwardKinematics) against the task.
PoseError poseError(const KinematicsWorkspace& kin, const PoseTask& task);

// An orthonormal pair perpendicular to unit vector a (deterministic choice): the basis of the two
// angular rows of a tool-axis task.
void perpendicularBasis(const Eigen::Vector3d& a, Eigen::Vector3d& b1, Eigen::Vector3d& b2);
// The rotation vector (in W, angle * unit axis) turning unit vector a onto unit vector b, and with
// `angle` the angle between them, atan2(|a x b|, a . b); antiparallel: about perpendicularBasis'
// first vector. The tool-axis task's error.
Eigen::Vector3d rotationBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                double* angle = nullptr);

// The spray direction of the spraying task (thesis eq. 3.1, Fig. 3.7): d = Rx(alpha) Rz(gamma) e_y
// in W, i.e. +y at alpha = gamma = 0, turned by gamma about the vertical, then tilted by alpha
// about x: d = (-sin gamma, cos alpha cos gamma, sin alpha cos gamma).
Eigen::Vector3d sprayDirection(double alpha, double gamma);

// The task of a pose w_d of a task space: the spraying space (x, y, z, alpha, gamma) is the
// tool-axis task along sprayDirection(alpha, gamma) (beta plays no part); the full space is the
// pose of eq. 5.3 (R_WT from the Cardan angles of w_d, the file format); position selects the
// position; any other selection of angles is a CardanAngles task.
PoseTask taskTarget(const TaskSpace& task_space, const TaskVector6& w_d);
// True for a selection of Cardan angles other than spraying (e.g. "x,y,z,gamma"): the only task
// spaces that use an angle representation (and can report RepresentationSingularity).
bool usesCardanAngles(const TaskSpace& task_space);

}  // namespace armstudy
