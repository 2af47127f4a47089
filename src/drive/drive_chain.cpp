#include "drive/drive_chain.hpp"

#include <cmath>

#include "common/errors.hpp"

namespace armstudy::drive {

MotorState motorState(const Drive& d, const FrictionParams& f, double joint_speed,
                      double joint_accel, double joint_effort, double temperature_C,
                      double current_rate_Aps, const DriveChainOptions& options) {
  ARMSTUDY_CHECK(d.gear_ratio > 0 && d.torque_constant_NmpA > 0,
                 "drive needs a positive gear ratio and torque constant");
  MotorState s;
  const double N = d.gear_ratio;
  s.motor_speed_radps = N * joint_speed;
  s.motor_accel_radps2 = N * joint_accel;
  s.friction_torque_Nm = frictionTorque(f, s.motor_speed_radps, joint_effort, temperature_C);
  // Thesis eq. (3.27a) (friction as a loss) plus the rotor inertia of eq. (4.1a).
  s.motor_torque_Nm = joint_effort / N + s.friction_torque_Nm;
  if (options.include_rotor_inertia)
    s.motor_torque_Nm += d.rotor_inertia_kgm2 * s.motor_accel_radps2;
  s.current_A = s.motor_torque_Nm / d.torque_constant_NmpA;  // eq. (4.5)
  if (d.resistance_ohm > 0) {
    // Thesis eq. (3.29): L dI/dt + R I + k_m phi_dot = U.
    s.voltage_V = d.inductance_H * current_rate_Aps + d.resistance_ohm * s.current_A +
                  d.torque_constant_NmpA * s.motor_speed_radps;
    s.voltage_known = true;
  }
  const double I = std::abs(s.current_A);
  s.over.peak_current = d.peak_current_A > 0 && I > d.peak_current_A;
  s.over.continuous_current = d.continuous_current_A > 0 && I > d.continuous_current_A;
  s.over.motor_speed =
      d.max_motor_speed_radps > 0 && std::abs(s.motor_speed_radps) > d.max_motor_speed_radps;
  s.over.voltage =
      s.voltage_known && d.max_voltage_V > 0 && std::abs(s.voltage_V) > d.max_voltage_V;
  return s;
}

double testBedCurrent(const Drive& d, const FrictionParams& f, double motor_speed, double load,
                      double temperature_C) {
  // Thesis eq. (4.3) with T_f = -T_loss, and eq. (4.5).
  return (load / d.gear_ratio + frictionTorque(f, motor_speed, load, temperature_C)) /
         d.torque_constant_NmpA;
}

}  // namespace armstudy::drive
