#pragma once
// Boundary surface of a sampled 3-D region (the reachable part of a 3-D task grid) and its
// volume, from a CGAL 3-D alpha shape of the sample points. Reusable by other stages that sample
// regions on grids (dexterous workspace, torque-feasible region).
#include <Eigen/Core>
#include <array>
#include <vector>

namespace armstudy {

struct BoundarySurface {
  std::vector<Eigen::Vector3d> vertices;      // m
  std::vector<std::array<int, 3>> triangles;  // outward-facing boundary facets
  double volume_m3 = 0;                       // volume of the alpha shape's solid part
  int components = 0;                         // solid cells present (0 = empty shape)
};

// Regularized alpha shape of `points` with alpha = alpha_radius^2 (CGAL Alpha_shape_3). For
// points on a regular grid with spacing (hx, hy, hz), an alpha_radius slightly above the cell's
// circumradius 0.5 * |(hx, hy, hz)| fills every cell whose 8 corners are all sampled, so the
// volume equals the volume spanned by the sampled cells (half a cell short of the voxel count
// estimate at the boundary).
BoundarySurface alphaShapeSurface(const std::vector<Eigen::Vector3d>& points, double alpha_radius);

// Alpha radius for a grid with the given spacing (1.05 x the cell circumradius).
double gridAlphaRadius(const std::array<double, 3>& spacing);

}  // namespace armstudy
