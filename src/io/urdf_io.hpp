#pragma once
// URDF in and out (docs/design-format.md, "URDF").
//
// Import: urdfdom parses the file; the serial chain from `base_link` to `tip_link` becomes a
// design. Joint values keep their URDF meaning (angle about / displacement along the URDF axis,
// base to tip): each joint frame is the URDF joint origin rotated by a fixed R_a with R_a e_z =
// axis, so the armstudy body frame i is F_i = L_i R_a (L_i = URDF child link frame), and every
// quantity of the link (inertial, collision geometry, the next joint origin) is re-expressed in
// F_i. Fixed joints on the chain are folded into the neighbouring transforms; the kinematics and
// collision geometry of branches off the chain are ignored with a note in the design's
// assumptions, their masses ride on the chain (io/urdf_arm.hpp).
//
// Export: one URDF link per body (base, the body after each joint, the TCP frame), inertials at
// the COM, limits with velocity and effort. A link named after an imported URDF link is that
// link's frame L_i = F_i R_FL (position and orientation), so joint origins and axes are the table
// rows re-expressed in those frames; without URDF facts L_i = F_i and every axis is 0 0 1.
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "common/angles.hpp"
#include "model/model.hpp"

namespace armstudy {

namespace defaults {
// Assumption: a `continuous` joint sweeps [-2 pi, 2 pi] (two full turns, so every angle is an
// interior point for the bounded IK and a sweep covers the full circle; the URDF gives no limits).
inline constexpr double kContinuousJointRange_rad = kFullTurn_rad;
// Assumption: at most this many swept-sphere volumes are fitted to one collision mesh or box.
inline constexpr int kUrdfSsvMaxVolumesPerMesh = 3;
}  // namespace defaults

struct UrdfOptions {
  std::string base_link;  // "" = the root link
  std::string tip_link;   // "" = the default tip (UrdfChains::chosen)
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
  // designs written without URDF links; a design TOML carries it as [[joint]] link_axis, the
  // URDF axis in L_i).
  Eigen::Matrix3d R_FL = Eigen::Matrix3d::Identity();
};
struct UrdfInfo {
  std::string base_link, tcp_link;
  std::vector<UrdfJointInfo> joints;  // one per joint (empty = none given)
};

// The chains of a URDF below its base link (describe; the default tip). A chain runs over arm
// joints (revolute, continuous, prismatic; not mimic, not named as a gripper or finger joint)
// and fixed joints; it ends where no arm joint follows.
struct UrdfChainEnd {
  std::string link;                       // the child link of the chain's last arm joint
  int joints = 0;                         // arm joints from the base to `link`
  std::vector<std::string> fixed_frames;  // links after `link` over fixed joints (tool0, flange)
  std::vector<std::string> left_out;      // joints after `link` that are no arm joints, with why
};
struct UrdfChains {
  std::string base;
  std::vector<UrdfChainEnd> ends;  // longest first
  std::string chosen;              // the default tip link; "" when there is none
  std::string reason;              // why `chosen` (or why none)
};
// The chains of the URDF file at `path` below options.base_link (or the root link).
UrdfChains findUrdfChains(const std::string& path, const UrdfOptions& options);

// The rotation R_a with R_a e_z = a (a unit): the body frame of a URDF joint is its child link
// frame rotated by R_a, so that its z axis is the URDF axis (UrdfJointInfo::R_FL = R_a^T).
Eigen::Matrix3d urdfAxisFrame(const Eigen::Vector3d& a);

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
