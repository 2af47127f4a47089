#pragma once
// The immutable robot model. A design file is parsed (io/design_io), validated, then frozen into
// a const Model; every algorithm takes `const Model&` plus a per-thread workspace.
//
// Conventions (docs/conventions.md): SI units inside (m, rad, kg, s); frame i is the body frame
// after joint i; the fixed part of joint i is T_PJ = Trans(x,y,z) * Rx(alpha) * Ry(beta) *
// Rz(gamma) (thesis Table 3.1, eq. 5.10); a revolute joint adds q to gamma (rotation about the new
// z axis), a prismatic joint translates by q along the new z axis (thesis Appendix B, eq. B.16).
#include <Eigen/Geometry>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/defaults.hpp"

namespace armstudy {

enum class JointType { Revolute, Prismatic };
const char* toString(JointType t);

// Fixed-angle x-y-z pose: p (m) and alpha, beta, gamma (rad) in the parent frame.
struct PoseXYZABG {
  double x = 0, y = 0, z = 0, alpha = 0, beta = 0, gamma = 0;
  Eigen::Isometry3d toIsometry() const;
};

struct JointLimits {
  double q_min = 0, q_max = 0;  // rad (revolute) or m (prismatic)
  double qd_max = 0;            // rad/s or m/s; 0 = not given
};

// Joint-side friction, armature and effort offset of one joint (docs/design-format.md, `[[joint]]`
// `coulomb`, `viscous`, `armature`, `effort_offset`; URDF `<dynamics friction damping>`): the
// effort of the joint itself, beside any [[drive]]. The trajectory calibration adds
// coulomb tanh(qd / w) + viscous qd + armature qdd + effort_offset to the joint's effort (SI: N m,
// N m s/rad, kg m^2, N m for a revolute joint; N, N s/m, kg, N for a prismatic one).
struct JointDynamics {
  double coulomb = 0, viscous = 0, armature = 0, effort_offset = 0;
  bool any() const { return coulomb != 0 || viscous != 0 || armature != 0 || effort_offset != 0; }
};

struct Joint {
  std::string name;
  JointType type = JointType::Revolute;
  PoseXYZABG offset;  // the table row: x, y, z, alpha, beta, gamma in the parent frame
  JointLimits limits;
  Eigen::Isometry3d T_PJ0;  // Trans * Rx * Ry * Rz(gamma), precomputed
  JointDynamics dynamics;
  int source_line = 0;  // line in the design file, for messages
};

// Optional per-link inertial data (mass, centre of mass, inertia about the centre of mass).
struct LinkInertia {
  double mass_kg = 0;
  Eigen::Vector3d p_com_m = Eigen::Vector3d::Zero();     // in the link frame
  Eigen::Matrix3d I_com_kgm2 = Eigen::Matrix3d::Zero();  // about the COM, link-frame axes
  bool given = false;
};

// One joint drive (thesis eq. 3.27, Tables A.1/A.2). Optional; the dynamics and calibration code
// read it.
struct Drive {
  std::string joint;      // joint name it drives
  std::string module;     // e.g. "B.2" (Table A.2) — informative
  double gear_ratio = 1;  // N = motor speed / joint speed (incl. belt)
  double torque_constant_NmpA = 0;
  double rotor_inertia_kgm2 = 0;
  // Limits (0 = not given)
  double peak_current_A = 0, continuous_current_A = 0, max_motor_speed_radps = 0, max_voltage_V = 0;
  double resistance_ohm = 0, inductance_H = 0;
  // Friction parameters by name (friction law parameters, SI), e.g. "law" selects the law.
  std::string friction_law;  // "", "harmonic_drive", "stribeck", "prismatic"
  std::map<std::string, double> friction;
  int source_line = 0;
};

// Self-collision model (thesis section 3.4.4, Fig. 3.24; docs/collision.md): swept-sphere volumes
// (SSVs) rigidly attached to link frames. A point SSV is a sphere, a line SSV a capsule, a
// triangle SSV a triangle swept by a sphere.
enum class SsvType { Point = 1, Line = 2, Triangle = 3 };  // value = number of core points
const char* toString(SsvType t);

struct CollisionVolume {
  std::string name;  // optional label, e.g. "upper_arm"
  int link = -1;     // joint index of the body it is attached to; -1 = the fixed base
  SsvType type = SsvType::Point;
  std::array<Eigen::Vector3d, 3> p_L{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                     Eigen::Vector3d::Zero()};  // core points in the link frame [m]
  double radius_m = 0;
  int source_line = 0;
};

struct CollisionModel {
  std::vector<CollisionVolume> volumes;
  // Link pairs (joint index, -1 = base) excluded from self-collision checks besides the
  // neighbours, e.g. bodies that touch by construction at a wrist. Stored with first < second.
  std::vector<std::array<int, 2>> allowed_pairs;
  bool empty() const { return volumes.empty(); }
};

struct Model {
  std::string name;  // stable design (or variant) name, appears in every output
  std::string description;
  std::string source;  // e.g. "Thesis Table 3.1, joints 1-6"
  std::vector<std::string> assumptions;
  std::string file;       // design file it came from
  std::string file_hash;  // content hash of that file

  std::vector<Joint> joints;
  PoseXYZABG tcp;          // TCP offset from the last joint frame
  Eigen::Isometry3d T_NT;  // precomputed from tcp
  // The tool axis (unit, in the TCP frame T): the direction a tool-axis task points at its target
  // (the spray axis of the spraying task, the approach axis of the stem tasks); the roll about it
  // is free. `[tcp] tool_axis` in the design file, overridable per study design entry; default z.
  Eigen::Vector3d tool_axis_T = Eigen::Vector3d::UnitZ();
  PoseXYZABG base;         // pose of the robot base frame B in the task/world frame W
  Eigen::Isometry3d T_WB;  // precomputed from base

  std::vector<LinkInertia> inertias;  // empty or one per joint (link i = body after joint i)
  double payload_kg = 0;              // end-effector + payload at the TCP
  Eigen::Vector3d p_payload_com_T = Eigen::Vector3d::Zero();
  std::vector<Drive> drives;
  std::vector<std::string> effects;  // enabled model effects (docs/calibration.md)
  CollisionModel collision;          // [[collision]] volumes; empty = no collision model

  int dof() const { return static_cast<int>(joints.size()); }
  int jointIndex(const std::string& joint_name) const;  // -1 when absent

  // Recompute the cached transforms after editing offsets (used when deriving variants).
  void finalize();
};

}  // namespace armstudy
