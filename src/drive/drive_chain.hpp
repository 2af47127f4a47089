#pragma once
// The drive chain from joint to motor (thesis eq. 3.27, 3.29, 4.1a, 4.5): gear ratio, friction,
// rotor inertia, torque constant, winding. Joint quantities in, motor quantities out.
//
//   motor speed      phi_dot  = N * q_dot                               (N = gear_ratio, incl.
//   belt) motor torque     T_a      = Q / N + T_loss(phi_dot, Q, theta) + J_m * N * q_ddot
//   (eq. 3.27a, 4.1a) current          I        = T_a / k_m                               (eq. 4.5)
//   voltage          U        = R * I + L * dI/dt + k_m * phi_dot       (eq. 3.29)
//
// Q is the joint torque [N m] (force [N] for a prismatic joint) the drive must deliver to the
// joint; T_loss is the friction loss of friction.hpp (positive in the direction of motion).
#include "drive/friction.hpp"
#include "model/model.hpp"

namespace armstudy::drive {

struct DriveChainOptions {
  // Add J_m * phi_ddot to the motor torque. Set false when the rigid-body dynamics already
  // includes the reflected rotor inertia N^2 J_m in the mass matrix.
  bool include_rotor_inertia = true;
};

// Which drive limits an operating point exceeds (limits that are 0 in the design are not checked).
struct DriveLimitFlags {
  bool peak_current = false;
  bool continuous_current =
      false;  // meaningful for RMS currents; flagged for the instantaneous value
  bool motor_speed = false;
  bool voltage = false;
  bool any() const { return peak_current || continuous_current || motor_speed || voltage; }
};

struct MotorState {
  double motor_speed_radps = 0;
  double motor_accel_radps2 = 0;
  double friction_torque_Nm = 0;  // T_loss at the motor shaft
  double motor_torque_Nm = 0;     // T_a
  double current_A = 0;           // I
  double voltage_V = 0;           // U (only when voltage_known)
  bool voltage_known = false;     // false when the design gives no winding resistance
  DriveLimitFlags over;
};

// Motor state for one joint operating point. joint_effort is Q; current_rate_Aps is dI/dt (0 for
// quasi-static points). Precondition: drive.torque_constant_NmpA > 0 and drive.gear_ratio > 0.
MotorState motorState(const Drive& drive, const FrictionParams& friction, double joint_speed,
                      double joint_accel, double joint_effort, double temperature_C,
                      double current_rate_Aps = 0.0, const DriveChainOptions& options = {});

// Current the quasi-static test bed measures for motor speed phi_dot and load T_l (thesis eq. 4.3,
// 4.5): I = (T_l / N + T_loss) / k_m.
double testBedCurrent(const Drive& drive, const FrictionParams& friction, double motor_speed_radps,
                      double load, double temperature_C);

}  // namespace armstudy::drive
