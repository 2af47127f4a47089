#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "collision/collision.hpp"
#include "collision/ssv_fit.hpp"
#include "common/errors.hpp"
#include "common/escape.hpp"
#include "common/format.hpp"
#include "io/files.hpp"
#include "io/urdf_io.hpp"
#include "kinematics/kinematics.hpp"

namespace armstudy {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {
bool isIdentity(const Isometry3d& T) { return T.isApprox(Isometry3d::Identity(), 1e-15); }
// A TCP frame this close to the last link frame is that frame (rounding of the Cardan angles that
// carry it through the design table).
constexpr double kSameFrameTolerance = 1e-12;

Isometry3d rotation(const Matrix3d& R) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = R;
  return T;
}

std::string vec(const Vector3d& v) {
  return formatRoundTrip(v.x()) + " " + formatRoundTrip(v.y()) + " " + formatRoundTrip(v.z());
}
std::string origin(const Isometry3d& T) {
  const Vector3d ypr = T.linear().eulerAngles(2, 1, 0);  // R = Rz(yaw) Ry(pitch) Rx(roll)
  return "<origin xyz=\"" + vec(T.translation()) + "\" rpy=\"" + formatRoundTrip(ypr[2]) + " " +
         formatRoundTrip(ypr[1]) + " " + formatRoundTrip(ypr[0]) + "\"/>";
}
std::string inertial(double mass, const Vector3d& c, const Matrix3d& I) {
  return "    <inertial>\n      <origin xyz=\"" + vec(c) +
         "\" rpy=\"0 0 0\"/>\n      <mass value=\"" + formatRoundTrip(mass) +
         "\"/>\n      <inertia ixx=\"" + formatRoundTrip(I(0, 0)) + "\" ixy=\"" +
         formatRoundTrip(I(0, 1)) + "\" ixz=\"" + formatRoundTrip(I(0, 2)) + "\" iyy=\"" +
         formatRoundTrip(I(1, 1)) + "\" iyz=\"" + formatRoundTrip(I(1, 2)) + "\" izz=\"" +
         formatRoundTrip(I(2, 2)) + "\"/>\n    </inertial>\n";
}
}  // namespace

std::string exportUrdf(const Model& m, const UrdfInfo& info) {
  const bool has_joint_info = info.joints.size() == m.joints.size();
  std::ostringstream o;
  std::set<std::string> used;
  auto unique = [&](std::string n) {
    while (!used.insert(n).second) n += "_";
    return n;
  };
  const std::string base = unique(info.base_link.empty() ? "base_link" : info.base_link);
  std::vector<std::string> links;
  for (int i = 0; i < m.dof(); ++i) {
    const std::string& l = has_joint_info ? info.joints[i].link : std::string();
    links.push_back(unique(l.empty() ? m.joints[i].name + "_link" : l));
  }
  // R_FL[i]: the URDF link frame L_i in the body frame F_i (R_FL[0]: the base, identity).
  std::vector<Matrix3d> R_FL(m.dof() + 1, Matrix3d::Identity());
  for (int i = 0; i < m.dof() && has_joint_info; ++i) R_FL[i + 1] = info.joints[i].R_FL;
  const Isometry3d T_LT = rotation(R_FL.back()).inverse() * m.T_NT;  // TCP in the last link frame
  const bool tcp_is_last = T_LT.isApprox(Isometry3d::Identity(), kSameFrameTolerance) &&
                           m.payload_kg == 0 &&
                           (info.tcp_link.empty() || info.tcp_link == links.back());
  const std::string tcp =
      tcp_is_last ? links.back() : unique(info.tcp_link.empty() ? "tcp" : info.tcp_link);
  o << "<?xml version=\"1.0\"?>\n<!-- Written by armstudy from design '" << xmlEscape(m.name)
    << "' (docs/design-format.md, \"URDF\"). Not exported: drives, model effects, collision "
       "volumes. -->\n";
  o << "<robot name=\"" << xmlEscape(m.name) << "\">\n";
  if (!isIdentity(m.T_WB)) {
    const std::string world = unique("world");
    o << "  <link name=\"" << world << "\"/>\n  <joint name=\"" << unique(world + "_joint")
      << "\" type=\"fixed\">\n    <parent link=\"" << world << "\"/>\n    <child link=\""
      << xmlEscape(base) << "\"/>\n    " << origin(m.T_WB) << "\n  </joint>\n";
  }
  o << "  <link name=\"" << xmlEscape(base) << "\"/>\n";
  for (int i = 0; i < m.dof(); ++i) {
    const Joint& j = m.joints[i];
    const UrdfJointInfo ji = has_joint_info ? info.joints[i] : UrdfJointInfo{};
    const char* type = j.type == JointType::Prismatic ? "prismatic"
                       : ji.continuous                ? "continuous"
                                                      : "revolute";
    // L_{i-1}^-1 L_i = R_FL[i-1]^T T_PJ0 M_z(q) R_FL[i] = (R_FL[i-1]^T T_PJ0 R_FL[i]) M_a(q),
    // a motion about (along) a = R_FL[i]^T e_z in L_i.
    const Isometry3d T_origin = rotation(R_FL[i]).inverse() * j.T_PJ0 * rotation(R_FL[i + 1]);
    const Vector3d axis = R_FL[i + 1].transpose() * Vector3d::UnitZ();
    o << "  <joint name=\"" << xmlEscape(j.name) << "\" type=\"" << type
      << "\">\n    <parent link=\"" << xmlEscape(i == 0 ? base : links[i - 1])
      << "\"/>\n    <child link=\"" << xmlEscape(links[i]) << "\"/>\n    " << origin(T_origin)
      << "\n    <axis xyz=\"" << (R_FL[i + 1].isIdentity(0) ? "0 0 1" : vec(axis))
      << "\"/>\n    <limit";
    if (!ji.continuous)
      o << " lower=\"" << formatRoundTrip(j.limits.q_min) << "\" upper=\""
        << formatRoundTrip(j.limits.q_max) << "\"";
    o << " effort=\"" << formatRoundTrip(ji.effort_max) << "\" velocity=\""
      << formatRoundTrip(j.limits.qd_max) << "\"/>\n";
    if (j.dynamics.coulomb != 0 || j.dynamics.viscous != 0)
      o << "    <dynamics damping=\"" << formatRoundTrip(j.dynamics.viscous) << "\" friction=\""
        << formatRoundTrip(j.dynamics.coulomb) << "\"/>\n";
    o << "  </joint>\n";
    o << "  <link name=\"" << xmlEscape(links[i]) << "\">\n";
    if (!m.inertias.empty() && m.inertias[i].given) {
      const Matrix3d R_LF = R_FL[i + 1].transpose();
      o << inertial(m.inertias[i].mass_kg, R_LF * m.inertias[i].p_com_m,
                    R_LF * m.inertias[i].I_com_kgm2 * R_LF.transpose());
    }
    o << "  </link>\n";
  }
  if (!tcp_is_last) {
    o << "  <joint name=\"" << unique(tcp + "_joint") << "\" type=\"fixed\">\n    <parent link=\""
      << xmlEscape(links.back()) << "\"/>\n    <child link=\"" << xmlEscape(tcp) << "\"/>\n    "
      << origin(T_LT) << "\n  </joint>\n  <link name=\"" << xmlEscape(tcp) << "\">\n";
    if (m.payload_kg > 0) o << inertial(m.payload_kg, m.p_payload_com_T, Matrix3d::Zero());
    o << "  </link>\n";
  }
  o << "</robot>\n";
  return o.str();
}

}  // namespace armstudy
