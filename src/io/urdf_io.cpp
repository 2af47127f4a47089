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
#include "io/files.hpp"
#include "io/units.hpp"
#include "io/urdf_internal.hpp"
#include "kinematics/kinematics.hpp"

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

bool isUrdfPath(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".urdf";
}

namespace urdf_detail {

namespace {

// The end of the markup starting at text[i] ('<'), one past its '>', or npos when unterminated;
// quoted attribute values may hold '>'.
std::size_t markupEnd(const std::string& text, std::size_t i) {
  for (const auto& [open, close] :
       {std::pair<const char*, const char*>{"<!--", "-->"}, {"<![CDATA[", "]]>"}, {"<?", "?>"}})
    if (text.compare(i, std::strlen(open), open) == 0) {
      const std::size_t e = text.find(close, i + std::strlen(open));
      return e == std::string::npos ? e : e + std::strlen(close);
    }
  char quote = 0;
  for (std::size_t j = i + 1; j < text.size(); ++j) {
    const char c = text[j];
    if (quote) {
      if (c == quote) quote = 0;
    } else if ((c == '"' || c == '\'') && text[i + 1] != '!') {
      quote = c;
    } else if (c == '>') {
      return j + 1;
    }
  }
  return std::string::npos;
}

}  // namespace

// Scans the tags of `text`. Elements nested more than defaults::kMaxXmlNesting deep are an
// InputError at the line of the first too deep one: the XML parsers recurse once per level, and a
// file of 60,000 nested elements would overflow the stack.
XmlTagScan scanXmlTags(const std::string& text, const std::string& file) {
  XmlTagScan out;
  std::vector<std::pair<std::string, int>> open;  // element name, line
  int line = 1;                                   // the line at text[i]
  std::size_t i = 0;
  auto problem = [&](int at) {
    if (!out.problem_line) out.problem_line = at;
  };
  auto lines = [&](std::size_t a, std::size_t b) {
    return static_cast<int>(
        std::count(text.begin() + static_cast<long>(a), text.begin() + static_cast<long>(b), '\n'));
  };
  for (std::size_t lt; (lt = text.find('<', i)) != std::string::npos;) {
    const std::size_t end = markupEnd(text, lt);
    const std::size_t stop = end == std::string::npos ? text.size() : end;
    const int tag_line = line + lines(i, lt);
    line = tag_line + lines(lt, stop);
    i = stop;
    if (end == std::string::npos) {
      problem(tag_line);
      break;
    }
    if (text[lt + 1] == '!' || text[lt + 1] == '?') continue;
    const bool closing = text[lt + 1] == '/';
    const std::size_t name_at = lt + (closing ? 2 : 1);
    const std::size_t name_end = text.find_first_of(" \t\r\n/>", name_at);
    const std::string name = text.substr(name_at, name_end - name_at);
    const unsigned char first = name.empty() ? 0 : static_cast<unsigned char>(name[0]);
    if (!(std::isalpha(first) || first == '_' || first == ':' || first >= 0x80))
      problem(tag_line);  // no element name: a stray '<'
    if (closing) {
      if (open.empty() || open.back().first != name) problem(tag_line);
      if (!open.empty()) open.pop_back();
    } else if (text[end - 2] != '/') {
      open.emplace_back(name, tag_line);
      if (open.size() > static_cast<std::size_t>(defaults::kMaxXmlNesting))
        throw InputError(file, tag_line, "xml",
                         "elements nested more than " + std::to_string(defaults::kMaxXmlNesting) +
                             " deep (<" + name + "> here; a robot description needs a few)");
    }
  }
  if (!open.empty()) problem(open.back().second);
  return out;
}

}  // namespace urdf_detail

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

std::string elementLabel(const TiXmlElement* e) {
  const char* name = e->Attribute("name");
  return std::string(e->Value()) + (name ? " '" + std::string(name) + "'" : std::string());
}

// Where URDF defines numbers: element paths below <joint> and <link>, with their numeric
// attributes. Other elements (vendor extensions such as <verbose>, <selfCollide>) are not URDF's
// and are ignored, as urdfdom does.
using NumberSchema = std::vector<std::pair<const char*, std::vector<const char*>>>;
const NumberSchema kJointNumbers = {
    {"origin", {"xyz", "rpy"}},
    {"axis", {"xyz"}},
    {"limit", {"lower", "upper", "effort", "velocity"}},
    {"dynamics", {"damping", "friction"}},
    {"mimic", {"multiplier", "offset"}},
    {"calibration", {"rising", "falling"}},
    {"safety_controller", {"soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"}}};
const NumberSchema kLinkNumbers = {{"inertial/origin", {"xyz", "rpy"}},
                                   {"inertial/mass", {"value"}},
                                   {"inertial/inertia", {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"}},
                                   {"visual/origin", {"xyz", "rpy"}},
                                   {"visual/geometry/box", {"size"}},
                                   {"visual/geometry/cylinder", {"radius", "length"}},
                                   {"visual/geometry/sphere", {"radius"}},
                                   {"visual/geometry/mesh", {"scale"}},
                                   {"collision/origin", {"xyz", "rpy"}},
                                   {"collision/geometry/box", {"size"}},
                                   {"collision/geometry/cylinder", {"radius", "length"}},
                                   {"collision/geometry/sphere", {"radius"}},
                                   {"collision/geometry/mesh", {"scale"}}};

// The dimension whose plausible magnitude (io/units.hpp) bounds a URDF attribute: lengths and
// positions (limits of prismatic joints too: both bounds are 1e3), angles, velocities; nullptr for
// plain numbers (masses, inertias, efforts, scales, gains).
const Dimension* attributeDimension(const std::string& attr) {
  static const Dimension length = Dimension::Length, angle = Dimension::Angle,
                         velocity = Dimension::AngularVelocity;
  static const std::set<std::string> lengths = {
      "xyz",   "size",  "radius",           "length",           "rising",
      "lower", "upper", "soft_lower_limit", "soft_upper_limit", "falling"};
  if (lengths.count(attr)) return &length;
  if (attr == "rpy") return &angle;
  if (attr == "velocity") return &velocity;
  return nullptr;
}

// Every number of attribute `attr` of element `e` must be finite and plausible: report the element
// and its line.
void checkAttribute(const TiXmlElement* e, const char* attr, const std::string& owner,
                    const std::string& file) {
  const char* v = e->Attribute(attr);
  if (!v) return;
  std::istringstream in(v);
  in.imbue(std::locale::classic());
  std::string tok;
  while (in >> tok) {
    std::string problem;
    try {
      std::size_t used = 0;
      const double d = std::stod(tok, &used);
      if (used != tok.size() || !std::isfinite(d))
        problem = "'" + tok + "' is not a finite number";
      else if (const std::string p = implausible(d, attributeDimension(attr)); !p.empty())
        problem = "'" + tok + "': " + p;
    } catch (const std::exception&) {
      problem = "'" + tok + "' is not a finite number";
    }
    if (!problem.empty())
      throw InputError(file, e->Row(), owner + "/" + e->Value() + "@" + attr, problem);
  }
}

// The elements at `path` ("a/b/c") below `e`, each checked for the attributes `attrs`.
void checkAt(const TiXmlElement* e, const std::string& path, const std::vector<const char*>& attrs,
             const std::string& owner, const std::string& file) {
  const auto slash = path.find('/');
  const std::string head = path.substr(0, slash);
  for (const TiXmlElement* c = e->FirstChildElement(head.c_str()); c;
       c = c->NextSiblingElement(head.c_str())) {
    if (slash != std::string::npos) {
      checkAt(c, path.substr(slash + 1), attrs, owner, file);
      continue;
    }
    for (const char* a : attrs) checkAttribute(c, a, owner, file);
  }
}

void checkNumbers(const TiXmlElement* e, const NumberSchema& schema, const std::string& owner,
                  const std::string& file) {
  for (const auto& [path, attrs] : schema) checkAt(e, path, attrs, owner, file);
}

// Joints whose <limit> lacks lower or upper (URDF reads them as 0).
bool limitWithoutBounds(const TiXmlElement* joint) {
  const TiXmlElement* l = joint->FirstChildElement("limit");
  return l && (!l->Attribute("lower") || !l->Attribute("upper"));
}

XmlIndex indexAndCheck(const std::string& text, const std::string& file) {
  const XmlTagScan tags = scanXmlTags(text, file);
  TiXmlDocument doc;
  doc.Parse(text.c_str());
  if (doc.Error()) {
    // TinyXML gives no row for some errors (a comment never closed, say) and a later one for
    // others (a stray '<'): the earlier of its row and the scan's line.
    int line = doc.ErrorRow() > 0 ? doc.ErrorRow() : 1;
    if (tags.problem_line > 0 && (doc.ErrorRow() <= 0 || tags.problem_line < line))
      line = tags.problem_line;
    throw InputError(file, line, "xml", std::string("not well-formed XML: ") + doc.ErrorDesc());
  }
  const TiXmlElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw InputError(file, 1, "robot", "no <robot> element: not a URDF file");
  XmlIndex out;
  out.robot_line = robot->Row();
  struct {
    std::map<std::string, const TiXmlElement*> links, joints;
  } idx;
  static const std::set<std::string> kTypes = {"revolute", "continuous", "prismatic",
                                               "fixed",    "floating",   "planar"};
  for (const TiXmlElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string tag = e->Value();
    if (tag != "link" && tag != "joint") continue;
    const char* name = e->Attribute("name");
    if (!name) throw InputError(file, e->Row(), tag, "<" + tag + "> without a name");
    auto& map = tag == "link" ? idx.links : idx.joints;
    if (map.count(name))
      throw InputError(file, e->Row(), elementLabel(e), tag + " name '" + name + "' is used twice");
    map[name] = e;
  }
  for (const auto& [name, e] : idx.joints) {
    const std::string label = elementLabel(e);
    const char* type = e->Attribute("type");
    if (!type || !kTypes.count(type))
      throw InputError(file, e->Row(), label + "@type",
                       "unknown joint type '" + std::string(type ? type : "") +
                           "' (URDF: revolute, continuous, prismatic, fixed, floating, planar)");
    for (const char* role : {"parent", "child"}) {
      const TiXmlElement* r = e->FirstChildElement(role);
      const char* link = r ? r->Attribute("link") : nullptr;
      if (!link)
        throw InputError(file, e->Row(), label + "/" + role,
                         std::string("joint has no <") + role + " link=...>");
      if (!idx.links.count(link))
        throw InputError(file, r->Row(), label + "/" + role,
                         std::string(role) + " link '" + link + "' is not defined in this file");
    }
    checkNumbers(e, kJointNumbers, label, file);
    if (limitWithoutBounds(e)) out.joints_without_bounds.insert(name);
  }
  for (const auto& [name, e] : idx.links) checkNumbers(e, kLinkNumbers, elementLabel(e), file);
  // Each link has at most one parent joint; following parents from any link must reach a root.
  std::map<std::string, std::string> parent_of;  // child link -> joint
  for (const auto& [name, e] : idx.joints) {
    const std::string child = e->FirstChildElement("child")->Attribute("link");
    if (parent_of.count(child))
      throw InputError(file, e->Row(), elementLabel(e),
                       "link '" + child + "' has two parent joints ('" + parent_of[child] +
                           "' and '" + name + "'): a URDF is a tree");
    parent_of[child] = name;
  }
  for (const auto& [link, joint] : parent_of) {
    std::set<std::string> seen{link};
    std::string cur = link;
    while (parent_of.count(cur)) {
      const TiXmlElement* j = idx.joints.at(parent_of[cur]);
      cur = j->FirstChildElement("parent")->Attribute("link");
      if (!seen.insert(cur).second)
        throw InputError(file, j->Row(), elementLabel(j),
                         "the joints form a cycle through link '" + cur + "'");
    }
  }
  for (const auto& [name, e] : idx.links) out.links[name] = e->Row();
  for (const auto& [name, e] : idx.joints) out.joints[name] = e->Row();
  return out;  // the document dies here: keep lines, not elements
}

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

// Inertials of the links of one body, merged into one rigid body about its COM, in frame F.
LinkInertia mergeInertials(const std::vector<LinkInBody>& links) {
  LinkInertia out;
  double mass = 0;
  Vector3d mc = Vector3d::Zero();
  struct Part {
    double m;
    Vector3d c;
    Matrix3d I;
  };
  std::vector<Part> parts;
  for (const auto& lb : links) {
    const auto& in = lb.link->inertial;
    if (!in) continue;
    out.given = true;
    const Isometry3d T = lb.T_FL * toIso(in->origin);  // inertial frame in F
    Matrix3d I;
    I << in->ixx, in->ixy, in->ixz, in->ixy, in->iyy, in->iyz, in->ixz, in->iyz, in->izz;
    const Matrix3d R = T.linear();
    parts.push_back({in->mass, T.translation(), R * I * R.transpose()});
    mass += in->mass;
    mc += in->mass * T.translation();
  }
  if (!out.given) return out;
  out.mass_kg = mass;
  out.p_com_m = mass > 0 ? Vector3d(mc / mass) : parts.front().c;
  Matrix3d I = Matrix3d::Zero();
  for (const Part& p : parts) {  // parallel-axis theorem to the common COM
    const Vector3d d = p.c - out.p_com_m;
    I += p.I + p.m * (d.squaredNorm() * Matrix3d::Identity() - d * d.transpose());
  }
  out.I_com_kgm2 = I;
  return out;
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
      if (!(J.limits.q_min < J.limits.q_max))
        throw InputError(file, jointLine(j.name), jl + "/limit",
                         "lower limit must be below upper limit (armstudy sweeps the joint range)");
    }
    if (j.limits) {
      J.limits.qd_max = std::max(0.0, j.limits->velocity);
      ji.effort_max = std::max(0.0, j.limits->effort);
    }
    ji.R_FL = R_a.linear().transpose();
    m.joints.push_back(J);
    info.joints.push_back(ji);
    T_acc = R_a.inverse();  // F_i = L_i R_a, so L_i = F_i R_a^T
    bodies.push_back({{robot->getLink(j.child_link_name), T_acc}});
  }

  // A warning for each branch off the chain (fingers, sensors, tool frames): they are ignored.
  void warnBranches() {
    for (const auto& [name, link] : robot->links_)
      if (!on_chain.count(name) && link->parent_joint &&
          on_chain.count(link->parent_joint->parent_link_name))
        warnings.push_back("URDF import: branch at link '" + name + "' (joint '" +
                           link->parent_joint->name + "') is off the chain " + base->name + " -> " +
                           tip->name + " and ignored");
  }

  // Inertias: the body after joint i carries its link and the links folded onto it.
  void mergeBodyInertias() {
    bool any_inertia = false;
    std::vector<LinkInertia> inertias;
    for (std::size_t b = 1; b < bodies.size(); ++b) {
      inertias.push_back(mergeInertials(bodies[b]));
      any_inertia = any_inertia || inertias.back().given;
    }
    if (any_inertia) m.inertias = inertias;
  }

  // The collision volumes of every body (when asked for) and the design hash over text, chain
  // and meshes.
  void addCollisionAndHash() {
    std::string mesh_hashes;
    if (o.collision)
      for (std::size_t b = 0; b < bodies.size(); ++b)
        for (const auto& lb : bodies[b])
          addCollision(m, static_cast<int>(b) - 1, lb, file, o, xml, warnings, mesh_hashes);
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
