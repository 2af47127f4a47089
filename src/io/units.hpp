#pragma once
// Quantities as written in design and study files. A bare number is in SI (m, rad, m/s, rad/s).
// A string holds an arithmetic expression (numbers, pi, + - * / and parentheses) with an optional
// unit suffix, so table entries read as in the thesis: "pi/2", "-pi/2", "90 deg", "230 mm".
// The unit is checked against the quantity's dimension: "90 deg" for a length is an error.
#include <string>

namespace armstudy {

enum class Dimension { Length, Angle, LinearVelocity, AngularVelocity, Dimensionless };
const char* toString(Dimension d);

// Converts `text` to SI. Returns false with a message in `error` when the expression is malformed,
// the unit is unknown, or the unit does not fit `dim`.
bool parseQuantity(const std::string& text, Dimension dim, double& value_si, std::string& error);

}  // namespace armstudy
