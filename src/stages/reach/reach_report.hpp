#pragma once
// What the reach stage's report is made of (private to stages/reach): pose statistics, texts,
// image planes and figures of a task grid, VTK arrays of a sweep, obstacle rows.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/angles.hpp"
#include "io/vtk_io.hpp"
#include "reach/reach_sweep.hpp"
#include "report/plot.hpp"
#include "stages/reach/reach_config.hpp"
#include "study/writer.hpp"

namespace armstudy::reach_report {

inline const char* const kAxis[3] = {"x", "y", "z"};

struct Extent {
  std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  nlohmann::ordered_json json() const;  // {"x_m": [lo, hi], ...}, null when empty
  std::string text() const;             // "x 0.10..0.50, y ... m", "none" when empty
  bool empty() const { return !(lo[0] <= hi[0]); }
  void add(const Eigen::Vector3d& p) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
};

struct Stats {
  long n = 0, reachable = 0;
  std::array<long, kReachStatusCount> status{};
  Extent extent;
  double manip_sum = 0, manip_min = INFINITY, manip_max = 0;
  long parts_n = 0;                              // reachable poses whose parts were added
  double translation_sum = 0, rotation_sum = 0;  // the manipulability's parts (ManipulabilityParts)
  bool collision = false, obstacles = false;
  std::map<std::string, long> colliding_pairs;  // poses reachable only in collision, per pair
  double min_distance_m = INFINITY;             // smallest distance over the reachable poses
  double min_obstacle_distance_m = INFINITY;    //   ... to an obstacle
  void add(const PoseSweep& s, long i, const Eigen::Vector3d& p) {
    ++n;
    ++status[s.status[i]];
    if (s.collision) {
      collision = true;
      const int c = s.colliding_pair[i];
      if (c >= 0) ++colliding_pairs[s.pair_names[c]];
      if (s.reachable(i)) min_distance_m = std::min(min_distance_m, s.min_distance_m[i]);
    }
    if (s.obstacles) {
      obstacles = true;
      if (s.reachable(i))
        min_obstacle_distance_m = std::min(min_obstacle_distance_m, s.obstacle_distance_m[i]);
    }
    if (s.reachable(i)) {
      ++reachable;
      extent.add(p);
      manip_sum += s.manipulability[i];
      manip_min = std::min(manip_min, s.manipulability[i]);
      manip_max = std::max(manip_max, s.manipulability[i]);
    }
  }
  void addParts(const ManipulabilityParts& mp) {
    ++parts_n;
    translation_sum += mp.translation;
    rotation_sum += mp.rotation;
  }
  nlohmann::ordered_json json() const;  // the summary.json block of these poses
  double fraction() const { return n ? static_cast<double>(reachable) / n : 0.0; }
};

// The two image axes of a grid: the first two multi-valued axes (2-D), or for 3-D grids the two
// axes other than the one with the fewest values (that one is projected out).
struct ImagePlane {
  int a = 0, b = 1, projected = -1;
};

inline long pointIndex(const TaskGrid& g, int i, int j, int k) {
  const auto d = g.dims();
  return (static_cast<long>(k) * d[1] + j) * d[0] + i;
}

// Calls f(point) for every grid point of image cell (u, v) (several along the projected axis).
template <class F>
void forCell(const TaskGrid& g, const ImagePlane& p, int u, int v, F&& f) {
  const auto d = g.dims();
  std::array<int, 3> c{0, 0, 0};
  c[p.a] = u;
  if (p.b != p.a && d[p.b] > 1) c[p.b] = v;
  if (p.projected < 0) {
    f(pointIndex(g, c[0], c[1], c[2]));
    return;
  }
  for (int w = 0; w < d[p.projected]; ++w) {
    c[p.projected] = w;
    f(pointIndex(g, c[0], c[1], c[2]));
  }
}

// The unit of the task rows' manipulability (ik/reach_solver.hpp taskManipulability): m^k for k
// position rows, the angular rows (dimensionless, weighed by 1 m) named when there are any:
// "m^3" (position task), "m^3; 5 rows, the 2 angular ones weighed by 1 m" (spraying).
inline std::string taskManipulabilityUnit(const TaskSpace& t) {
  const int pos = int(t.selected[0]) + int(t.selected[1]) + int(t.selected[2]);
  const std::string unit = "m^" + std::to_string(pos);
  if (t.dim() == pos) return unit;
  const int ang = t.dim() - pos;
  return unit + "; " + std::to_string(t.dim()) + " rows, the " + std::to_string(ang) +
         (ang == 1 ? " angular one" : " angular ones") + " weighed by 1 m";
}

std::string orientationText(const TaskGrid& g, int k);
std::string axisText(const AxisRange& a);
std::string suffix(const TaskGrid& g, int k);
ImagePlane imagePlane(const TaskGrid& g);
std::string imageCaptionAxes(const TaskGrid& g, const ImagePlane& p);
io::NamedArray arrayOf(const std::string& name, io::ArrayType type, const TaskGrid* g, long points,
                       int k, int components, const std::function<double(long, int)>& value);
void addPoseArrays(std::vector<io::NamedArray>& out, const PoseSweep& s, const TaskGrid* g,
                   long points, int k, const std::string& sfx);
// The translational and rotational parts of the manipulability of every pose of a grid's sweep at
// its stored q (taskManipulabilityParts of the grid's task target; zero where unreachable), on
// `threads` threads (1 inside a parallel region).
std::vector<ManipulabilityParts> manipulabilityParts(const Model& model, const TaskGrid& g,
                                                     const PoseSweep& s, int threads);
// The parts as VTK arrays manipulability_translation / manipulability_rotation (NaN where
// unreachable).
void addPartArrays(std::vector<io::NamedArray>& out, const PoseSweep& s,
                   const std::vector<ManipulabilityParts>& parts, const TaskGrid& g, long points,
                   int k, const std::string& sfx);
// Reachable poses of a grid with an unreachable neighbour (one step along an axis, same
// orientation): where the reach boundary lies, known to within one grid spacing.
long boundaryPoses(const TaskGrid& g, const PoseSweep& s);
// Field data of a sweep's VTK file (docs/paraview.md): units of the pose arrays, the status and
// colliding-pair legends; with a grid `g` of several orientations, what each array suffix means.
std::vector<io::FieldStrings> poseFieldData(const PoseSweep& s, const TaskGrid* g);
// Writes the arm at the sweep's reachable pose of the largest manipulability to out.path(rel)
// (scene::robotPolyData) and lists it; false (nothing written) when no pose is reachable.
bool writeBestRobot(Writer& out, const std::string& rel, const Model& model, const PoseSweep& s);
// The raw map as <stem>.png and the figure with axes and legend as <stem>.svg (stem relative to
// the study folder, under reach/); returns the .svg path relative to reach/report.md (its link).
std::string writeFigure(Writer& out, const std::string& stem, const report::RasterImage& img,
                        const report::MapFigure& fig);
// The status map of orientation k of a grid's sweep (on 3-D grids the fraction of reachable
// cells along the projected axis), titled `title`, with the legend of the statuses counted in
// `counts`, written by writeFigure to <stem>; returns what writeFigure returns.
std::string writeStatusFigure(Writer& out, const std::string& stem, const TaskGrid& grid,
                              const ImagePlane& plane, const PoseSweep& map, int k,
                              const std::array<long, kReachStatusCount>& counts,
                              const std::string& title);
// Axes of a grid's image plane (x to the right, y upwards; a 1-row image has no y extent).
report::MapFigure mapAxes(const TaskGrid& g, const ImagePlane& p, std::string title);
// Legend of the status map: the statuses that occur in it.
std::vector<report::LegendEntry> statusLegend(const std::array<long, kReachStatusCount>& counts);
// The self-collision and obstacle-collision columns of the report tables (when checked).
void insertCollisionColumns(const ReachConfig& cfg, std::vector<std::string>& row, int at,
                            const Stats& st);
void insertCollisionColumns(const ReachConfig& cfg, std::vector<std::string>& header, int at);
const char* ssvTypeName(SsvType t);
nlohmann::ordered_json obstacleJson(const collision::Obstacle& o);
std::vector<std::string> obstacleRow(const collision::Obstacle& o);

}  // namespace armstudy::reach_report
