#include "io/design_io.hpp"

#include <Eigen/Eigenvalues>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "collision/collision_model.hpp"
#include "common/names.hpp"
#include "drive/friction.hpp"
#include "io/design_keys.hpp"
#include "io/files.hpp"
#include "io/ssv_io.hpp"
#include "io/toml_reader.hpp"
#include "io/urdf_arm.hpp"
#include "io/urdf_io.hpp"
#include "model/model_notes.hpp"

namespace armstudy {
namespace {

using io::TableReader;

PoseXYZABG readPose(TableReader& r, bool all_required) {
  PoseXYZABG p;
  auto len = [&](const char* k) {
    return all_required ? r.quantity(k, Dimension::Length) : r.quantity(k, Dimension::Length, 0.0);
  };
  auto ang = [&](const char* k) {
    return all_required ? r.quantity(k, Dimension::Angle) : r.quantity(k, Dimension::Angle, 0.0);
  };
  p.x = len("x");
  p.y = len("y");
  p.z = len("z");
  p.alpha = ang("alpha");
  p.beta = ang("beta");
  p.gamma = ang("gamma");
  return p;
}

}  // namespace

Eigen::Vector3d readToolAxis(io::TableReader& r, const std::string& key,
                             const Eigen::Vector3d& fallback) {
  if (!r.has(key)) return fallback;
  const toml::node* n = r.node(key);
  if (n->is_string()) {
    std::string t = n->value_or(std::string());
    double sign = 1;
    if (!t.empty() && (t[0] == '-' || t[0] == '+')) {
      sign = t[0] == '-' ? -1 : 1;
      t = t.substr(1);
    }
    if (t == "x") return sign * Eigen::Vector3d::UnitX();
    if (t == "y") return sign * Eigen::Vector3d::UnitY();
    if (t == "z") return sign * Eigen::Vector3d::UnitZ();
    r.fail(key, "unknown tool axis '" + n->value_or(std::string()) +
                    "': use \"x\", \"y\", \"z\" (optionally with a sign, e.g. \"-y\") or [x, y, z] "
                    "in the TCP frame");
  }
  const auto v = r.numberArray(key);
  if (v.size() != 3)
    r.fail(key,
           "expected a tool axis \"x\", \"y\", \"z\" or three numbers [x, y, z] in the TCP frame");
  const Eigen::Vector3d a(v[0], v[1], v[2]);
  if (!(a.norm() > 1e-9) || !a.allFinite())
    r.fail(key, "the tool axis must be a non-zero direction");
  return a.normalized();
}

namespace {

Eigen::Vector3d readVec3(TableReader& r, const std::string& key, Eigen::Vector3d fallback) {
  if (!r.has(key)) return fallback;
  const auto v = r.numberArray(key);
  if (v.size() != 3) r.fail(key, "expected three numbers [x, y, z] in metres");
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

// [[collision]] swept-sphere volumes and [[collision_allowed]] link pairs (docs/collision.md).
void readCollisionModel(TableReader& top, Model& m) {
  top.forEachTable("collision", [&](TableReader& r) {
    CollisionVolume v;
    v.source_line = r.line();
    v.name = r.string("name", "");
    const std::string link = r.string("link");
    v.link = collision::bodyIndex(m, link);
    if (v.link < -1) r.fail("link", "no link named '" + link + "' (use a joint name or \"base\")");
    const io::SsvGeometry g = io::readSsvGeometry(r, false, "the link frame");
    v.type = g.type;
    v.p_L = g.p;
    v.radius_m = g.radius_m;
    m.collision.volumes.push_back(v);
  });
  if (static_cast<int>(m.collision.volumes.size()) > defaults::kMaxCollisionVolumes)
    throw InputError(top.file(), m.collision.volumes.back().source_line, "collision",
                     "more than " + std::to_string(defaults::kMaxCollisionVolumes) +
                         " collision volumes are not supported");
  top.forEachTable("collision_allowed", [&](TableReader& r) {
    const auto links = r.stringArray("links");
    if (links.size() != 2) r.fail("links", "expected two link names [\"a\", \"b\"]");
    std::array<int, 2> pair{};
    for (int i = 0; i < 2; ++i) {
      pair[i] = collision::bodyIndex(m, links[i]);
      if (pair[i] < -1)
        r.fail("links", "no link named '" + links[i] + "' (use a joint name or \"base\")");
    }
    if (pair[0] == pair[1]) r.fail("links", "a link cannot be paired with itself");
    if (pair[0] > pair[1]) std::swap(pair[0], pair[1]);
    for (const auto& p : m.collision.allowed_pairs)
      if (p == pair) r.fail("links", "pair listed twice");
    r.string("reason", "");
    m.collision.allowed_pairs.push_back(pair);
  });
}

// Drive friction laws and the "<joint>.<effect>" entries of [model].effects
// (src/drive/friction.hpp).
void validateDriveEffects(const Model& m, const std::string& file, int effects_line) {
  for (const std::string& entry : m.effects) {
    const auto dot = entry.find('.');
    if (dot == std::string::npos) continue;
    const std::string joint = entry.substr(0, dot);
    drive::Effect e;
    const bool is_drive_effect = drive::parseEffect(entry.substr(dot + 1), e);
    bool has_drive = false;
    for (const Drive& d : m.drives) has_drive = has_drive || d.joint == joint;
    if (is_drive_effect && !has_drive)
      throw InputError(
          file, effects_line, "model.effects",
          "effect '" + entry + "': the design has no [[drive]] for joint '" + joint + "'");
    if (has_drive && !is_drive_effect)
      throw InputError(file, effects_line, "model.effects",
                       "effect '" + entry +
                           "': unknown drive effect (expected coulomb, viscous, "
                           "load_coulomb, load_viscous, stribeck, asymmetry or temperature)");
  }
  for (const Drive& d : m.drives) {
    std::string key;
    const std::string msg = drive::validateFriction(d, drive::extraEffects(m, d.joint), key);
    if (!msg.empty())
      throw InputError(file, d.source_line,
                       key == "effects" ? "model.effects" : "drive." + d.joint + "." + key, msg);
  }
}

// [design]: the design's name, description, source and assumptions.
void readDesignHeader(TableReader& top, Model& m) {
  TableReader r = top.requiredTable("design");
  m.name = r.string("name");
  if (const std::string bad = designNameError(m.name); !bad.empty()) r.fail("name", bad);
  m.description = r.string("description", "");
  m.source = r.string("source", "");
  m.assumptions = r.stringArray("assumptions");
  r.finish();
}

// One [[joint]] row: name (unique in `names`), type, offset, limits; its URDF facts into urdf.
Joint readJoint(TableReader& r, std::set<std::string>& names, UrdfInfo& urdf) {
  Joint j;
  j.source_line = r.line();
  j.name = r.string("name");
  if (j.name.empty()) r.fail("name", "joint name is empty");
  if (!names.insert(j.name).second) r.fail("name", "duplicate joint name '" + j.name + "'");
  const std::string type = r.string("type");
  if (type == "revolute")
    j.type = JointType::Revolute;
  else if (type == "prismatic")
    j.type = JointType::Prismatic;
  else
    r.fail("type", "unknown joint type '" + type + "' (expected revolute or prismatic)");
  j.offset = readPose(r, true);
  UrdfJointInfo ji;  // URDF facts (io/urdf_io.hpp), optional
  ji.link = r.string("link", "");
  if (r.has("link_axis")) {  // the URDF axis in its child link frame: R_FL = urdfAxisFrame(a)^T
    const auto v = r.numberArray("link_axis");
    const Eigen::Vector3d a =
        v.size() == 3 ? Eigen::Vector3d(v[0], v[1], v[2]) : Eigen::Vector3d::Zero();
    if (!(a.norm() > 0.5 && a.norm() < 2))
      r.fail("link_axis",
             "expected a unit vector [x, y, z]: the joint axis in the URDF link frame");
    ji.R_FL = urdfAxisFrame(a.normalized()).transpose();
  }
  ji.continuous = r.boolean("continuous", false);
  if (ji.continuous && j.type != JointType::Revolute)
    r.fail("continuous", "only a revolute joint can be continuous");
  const Dimension qd = j.type == JointType::Revolute ? Dimension::Angle : Dimension::Length;
  const Dimension vd =
      j.type == JointType::Revolute ? Dimension::AngularVelocity : Dimension::LinearVelocity;
  if (ji.continuous) {  // no position limits: the documented stand-in range unless given
    j.limits.q_min = r.quantity("min", qd, -defaults::kContinuousJointRange_rad);
    j.limits.q_max = r.quantity("max", qd, defaults::kContinuousJointRange_rad);
  } else {
    j.limits.q_min = r.quantity("min", qd);
    j.limits.q_max = r.quantity("max", qd);
  }
  j.limits.qd_max = r.quantity("max_velocity", vd, 0.0);
  ji.effort_max = r.number("max_effort", 0.0);
  if (!(ji.effort_max >= 0) || !std::isfinite(ji.effort_max))
    r.fail("max_effort", "effort limit must be finite and not negative (N m or N; 0 = not given)");
  for (const JointDynamicsValue& v : kJointDynamicsValues) {
    double& x = j.dynamics.*v.value;
    x = r.number(v.key, 0.0);
    if (!std::isfinite(x) || (v.non_negative && x < 0))
      r.fail(v.key, std::string(v.what) + " must be finite" +
                        (v.non_negative ? " and not negative" : "") + " (SI, joint side)");
  }
  urdf.joints.push_back(ji);
  if (!(j.limits.q_min < j.limits.q_max))
    r.fail("max", "joint limits are inverted or empty (min must be below max)");
  if (j.limits.qd_max < 0) r.fail("max_velocity", "velocity limit must not be negative");
  return j;
}

// The [[joint]] table, then its size checks (not empty, at most defaults::kMaxDof).
void readJoints(TableReader& top, const std::string& file, Model& m, UrdfInfo& urdf) {
  std::set<std::string> names;
  top.forEachTable("joint", [&](TableReader& r) { m.joints.push_back(readJoint(r, names, urdf)); });
  if (m.joints.empty())
    throw InputError(file, top.line(), "joint", "the kinematic table is empty: add [[joint]] rows");
  if (m.dof() > defaults::kMaxDof)
    throw InputError(
        file, m.joints.back().source_line, "joint",
        "more than " + std::to_string(defaults::kMaxDof) + " joints are not supported");
}

// [tcp] (offset, tool axis, URDF link) and the optional [base] (placement, URDF link).
void readTcpAndBase(TableReader& top, const std::string& file, Model& m, UrdfInfo& urdf) {
  {
    TableReader r = top.requiredTable("tcp", " (TCP offset from the last frame)");
    m.tcp = readPose(r, false);
    m.tool_axis_T = readToolAxis(r, "tool_axis", Eigen::Vector3d::UnitZ());
    // A design converted from URDF carries where its axis came from (or that it is open): the
    // file's own [tcp] tool_axis replaces that.
    if (r.has("tool_axis") &&
        !(notes::toolAxisOpen(m).empty() && notes::last(m, notes::kToolAxisFrom).empty()))
      notes::toolAxisNamed(m, "[tcp] tool_axis of the design file");
    urdf.tcp_link = r.string("link", "");
    r.finish();
  }
  if (const toml::table* t = top.table("base")) {
    TableReader r(*t, file, "base");
    m.base = readPose(r, false);
    urdf.base_link = r.string("link", "");
    r.finish();
  }
}

// [[inertia]] rows: mass, COM and a physical inertia tensor per link, each given once.
void readInertias(TableReader& top, Model& m) {
  top.forEachTable("inertia", [&](TableReader& r) {
    const std::string link = r.string("link");
    const int idx = m.jointIndex(link);
    if (idx < 0) r.fail("link", "no joint named '" + link + "' in this design");
    if (m.inertias.empty()) m.inertias.resize(m.joints.size());
    LinkInertia& li = m.inertias[idx];
    if (li.given) r.fail("link", "inertia for link '" + link + "' given twice");
    li.given = true;
    li.mass_kg = r.number("mass");
    if (li.mass_kg < 0) r.fail("mass", "mass must not be negative");
    li.p_com_m = readVec3(r, "com", Eigen::Vector3d::Zero());
    const auto I = r.numberArray("inertia");
    if (I.size() != 6) r.fail("inertia", "expected [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] in kg m^2");
    li.I_com_kgm2 << I[0], I[3], I[4], I[3], I[1], I[5], I[4], I[5], I[2];
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(li.I_com_kgm2);
    const Eigen::Vector3d ev = es.eigenvalues();
    const double tol = 1e-12 * ev.cwiseAbs().maxCoeff();
    // A point mass (all zero, as URDFs give small parts) or a thin rod (one moment zero) is a
    // physical body; a negative moment is not.
    if (ev.minCoeff() < -tol)
      r.fail("inertia",
             "inertia tensor is not positive semidefinite (a negative principal moment)");
    if (ev[0] + ev[1] < ev[2] - tol || ev[0] + ev[2] < ev[1] - tol || ev[1] + ev[2] < ev[0] - tol)
      r.fail("inertia", "principal moments break the triangle inequality (not a physical body)");
  });
}

// One [[drive]] row: joint (one drive each), gear, torque constant, optional values, friction.
Drive readDrive(TableReader& r, const std::string& file, const Model& m) {
  Drive d;
  d.source_line = r.line();
  d.joint = r.string("joint");
  if (m.jointIndex(d.joint) < 0) r.fail("joint", "no joint named '" + d.joint + "' in this design");
  for (const auto& other : m.drives)
    if (other.joint == d.joint) r.fail("joint", "two drives for joint '" + d.joint + "'");
  d.module = r.string("module", "");
  d.gear_ratio = r.number("gear_ratio");
  if (!(d.gear_ratio > 0)) r.fail("gear_ratio", "gear ratio must be positive");
  d.torque_constant_NmpA = r.number("torque_constant");
  if (!(d.torque_constant_NmpA > 0)) r.fail("torque_constant", "torque constant must be positive");
  for (const OptionalDriveValue& v : kOptionalDriveValues)
    d.*v.value = v.angular_velocity ? r.quantity(v.key, Dimension::AngularVelocity, 0.0)
                                    : r.number(v.key, 0.0);
  for (const OptionalDriveValue& v : kOptionalDriveValues)
    if (d.*v.value < 0) r.fail(v.key, "must not be negative");
  if (d.peak_current_A > 0 && d.continuous_current_A > d.peak_current_A)
    r.fail("peak_current", "peak current is below the continuous current");
  if (const toml::table* f = r.table("friction")) {
    TableReader fr(*f, file, r.path() + ".friction");
    d.friction_law = fr.string("law");
    for (auto&& [k, v] : *f) {
      const std::string key(k.str());
      if (key == "law") continue;
      d.friction[key] = fr.number(key);
    }
    fr.finish();
  }
  return d;
}

// [payload], [[drive]] rows and [model].effects, the drives' effects validated.
void readPayloadDrivesEffects(TableReader& top, const std::string& file, Model& m) {
  if (const toml::table* t = top.table("payload")) {
    TableReader r(*t, file, "payload");
    m.payload_kg = r.number("mass");
    if (m.payload_kg < 0) r.fail("mass", "mass must not be negative");
    m.p_payload_com_T = readVec3(r, "com", Eigen::Vector3d::Zero());
    r.finish();
  }
  top.forEachTable("drive", [&](TableReader& r) { m.drives.push_back(readDrive(r, file, m)); });
  int effects_line = top.line();
  if (const toml::table* t = top.table("model")) {
    TableReader r(*t, file, "model");
    m.effects = r.stringArray("effects");
    effects_line = r.line("effects");
    r.finish();
  }
  validateDriveEffects(m, file, effects_line);
}

// A design file's tables, in reading order, into a finalised and validated model.
Model buildModel(const toml::table& root, const std::string& file, UrdfInfo* info) {
  UrdfInfo urdf;
  Model m;
  m.file = file;
  TableReader top(root, file, "");
  readDesignHeader(top, m);
  readJoints(top, file, m, urdf);
  readTcpAndBase(top, file, m, urdf);
  readInertias(top, m);
  readPayloadDrivesEffects(top, file, m);
  readCollisionModel(top, m);
  top.finish();
  m.finalize();
  validateModel(m, file);
  if (info) *info = urdf;
  return m;
}

}  // namespace

Model parseDesign(const std::string& text, const std::string& file_label) {
  return parseDesignWithUrdfInfo(text, file_label, nullptr);
}

Model parseDesignWithUrdfInfo(const std::string& text, const std::string& file_label,
                              UrdfInfo* info) {
  const toml::table root = io::parseTomlText(text, file_label);
  Model m = buildModel(root, file_label, info);
  m.file_hash = contentHash(text);
  return m;
}

// A `.urdf` design is imported with the default chain (io/urdf_io.hpp, loadAnyDesign for others).
Model loadDesign(const std::string& path) { return loadAnyDesign(path, UrdfOptions{}); }

Model loadAnyDesign(const std::string& path, const UrdfOptions& urdf, UrdfInfo* info,
                    std::vector<std::string>* warnings) {
  if (isUrdfPath(path)) return importUrdf(path, urdf, info, warnings);
  const std::string text = readFileOrThrow(path);
  rejectUnexpandedXacro(text, path);
  return parseDesignWithUrdfInfo(text, path, info);
}

std::string designNameError(const std::string& name) {
  if (name.empty()) return "design name is empty";
  if (!isPlainName(name, kDesignNamePunctuation))
    return "design names use letters, digits, '_', '-' and '.' only, not dots alone (they name "
           "files)";
  return "";
}

void validateModel(const Model& m, const std::string& file) {
  for (const Joint& j : m.joints) {
    const std::string k = "joint." + j.name;
    if (!(std::isfinite(j.limits.q_min) && std::isfinite(j.limits.q_max)))
      throw InputError(file, j.source_line, k + ".min", "joint limits must be finite");
    if (!(j.limits.q_min < j.limits.q_max))
      throw InputError(file, j.source_line, k + ".max",
                       "joint limits are inverted or empty (min must be below max)");
    const PoseXYZABG& o = j.offset;
    for (double v : {o.x, o.y, o.z, o.alpha, o.beta, o.gamma})
      if (!std::isfinite(v)) throw InputError(file, j.source_line, k, "table entry is not finite");
  }
}

namespace {
double* poseField(PoseXYZABG& p, const std::string& f, Dimension& dim) {
  dim = Dimension::Length;
  if (f == "x") return &p.x;
  if (f == "y") return &p.y;
  if (f == "z") return &p.z;
  dim = Dimension::Angle;
  if (f == "alpha") return &p.alpha;
  if (f == "beta") return &p.beta;
  if (f == "gamma") return &p.gamma;
  return nullptr;
}

double* entryPointer(Model& m, const std::string& key, Dimension& dim, std::string& error) {
  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string s; std::getline(ss, s, '.');) parts.push_back(s);
  if (parts.size() == 3 && parts[0] == "joint") {
    const int idx = m.jointIndex(parts[1]);
    if (idx < 0) {
      error = "no joint named '" + parts[1] + "' in design '" + m.name + "'";
      return nullptr;
    }
    Joint& j = m.joints[idx];
    if (double* p = poseField(j.offset, parts[2], dim)) return p;
    const bool rev = j.type == JointType::Revolute;
    dim = rev ? Dimension::Angle : Dimension::Length;
    if (parts[2] == "min") return &j.limits.q_min;
    if (parts[2] == "max") return &j.limits.q_max;
    dim = rev ? Dimension::AngularVelocity : Dimension::LinearVelocity;
    if (parts[2] == "max_velocity") return &j.limits.qd_max;
  } else if (parts.size() == 2 && (parts[0] == "tcp" || parts[0] == "base")) {
    if (double* p = poseField(parts[0] == "tcp" ? m.tcp : m.base, parts[1], dim)) return p;
  } else if (parts.size() == 2 && parts[0] == "payload" && parts[1] == "mass") {
    dim = Dimension::Dimensionless;
    return &m.payload_kg;
  }
  error = "unknown table entry '" + key +
          "' (expected joint.<name>.<x|y|z|alpha|beta|gamma|min|max|max_velocity>, "
          "tcp.<x..gamma>, base.<x..gamma> or payload.mass)";
  return nullptr;
}
}  // namespace

bool setModelEntry(Model& m, const std::string& key, double value_si, std::string& error) {
  Dimension dim;
  double* p = entryPointer(m, key, dim, error);
  if (!p) return false;
  error = implausible(value_si, &dim);
  if (!error.empty()) return false;
  *p = value_si;
  m.finalize();
  return true;
}

bool modelEntryDimension(const Model& m, const std::string& key, Dimension& dim,
                         std::string& error) {
  Model copy = m;
  return entryPointer(copy, key, dim, error) != nullptr;
}

}  // namespace armstudy

namespace armstudy {

bool modelEntryValue(const Model& m, const std::string& key, double& value_si, std::string& error) {
  Model copy = m;
  Dimension dim;
  const double* p = entryPointer(copy, key, dim, error);
  if (!p) return false;
  value_si = *p;
  return true;
}

}  // namespace armstudy
