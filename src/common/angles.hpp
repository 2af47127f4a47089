// The project's one set of angle constants and conversions. pi itself is std::numbers::pi
// (<numbers>); no M_PI, no local copies.
#pragma once

#include <numbers>

namespace armstudy {

inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;  // [deg/rad]
inline constexpr double kDegToRad = std::numbers::pi / 180.0;  // [rad/deg]
inline constexpr double kFullTurn_rad = 2 * std::numbers::pi;  // one revolution [rad]

// An angle in degrees for text, computed as rad * 180 / pi. Rounding differs from rad * kRadToDeg
// in the last bit for some angles, which can move a printed value at a rounding boundary (22.5
// with no decimals), so the texts that have always been written this way keep this order.
constexpr double toDegrees(double rad) { return rad * 180.0 / std::numbers::pi; }

}  // namespace armstudy
