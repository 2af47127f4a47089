#pragma once
// Stem-centric task grid of the harvesting task (thesis Fig. 3.4, section 3.2.1): the TCP on a
// circle of radius r around a stem at (x_s, y_s), at angle gamma, at height z, the tool axis z_T
// pointing at the stem centre. u (the transmission direction of eq. 5.60) is the unit vector from
// the TCP to the stem centre.
//
// Convention (docs/dexterity.md): gamma is measured in the horizontal plane from the +y axis of W
// (the direction from the robot base towards the row), positive towards +x:
//   u(gamma)   = ( sin gamma,  cos gamma, 0)
//   p_WT       = (x_s, y_s, z) - r u(gamma)
// so gamma = 0 approaches the stem straight from the robot side, gamma = +pi/2 from -x (the side of
// the base origin when x_s > 0), gamma = -pi/2 from +x.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "collision/collision.hpp"
#include "ik/nullspace.hpp"

namespace armstudy::dexterity {

struct AxisRange {
  double min = 0, max = 0;
  int count = 1;  // number of samples, min and max included (count = 1: only min)
  double value(int i) const { return count == 1 ? min : min + (max - min) * i / (count - 1); }
  double step() const { return count == 1 ? 0.0 : (max - min) / (count - 1); }
  // The samples 0, k, 2k, ... of this range (k >= 1), as a range of their own.
  AxisRange every(int k) const {
    AxisRange a = *this;
    a.count = (count - 1) / k + 1;
    a.max = value((a.count - 1) * k);
    return a;
  }
};

struct StemGrid {
  double stem_x_m = 0, stem_y_m = 0;
  double radius_m = 0.15;
  AxisRange gamma_rad;  // fastest-varying index
  AxisRange z_m;
  PoseTaskKind task = PoseTaskKind::PositionAxis;  // roll about the tool axis free
  double roll_rad = 0;  // FullPose only: tool x axis = down (-z_W) rotated by roll about z_T

  std::string validate() const;  // empty when valid
  int size() const { return gamma_rad.count * z_m.count; }
  int index(int i_gamma, int i_z) const { return i_z * gamma_rad.count + i_gamma; }

  struct Cell {
    PoseTask target;
    Eigen::Vector3d u_W;  // TCP -> stem centre, unit
    double gamma = 0, z = 0;
  };
  Cell cell(int i_gamma, int i_z) const;
};

// The plants of the row around the map's stem as obstacles (docs/dexterity.md, "Collisions"):
// the stem itself and `neighbours` stems on each side along the row (the x axis of W) at
// `spacing_m`, each a vertical capsule of radius_m from bottom_m to top_m.
struct StemRow {
  bool stem = false;     // the map's own stem
  int neighbours = 0;    // per side; needs spacing_m > 0
  double spacing_m = 0;  // stem to stem along x (thesis Table 2.2: 0.192 m nominal)
  double radius_m = 0.012;
  double bottom_m = 0, top_m = 2;
  std::string validate() const;  // empty when valid
};
// "stem" and "stem_-1", "stem_+1", ... (neighbours by their place along +x).
std::vector<collision::Obstacle> rowObstacles(const StemGrid& grid, const StemRow& row);

}  // namespace armstudy::dexterity
