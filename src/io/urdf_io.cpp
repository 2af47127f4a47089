#include "io/urdf_io.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "collision/collision.hpp"
#include "collision/ssv_fit.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"
#include "io/files.hpp"
#include "io/units.hpp"
#include "io/urdf_arm.hpp"
#include "io/urdf_internal.hpp"
#include "kinematics/kinematics.hpp"
#include "model/model_notes.hpp"

namespace armstudy {
namespace fs = std::filesystem;

std::pair<std::string, std::string> parsePackageOption(const std::string& text,
                                                       const std::string& option) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw InputError(option, 0, "package", "expected NAME=DIR, got '" + text + "'");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

Eigen::Matrix3d urdfAxisFrame(const Eigen::Vector3d& a) {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), a).toRotationMatrix();
}

void rejectUnexpandedXacro(const std::string& text, const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const std::size_t at = text.find("<xacro:");
  // A URDF written by xacro may keep the namespace declaration; its elements are what tells.
  const bool xacro = ext == ".xacro" || at != std::string::npos;
  if (!xacro) return;
  const int line = at == std::string::npos
                       ? 1
                       : 1 + static_cast<int>(std::count(
                                 text.begin(), text.begin() + static_cast<long>(at), '\n'));
  const std::string stem = fs::path(path).stem().string();
  const std::string out =
      (fs::path(path).parent_path() /
       (stem.size() > 5 && stem.compare(stem.size() - 5, 5, ".urdf") == 0 ? stem : stem + ".urdf"))
          .string();
  throw InputError(path, line, "xacro",
                   "a xacro file (URDF with macros), which armstudy does not expand: expand it "
                   "first with `xacro " +
                       path + " -o " + out +
                       "` (the ROS package xacro; `pip install xacro` gives it without ROS; add "
                       "NAME:=VALUE for the file's arguments), then use " +
                       out);
}

bool isUrdfPath(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".urdf";
}

namespace {

using namespace urdf_detail;
using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;

// urdfdom reports its errors only through console_bridge: collect them for our message.
class CaptureHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) messages.push_back(text);
  }
  std::vector<std::string> messages;
};

PoseXYZABG poseFromIso(const Isometry3d& T) {
  PoseXYZABG p;
  p.x = T.translation().x();
  p.y = T.translation().y();
  p.z = T.translation().z();
  const Vector3d a = T.linear().eulerAngles(0, 1, 2);  // R = Rx(a0) Ry(a1) Rz(a2)
  p.alpha = a[0];
  p.beta = a[1];
  p.gamma = a[2];
  return p;
}

std::string sanitizeName(const std::string& s) {
  std::string o;
  for (char c : s)
    o +=
        (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.') ? c : '_';
  return o.empty() ? "urdf_robot" : o;
}

// "no link named ..." with what the file has: its links.
std::string linkNotFoundMessage(const XmlIndex& xml, const std::string& file,
                                const std::string& name, const std::string& option) {
  std::string list;
  for (const auto& [n, line] : xml.links) list += (list.empty() ? "" : ", ") + n;
  return "no link named '" + name + "' (" + option + ") in " + file + "; its " +
         std::to_string(xml.links.size()) + " links: " + list +
         " (armstudy describe FILE lists the chains)";
}

// The URDF as urdfdom reads it; its complaints (console_bridge) become one InputError at the
// element they name.
urdf::ModelInterfaceSharedPtr parseWithUrdfdom(const std::string& text, const std::string& file,
                                               const XmlIndex& xml) {
  CaptureHandler capture;
  console_bridge::OutputHandler* previous = console_bridge::getOutputHandler();
  console_bridge::useOutputHandler(&capture);
  urdf::ModelInterfaceSharedPtr urdf;
  try {
    urdf = urdf::parseURDF(text);
  } catch (const std::exception& e) {
    capture.messages.push_back(e.what());
  }
  console_bridge::useOutputHandler(previous);
  if (!urdf) {
    std::string msg = "urdfdom cannot parse the file";
    for (const auto& s : capture.messages) msg += ": " + s;
    // Name the element when urdfdom's message does ("... [name] ...").
    int line = xml.robot_line;
    std::string key = "robot";
    for (const auto& s : capture.messages)
      for (std::size_t a = s.find('['); a != std::string::npos; a = s.find('[', a + 1)) {
        const auto b = s.find(']', a);
        if (b == std::string::npos) break;
        const std::string n = s.substr(a + 1, b - a - 1);
        if (xml.joints.count(n))
          line = xml.joints.at(n), key = "joint '" + n + "'";
        else if (xml.links.count(n))
          line = xml.links.at(n), key = "link '" + n + "'";
      }
    throw InputError(file, line, key, msg);
  }
  return urdf;
}

// One import: the parsed URDF, the chain from base to tip, and the model built along it.
struct UrdfImport {
  const std::string& text;
  const std::string& file;
  const UrdfOptions& o;
  const XmlIndex& xml;
  urdf::ModelInterfaceSharedPtr robot;
  urdf::LinkConstSharedPtr base, tip;
  std::vector<urdf::JointConstSharedPtr> chain;
  Model m;
  UrdfInfo info;
  std::vector<std::string> warnings;
  std::vector<std::vector<LinkInBody>> bodies;  // bodies[0] = base, bodies[i + 1] = after joint i
  std::set<std::string> on_chain;
  Isometry3d T_acc = Isometry3d::Identity();  // current body frame F -> current link frame L

  UrdfImport(const std::string& t, const std::string& f, const UrdfOptions& opt, const XmlIndex& x,
             urdf::ModelInterfaceSharedPtr r)
      : text(t), file(f), o(opt), xml(x), robot(std::move(r)) {}

  // Line of a joint (link) element, or of <robot> when the name is unknown.
  int jointLine(const std::string& n) const {
    return xml.joints.count(n) ? xml.joints.at(n) : xml.robot_line;
  }
  int linkLine(const std::string& n) const {
    return xml.links.count(n) ? xml.links.at(n) : xml.robot_line;
  }

  // The base link (--base or the URDF root) and the tip link (--tip or the default tip).
  void chooseBaseAndTip() {
    base = robot->getRoot();
    if (!o.base_link.empty()) {
      base = robot->getLink(o.base_link);
      if (!base)
        throw InputError(file, xml.robot_line, "base_link",
                         linkNotFound(o.base_link, "--base; base_link in a study"));
    }
    if (!o.tip_link.empty()) {
      tip = robot->getLink(o.tip_link);
      if (!tip)
        throw InputError(file, xml.robot_line, "tip_link",
                         linkNotFound(o.tip_link, "--tip; tip_link in a study"));
      return;
    }
    const UrdfChains c = findChains(*robot, base);
    if (c.ends.empty())
      throw InputError(
          file, linkLine(base->name), "link '" + base->name + "'",
          c.reason + "; choose the arm's base link with --base (base_link in a study)");
    if (c.chosen.empty())
      throw InputError(file, xml.robot_line, "tip_link",
                       c.reason + "; choose one with --tip (tip_link in a study)");
    tip = robot->getLink(c.chosen);
  }

  std::string linkNotFound(const std::string& name, const std::string& option) const {
    return linkNotFoundMessage(xml, file, name, option);
  }

  // The joints from base to tip, in order; then the model's names and the info's links.
  void collectChain() {
    for (urdf::LinkConstSharedPtr l = tip; l != base;) {
      if (!l->parent_joint)
        throw InputError(
            file, linkLine(tip->name), "link '" + tip->name + "'",
            "tip link '" + tip->name + "' is not below base link '" + base->name + "'");
      chain.push_back(l->parent_joint);
      l = robot->getLink(l->parent_joint->parent_link_name);
    }
    std::reverse(chain.begin(), chain.end());
    m.name = sanitizeName(robot->getName());
    m.file = file;
    m.source =
        "URDF " + fs::path(file).filename().string() + ", chain " + base->name + " -> " + tip->name;
    m.description = "Imported from " + file + " (robot '" + robot->getName() + "')";
    info.base_link = base->name;
    info.tcp_link = tip->name;
  }

  // Walks the chain: fixed joints fold their link onto the current body, movable ones start a
  // body and become model joints; then the joint count checks and the TCP.
  void buildJoints() {
    bodies.assign(1, {});
    bodies[0].push_back({base, Isometry3d::Identity()});
    on_chain.insert(base->name);
    for (const auto& j : chain) {
      const Isometry3d T_o = toIso(j->parent_to_joint_origin_transform);
      on_chain.insert(j->child_link_name);
      if (j->type == urdf::Joint::FIXED) {
        T_acc = T_acc * T_o;
        bodies.back().push_back({robot->getLink(j->child_link_name), T_acc});
        continue;
      }
      addMovableJoint(*j, T_o);
    }
    if (m.joints.empty())
      throw InputError(file, linkLine(tip->name), "link '" + tip->name + "'",
                       "no movable joint between '" + base->name + "' and '" + tip->name + "'");
    if (m.dof() > defaults::kMaxDof)
      throw InputError(
          file, linkLine(tip->name), "link '" + tip->name + "'",
          "more than " + std::to_string(defaults::kMaxDof) + " movable joints are not supported");
    m.tcp = poseFromIso(T_acc);
  }

  // One revolute, continuous or prismatic joint with origin T_o: its model joint, info and body.
  void addMovableJoint(const urdf::Joint& j, const Isometry3d& T_o) {
    const std::string jl = "joint '" + j.name + "'";
    if (j.type != urdf::Joint::REVOLUTE && j.type != urdf::Joint::CONTINUOUS &&
        j.type != urdf::Joint::PRISMATIC)
      throw InputError(file, jointLine(j.name), jl,
                       "joint type on the chain is not supported (floating and planar joints are "
                       "not serial-arm joints)");
    if (j.mimic)
      throw InputError(
          file, jointLine(j.name), jl + "/mimic",
          "mimic joints on the chain are not supported (the joint would not be independent); "
          "choose another --tip");
    Vector3d a(j.axis.x, j.axis.y, j.axis.z);
    if (!(a.norm() > 1e-12))
      throw InputError(file, jointLine(j.name), jl + "/axis", "joint axis is zero");
    a.normalize();
    Isometry3d R_a = Isometry3d::Identity();
    R_a.linear() = urdfAxisFrame(a);
    Joint J;
    UrdfJointInfo ji;
    J.name = j.name;
    ji.link = j.child_link_name;
    J.source_line = jointLine(j.name);
    J.type = j.type == urdf::Joint::PRISMATIC ? JointType::Prismatic : JointType::Revolute;
    J.offset = poseFromIso(T_acc * T_o * R_a);
    if (j.type == urdf::Joint::CONTINUOUS) {
      ji.continuous = true;
      J.limits.q_min = -defaults::kContinuousJointRange_rad;
      J.limits.q_max = defaults::kContinuousJointRange_rad;
    } else {
      if (!j.limits)
        throw InputError(file, jointLine(j.name), jl + "/limit",
                         "revolute and prismatic joints need <limit>");
      if (xml.joints_without_bounds.count(j.name))
        throw InputError(file, jointLine(j.name), jl + "/limit",
                         "<limit> has no lower or upper attribute (URDF then reads 0): give both, "
                         "or make a revolute joint without stops type=\"continuous\"");
      J.limits.q_min = j.limits->lower;
      J.limits.q_max = j.limits->upper;
      if (!(J.limits.q_min < J.limits.q_max)) {
        const std::string range =
            "lower = " + formatG(J.limits.q_min, 6) + ", upper = " + formatG(J.limits.q_max, 6);
        const std::string swapped = "lower=\"" + formatG(J.limits.q_max, 6) + "\" upper=\"" +
                                    formatG(J.limits.q_min, 6) + "\"";
        const std::string fix =
            J.limits.q_min > J.limits.q_max
                ? "the bounds are swapped: write " + std::string(swapped)
                : "the joint cannot move: give its range, make a revolute joint without stops "
                  "type=\"continuous\", or a joint that never moves type=\"fixed\"";
        throw InputError(file, jointLine(j.name), jl + "/limit",
                         std::string(range) +
                             ": the lower limit must be below the upper one "
                             "(armstudy sweeps the joint range); " +
                             fix);
      }
    }
    if (j.limits) {
      J.limits.qd_max = std::max(0.0, j.limits->velocity);
      ji.effort_max = std::max(0.0, j.limits->effort);
    }
    if (j.dynamics) {  // the joint's own friction (URDF: friction = Coulomb, damping = viscous)
      J.dynamics.coulomb = std::max(0.0, j.dynamics->friction);
      J.dynamics.viscous = std::max(0.0, j.dynamics->damping);
    }
    ji.R_FL = R_a.linear().transpose();
    m.joints.push_back(J);
    info.joints.push_back(ji);
    T_acc = R_a.inverse();  // F_i = L_i R_a, so L_i = F_i R_a^T
    bodies.push_back({{robot->getLink(j.child_link_name), T_acc}});
  }

  // A warning for each branch off the chain (fingers, sensors, tool frames): masses lumped only.
  void warnBranches() {
    for (const auto& [name, link] : robot->links_)
      if (!on_chain.count(name) && link->parent_joint &&
          on_chain.count(link->parent_joint->parent_link_name))
        warnings.push_back("URDF import: branch at link '" + name + "' (joint '" +
                           link->parent_joint->name + "') is off the chain " + base->name + " -> " +
                           tip->name +
                           ": its masses ride on the chain link it hangs from "
                           "(branch joints held at 0, clamped into their limits), "
                           "its collision geometry is not checked");
  }

  // Inertias: the body after joint i carries its link, the links folded onto it and the links
  // off the chain that ride on them (fixed links beyond the tip, branches with their joints held).
  void mergeBodyInertias() {
    std::vector<std::vector<LinkInBody>> masses(bodies.begin(), bodies.end());
    std::map<std::string, std::pair<std::size_t, Isometry3d>> body_of;  // chain link -> body, T_FL
    for (std::size_t b = 0; b < bodies.size(); ++b)
      for (const auto& lb : bodies[b]) body_of[lb.link->name] = {b, lb.T_FL};
    for (const OffChainLink& o : offChainLinks(*robot, on_chain)) {
      const auto& [b, T_FC] = body_of.at(o.chain_link);
      // The base does not move: masses on it do nothing; massless links add nothing.
      if (b == 0 || !o.link->inertial || !(o.link->inertial->mass > 0)) continue;
      masses[b].push_back({o.link, T_FC * o.T_CL});
      std::string held;
      for (const auto& h : o.held) held += (held.empty() ? "" : ", ") + h;
      const std::string kg = formatG(o.link->inertial->mass, 4) + " kg";
      notes::add(m, notes::kLumped,
                 "'" + o.link->name + "' (" + kg + ") onto '" + o.chain_link +
                     "' (body of joint '" + m.joints[b - 1].name + "')" +
                     (held.empty() ? ", rigidly" : ", joints held: " + held));
    }
    bool any_inertia = false;
    std::vector<LinkInertia> inertias;
    for (std::size_t b = 1; b < masses.size(); ++b) {
      inertias.push_back(mergeInertials(masses[b]));
      any_inertia = any_inertia || inertias.back().given;
    }
    if (any_inertia) m.inertias = inertias;
  }

  // The collision volumes of every body (when asked for) and the design hash over text, chain
  // and meshes.
  void addCollisionAndHash() {
    std::string mesh_hashes;
    if (o.collision)
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        const std::size_t before_body = m.collision.volumes.size();
        bool any_geometry = false;
        for (const auto& lb : bodies[b]) {
          const std::size_t before = m.collision.volumes.size();
          addCollision(m, static_cast<int>(b) - 1, lb, file, o, xml, warnings, mesh_hashes);
          const bool geometry = !lb.link->collision_array.empty();
          any_geometry = any_geometry || geometry;
          if (geometry && m.collision.volumes.size() == before)
            notes::add(m, notes::kNoCollision,
                       "'" + lb.link->name + "' (collision mesh not found or unreadable)");
        }
        if (!any_geometry && m.collision.volumes.size() == before_body)
          notes::add(m, notes::kNoCollision,
                     "'" + bodies[b].front().link->name + "' (no <collision> element)");
      }
    // The design hash covers what the model is made of: the URDF text, the chain and the meshes.
    m.file_hash =
        contentHash(text + "\nchain " + base->name + " " + tip->name + "\n" + mesh_hashes);
    if (static_cast<int>(m.collision.volumes.size()) > defaults::kMaxCollisionVolumes)
      throw InputError(
          file, xml.robot_line, "collision",
          "more than " + std::to_string(defaults::kMaxCollisionVolumes) + " collision volumes");
  }

  // Body pairs whose volumes touch at the reference configuration become allowed pairs.
  void allowTouchingPairs() {
    // Assumption (like MoveIt's "adjacent/default" pairs): bodies whose volumes touch at the
    // reference configuration (q = 0 clamped into the limits) touch by construction; they become
    // [[collision_allowed]] pairs, so a self-collision check reports real contacts only.
    Eigen::VectorXd q_ref(m.dof());
    for (int i = 0; i < m.dof(); ++i)
      q_ref[i] = std::clamp(0.0, m.joints[i].limits.q_min, m.joints[i].limits.q_max);
    KinematicsWorkspace kin(m);
    forwardKinematics(m, kin, q_ref);
    collision::CollisionWorkspace cws(m);
    collision::collisionDistances(m, kin, {}, cws);
    std::vector<std::string> allowed;
    for (int k = 0; k < cws.num_self; ++k) {
      const collision::PairDistance& p = cws.self[k];
      if (p.distance_m > 0) continue;
      m.collision.allowed_pairs.push_back(
          {std::min(p.link_a, p.link_b), std::max(p.link_a, p.link_b)});
      allowed.push_back(collision::pairName(m, p, false));
    }
    if (!allowed.empty()) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      m.assumptions.push_back(
          "URDF import: body pairs whose volumes touch at q = 0 (clamped into the limits) are "
          "allowed to touch: " +
          list);
    }
  }

  // The import's assumptions, then its warnings, into the model.
  void addAssumptions() {
    m.assumptions.push_back(
        "URDF import: joint values are the URDF's (about/along each URDF axis); body frame i "
        "is the URDF child link frame rotated so that its z axis is the joint axis");
    m.assumptions.push_back(
        "URDF import: a continuous joint sweeps +-2 pi (defaults::kContinuousJointRange_rad)");
    m.assumptions.push_back(
        "URDF import: collision meshes and boxes are fitted with at most " +
        std::to_string(defaults::kUrdfSsvMaxVolumesPerMesh) +
        " swept-sphere volumes each, cylinders become capsules, spheres points");
    for (const auto& w : warnings) m.assumptions.push_back(w);
  }
};

}  // namespace

UrdfChains findUrdfChains(const std::string& path, const UrdfOptions& o) {
  const std::string text = readFileOrThrow(path);
  const XmlIndex xml = indexAndCheck(text, path);
  const auto robot = parseWithUrdfdom(text, path, xml);
  urdf::LinkConstSharedPtr base = robot->getRoot();
  if (!o.base_link.empty() && !(base = robot->getLink(o.base_link)))
    throw InputError(path, xml.robot_line, "base_link",
                     linkNotFoundMessage(xml, path, o.base_link, "--base; base_link in a study"));
  return findChains(*robot, base);
}

// Checks the XML, parses it with urdfdom, then builds the model along the chain base -> tip.
Model importUrdfText(const std::string& text, const std::string& file, const UrdfOptions& o,
                     UrdfInfo* info_out, std::vector<std::string>* warnings_out) {
  rejectUnexpandedXacro(text, file);
  const XmlIndex xml = indexAndCheck(text, file);
  UrdfImport im(text, file, o, xml, parseWithUrdfdom(text, file, xml));
  im.chooseBaseAndTip();
  im.collectChain();
  im.buildJoints();
  im.warnBranches();
  im.mergeBodyInertias();
  im.addCollisionAndHash();
  im.m.finalize();
  if (!im.m.collision.empty()) im.allowTouchingPairs();
  im.addAssumptions();
  applyToolAxisFromArm(im.m);
  if (warnings_out) *warnings_out = im.warnings;
  if (info_out) *info_out = im.info;
  im.m.finalize();
  return im.m;
}

Model importUrdf(const std::string& path, const UrdfOptions& o, UrdfInfo* info,
                 std::vector<std::string>* warnings) {
  return importUrdfText(readFileOrThrow(path), path, o, info, warnings);
}

}  // namespace armstudy
