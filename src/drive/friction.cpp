#include "drive/friction.hpp"

#include <cmath>
#include <iterator>

#include "common/enum_names.hpp"

namespace armstudy::drive {
namespace {

double sgn(double v) { return (v > 0) - (v < 0); }

constexpr const char* kCoulomb = "coulomb";
constexpr const char* kViscous = "viscous";
constexpr const char* kLoadCoulomb = "load_coulomb";
constexpr const char* kLoadViscous = "load_viscous";
constexpr const char* kStribeckTorque = "stribeck_torque";
constexpr const char* kStribeckVelocity = "stribeck_velocity";
constexpr const char* kAsymmetry = "asymmetry";
constexpr const char* kTemperatureCoefficient = "temperature_coefficient";
constexpr const char* kTemperatureViscousCoefficient = "temperature_viscous_coefficient";
constexpr const char* kReferenceTemperature = "reference_temperature";

double value(const Drive& d, const char* key, double fallback) {
  const auto it = d.friction.find(key);
  return it == d.friction.end() ? fallback : it->second;
}

}  // namespace

constexpr const char* kFrictionLawNames[] = {"none", "harmonic_drive", "stribeck", "prismatic"};
const char* toString(FrictionLaw law) { return enumName(law, kFrictionLawNames); }

constexpr const char* kEffectNames[] = {
    "coulomb",  "viscous",   "load_coulomb", "load_viscous",
    "stribeck", "asymmetry", "temperature",  "temperature_viscous"};
static_assert(std::size(kEffectNames) == kEffectCount);
const char* toString(Effect e) { return enumName(e, kEffectNames); }

bool parseFrictionLaw(std::string_view name, FrictionLaw& out) {
  return parseEnumName(name, kFrictionLawNames, out);
}

bool parseEffect(std::string_view name, Effect& out) {
  return parseEnumName(name, kEffectNames, out);
}

std::vector<Effect> lawEffects(FrictionLaw law) {
  switch (law) {
    case FrictionLaw::None:
      return {};
    case FrictionLaw::HarmonicDrive:
      return {Effect::Coulomb, Effect::LoadCoulomb, Effect::Viscous, Effect::LoadViscous};
    case FrictionLaw::Stribeck:
      return {Effect::Coulomb, Effect::LoadCoulomb, Effect::Viscous, Effect::Stribeck};
    case FrictionLaw::Prismatic:
      return {Effect::Coulomb, Effect::Viscous};
  }
  return {};
}

bool lawIsJointSide(FrictionLaw law) { return law == FrictionLaw::Prismatic; }

std::vector<std::string> effectKeys(Effect e) {
  switch (e) {
    case Effect::Coulomb:
      return {kCoulomb};
    case Effect::Viscous:
      return {kViscous};
    case Effect::LoadCoulomb:
      return {kLoadCoulomb};
    case Effect::LoadViscous:
      return {kLoadViscous};
    case Effect::Stribeck:
      return {kStribeckTorque, kStribeckVelocity};
    case Effect::Asymmetry:
      return {kAsymmetry};
    case Effect::Temperature:
      return {kTemperatureCoefficient};
    case Effect::TemperatureViscous:
      return {kTemperatureViscousCoefficient};
  }
  return {};
}

std::vector<Effect> extraEffects(const Model& model, const std::string& joint) {
  std::vector<Effect> out;
  const std::string prefix = joint + ".";
  for (const std::string& entry : model.effects) {
    if (entry.rfind(prefix, 0) != 0) continue;
    Effect e;
    if (parseEffect(std::string_view(entry).substr(prefix.size()), e)) out.push_back(e);
  }
  return out;
}

std::string validateFriction(const Drive& d, const std::vector<Effect>& extra, std::string& key) {
  key = "friction.law";
  FrictionLaw law = FrictionLaw::None;
  if (d.friction_law.empty() && d.friction.empty() && extra.empty()) return "";
  if (!parseFrictionLaw(d.friction_law, law))
    return "unknown friction law '" + d.friction_law +
           "' (expected harmonic_drive, stribeck, prismatic or none)";
  std::array<bool, kEffectCount> on{};
  for (Effect e : lawEffects(law)) on[static_cast<int>(e)] = true;
  for (Effect e : extra) {
    key = "effects";
    if (on[static_cast<int>(e)])
      return "effect '" + d.joint + "." + toString(e) + "' is already part of the law '" +
             toString(law) + "'";
    on[static_cast<int>(e)] = true;
  }
  for (const auto& [k, v] : d.friction) {
    key = "friction." + k;
    if (!std::isfinite(v)) return "friction parameter must be finite";
    if (k == kReferenceTemperature) {
      if (!on[static_cast<int>(Effect::Temperature)] &&
          !on[static_cast<int>(Effect::TemperatureViscous)])
        return "reference_temperature belongs to the temperature effects, which are not enabled "
               "(add \"" +
               d.joint + ".temperature\" or \"" + d.joint +
               ".temperature_viscous\" to [model].effects)";
      continue;
    }
    bool known = false;
    for (Effect e : kAllEffects)
      for (const std::string& ek : effectKeys(e))
        if (ek == k) {
          known = true;
          if (!on[static_cast<int>(e)])
            return "parameter '" + k + "' belongs to the effect '" + toString(e) +
                   "', which is neither part of the law '" + toString(law) +
                   "' nor enabled in [model].effects as \"" + d.joint + "." + toString(e) + "\"";
        }
    if (!known) return "unknown friction parameter '" + k + "'";
  }
  for (Effect e : kAllEffects) {
    if (!on[static_cast<int>(e)]) continue;
    for (const std::string& ek : effectKeys(e)) {
      key = "friction." + ek;
      if (!d.friction.count(ek))
        return "effect '" + std::string(toString(e)) + "' needs the parameter '" + ek + "'";
    }
  }
  for (const char* k : {kCoulomb, kViscous, kLoadCoulomb, kLoadViscous, kStribeckTorque}) {
    key = std::string("friction.") + k;
    if (value(d, k, 0.0) < 0) return "must not be negative (thesis eq. 3.32)";
  }
  key = std::string("friction.") + kStribeckVelocity;
  if (on[static_cast<int>(Effect::Stribeck)] && !(value(d, kStribeckVelocity, 0.0) > 0))
    return "Stribeck velocity must be positive";
  key.clear();
  return "";
}

double* parameter(FrictionParams& p, std::string_view key) {
  if (key == kCoulomb) return &p.coulomb;
  if (key == kViscous) return &p.viscous;
  if (key == kLoadCoulomb) return &p.load_coulomb;
  if (key == kLoadViscous) return &p.load_viscous;
  if (key == kStribeckTorque) return &p.stribeck_torque;
  if (key == kStribeckVelocity) return &p.stribeck_velocity;
  if (key == kAsymmetry) return &p.asymmetry;
  if (key == kTemperatureCoefficient) return &p.temperature_coefficient;
  if (key == kTemperatureViscousCoefficient) return &p.temperature_viscous_coefficient;
  if (key == kReferenceTemperature) return &p.reference_temperature_C;
  return nullptr;
}

double parameter(const FrictionParams& p, std::string_view key) {
  const double* v = parameter(const_cast<FrictionParams&>(p), key);
  return v ? *v : 0.0;
}

FrictionParams frictionParams(const Drive& d, const std::vector<Effect>& extra) {
  FrictionParams p;
  parseFrictionLaw(d.friction_law.empty() ? "none" : d.friction_law, p.law);
  for (Effect e : lawEffects(p.law)) p.on[static_cast<int>(e)] = true;
  for (Effect e : extra) p.on[static_cast<int>(e)] = true;
  p.coulomb = value(d, kCoulomb, 0.0);
  p.viscous = value(d, kViscous, 0.0);
  p.load_coulomb = value(d, kLoadCoulomb, 0.0);
  p.load_viscous = value(d, kLoadViscous, 0.0);
  p.stribeck_torque = value(d, kStribeckTorque, 0.0);
  p.stribeck_velocity = value(d, kStribeckVelocity, 1.0);
  p.asymmetry = value(d, kAsymmetry, 0.0);
  p.temperature_coefficient = value(d, kTemperatureCoefficient, 0.0);
  p.temperature_viscous_coefficient = value(d, kTemperatureViscousCoefficient, 0.0);
  p.reference_temperature_C = value(d, kReferenceTemperature, 20.0);
  p.gear_ratio = d.gear_ratio;
  p.joint_side = lawIsJointSide(p.law);
  return p;
}

FrictionParams frictionParams(const Model& model, const Drive& d) {
  return frictionParams(d, extraEffects(model, d.joint));
}

double effectTorque(const FrictionParams& p, Effect e, double motor_speed, double load,
                    double temperature_C) {
  if (!p.has(e)) return 0.0;
  // Law side: joint-side laws see the joint speed and return a joint force (eq. 3.27a).
  const double side = p.joint_side ? 1.0 / p.gear_ratio : 1.0;
  const double v = motor_speed * side;
  const double s = sgn(v);
  const double L = std::abs(load);
  double t = 0;
  switch (e) {
    case Effect::Coulomb:
      t = p.coulomb * s;
      break;  // eq. (3.30) T_f0
    case Effect::Viscous:
      t = p.viscous * v;
      break;  // eq. (3.30) b
    case Effect::LoadCoulomb:
      t = p.load_coulomb * L * s;
      break;  // eq. (3.30) mu |T_l|
    case Effect::LoadViscous:
      t = p.load_viscous * L * v;
      break;                  // eq. (3.30) gamma |T_l|
    case Effect::Stribeck: {  // eq. (3.33), odd in v
      const double x = v / p.stribeck_velocity;
      const double c = p.has(Effect::Coulomb) ? p.coulomb : 0.0;
      t = (p.stribeck_torque - c) * s / (1.0 + x * x);
      break;
    }
    case Effect::Asymmetry:
      t = p.asymmetry * s * s;
      break;
    case Effect::Temperature:
      t = p.temperature_coefficient * (temperature_C - p.reference_temperature_C) * s;
      break;
    case Effect::TemperatureViscous:  // the viscous term's change with the lubricant temperature
      t = p.temperature_viscous_coefficient * (temperature_C - p.reference_temperature_C) * v;
      break;
  }
  return t * side;
}

double frictionTorque(const FrictionParams& p, double motor_speed, double load,
                      double temperature_C) {
  double t = 0;
  for (Effect e : kAllEffects)
    if (p.has(e)) t += effectTorque(p, e, motor_speed, load, temperature_C);
  return t;
}

double frictionTorque(const Drive& drive, double motor_speed, double load, double temperature_C) {
  return frictionTorque(frictionParams(drive, {}), motor_speed, load, temperature_C);
}

FrictionDerivatives frictionDerivatives(const FrictionParams& p, double motor_speed, double load,
                                        double temperature_C) {
  const double side = p.joint_side ? 1.0 / p.gear_ratio : 1.0;
  const double v = motor_speed * side;
  const double s = sgn(v);
  const double L = std::abs(load);
  const double sL = sgn(load);
  double dv = 0, dL = 0;  // law-side derivatives of the law-side loss
  if (p.has(Effect::Viscous)) dv += p.viscous;
  if (p.has(Effect::TemperatureViscous))
    dv += p.temperature_viscous_coefficient * (temperature_C - p.reference_temperature_C);
  if (p.has(Effect::LoadCoulomb)) dL += p.load_coulomb * s * sL;
  if (p.has(Effect::LoadViscous)) {
    dv += p.load_viscous * L;
    dL += p.load_viscous * v * sL;
  }
  if (p.has(Effect::Stribeck)) {
    const double c = p.has(Effect::Coulomb) ? p.coulomb : 0.0;
    const double x = v / p.stribeck_velocity;
    const double den = 1.0 + x * x;
    dv += -(p.stribeck_torque - c) * s * 2.0 * x / (p.stribeck_velocity * den * den);
  }
  // d/d(motor speed) = side * d/dv; the loss itself is scaled by side once more.
  return {dv * side * side, dL * side};
}

}  // namespace armstudy::drive
