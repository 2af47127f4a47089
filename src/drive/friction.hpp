#pragma once
// Friction laws of the joint drives (thesis section 3.4.3) and the effect terms they are built of.
//
// Sign convention (docs/drives.md): every function here returns the friction LOSS the motor has to
// supply, T_loss, positive in the direction of motion (it carries the sign of the motor speed).
// The thesis writes the friction as a torque acting on the shaft, T_f = -T_loss (eq. 3.30, 3.33,
// 3.35). The balance at the motor shaft is then k_m * I = T_l / N + T_loss (thesis eq. 4.3, 4.5),
// and at standstill (speed exactly 0) every law returns 0 (static friction is set-valued there).
//
// A drive's friction is the sum of named terms ("effects"). The law in [drive.friction] selects a
// thesis formula, i.e. a fixed set of terms; further terms can be switched on by listing
// "<joint>.<effect>" in [model].effects and giving their parameters in [drive.friction]:
//
//   effect        keys (SI, law side)                          term of T_loss
//   coulomb       coulomb [N m | N]                            c sgn(v)
//   viscous       viscous [N m s/rad | N s/m]                  b v
//   load_coulomb  load_coulomb [-]                             mu |T_l| sgn(v)
//   load_viscous  load_viscous [s/rad | s/m]                   gamma |T_l| v
//   stribeck      stribeck_torque T_S [N m | N],               (T_S - c) sgn(v) / (1 + (v/v_S)^2)
//                 stribeck_velocity v_S [rad/s | m/s]
//   asymmetry     asymmetry d [N m | N]                        d (while moving; + direction c+d,
//                                                                 - direction c-d)
//   temperature   temperature_coefficient k [N m/K | N/K],     k (theta - theta_ref) sgn(v)
//                 reference_temperature theta_ref [deg C] (default 20, the catalog temperature)
//   temperature_viscous                                        k_b (theta - theta_ref) v
//                 temperature_viscous_coefficient k_b [N m s/(rad K) | N s/(m K)],
//                 reference_temperature as above (the lubricant's viscosity falls as it warms)
//
// Laws: "harmonic_drive" (eq. 3.30: coulomb, load_coulomb, viscous, load_viscous), "stribeck"
// (eq. 3.33: coulomb, load_coulomb, viscous, stribeck), "prismatic" (eq. 3.35: coulomb, viscous on
// the joint side in N and N s/m), "none" (no terms; effects only).
// "Law side": harmonic_drive, stribeck and none act on the motor shaft, v = motor speed [rad/s],
// T_l = output load torque [N m], loss in N m. prismatic acts on the joint: v = joint speed
// = motor speed / N [m/s], T_l = joint force [N], loss in N; the motor sees loss / N.
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "model/model.hpp"

namespace armstudy::drive {

enum class FrictionLaw { None, HarmonicDrive, Stribeck, Prismatic };

enum class Effect {
  Coulomb,
  Viscous,
  LoadCoulomb,
  LoadViscous,
  Stribeck,
  Asymmetry,
  Temperature,
  TemperatureViscous
};
inline constexpr int kEffectCount = 8;
inline constexpr std::array<Effect, kEffectCount> kAllEffects = {
    Effect::Coulomb,  Effect::Viscous,   Effect::LoadCoulomb, Effect::LoadViscous,
    Effect::Stribeck, Effect::Asymmetry, Effect::Temperature, Effect::TemperatureViscous};
// The effects that need a temperature (data column or operating temperature).
inline bool isTemperatureEffect(Effect e) {
  return e == Effect::Temperature || e == Effect::TemperatureViscous;
}

const char* toString(FrictionLaw law);
const char* toString(Effect effect);
bool parseFrictionLaw(std::string_view name, FrictionLaw& out);
bool parseEffect(std::string_view name, Effect& out);

// The terms a law contains by itself.
std::vector<Effect> lawEffects(FrictionLaw law);
// True when the law acts on the joint side (prismatic, eq. 3.35).
bool lawIsJointSide(FrictionLaw law);

// Resolved friction of one drive: the law, which terms are on, their parameters (SI, law side).
struct FrictionParams {
  FrictionLaw law = FrictionLaw::None;
  std::array<bool, kEffectCount> on{};  // indexed by Effect
  double coulomb = 0;                   // c
  double viscous = 0;                   // b
  double load_coulomb = 0;              // mu
  double load_viscous = 0;              // gamma
  double stribeck_torque = 0;           // T_S (absolute friction level at standstill, eq. 3.33)
  double stribeck_velocity = 1;         // v_S > 0
  double asymmetry = 0;                 // d
  double temperature_coefficient = 0;   // k
  double temperature_viscous_coefficient = 0;  // k_b
  double reference_temperature_C = 20;         // theta_ref
  double gear_ratio = 1;                       // N (maps motor to law side for joint-side laws)
  bool joint_side = false;

  bool has(Effect e) const { return on[static_cast<int>(e)]; }
};

// Parameter keys of one effect in [drive.friction] (reference_temperature is an optional setting of
// the temperature effect, not a fitted parameter, and is not listed).
std::vector<std::string> effectKeys(Effect effect);

// The parameter of FrictionParams named by its [drive.friction] key (effectKeys, plus
// reference_temperature); nullptr for an unknown key. The one place that maps keys to fields.
double* parameter(FrictionParams& p, std::string_view key);
double parameter(const FrictionParams& p, std::string_view key);  // 0 for an unknown key

// Builds the resolved parameters from a drive plus the extra effects enabled for it (the
// "<joint>.<effect>" entries of [model].effects). Precondition: validateFriction passed.
FrictionParams frictionParams(const Drive& drive, const std::vector<Effect>& extra_effects);
// Same, reading the extra effects of drive.joint from model.effects.
FrictionParams frictionParams(const Model& model, const Drive& drive);
// Extra effects enabled for a joint in model.effects ("<joint>.<effect>" entries).
std::vector<Effect> extraEffects(const Model& model, const std::string& joint);

// Checks one drive's friction section against its extra effects: known law, every parameter the
// law and the effects need present, no parameter without its effect, values within bounds
// (c, b, mu, gamma, T_S >= 0 as in thesis eq. 3.32, v_S > 0). Returns "" when valid, otherwise
// the message and (in `key`) the offending key.
std::string validateFriction(const Drive& drive, const std::vector<Effect>& extra_effects,
                             std::string& key);

// Friction loss at the motor shaft [N m] for motor speed phi_dot [rad/s], output load T_l [N m or N
// for prismatic], temperature [deg C] (ignored unless the temperature term is on).
// Thesis eq. (3.30), (3.33), (3.35) with T_loss = -T_f.
double frictionTorque(const FrictionParams& p, double motor_speed_radps, double load,
                      double temperature_C);
// Convenience: resolves the drive (law terms only, no extra effects) on every call.
double frictionTorque(const Drive& drive, double motor_speed_radps, double load,
                      double temperature_C);

// Partial derivatives of frictionTorque (away from speed 0, where the sgn terms jump, and load 0).
struct FrictionDerivatives {
  double d_speed = 0;  // d T_loss / d phi_dot   [N m s/rad]
  double d_load = 0;   // d T_loss / d T_l       [-] (or [m] for prismatic)
};
FrictionDerivatives frictionDerivatives(const FrictionParams& p, double motor_speed_radps,
                                        double load, double temperature_C);

// The contribution of a single effect term to the loss at the motor shaft [N m]. Summing over the
// switched-on effects gives frictionTorque. Used by calibration to attribute residual patterns.
double effectTorque(const FrictionParams& p, Effect effect, double motor_speed_radps, double load,
                    double temperature_C);

}  // namespace armstudy::drive
