// The friction effects, each declared once (friction.hpp): name, [drive.friction] parameters with
// units, bounds and typical values, the term of T_loss with its derivatives, and the words of its
// docs rows. Adding an effect is one entry here (with its Effect value and the FrictionParams
// member of each parameter) plus its rows in docs/drives.md and docs/calibration.md
// (docs/drives.md, "Adding an effect").
#include <cmath>
#include <limits>

#include "drive/friction.hpp"

namespace armstudy::drive {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using P = FrictionParams;

// The Coulomb level a Stribeck term is measured from (eq. 3.33: T_S - T_f0).
double coulombLevel(const P& p) { return p.has(Effect::Coulomb) ? p.coulomb : 0.0; }

}  // namespace

const std::vector<EffectDeclaration>& effectDeclarations() {
  static const std::vector<EffectDeclaration> decl = {
      {Effect::Coulomb,
       "coulomb",
       {{"coulomb", &P::coulomb, "N m", "N", 0, kInf, false, 0.08, 1, false}},
       [](const P& p, const LawPoint& x) { return p.coulomb * x.s; },  // eq. (3.30) T_f0
       [](const P&, const LawPoint&) { return TermSlope{}; },
       false,
       false,
       "c sgn(v)",
       "eq. (3.30) T_f0",
       "a step at zero speed: residual of constant magnitude, sign of the speed, independent of "
       "load"},
      {Effect::Viscous,
       "viscous",
       {{"viscous", &P::viscous, "N m s/rad", "N s/m", 0, kInf, false, 1.5e-4, 2, false}},
       [](const P& p, const LawPoint& x) { return p.viscous * x.v; },  // eq. (3.30) b
       [](const P& p, const LawPoint&) {
         return TermSlope{p.viscous, 0};
       },
       false,
       false,
       "b v",
       "eq. (3.30) b",
       "a straight line through the origin in speed, independent of load"},
      {Effect::LoadCoulomb,
       "load_coulomb",
       {{"load_coulomb", &P::load_coulomb, "-", "-", 0, kInf, false, 4e-3, 0, false}},
       [](const P& p, const LawPoint& x) { return p.load_coulomb * x.L * x.s; },  // eq. (3.30) mu
       [](const P& p, const LawPoint& x) {
         return TermSlope{0, p.load_coulomb * x.s * x.sL};
       },
       false,
       false,
       "mu |T_l| sgn(v)",
       "eq. (3.30) mu",
       "grows with |load|, sign of the speed, the same at every speed"},
      {Effect::LoadViscous,
       "load_viscous",
       {{"load_viscous", &P::load_viscous, "s/rad", "s/m", 0, kInf, false, 7e-6, 1, false}},
       [](const P& p, const LawPoint& x) { return p.load_viscous * x.L * x.v; },  // eq. (3.30)
       [](const P& p, const LawPoint& x) {
         return TermSlope{p.load_viscous * x.L, p.load_viscous * x.v * x.sL};
       },
       false,
       false,
       "gamma |T_l| v",
       "eq. (3.30) gamma",
       "fan of lines through the origin in speed whose slope grows with |load|"},
      {Effect::Stribeck,
       "stribeck",
       {{"stribeck_torque", &P::stribeck_torque, "N m", "N", 0, kInf, false, 0.04, 1, false},
        {"stribeck_velocity", &P::stribeck_velocity, "rad/s", "m/s", 0, kInf, true, 60, -1, true}},
       [](const P& p, const LawPoint& x) {  // eq. (3.33), odd in v
         const double r = x.v / p.stribeck_velocity;
         return (p.stribeck_torque - coulombLevel(p)) * x.s / (1.0 + r * r);
       },
       [](const P& p, const LawPoint& x) {
         const double r = x.v / p.stribeck_velocity;
         const double den = 1.0 + r * r;
         return TermSlope{-(p.stribeck_torque - coulombLevel(p)) * x.s * 2.0 * r /
                              (p.stribeck_velocity * den * den),
                          0};
       },
       false,
       true,
       "(T_S - c) sgn(v) / (1 + (v/v_S)^2)",
       "eq. (3.33) T_fS, phi_S",
       "a bend at low speed: residual largest near standstill, fading above the Stribeck "
       "velocity"},
      {Effect::Asymmetry,
       "asymmetry",
       {{"asymmetry", &P::asymmetry, "N m", "N", -kInf, kInf, false, 0.02, 1, false}},
       [](const P& p, const LawPoint& x) { return p.asymmetry * x.s * x.s; },
       [](const P&, const LawPoint&) { return TermSlope{}; },
       false,
       false,
       "d",
       "direction-dependent friction (not in the thesis laws)",
       "an offset of the same sign in both directions: friction larger one way than the other"},
      {Effect::Temperature,
       "temperature",
       {{"temperature_coefficient", &P::temperature_coefficient, "N m/K", "N/K", -kInf, kInf, false,
         -2e-3, 1, false}},
       [](const P& p, const LawPoint& x) { return p.temperature_coefficient * x.dtheta * x.s; },
       [](const P&, const LawPoint&) { return TermSlope{}; },
       true,
       false,
       "k (theta - theta_ref) sgn(v)",
       "temperature dependence (thesis section 4.4.1, 4.6.2)",
       "residual drifts with temperature, sign of the speed"},
      {Effect::TemperatureViscous,
       "temperature_viscous",
       {{"temperature_viscous_coefficient", &P::temperature_viscous_coefficient, "N m s/(rad K)",
         "N s/(m K)", -kInf, kInf, false, -3e-6, 2, false}},
       // The viscous term's change with the lubricant temperature.
       [](const P& p, const LawPoint& x) {
         return p.temperature_viscous_coefficient * x.dtheta * x.v;
       },
       [](const P& p, const LawPoint& x) {
         return TermSlope{p.temperature_viscous_coefficient * x.dtheta, 0};
       },
       true,
       false,
       "k_b (theta - theta_ref) v",
       "temperature dependence of the viscous term (lubricant viscosity; thesis section 4.4.1)",
       "a fan of lines through the origin in speed whose slope drifts with temperature"},
  };
  return decl;
}

const EffectDeclaration& declaration(Effect e) { return effectDeclarations()[static_cast<int>(e)]; }

}  // namespace armstudy::drive
