#pragma once
// Quantities as written in design and study files. A bare number is in SI (m, rad, m/s, rad/s).
// A string holds an arithmetic expression (numbers, pi, + - * / and parentheses) with an optional
// unit suffix, so table entries read as in the thesis: "pi/2", "-pi/2", "90 deg", "230 mm".
// The unit is checked against the quantity's dimension: "90 deg" for a length is an error. A length
// or linear velocity written as a string must carry its unit ("924.5" is an error, "924.5 mm" is
// read); an angle without a unit is in radians ("pi/2").
#include <string>

namespace armstudy {

enum class Dimension { Length, Angle, LinearVelocity, AngularVelocity, Dimensionless };
const char* toString(Dimension d);
// The SI unit of a dimension as written on an axis: "m", "rad", "m/s", "rad/s", "1".
const char* siUnit(Dimension d);

// Converts `text` to SI. Returns false with a message in `error` when the expression is malformed,
// the unit is unknown, or the unit does not fit `dim`.
bool parseQuantity(const std::string& text, Dimension dim, double& value_si, std::string& error);

// Plausible magnitudes (docs/design-format.md, "Plausible magnitudes"): the largest
// |value| in SI that an input may hold for a quantity of each dimension, and for a plain number
// (masses, inertias, gear ratios, friction coefficients, currents, torques, measured samples).
// They reject absurd values (1e308 as a link offset, a current of 1e308 A), not unusual designs.
// ASSUMPTION: the thesis gives no such limits; these are orders of magnitude above any arm, task
// or test bed in it (lengths of metres, speeds of rad/s, currents of amperes).
inline constexpr double kMaxLength_m = 1e3;
inline constexpr double kMaxAngle_rad = 1e3;
inline constexpr double kMaxLinearVelocity_mps = 1e3;
inline constexpr double kMaxAngularVelocity_radps = 1e4;
inline constexpr double kMaxDimensionless = 1e9;
inline constexpr double kMaxPlainNumber = 1e12;
double plausibleMagnitude(Dimension dim);
// Empty when |value_si| is within plausibleMagnitude(dim) (or kMaxPlainNumber for plain numbers,
// dim = nullptr), else the message for the input error.
std::string implausible(double value_si, const Dimension* dim);
// Empty when `w` is a plausible weight or gain: within [defaults::kMinWeight,
// defaults::kMaxWeight], or 0 where `zero_allowed` (a term switched off); else the message.
std::string implausibleWeight(double w, bool zero_allowed);

}  // namespace armstudy
