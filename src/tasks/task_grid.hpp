#pragma once
// Task descriptions for reachability sweeps (docs/reachability.md):
//  - Cartesian grids: a range and step per axis (thesis eq. 3.3) times a set of orientations, in a
//    task space (full pose eq. 5.3, spraying eq. 3.1, position only);
//  - explicit pose lists read from CSV (header `x,y,z[,alpha,beta,gamma]`, metres and radians).
// A pose w_d = (x, y, z, alpha, beta, gamma) is given in the task/world frame W; components the
// task space does not select are free (left to the solver).
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "kinematics/kinematics.hpp"

namespace armstudy {

// Values from, from + step, ... up to `to` (inclusive within a 1e-9 relative slack).
// A single value has from == to (step then only needs to be positive).
struct AxisRange {
  double from = 0, to = 0, step = 1;
  int count() const;
  double value(int i) const { return from + i * step; }
  // Empty string when valid, else the reason (non-positive step, empty range, too many values).
  std::string validate() const;
};

// Desired orientation as Cardan angles R = Rx(alpha) Ry(beta) Rz(gamma) [rad].
struct Orientation {
  double alpha = 0, beta = 0, gamma = 0;
};

// Desired task vector w_d (eq. 5.3); all six components, the task space says which count.
using TaskVector6 = Eigen::Matrix<double, 6, 1>;
TaskVector6 makeTaskVector(const Eigen::Vector3d& p_W, const Orientation& o);

// A regular grid of positions times a list of orientations. Flat pose index layout:
//   index = ((o * nz + k) * ny + j) * nx + i  (x fastest, then y, z, orientation).
struct TaskGrid {
  std::string name;
  TaskSpace task_space = TaskSpace::spraying();
  std::array<AxisRange, 3> axes;          // x, y, z [m]
  std::vector<Orientation> orientations;  // at least one (ignored for position-only tasks)
  std::string reference;  // optional statement to compare against (shown in reports)

  std::array<int, 3> dims() const { return {axes[0].count(), axes[1].count(), axes[2].count()}; }
  long points() const;  // nx * ny * nz
  long size() const { return points() * static_cast<long>(orientations.size()); }
  int spatialDimension() const;                // number of axes with more than one value
  Eigen::Vector3d position(long point) const;  // point = (k * ny + j) * nx + i
  TaskVector6 pose(long index) const;
  long pointOf(long index) const { return index % points(); }
  int orientationOf(long index) const { return static_cast<int>(index / points()); }
  // Sweep lines: consecutive indices along the first axis with more than one value. A sweep
  // processes each line in order and warm-starts only from the same line (deterministic).
  long lineLength() const;
  long lines() const { return size() / lineLength(); }
  std::string validate() const;  // empty when valid
};

// An explicit list of poses, e.g. read from CSV.
struct PoseList {
  std::string name;
  std::string file;  // source file (for messages and manifests)
  TaskSpace task_space = TaskSpace::position();
  std::vector<TaskVector6> poses;
  std::vector<int> lines;        // source line of each pose (1-based)
  bool has_orientation = false;  // the CSV carried alpha, beta, gamma columns
};

}  // namespace armstudy
