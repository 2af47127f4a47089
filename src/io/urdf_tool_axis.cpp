// The tool axis of a URDF arm from its last joint (io/urdf_io.hpp, applyToolAxisFromArm).
#include <cmath>
#include <string>

#include "common/angles.hpp"
#include "common/format.hpp"
#include "io/urdf_arm.hpp"
#include "io/urdf_io.hpp"
#include "model/model_notes.hpp"

namespace armstudy {

namespace {

std::string vecText(const Eigen::Vector3d& v) {
  // + 0.0 writes -0 as 0.
  return "[" + formatFixed(v.x() + 0.0, 4) + ", " + formatFixed(v.y() + 0.0, 4) + ", " +
         formatFixed(v.z() + 0.0, 4) + "]";
}

// The signed TCP axis nearest to the unit vector a ("y", "-z", ...) and its angle to a.
std::pair<std::string, double> nearestTcpAxis(const Eigen::Vector3d& a, Eigen::Vector3d* unit) {
  int k = 0;
  a.cwiseAbs().maxCoeff(&k);
  const double sign = a[k] < 0 ? -1.0 : 1.0;
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  e[k] = sign;
  if (unit) *unit = e;
  const double angle = std::atan2(a.cross(e).norm(), a.dot(e));
  return {std::string(sign < 0 ? "-" : "") + "xyz"[k], angle};
}

}  // namespace

ArmToolAxis lastJointAxisInTcp(const Model& m) {
  ArmToolAxis out;
  if (m.joints.empty()) return out;
  out.joint = m.joints.back().name;
  // In the frame N after the last joint, its axis is the z axis through N's origin (for any q).
  const Eigen::Vector3d p = m.T_NT.translation();
  const Eigen::Matrix3d R = m.T_NT.linear();
  out.off_axis_m = std::hypot(p.x(), p.y());
  out.along_m = p.z();
  // The direction away from the joint's origin towards the TCP; the URDF axis direction when the
  // TCP is at the joint's origin along the axis (a tool points away from the arm).
  const double sign = out.along_m < -defaults::kToolOnAxis_m ? -1.0 : 1.0;
  out.axis_T = R.transpose() * Eigen::Vector3d(0, 0, sign);
  Eigen::Vector3d e;
  const auto [name, angle] = nearestTcpAxis(out.axis_T, &e);
  out.nearest = name;
  out.nearest_angle_rad = angle;
  if (angle <= defaults::kToolAxisSnap_rad) out.axis_T = e;  // exactly a TCP axis
  out.on_axis = out.off_axis_m <= defaults::kToolOnAxis_m;
  return out;
}

void applyToolAxisFromArm(Model& m) {
  m.finalize();
  const ArmToolAxis a = lastJointAxisInTcp(m);
  if (a.joint.empty()) return;
  const std::string mm = formatFixed(a.off_axis_m * 1e3, 1) + " mm";
  const std::string named = a.nearest_angle_rad <= defaults::kToolAxisSnap_rad
                                ? "\"" + a.nearest + "\""
                                : vecText(a.axis_T);
  if (a.on_axis) {
    m.tool_axis_T = a.axis_T;
    notes::toolAxisNamed(m, "the last joint's axis ('" + a.joint + "'), TCP " + named +
                                ": the TCP lies on it (" + mm + " off it, within " +
                                std::to_string(static_cast<int>(defaults::kToolOnAxis_m * 1e3)) +
                                " mm)");
    return;
  }
  m.tool_axis_T = Eigen::Vector3d::UnitZ();
  notes::set(
      m, notes::kToolAxisFrom,
      "not taken from the arm: the TCP is " + std::string(mm) + " off the last joint's axis");
  const std::string deg = formatFixed(toDegrees(a.nearest_angle_rad), 1) + " deg";
  // The candidates: the TCP axis nearest the joint's axis, z (the TCP's own default), and the
  // joint's axis itself when no TCP axis is parallel to it.
  std::string candidates =
      "\"" + a.nearest + "\" (the TCP axis nearest the joint's axis, " + deg + " from it)";
  if (a.nearest != "z") candidates += ", \"z\" (the TCP z axis)";
  if (a.nearest_angle_rad > defaults::kToolAxisSnap_rad)
    candidates += ", " + vecText(a.axis_T) + " (the joint's axis)";
  notes::set(m, notes::kToolAxisOpen,
             "the TCP of design '" + m.name + "' is " + mm + " off the last joint's axis ('" +
                 a.joint + "', " + vecText(a.axis_T) +
                 " in the TCP frame), so the tool axis is not taken from the arm; candidates: " +
                 candidates +
                 "; name one with tool_axis in the study's [[design]] entry (or the stage's "
                 "tool_axis table, or [tcp] tool_axis of a design TOML), or choose a tip on the "
                 "joint's axis (--tip, tip_link)");
}

}  // namespace armstudy
