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
// "<joint>.<effect>" in [model].effects and giving their parameters in [drive.friction]. Each
// effect is declared once, in effectDeclarations() (friction_effects.cpp): its name, its
// parameters with units and bounds, its term of T_loss and that term's derivatives, and the words
// of its docs rows. The validation of [drive.friction], the drive and trajectory calibration
// candidates and `armstudy fit --help` read the declarations; docs/drives.md ("Terms and laws")
// lists them, and tests/calibration/effect_docs_test.cpp checks that table against them.
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
bool isTemperatureEffect(Effect e);

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

// The law-side operating point an effect term is evaluated at.
struct LawPoint {
  double v = 0;       // law-side speed [rad/s | m/s]
  double s = 0;       // sgn(v)
  double L = 0;       // |T_l|
  double sL = 0;      // sgn(T_l)
  double dtheta = 0;  // temperature - reference temperature [K]
};
// The derivatives of one term's law-side loss by the law-side speed and by the load.
struct TermSlope {
  double d_v = 0, d_L = 0;
};

// One parameter of an effect in [drive.friction].
struct EffectParameter {
  const char* key;                // [drive.friction] key
  double FrictionParams::*field;  // where FrictionParams holds it
  const char* unit_motor;         // unit for motor-side laws
  const char* unit_joint;         // unit for joint-side (prismatic) laws
  double lower, upper;            // bounds (law side, SI); +-inf when unbounded
  bool positive;                  // strictly above `lower` (a velocity scale)
  double typical;                 // magnitude `armstudy synth` hides by default (motor side)
  int joint_side_power;           // a joint-side law sees typical x N^joint_side_power
  bool profiled;  // the loss is nonlinear in it: calibration scans it on a grid of law-side speeds
};

// One friction effect, declared once.
struct EffectDeclaration {
  Effect effect;
  const char* name;                     // in [model].effects and calibration
  std::vector<EffectParameter> params;  // the fitted ones first, then a profiled one
  double (*term)(const FrictionParams& p, const LawPoint& x);      // law-side loss
  TermSlope (*slope)(const FrictionParams& p, const LawPoint& x);  // its derivatives
  bool needs_temperature;  // evaluated at a temperature (reference_temperature applies)
  bool starts_at_coulomb;  // a candidate's first parameter starts at the Coulomb level
  const char* law;         // the term as docs/drives.md writes it
  const char* thesis;      // where the term comes from
  const char* pattern;     // the residual pattern it explains (calibration reports, docs)
};
// Every effect, indexed by Effect.
const std::vector<EffectDeclaration>& effectDeclarations();
const EffectDeclaration& declaration(Effect effect);
// N^joint_side_power: the factor from a motor-side typical value to a joint-side law's.
double jointSideScale(const EffectParameter& parameter, double gear_ratio);
// A [drive.friction] key in words, for messages: "stribeck_velocity" -> "Stribeck velocity".
std::string inWords(std::string key);

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
