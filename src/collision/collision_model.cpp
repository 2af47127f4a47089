#include "collision/collision_model.hpp"

#include <cmath>

#include "common/defaults.hpp"
#include "common/enum_names.hpp"

namespace armstudy {

constexpr const char* kSsvTypeNames[] = {"point", "line", "triangle"};  // from Point = 1
const char* toString(SsvType t) { return enumName(t, kSsvTypeNames, 1); }

namespace collision {

std::string volumeGeometryProblem(SsvType type, const std::array<Eigen::Vector3d, 3>& p,
                                  double radius_m) {
  if (!std::isfinite(radius_m)) return "radius is not finite";
  if (radius_m < 0) return "radius must not be negative";
  const int n = static_cast<int>(type);
  for (int i = 0; i < n; ++i)
    if (!p[i].allFinite()) return "point coordinates must be finite";
  const double eps = defaults::kCollisionCoincident_m;
  if (type == SsvType::Line && (p[1] - p[0]).norm() < eps)
    return "the two points of a line SSV coincide (use type = \"point\" for a sphere)";
  if (type == SsvType::Triangle) {
    for (int i = 0; i < 3; ++i)
      if ((p[(i + 1) % 3] - p[i]).norm() < eps)
        return "two corners of a triangle SSV coincide (use type = \"line\" for a capsule)";
    // Height of each corner over the opposite edge: collinear corners make no triangle.
    const double twice_area = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    for (int i = 0; i < 3; ++i) {
      const double edge = (p[(i + 2) % 3] - p[(i + 1) % 3]).norm();
      if (twice_area / edge < eps)
        return "the corners of a triangle SSV are collinear (use type = \"line\" for a capsule)";
    }
  }
  return "";
}

std::string bodyName(const Model& model, int link) {
  return link < 0 ? std::string("base") : model.joints[link].name;
}

int bodyIndex(const Model& model, const std::string& name) {
  const int j = model.jointIndex(name);
  if (j >= 0) return j;
  return name == "base" ? -1 : -2;
}

bool isCollisionPair(const Model& model, int a, int b) {
  if (a == b || std::abs(a - b) == 1) return false;
  const std::array<int, 2> key{std::min(a, b), std::max(a, b)};
  for (const auto& p : model.collision.allowed_pairs)
    if (p == key) return false;
  return true;
}

}  // namespace collision
}  // namespace armstudy
