#pragma once
// URDF in and out (docs/design-format.md, "URDF").
//
// Import: urdfdom parses the file; the serial chain from `base_link` to `tip_link` becomes a
// design. Joint values keep their URDF meaning (angle about / displacement along the URDF axis,
// base to tip): each joint frame is the URDF joint origin rotated by a fixed R_a with R_a e_z =
// axis, so the armstudy body frame i is F_i = L_i R_a (L_i = URDF child link frame), and every
// quantity of the link (inertial, collision geometry, the next joint origin) is re-expressed in
// F_i. Fixed joints on the chain are folded into the neighbouring transforms; branches off the
// chain are ignored with a note in the design's assumptions.
//
// Export: one URDF link per body (base, the body after each joint, the TCP frame), joint origins
// from the table rows, axis 0 0 1, inertials at the COM, limits with velocity and effort.
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "model/model.hpp"

namespace armstudy {

namespace defaults {
// Assumption: a `continuous` joint sweeps [-2 pi, 2 pi] (two full turns, so every angle is an
// interior point for the bounded IK and a sweep covers the full circle; the URDF gives no limits).
inline constexpr double kContinuousJointRange_rad = 2 * 3.14159265358979323846;
// Assumption: at most this many swept-sphere volumes are fitted to one collision mesh or box.
inline constexpr int kUrdfSsvMaxVolumesPerMesh = 3;
}  // namespace defaults

struct UrdfOptions {
  std::string base_link;  // "" = the root link
  std::string tip_link;   // "" = the end of the longest chain of movable joints, when unique
  // package://NAME/... resolves to DIR/... ; searched before the folders above the URDF file.
  std::vector<std::pair<std::string, std::string>> packages;
  bool collision = true;  // fit swept-sphere volumes to the links' collision geometry
};

// URDF facts a kinematic table does not need but the way back to URDF does. Design TOML files carry
// them as optional keys: [[joint]] link / continuous / max_effort, [base] link, [tcp] link.
struct UrdfJointInfo {
  std::string link;         // the URDF child link (the body after the joint)
  bool continuous = false;  // URDF `continuous`: limits are defaults::kContinuousJointRange_rad
  double effort_max = 0;    // <limit effort>: N m (revolute) or N (prismatic); 0 = not given
  // Orientation of the URDF child link frame L_i in the body frame F_i (R_a^T; identity for
  // designs read from TOML, whose body frames are the link frames of their URDF export).
  Eigen::Matrix3d R_FL = Eigen::Matrix3d::Identity();
};
struct UrdfInfo {
  std::string base_link, tcp_link;
  std::vector<UrdfJointInfo> joints;  // one per joint (empty = none given)
};

// Parses "NAME=DIR" (the --package option). Throws InputError naming `option` when malformed.
std::pair<std::string, std::string> parsePackageOption(const std::string& text,
                                                       const std::string& option);

bool isUrdfPath(const std::string& path);

// Imports the chain. Throws InputError (file, line, element) on bad input. Notes (missing meshes,
// ignored branches) go into the model's assumptions and into `warnings` when given.
Model importUrdf(const std::string& path, const UrdfOptions& options, UrdfInfo* info = nullptr,
                 std::vector<std::string>* warnings = nullptr);
Model importUrdfText(const std::string& text, const std::string& file_label,
                     const UrdfOptions& options, UrdfInfo* info = nullptr,
                     std::vector<std::string>* warnings = nullptr);

// Any design file: `.urdf` is imported with `urdf` choosing the chain, anything else is a design
// TOML (io/design_io.hpp). `info` receives the URDF facts of either.
Model loadAnyDesign(const std::string& path, const UrdfOptions& urdf, UrdfInfo* info = nullptr,
                    std::vector<std::string>* warnings = nullptr);
// A design TOML's text with its URDF facts (defined in io/design_io.cpp).
Model parseDesignWithUrdfInfo(const std::string& text, const std::string& file_label,
                              UrdfInfo* info);

// A design as URDF text (loads in urdfdom and kdl_parser; same kinematics, inertias and limits).
std::string exportUrdf(const Model& model, const UrdfInfo& info = {});

// A design as TOML text in the design format; parseDesign of it gives the same model (numbers with
// 17 significant digits) and parseDesignWithUrdfInfo the same `info`.
std::string designToToml(const Model& model, const UrdfInfo& info = {});

}  // namespace armstudy
