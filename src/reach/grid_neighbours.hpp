#pragma once
// Private to reach/reach_search.cpp: the neighbourhoods of a grid pose that the map search seeds
// from, in a fixed order.
#include "tasks/task_grid.hpp"

namespace armstudy::sweep_detail {

// A grid's index layout, computed once per search (TaskGrid::dims() recomputes each axis' count
// from floating-point ranges; the neighbour look-ups below run millions of times per search).
struct GridShape {
  long d[3];
  long P, O;  // points, orientations
  explicit GridShape(const TaskGrid& g) {
    const auto dims = g.dims();
    for (int a = 0; a < 3; ++a) d[a] = dims[a];
    P = d[0] * d[1] * d[2];
    O = static_cast<long>(g.orientations.size());
  }
};

// The neighbours of grid pose i: +-1 along each spatial axis, and the same point in the previous
// and next orientation of the grid's list, in a fixed order.
inline int gridNeighbours(const GridShape& g, long i, long out[8]) {
  const long* d = g.d;
  const long P = g.P, O = g.O;
  const long o = i / P, p = i % P;
  const long ix = p % d[0], iy = (p / d[0]) % d[1], iz = p / (d[0] * d[1]);
  const long c[3] = {ix, iy, iz};
  const long stride[3] = {1, d[0], d[0] * d[1]};
  int n = 0;
  for (int a = 0; a < 3; ++a) {
    if (c[a] > 0) out[n++] = i - stride[a];
    if (c[a] + 1 < d[a]) out[n++] = i + stride[a];
  }
  if (o > 0) out[n++] = i - P;
  if (o + 1 < O) out[n++] = i + P;
  return n;
}

// Pose i's wider neighbourhood: the other points of the 3 x 3 x 3 box around it (same orientation)
// and the previous and next orientation at its point, in a fixed order; at most 28.
inline int gridBoxNeighbours(const GridShape& g, long i, long out[28]) {
  const long* d = g.d;
  const long P = g.P, O = g.O;
  const long o = i / P, p = i % P;
  const long ix = p % d[0], iy = (p / d[0]) % d[1], iz = p / (d[0] * d[1]);
  int n = 0;
  for (long dz = -1; dz <= 1; ++dz)
    for (long dy = -1; dy <= 1; ++dy)
      for (long dx = -1; dx <= 1; ++dx) {
        const long x = ix + dx, y = iy + dy, z = iz + dz;
        if ((dx == 0 && dy == 0 && dz == 0) || x < 0 || y < 0 || z < 0 || x >= d[0] || y >= d[1] ||
            z >= d[2])
          continue;
        out[n++] = o * P + x + d[0] * (y + d[1] * z);
      }
  if (o > 0) out[n++] = i - P;
  if (o + 1 < O) out[n++] = i + P;
  return n;
}

}  // namespace armstudy::sweep_detail
