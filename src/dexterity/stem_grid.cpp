#include "dexterity/stem_grid.hpp"

#include <cmath>

#include "common/angles.hpp"

namespace armstudy::dexterity {

std::string StemGrid::validate() const {
  if (!std::isfinite(stem_x_m) || !std::isfinite(stem_y_m)) return "stem position must be finite";
  if (!std::isfinite(radius_m) || radius_m <= 0) return "stem radius must be > 0";
  for (const AxisRange* a : {&gamma_rad, &z_m}) {
    if (!std::isfinite(a->min) || !std::isfinite(a->max)) return "range limits must be finite";
    if (a->count < 1) return "a range needs at least one sample";
    if (a->count > 1 && !(a->max > a->min)) return "range max must be greater than min";
  }
  if (gamma_rad.max - gamma_rad.min > kFullTurn_rad + 1e-9)
    return "gamma range exceeds a full turn";
  if (!std::isfinite(roll_rad)) return "roll must be finite";
  return "";
}

StemGrid::Cell StemGrid::cell(int i_gamma, int i_z) const {
  Cell c;
  c.gamma = gamma_rad.value(i_gamma);
  c.z = z_m.value(i_z);
  c.u_W = Eigen::Vector3d(std::sin(c.gamma), std::cos(c.gamma), 0.0);
  c.target.kind = task;
  c.target.p_WT = Eigen::Vector3d(stem_x_m, stem_y_m, c.z) - radius_m * c.u_W;
  // Tool frame: z_T = u; x_T = -z_W rotated by `roll` about z_T; y_T = z_T x x_T.
  const Eigen::Vector3d zt = c.u_W;
  const Eigen::Vector3d down(0, 0, -1);
  const Eigen::Vector3d xt = std::cos(roll_rad) * down + std::sin(roll_rad) * zt.cross(down);
  c.target.R_WT.col(0) = xt;
  c.target.R_WT.col(1) = zt.cross(xt);
  c.target.R_WT.col(2) = zt;
  c.target.axis_W = zt;
  return c;
}

std::string StemRow::validate() const {
  if (!std::isfinite(radius_m) || radius_m <= 0) return "stem radius must be > 0";
  if (!std::isfinite(bottom_m) || !std::isfinite(top_m) || !(top_m > bottom_m))
    return "stem top must lie above its bottom";
  if (neighbours < 0) return "neighbours must be >= 0";
  if (neighbours > 0 && !(std::isfinite(spacing_m) && spacing_m > 2 * radius_m))
    return "neighbouring stems need a spacing larger than the stem diameter";
  return "";
}

std::vector<collision::Obstacle> rowObstacles(const StemGrid& g, const StemRow& row) {
  std::vector<collision::Obstacle> out;
  auto add = [&](const std::string& name, double x) {
    out.push_back(collision::capsuleObstacle(name, Eigen::Vector3d(x, g.stem_y_m, row.bottom_m),
                                             Eigen::Vector3d(x, g.stem_y_m, row.top_m),
                                             row.radius_m));
  };
  if (row.stem) add("stem", g.stem_x_m);
  for (int k = 1; k <= row.neighbours; ++k) {
    add("stem_-" + std::to_string(k), g.stem_x_m - k * row.spacing_m);
    add("stem_+" + std::to_string(k), g.stem_x_m + k * row.spacing_m);
  }
  return out;
}

}  // namespace armstudy::dexterity
