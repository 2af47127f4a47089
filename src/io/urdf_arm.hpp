#pragma once
// What a URDF arm says by itself (docs/design-format.md, "URDF designs"): its tool axis, and the
// xacro files armstudy does not expand. The importer (io/urdf_io.hpp) also lumps the masses of
// links off the chain onto the chain link they hang from (fixed links beyond the tip, branches such
// as a head or fingers with their joints held at q = 0 clamped into their limits); the design's
// notes (model/model_notes.hpp) list them.
#include <Eigen/Core>
#include <string>

#include "model/model.hpp"

namespace armstudy {

namespace defaults {
// Assumption: a URDF arm's TCP lies on its last joint's axis when it is at most 1 mm from it; a
// direction within 1e-6 rad of a TCP frame axis is that axis exactly.
inline constexpr double kToolOnAxis_m = 1e-3;
inline constexpr double kToolAxisSnap_rad = 1e-6;
}  // namespace defaults

// The last joint's axis seen from the TCP (describe, the default tool axis of a URDF arm).
struct ArmToolAxis {
  std::string joint;                                  // the last joint ("" without joints)
  Eigen::Vector3d axis_T = Eigen::Vector3d::UnitZ();  // unit, in the TCP frame, towards the TCP
  double off_axis_m = 0;                              // the TCP's distance from the axis
  double along_m = 0;                                 // the TCP's position along the axis
  bool on_axis = false;                               // off_axis_m <= defaults::kToolOnAxis_m
  std::string nearest;                                // the nearest signed TCP axis ("y", "-z")
  double nearest_angle_rad = 0;
};
// The last joint's axis in the TCP frame of `m` (finalized). Its direction points from the joint's
// origin towards the TCP along the axis (the URDF axis direction when the TCP is within
// defaults::kToolOnAxis_m of the origin along it).
ArmToolAxis lastJointAxisInTcp(const Model& m);

// The default tool axis of a design imported from URDF: the last joint's axis in the TCP frame when
// the TCP lies on it (the note notes::kToolAxisFrom says so); otherwise tool_axis_T stays z and the
// note notes::kToolAxisOpen holds the candidates and the keys that name one.
void applyToolAxisFromArm(Model& m);

// A xacro file (extension .xacro, or <xacro:...> elements in the text) is an InputError at its
// first xacro element with the `xacro` command that expands it into a URDF.
void rejectUnexpandedXacro(const std::string& text, const std::string& path);

}  // namespace armstudy
