#include "ik/pose_task.hpp"

#include <cmath>

#include "common/enum_names.hpp"
#include "common/errors.hpp"

namespace armstudy {

constexpr const char* kPoseTaskKindNames[] = {"position", "position_axis", "full", "cardan_angles"};
const char* toString(PoseTaskKind k) { return enumName(k, kPoseTaskKindNames); }

int PoseTask::positionRows() const {
  return (position_selected[0] ? 1 : 0) + (position_selected[1] ? 1 : 0) +
         (position_selected[2] ? 1 : 0);
}

int PoseTask::orientationRows() const {
  switch (kind) {
    case PoseTaskKind::Position:
      return 0;
    case PoseTaskKind::PositionAxis:
      return 2;
    case PoseTaskKind::FullPose:
      return 3;
    case PoseTaskKind::CardanAngles:
      break;
  }
  return (angle_selected[0] ? 1 : 0) + (angle_selected[1] ? 1 : 0) + (angle_selected[2] ? 1 : 0);
}

int taskDim(PoseTaskKind k) {
  ARMSTUDY_CHECK(k != PoseTaskKind::CardanAngles, "taskDim: the rows of Cardan angles vary");
  return k == PoseTaskKind::Position ? 3 : (k == PoseTaskKind::PositionAxis ? 5 : 6);
}

PoseTask positionTask(const Eigen::Vector3d& p_WT) {
  return {.kind = PoseTaskKind::Position, .p_WT = p_WT};
}

PoseTask positionAxisTask(const Eigen::Vector3d& p_WT, const Eigen::Vector3d& axis_W) {
  return {.kind = PoseTaskKind::PositionAxis, .p_WT = p_WT, .axis_W = axis_W};
}

PoseTask fullPoseTask(const Eigen::Vector3d& p_WT, const Eigen::Matrix3d& R_WT) {
  return {.kind = PoseTaskKind::FullPose, .p_WT = p_WT, .R_WT = R_WT};
}

void perpendicularBasis(const Eigen::Vector3d& a, Eigen::Vector3d& b1, Eigen::Vector3d& b2) {
  int k = 0;
  a.cwiseAbs().minCoeff(&k);
  b1 = a.cross(Eigen::Vector3d::Unit(k)).normalized();
  b2 = a.cross(b1);
}

Eigen::Vector3d rotationBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                double* angle_out) {
  const Eigen::Vector3d c = a.cross(b);
  const double s = c.norm(), co = a.dot(b);
  const double angle = std::atan2(s, co);
  if (angle_out) *angle_out = angle;
  if (s < 1e-300) {
    if (co > 0) return Eigen::Vector3d::Zero();
    Eigen::Vector3d b1, b2;  // antiparallel: any perpendicular axis
    perpendicularBasis(a, b1, b2);
    return angle * b1;
  }
  return (angle / s) * c;
}

Eigen::Vector3d sprayDirection(double alpha, double gamma) {
  return Eigen::Vector3d(-std::sin(gamma), std::cos(alpha) * std::cos(gamma),
                         std::sin(alpha) * std::cos(gamma));
}

PoseTask taskTarget(const TaskSpace& task_space, const TaskVector6& w_d) {
  const auto& s = task_space.selected;
  PoseTask t;
  t.position_selected = {s[0], s[1], s[2]};
  t.p_WT = w_d.head<3>();
  if (s[3] && !s[4] && s[5]) {  // spraying: position (as selected) + the spray axis, roll free
    t.kind = PoseTaskKind::PositionAxis;
    t.axis_W = sprayDirection(w_d[3], w_d[5]);
  } else if (s[3] && s[4] && s[5]) {
    t.kind = PoseTaskKind::FullPose;
    t.R_WT = rotationFromCardan(w_d[3], w_d[4], w_d[5]);
  } else if (s[3] || s[4] || s[5]) {
    t.kind = PoseTaskKind::CardanAngles;
    t.angle_selected = {s[3], s[4], s[5]};
    t.angles = w_d.tail<3>();
  } else {
    t.kind = PoseTaskKind::Position;
  }
  return t;
}

bool usesCardanAngles(const TaskSpace& task_space) {
  const auto& s = task_space.selected;
  const bool any = s[3] || s[4] || s[5], full = s[3] && s[4] && s[5],
             spraying = s[3] && !s[4] && s[5];
  return any && !full && !spraying;
}

}  // namespace armstudy
