#pragma once
// The design TOML keys that the reader (design_io.cpp) and the writer (design_writer.cpp) both
// walk, in the order they are written (docs/design-format.md).
#include "model/model.hpp"

namespace armstudy {

// A drive's optional values ([[drive]] keys; 0 = not given, never negative), read and written in
// this order.
struct OptionalDriveValue {
  const char* key;
  double Drive::*value;
  bool angular_velocity;  // a quantity with a unit (else a plain number)
};
constexpr OptionalDriveValue kOptionalDriveValues[] = {
    {"rotor_inertia", &Drive::rotor_inertia_kgm2, false},
    {"peak_current", &Drive::peak_current_A, false},
    {"continuous_current", &Drive::continuous_current_A, false},
    {"max_motor_speed", &Drive::max_motor_speed_radps, true},
    {"max_voltage", &Drive::max_voltage_V, false},
    {"resistance", &Drive::resistance_ohm, false},
    {"inductance", &Drive::inductance_H, false},
};

// A joint's joint-side dynamics ([[joint]] keys, plain SI numbers, 0 = none), read and written in
// this order.
struct JointDynamicsValue {
  const char* key;
  double JointDynamics::*value;
  bool non_negative;
  const char* what;
};
constexpr JointDynamicsValue kJointDynamicsValues[] = {
    {"coulomb", &JointDynamics::coulomb, true, "Coulomb friction"},
    {"viscous", &JointDynamics::viscous, true, "viscous friction"},
    {"armature", &JointDynamics::armature, true, "armature"},
    {"effort_offset", &JointDynamics::effort_offset, false, "effort offset"},
};

}  // namespace armstudy
