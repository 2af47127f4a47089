// The project's one set of angle constants. pi itself is std::numbers::pi (<numbers>).
#pragma once

#include <numbers>

namespace armstudy {

inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;  // [deg/rad]
inline constexpr double kDegToRad = std::numbers::pi / 180.0;  // [rad/deg]

}  // namespace armstudy
