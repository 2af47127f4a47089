#include "io/ssv_io.hpp"

#include "collision/collision_model.hpp"
#include "io/toml_reader.hpp"

namespace armstudy::io {

SsvGeometry readSsvGeometry(TableReader& r, bool allow_obstacle_names, const std::string& frame) {
  SsvGeometry g;
  const std::string type = r.string("type");
  if (type == "point" || (allow_obstacle_names && type == "sphere"))
    g.type = SsvType::Point;
  else if (type == "line" || (allow_obstacle_names && type == "capsule"))
    g.type = SsvType::Line;
  else if (type == "triangle")
    g.type = SsvType::Triangle;
  else
    r.fail("type", "unknown SSV type '" + type + "' (expected point, line or triangle" +
                       (allow_obstacle_names
                            ? std::string("; sphere and capsule are aliases of point and line")
                            : "") +
                       ")");
  const int n = static_cast<int>(g.type);
  const toml::node* pts = r.node("points");
  if (!pts) r.fail("points", "missing required key");
  const toml::array* arr = pts->as_array();
  if (!arr || static_cast<int>(arr->size()) != n)
    r.fail("points", "a " + type + " needs " + std::to_string(n) + " point" + (n > 1 ? "s" : "") +
                         " [[x, y, z], ...] in " + frame);
  for (int i = 0; i < n; ++i) {
    const toml::array* xyz = (*arr)[i].as_array();
    if (!xyz || xyz->size() != 3) r.fail("points", "each point is [x, y, z] (metres or with unit)");
    for (int k = 0; k < 3; ++k)
      g.p[i][k] = nodeQuantity(*xyz->get(k), Dimension::Length, r.file(), r.keyPath("points"));
  }
  g.radius_m = r.quantity("radius", Dimension::Length);
  const std::string problem = collision::volumeGeometryProblem(g.type, g.p, g.radius_m);
  if (!problem.empty()) r.fail(problem.find("radius") == 0 ? "radius" : "points", problem);
  return g;
}

}  // namespace armstudy::io
