#include "drive/friction.hpp"

#include <array>
#include <cctype>
#include <cmath>

#include "common/enum_names.hpp"

namespace armstudy::drive {
namespace {

double sgn(double v) { return (v > 0) - (v < 0); }

constexpr const char* kReferenceTemperature = "reference_temperature";

double value(const Drive& d, const char* key, double fallback) {
  const auto it = d.friction.find(key);
  return it == d.friction.end() ? fallback : it->second;
}

}  // namespace

constexpr const char* kFrictionLawNames[] = {"none", "harmonic_drive", "stribeck", "prismatic"};
const char* toString(FrictionLaw law) { return enumName(law, kFrictionLawNames); }

const char* toString(Effect e) { return declaration(e).name; }

std::string inWords(std::string key) {
  for (char& c : key)
    if (c == '_') c = ' ';
  if (!key.empty()) key[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(key[0])));
  return key;
}

double jointSideScale(const EffectParameter& x, double N) {
  double scale = 1;
  for (int k = 0; k < x.joint_side_power; ++k) scale *= N;
  for (int k = 0; k > x.joint_side_power; --k) scale /= N;
  return scale;
}

bool isTemperatureEffect(Effect e) { return declaration(e).needs_temperature; }

bool parseFrictionLaw(std::string_view name, FrictionLaw& out) {
  return parseEnumName(name, kFrictionLawNames, out);
}

bool parseEffect(std::string_view name, Effect& out) {
  for (const EffectDeclaration& d : effectDeclarations())
    if (name == d.name) {
      out = d.effect;
      return true;
    }
  return false;
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
  std::vector<std::string> keys;
  for (const EffectParameter& p : declaration(e).params) keys.push_back(p.key);
  return keys;
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

namespace {

// The declared lower bounds: a parameter bounded below by 0 is not negative (thesis eq. 3.32), a
// positive one (v_S) is above 0 when its effect is on.
std::string checkBounds(const Drive& d, const std::array<bool, kEffectCount>& on,
                        std::string& key) {
  for (const EffectDeclaration& e : effectDeclarations())
    for (const EffectParameter& p : e.params) {
      key = std::string("friction.") + p.key;
      if (p.lower == 0 && !p.positive && value(d, p.key, 0.0) < 0)
        return "must not be negative (thesis eq. 3.32)";
    }
  for (const EffectDeclaration& e : effectDeclarations())
    for (const EffectParameter& p : e.params) {
      key = std::string("friction.") + p.key;
      if (p.positive && on[static_cast<int>(e.effect)] && !(value(d, p.key, 0.0) > p.lower))
        return inWords(p.key) + " must be positive";
    }
  key.clear();
  return "";
}

}  // namespace

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
      bool temperature_on = false;
      std::string names;
      for (const EffectDeclaration& e : effectDeclarations()) {
        if (!e.needs_temperature) continue;
        temperature_on = temperature_on || on[static_cast<int>(e.effect)];
        names += (names.empty() ? "\"" : " or \"") + d.joint + "." + e.name + "\"";
      }
      if (!temperature_on)
        return "reference_temperature belongs to the temperature effects, which are not enabled "
               "(add " +
               names + " to [model].effects)";
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
  return checkBounds(d, on, key);
}

double* parameter(FrictionParams& p, std::string_view key) {
  if (key == kReferenceTemperature) return &p.reference_temperature_C;
  for (const EffectDeclaration& e : effectDeclarations())
    for (const EffectParameter& x : e.params)
      if (key == x.key) return &(p.*x.field);
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
  for (const EffectDeclaration& e : effectDeclarations())
    for (const EffectParameter& x : e.params) p.*x.field = value(d, x.key, p.*x.field);
  p.reference_temperature_C = value(d, kReferenceTemperature, p.reference_temperature_C);
  p.gear_ratio = d.gear_ratio;
  p.joint_side = lawIsJointSide(p.law);
  return p;
}

FrictionParams frictionParams(const Model& model, const Drive& d) {
  return frictionParams(d, extraEffects(model, d.joint));
}

namespace {

// The law-side operating point of a motor speed, load and temperature; `side` maps motor to law
// side (joint-side laws see the joint speed and return a joint force, eq. 3.27a).
LawPoint lawPoint(const FrictionParams& p, double motor_speed, double load, double temperature_C,
                  double& side) {
  side = p.joint_side ? 1.0 / p.gear_ratio : 1.0;
  LawPoint x;
  x.v = motor_speed * side;
  x.s = sgn(x.v);
  x.L = std::abs(load);
  x.sL = sgn(load);
  x.dtheta = temperature_C - p.reference_temperature_C;
  return x;
}

}  // namespace

double effectTorque(const FrictionParams& p, Effect e, double motor_speed, double load,
                    double temperature_C) {
  if (!p.has(e)) return 0.0;
  double side = 1;
  const LawPoint x = lawPoint(p, motor_speed, load, temperature_C, side);
  return declaration(e).term(p, x) * side;
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
  double side = 1;
  const LawPoint x = lawPoint(p, motor_speed, load, temperature_C, side);
  double dv = 0, dL = 0;  // law-side derivatives of the law-side loss
  for (const EffectDeclaration& e : effectDeclarations()) {
    if (!p.has(e.effect)) continue;
    const TermSlope t = e.slope(p, x);
    dv += t.d_v;
    dL += t.d_L;
  }
  // d/d(motor speed) = side * d/dv; the loss itself is scaled by side once more.
  return {dv * side * side, dL * side};
}

}  // namespace armstudy::drive
