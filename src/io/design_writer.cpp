// The design TOML writer (designToToml, io/urdf_io.hpp): every value of a Model at full
// round-trip precision, so that the text read back is the same Model.
#include <sstream>

#include "common/format.hpp"
#include "io/design_keys.hpp"
#include "io/urdf_io.hpp"
#include "model/model_notes.hpp"

namespace armstudy {

namespace {
std::string quoted(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (c == '\n') {
      o += "\\n";
      continue;
    }
    o += c;
  }
  return o + "\"";
}
void writePose(std::ostringstream& o, const PoseXYZABG& p, bool all) {
  const std::pair<const char*, double> f[] = {
      {"x", p.x}, {"y", p.y}, {"z", p.z}, {"alpha", p.alpha}, {"beta", p.beta}, {"gamma", p.gamma}};
  for (const auto& [k, v] : f)
    if (all || v != 0) o << k << " = " << formatTomlFloat(v) << "\n";
}
std::string vec3(const Eigen::Vector3d& v) {
  return "[" + formatTomlFloat(v.x()) + ", " + formatTomlFloat(v.y()) + ", " +
         formatTomlFloat(v.z()) + "]";
}
}  // namespace

std::string designToToml(const Model& m, const UrdfInfo& info) {
  const bool has_joint_info = info.joints.size() == m.joints.size();
  std::ostringstream o;
  o << "# Written by armstudy (design format: docs/design-format.md). SI units: m, rad, kg, s.\n";
  o << "[design]\nname = " << quoted(m.name) << "\n";
  if (!m.description.empty()) o << "description = " << quoted(m.description) << "\n";
  if (!m.source.empty()) o << "source = " << quoted(m.source) << "\n";
  if (!m.assumptions.empty()) {
    o << "assumptions = [\n";
    for (const auto& a : m.assumptions) o << "  " << quoted(a) << ",\n";
    o << "]\n";
  }
  o << "\n[base]\n";
  if (!info.base_link.empty()) o << "link = " << quoted(info.base_link) << "\n";
  writePose(o, m.base, false);
  for (std::size_t i = 0; i < m.joints.size(); ++i) {
    const Joint& j = m.joints[i];
    const UrdfJointInfo ji = has_joint_info ? info.joints[i] : UrdfJointInfo{};
    o << "\n[[joint]]\nname = " << quoted(j.name) << "\ntype = " << quoted(toString(j.type))
      << "\n";
    if (!ji.link.empty()) o << "link = " << quoted(ji.link) << "\n";
    if (!ji.R_FL.isIdentity(0)) {
      const Eigen::Vector3d a = ji.R_FL.transpose() * Eigen::Vector3d::UnitZ();
      o << "link_axis = [" << formatTomlFloat(a.x()) << ", " << formatTomlFloat(a.y()) << ", "
        << formatTomlFloat(a.z()) << "]\n";
    }
    writePose(o, j.offset, true);
    if (ji.continuous) o << "continuous = true\n";
    o << "min = " << formatTomlFloat(j.limits.q_min)
      << "\nmax = " << formatTomlFloat(j.limits.q_max) << "\n";
    if (j.limits.qd_max > 0) o << "max_velocity = " << formatTomlFloat(j.limits.qd_max) << "\n";
    if (ji.effort_max > 0) o << "max_effort = " << formatTomlFloat(ji.effort_max) << "\n";
    for (const JointDynamicsValue& v : kJointDynamicsValues)
      if (j.dynamics.*v.value != 0)
        o << v.key << " = " << formatTomlFloat(j.dynamics.*v.value) << "\n";
  }
  o << "\n[tcp]\n";
  if (!info.tcp_link.empty()) o << "link = " << quoted(info.tcp_link) << "\n";
  writePose(o, m.tcp, false);
  if (notes::toolAxisOpen(m).empty() &&
      (m.tool_axis_T != Eigen::Vector3d::UnitZ() || !info.joints.empty()))
    o << "tool_axis = [" << formatTomlFloat(m.tool_axis_T.x()) << ", "
      << formatTomlFloat(m.tool_axis_T.y()) << ", " << formatTomlFloat(m.tool_axis_T.z()) << "]\n";
  for (std::size_t i = 0; i < m.inertias.size(); ++i) {
    const LinkInertia& li = m.inertias[i];
    if (!li.given) continue;
    const Eigen::Matrix3d& I = li.I_com_kgm2;
    o << "\n[[inertia]]\nlink = " << quoted(m.joints[i].name)
      << "\nmass = " << formatTomlFloat(li.mass_kg) << "\ncom = " << vec3(li.p_com_m)
      << "\ninertia = [" << formatTomlFloat(I(0, 0)) << ", " << formatTomlFloat(I(1, 1)) << ", "
      << formatTomlFloat(I(2, 2)) << ", " << formatTomlFloat(I(0, 1)) << ", "
      << formatTomlFloat(I(0, 2)) << ", " << formatTomlFloat(I(1, 2)) << "]\n";
  }
  if (m.payload_kg > 0)
    o << "\n[payload]\nmass = " << formatTomlFloat(m.payload_kg)
      << "\ncom = " << vec3(m.p_payload_com_T) << "\n";
  for (const Drive& d : m.drives) {
    o << "\n[[drive]]\njoint = " << quoted(d.joint) << "\n";
    if (!d.module.empty()) o << "module = " << quoted(d.module) << "\n";
    o << "gear_ratio = " << formatTomlFloat(d.gear_ratio)
      << "\ntorque_constant = " << formatTomlFloat(d.torque_constant_NmpA) << "\n";
    for (const OptionalDriveValue& v : kOptionalDriveValues)
      if (d.*v.value != 0) o << v.key << " = " << formatTomlFloat(d.*v.value) << "\n";
    if (!d.friction_law.empty()) {
      o << "[drive.friction]\nlaw = " << quoted(d.friction_law) << "\n";
      for (const auto& [k, v] : d.friction) o << k << " = " << formatTomlFloat(v) << "\n";
    }
  }
  if (!m.effects.empty()) {
    o << "\n[model]\neffects = [";
    for (std::size_t i = 0; i < m.effects.size(); ++i) o << (i ? ", " : "") << quoted(m.effects[i]);
    o << "]\n";
  }
  auto linkName = [&](int link) { return link < 0 ? std::string("base") : m.joints[link].name; };
  for (const CollisionVolume& v : m.collision.volumes) {
    o << "\n[[collision]]\n";
    if (!v.name.empty()) o << "name = " << quoted(v.name) << "\n";
    o << "link = " << quoted(linkName(v.link)) << "\ntype = " << quoted(toString(v.type))
      << "\npoints = [";
    for (int k = 0; k < static_cast<int>(v.type); ++k) o << (k ? ", " : "") << vec3(v.p_L[k]);
    o << "]\nradius = " << formatTomlFloat(v.radius_m) << "\n";
  }
  for (const auto& p : m.collision.allowed_pairs)
    o << "\n[[collision_allowed]]\nlinks = [" << quoted(linkName(p[0])) << ", "
      << quoted(linkName(p[1])) << "]\n";
  return o.str();
}

}  // namespace armstudy
