#include "tasks/task_grid.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "common/defaults.hpp"
#include "common/errors.hpp"

namespace armstudy {

int AxisRange::count() const {
  if (!(step > 0) || !(to >= from)) return 0;
  const double n = std::floor((to - from) / step * (1.0 + defaults::kGridRangeSlack) +
                              defaults::kGridRangeSlack) +
                   1.0;
  return n > defaults::kMaxGridAxisValues ? 0 : static_cast<int>(n);
}

std::string AxisRange::validate() const {
  if (!std::isfinite(from) || !std::isfinite(to) || !std::isfinite(step))
    return "range values must be finite";
  if (!(step > 0)) return "step must be positive";
  if (to < from) return "empty range: 'to' is below 'from'";
  if ((to - from) / step + 1.0 > defaults::kMaxGridAxisValues)
    return "too many values on one axis (more than " +
           std::to_string(defaults::kMaxGridAxisValues) + ")";
  return "";
}

TaskVector6 makeTaskVector(const Eigen::Vector3d& p_W, const Orientation& o) {
  TaskVector6 w;
  w << p_W, o.alpha, o.beta, o.gamma;
  return w;
}

long TaskGrid::points() const {
  const auto d = dims();
  return static_cast<long>(d[0]) * d[1] * d[2];
}

int TaskGrid::spatialDimension() const {
  int n = 0;
  for (int a = 0; a < 3; ++a) n += axes[a].count() > 1 ? 1 : 0;
  return n;
}

Eigen::Vector3d TaskGrid::position(long point) const {
  const auto d = dims();
  const long i = point % d[0];
  const long j = (point / d[0]) % d[1];
  const long k = point / (static_cast<long>(d[0]) * d[1]);
  return {axes[0].value(static_cast<int>(i)), axes[1].value(static_cast<int>(j)),
          axes[2].value(static_cast<int>(k))};
}

TaskVector6 TaskGrid::pose(long index) const {
  return makeTaskVector(position(pointOf(index)), orientations[orientationOf(index)]);
}

long TaskGrid::lineLength() const {
  // Axes before the first multi-valued axis have one value, so a line along it is contiguous.
  for (int a = 0; a < 3; ++a)
    if (axes[a].count() > 1) return axes[a].count();
  return 1;
}

std::string TaskGrid::validate() const {
  static const char* names[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const std::string why = axes[a].validate();
    if (!why.empty()) return std::string(names[a]) + ": " + why;
  }
  if (orientations.empty()) return "a grid needs at least one orientation";
  if (task_space.dim() == 0) return "empty task space";
  if (static_cast<double>(points()) * orientations.size() > defaults::kMaxGridPoses)
    return "grid too large (more than " +
           std::to_string(static_cast<long>(defaults::kMaxGridPoses)) + " poses)";
  return "";
}

}  // namespace armstudy
