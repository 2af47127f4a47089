// Designs: loading (TOML or URDF), inspecting joints, limits and collision volumes, converting.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>

#include "collision/collision.hpp"
#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "python/bindings.hpp"

namespace armstudy::python {

namespace {

py::dict poseDict(const PoseXYZABG& p) {
  py::dict d;
  d["x"] = p.x;
  d["y"] = p.y;
  d["z"] = p.z;
  d["alpha"] = p.alpha;
  d["beta"] = p.beta;
  d["gamma"] = p.gamma;
  return d;
}

py::array_t<double> vector3(const Eigen::Vector3d& v) {
  py::array_t<double> a(3);
  for (int k = 0; k < 3; ++k) a.mutable_at(k) = v[k];
  return a;
}

UrdfOptions urdfOptions(const std::string& base, const std::string& tip,
                        const std::map<std::string, std::filesystem::path>& packages,
                        bool collision) {
  UrdfOptions u;
  u.base_link = base;
  u.tip_link = tip;
  for (const auto& [name, folder] : packages) {
    const std::string dir = folder.string();
    if (!std::filesystem::is_directory(dir))
      throw InputError("packages", 0, "package",
                       "folder '" + dir + "' for package '" + name + "' does not exist (" +
                           std::filesystem::absolute(dir).string() + ")");
    u.packages.emplace_back(name, dir);
  }
  u.collision = collision;
  return u;
}

Design load(const std::filesystem::path& path, const std::string& base, const std::string& tip,
            const std::map<std::string, std::filesystem::path>& packages, bool collision) {
  Design d;
  d.model = std::make_shared<const Model>(loadAnyDesign(
      path.string(), urdfOptions(base, tip, packages, collision), &d.info, &d.warnings));
  return d;
}

py::list jointList(const Model& m) {
  py::list joints;
  for (const Joint& j : m.joints) {
    py::dict d = poseDict(j.offset);
    d["name"] = j.name;
    d["type"] = toString(j.type);
    d["min"] = j.limits.q_min;
    d["max"] = j.limits.q_max;
    d["max_velocity"] = j.limits.qd_max;
    d["line"] = j.source_line;
    joints.append(d);
  }
  return joints;
}

std::string bodyName(const Model& m, int link) {
  return link < 0 ? std::string("base") : m.joints[link].name;
}

py::list volumeList(const Model& m) {
  py::list volumes;
  for (const CollisionVolume& v : m.collision.volumes) {
    const int k = static_cast<int>(v.type);
    py::array_t<double> points({k, 3});
    for (int i = 0; i < k; ++i)
      for (int c = 0; c < 3; ++c) points.mutable_at(i, c) = v.p_L[i][c];
    py::dict d;
    d["name"] = v.name;
    d["link"] = bodyName(m, v.link);
    d["type"] = toString(v.type);
    d["points"] = points;
    d["radius"] = v.radius_m;
    d["line"] = v.source_line;
    volumes.append(d);
  }
  return volumes;
}

py::list collisionPairs(const Model& m) {
  py::list pairs;
  if (m.collision.empty()) return pairs;
  collision::CollisionWorkspace ws(m);
  for (int i = 0; i < ws.num_self; ++i)
    pairs.append(py::make_tuple(bodyName(m, ws.self[i].link_a), bodyName(m, ws.self[i].link_b)));
  return pairs;
}

py::array_t<double> limitArray(const Model& m, double JointLimits::*field) {
  py::array_t<double> a(m.dof());
  for (int i = 0; i < m.dof(); ++i) a.mutable_at(i) = m.joints[i].limits.*field;
  return a;
}

// A copy of the design with table entries set (study variants' keys; values finite and plausible
// for their dimension, as a study's variants), validated; `name` checked as design files' names.
Design withEntries(const Design& d, const std::map<std::string, double>& entries,
                   const std::string& name) {
  if (!name.empty())
    if (const std::string bad = designNameError(name); !bad.empty())
      throw InputError("arguments", 0, "name", bad);
  Model m = *d.model;
  for (const auto& [key, value] : entries) {
    std::string error;
    if (!setModelEntry(m, key, value, error)) throw InputError(m.file, 0, key, error);
  }
  if (!name.empty()) m.name = name;
  m.finalize();
  validateModel(m, m.file);
  Design out = d;
  out.model = std::make_shared<const Model>(std::move(m));
  return out;
}

// Pickling (multiprocessing hands designs to workers): the design TOML (designToToml: numbers with
// 17 significant digits, so the model is the same bit for bit, URDF facts included), the file and
// hash it came from, the import notes, and the design-file lines of joints and volumes.
py::tuple designState(const Design& d) {
  const Model& m = *d.model;
  std::vector<int> joint_lines, volume_lines;
  for (const Joint& j : m.joints) joint_lines.push_back(j.source_line);
  for (const CollisionVolume& v : m.collision.volumes) volume_lines.push_back(v.source_line);
  return py::make_tuple(1, designToToml(m, d.info), m.file, m.file_hash, d.warnings, joint_lines,
                        volume_lines);
}

Design designFromState(const py::tuple& state) {
  if (state.size() != 7 || state[0].cast<int>() != 1)
    throw std::invalid_argument("Design.__setstate__: not a pickled armstudy.Design");
  Design d;
  Model m =
      parseDesignWithUrdfInfo(state[1].cast<std::string>(), state[2].cast<std::string>(), &d.info);
  m.file = state[2].cast<std::string>();
  m.file_hash = state[3].cast<std::string>();
  d.warnings = state[4].cast<std::vector<std::string>>();
  const auto joint_lines = state[5].cast<std::vector<int>>();
  const auto volume_lines = state[6].cast<std::vector<int>>();
  for (std::size_t i = 0; i < joint_lines.size() && i < m.joints.size(); ++i)
    m.joints[i].source_line = joint_lines[i];
  for (std::size_t i = 0; i < volume_lines.size() && i < m.collision.volumes.size(); ++i)
    m.collision.volumes[i].source_line = volume_lines[i];
  d.model = std::make_shared<const Model>(std::move(m));
  return d;
}

}  // namespace

void bindDesign(py::module_& m) {
  py::class_<Design> design(m, "Design", R"(A robot-arm design (immutable).

Load one with armstudy.load_design (TOML or URDF) or armstudy.parse_design (TOML text).
Joint values are SI: radians for revolute, metres for prismatic joints; poses are in the world
frame W (the design's base placed in it).)");
  design
      .def_property_readonly(
          "name", [](const Design& d) { return d.model->name; },
          "The design name (a variant's own name).")
      .def_property_readonly(
          "description", [](const Design& d) { return d.model->description; },
          "The design file's description.")
      .def_property_readonly(
          "file", [](const Design& d) { return d.model->file; },
          "The design file it was loaded from (a label for parse_design).")
      .def_property_readonly(
          "file_hash", [](const Design& d) { return d.model->file_hash; },
          "Content hash of that file (manifests, checkpoints).")
      .def_property_readonly(
          "assumptions", [](const Design& d) { return d.model->assumptions; },
          "The design file's stated assumptions.")
      .def_property_readonly(
          "warnings", [](const Design& d) { return d.warnings; },
          "Notes of a URDF import (missing meshes, ignored branches).")
      .def_property_readonly(
          "dof", [](const Design& d) { return d.model->dof(); },
          "Number of joints (the length of q).")
      .def_property_readonly(
          "joint_names",
          [](const Design& d) {
            std::vector<std::string> n;
            for (const Joint& j : d.model->joints) n.push_back(j.name);
            return n;
          },
          "The joint names, in the order of q.")
      .def_property_readonly(
          "joints", [](const Design& d) { return jointList(*d.model); },
          "One dict per joint: name, type, the table row x, y, z, alpha, beta, gamma, the limits "
          "min, max, max_velocity (0 = not given) and the line in the design file.")
      .def_property_readonly(
          "lower", [](const Design& d) { return limitArray(*d.model, &JointLimits::q_min); },
          "Lower joint limits (dof,) [rad or m].")
      .def_property_readonly(
          "upper", [](const Design& d) { return limitArray(*d.model, &JointLimits::q_max); },
          "Upper joint limits (dof,) [rad or m].")
      .def_property_readonly(
          "max_velocity",
          [](const Design& d) { return limitArray(*d.model, &JointLimits::qd_max); },
          "Joint speed limits (dof,) [rad/s or m/s]; 0 = not given.")
      .def_property_readonly(
          "tcp", [](const Design& d) { return poseDict(d.model->tcp); },
          "TCP offset from the last joint frame: x, y, z [m], alpha, beta, gamma [rad].")
      .def_property_readonly(
          "base", [](const Design& d) { return poseDict(d.model->base); },
          "Pose of the robot base in W: x, y, z [m], alpha, beta, gamma [rad].")
      .def_property_readonly(
          "tool_axis", [](const Design& d) { return vector3(d.model->tool_axis_T); },
          "The tool axis (unit, in the TCP frame) a tool-axis task points.")
      .def_property_readonly(
          "payload_kg", [](const Design& d) { return d.model->payload_kg; },
          "End effector + payload mass at the TCP [kg].")
      .def_property_readonly(
          "has_inertia", [](const Design& d) { return !d.model->inertias.empty(); },
          "Whether the design has link inertias (dynamics needs them).")
      .def_property_readonly(
          "volumes", [](const Design& d) { return volumeList(*d.model); },
          "The collision volumes: name, link (body name, 'base' for the fixed base), type "
          "(point/line/triangle), points (k, 3) in the link frame [m], radius [m], line.")
      .def_property_readonly(
          "collision_pairs", [](const Design& d) { return collisionPairs(*d.model); },
          "The self-collision body pairs, in the column order of self_distances.")
      .def(
          "to_toml", [](const Design& d) { return designToToml(*d.model, d.info); },
          "The design as design-file TOML (what `armstudy convert X.urdf X.toml` writes).")
      .def(
          "to_urdf", [](const Design& d) { return exportUrdf(*d.model, d.info); },
          "The design as URDF text (what `armstudy convert X.toml X.urdf` writes).")
      .def("with_entries", &withEntries, py::arg("entries"), py::arg("name") = "",
           R"(A copy with table entries set, as a study variant does: keys such as
'joint.j3.min', 'joint.j2.z', 'tcp.z', 'base.y', 'payload.mass'; values in SI.)")
      .def(py::pickle(&designState, &designFromState))
      .def("__repr__", [](const Design& d) {
        return "<armstudy.Design '" + d.model->name + "', " + std::to_string(d.model->dof()) +
               " joints>";
      });
  bindKernels(design);
  bindSolve(m, design);

  m.def("load_design", &load, py::arg("path"), py::arg("base") = "", py::arg("tip") = "",
        py::arg("packages") = std::map<std::string, std::filesystem::path>{},
        py::arg("collision") = true,
        R"(Loads a design file: TOML, or URDF (.urdf) with the chain from `base` to `tip`
(defaults as `armstudy describe`), `packages` mapping package://NAME to a folder, and
`collision` fitting swept-sphere volumes to its meshes. Raises InputError on bad input.)");
  m.def(
      "parse_design",
      [](const std::string& text, const std::string& label) {
        Design d;
        d.model = std::make_shared<const Model>(parseDesignWithUrdfInfo(text, label, &d.info));
        return d;
      },
      py::arg("text"), py::arg("label") = "<string>",
      "Parses design TOML text; `label` names it in error messages.");
}

}  // namespace armstudy::python
