#include "stages/reach/reach_report.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string_view>

#include "common/errors.hpp"
#include "common/format.hpp"
#include "io/files.hpp"
#include "report/markdown.hpp"
#include "study/checkpoint.hpp"
#include "study/scene.hpp"

namespace armstudy::reach_report {

using nlohmann::ordered_json;

ordered_json Extent::json() const {
  if (empty()) return nullptr;
  ordered_json j;
  for (int a = 0; a < 3; ++a) j[std::string(kAxis[a]) + "_m"] = {lo[a], hi[a]};
  return j;
}

std::string Extent::text() const {
  if (empty()) return "none";
  std::string s;
  for (int a = 0; a < 3; ++a) {
    if (a) s += ", ";
    s += std::string(kAxis[a]) + " " + report::fixed(lo[a], 2) + ".." + report::fixed(hi[a], 2);
  }
  return s + " m";
}

ordered_json Stats::json() const {
  ordered_json j;
  j["poses"] = n;
  j["reachable"] = reachable;
  j["fraction"] = fraction();
  ordered_json sc = ordered_json::object();
  for (int k = 0; k < kReachStatusCount; ++k) sc[toString(static_cast<ReachStatus>(k))] = status[k];
  j["status_counts"] = sc;
  j["extent"] = extent.json();
  if (reachable) {
    j["manipulability"] = {{"mean", manip_sum / reachable}, {"min", manip_min}, {"max", manip_max}};
    if (parts_n) {
      j["manipulability"]["translation_mean"] = translation_sum / parts_n;
      j["manipulability"]["rotation_mean"] = rotation_sum / parts_n;
    }
  }
  if (collision) {
    ordered_json cp = ordered_json::object();
    for (const auto& [name, count] : colliding_pairs) cp[name] = count;
    j["colliding_pairs"] = cp;
    j["min_distance_m"] = reachable && std::isfinite(min_distance_m) ? ordered_json(min_distance_m)
                                                                     : ordered_json(nullptr);
  }
  if (obstacles)
    j["min_obstacle_distance_m"] = reachable && std::isfinite(min_obstacle_distance_m)
                                       ? ordered_json(min_obstacle_distance_m)
                                       : ordered_json(nullptr);
  return j;
}

std::string orientationText(const TaskGrid& g, int k) {
  const Orientation& o = g.orientations[k];
  std::string s;
  const char* names[3] = {"alpha", "beta", "gamma"};
  const double v[3] = {o.alpha, o.beta, o.gamma};
  for (int c = 0; c < 3; ++c)
    if (g.task_space.selected[3 + c]) {
      if (!s.empty()) s += ", ";
      s += std::string(names[c]) + " = " + report::fixed(v[c] * kRadToDeg, 1) + " deg";
    }
  return s.empty() ? "any orientation" : s;
}

std::string axisText(const AxisRange& a) {
  if (a.count() == 1) return report::fixed(a.from, 3) + " m";
  return report::fixed(a.from, 3) + ".." + report::fixed(a.to, 3) + " m step " +
         report::fixed(a.step, 3) + " m (" + std::to_string(a.count()) + ")";
}

std::string suffix(const TaskGrid& g, int k) {
  return g.orientations.size() > 1 ? "_o" + std::to_string(k) : "";
}

ImagePlane imagePlane(const TaskGrid& g) {
  const auto d = g.dims();
  std::vector<int> multi;
  for (int a = 0; a < 3; ++a)
    if (d[a] > 1) multi.push_back(a);
  ImagePlane p;
  if (multi.size() == 3) {
    int fewest = 0;
    for (int a = 1; a < 3; ++a)
      if (d[a] <= d[fewest]) fewest = a;
    p.projected = fewest;
    std::vector<int> rest;
    for (int a = 0; a < 3; ++a)
      if (a != fewest) rest.push_back(a);
    p.a = rest[0];
    p.b = rest[1];
  } else if (multi.size() == 2) {
    p.a = multi[0];
    p.b = multi[1];
  } else if (multi.size() == 1) {
    p.a = multi[0];
    p.b = multi[0] == 0 ? 1 : 0;
  }
  return p;
}

std::string imageCaptionAxes(const TaskGrid& g, const ImagePlane& p) {
  const auto d = g.dims();
  std::string s = std::string(kAxis[p.a]) + " " + report::fixed(g.axes[p.a].from, 2) + ".." +
                  report::fixed(g.axes[p.a].to, 2) + " m to the right";
  if (d[p.b] > 1)
    s += ", " + std::string(kAxis[p.b]) + " " + report::fixed(g.axes[p.b].from, 2) + ".." +
         report::fixed(g.axes[p.b].to, 2) + " m upwards";
  if (p.projected >= 0)
    s += "; fraction of the " + std::to_string(d[p.projected]) + " cells along " +
         kAxis[p.projected] + " that are reachable (viridis: dark = none, yellow = all)";
  return s;
}

io::NamedArray arrayOf(const std::string& name, io::ArrayType type, const TaskGrid* g, long points,
                       int k, int components, const std::function<double(long, int)>& value) {
  io::NamedArray a;
  a.name = name;
  a.type = type;
  a.components = components;
  a.values.resize(static_cast<std::size_t>(points) * components);
  const long offset = g ? static_cast<long>(k) * points : 0;
  for (long p = 0; p < points; ++p)
    for (int c = 0; c < components; ++c)
      a.values[static_cast<std::size_t>(p) * components + c] = value(offset + p, c);
  return a;
}

std::vector<ManipulabilityParts> manipulabilityParts(const Model& model, const TaskGrid& g,
                                                     const PoseSweep& s, int threads) {
  std::vector<ManipulabilityParts> parts(static_cast<std::size_t>(g.size()));
  const long n = g.size();
#pragma omp parallel num_threads(threads)
  {
    KinematicsWorkspace kin(model);
    JointVector q(s.dof);
#pragma omp for schedule(static, 256)
    for (long i = 0; i < n; ++i) {
      if (!s.reachable(i)) continue;
      for (int c = 0; c < s.dof; ++c) q[c] = s.q[static_cast<std::size_t>(i) * s.dof + c];
      forwardKinematicsAndJacobian(model, kin, q);
      parts[static_cast<std::size_t>(i)] =
          taskManipulabilityParts(kin, taskTarget(g.task_space, g.pose(i)));
    }
  }
  return parts;
}

long boundaryPoses(const TaskGrid& g, const PoseSweep& s) {
  const std::array<int, 3> n = g.dims();
  const long stride[3] = {1, n[0], static_cast<long>(n[0]) * n[1]};
  long count = 0;
  for (long i = 0; i < g.size(); ++i) {
    if (!s.reachable(i)) continue;
    const long p = g.pointOf(i);
    const long c[3] = {p % n[0], (p / n[0]) % n[1], p / stride[2]};
    bool edge = false;
    for (int a = 0; a < 3 && !edge; ++a)
      for (int d : {-1, 1}) {
        const long cc = c[a] + d;
        if (cc >= 0 && cc < n[a] && !s.reachable(i + d * stride[a])) edge = true;
      }
    count += edge;
  }
  return count;
}

void addPartArrays(std::vector<io::NamedArray>& out, const PoseSweep& s,
                   const std::vector<ManipulabilityParts>& parts, const TaskGrid& g, long points,
                   int k, const std::string& sfx) {
  const double none = std::numeric_limits<double>::quiet_NaN();
  out.push_back(arrayOf("manipulability_translation" + sfx, io::ArrayType::Float64, &g, points, k,
                        1, [&](long i, int) {
                          return s.reachable(i) ? parts[static_cast<std::size_t>(i)].translation
                                                : none;
                        }));
  if (g.task_space.hasOrientation())
    out.push_back(arrayOf("manipulability_rotation" + sfx, io::ArrayType::Float64, &g, points, k, 1,
                          [&](long i, int) {
                            return s.reachable(i) ? parts[static_cast<std::size_t>(i)].rotation
                                                  : none;
                          }));
}

void addPoseArrays(std::vector<io::NamedArray>& out, const PoseSweep& s, const TaskGrid* g,
                   long points, int k, const std::string& sfx) {
  using io::ArrayType;
  out.push_back(arrayOf("reachable" + sfx, ArrayType::UInt8, g, points, k, 1,
                        [&](long i, int) { return s.reachable(i) ? 1.0 : 0.0; }));
  out.push_back(arrayOf("status" + sfx, ArrayType::UInt8, g, points, k, 1,
                        [&](long i, int) { return s.status[i]; }));
  out.push_back(arrayOf("position_error_m" + sfx, ArrayType::Float64, g, points, k, 1,
                        [&](long i, int) { return s.position_error_m[i]; }));
  out.push_back(arrayOf("orientation_error_rad" + sfx, ArrayType::Float64, g, points, k, 1,
                        [&](long i, int) { return s.orientation_error_rad[i]; }));
  // NaN where the quantity does not exist (no solution): ParaView leaves those cells uncoloured.
  const double none = std::numeric_limits<double>::quiet_NaN();
  out.push_back(arrayOf("manipulability" + sfx, ArrayType::Float64, g, points, k, 1,
                        [&](long i, int) { return s.reachable(i) ? s.manipulability[i] : none; }));
  out.push_back(arrayOf("joint_limit_margin" + sfx, ArrayType::Float64, g, points, k, 1,
                        [&](long i, int) { return s.joint_limit_margin[i]; }));
  out.push_back(arrayOf("starts" + sfx, ArrayType::UInt8, g, points, k, 1,
                        [&](long i, int) { return s.starts[i]; }));
  out.push_back(arrayOf("q" + sfx, ArrayType::Float64, g, points, k, s.dof, [&](long i, int c) {
    return s.q[static_cast<std::size_t>(i) * s.dof + c];
  }));
  if (s.obstacles)
    out.push_back(arrayOf("obstacle_distance" + sfx, ArrayType::Float64, g, points, k, 1,
                          [&](long i, int) { return s.obstacle_distance_m[i]; }));
  if (s.collision) {
    out.push_back(arrayOf("min_distance" + sfx, ArrayType::Float64, g, points, k, 1,
                          [&](long i, int) { return s.min_distance_m[i]; }));
    out.push_back(arrayOf("colliding_pair" + sfx, ArrayType::Int32, g, points, k, 1,
                          [&](long i, int) { return double(s.colliding_pair[i]); }));
  }
}

// The figure with axes, colour bar and legend as <stem>.svg and the same figure as <stem>.png;
// returns the .svg path (what the report shows).
std::string writeFigure(Writer& out, const std::string& stem, const report::RasterImage& img,
                        const report::MapFigure& fig) {
  const report::Drawing d = report::mapFigure(img, fig, report::Format::svg_and_png);
  out.text(stem + ".svg", d.svg);
  out.text(stem + ".png", d.png);
  const std::string prefix = "reach/";
  return stem.compare(0, prefix.size(), prefix) == 0 ? stem.substr(prefix.size()) + ".svg"
                                                     : stem + ".svg";
}

std::string writeStatusFigure(Writer& out, const std::string& stem, const TaskGrid& grid,
                              const ImagePlane& plane, const PoseSweep& map, int k,
                              const std::array<long, kReachStatusCount>& counts,
                              const std::string& title) {
  const auto d = grid.dims();
  const long off = static_cast<long>(k) * grid.points();
  const int rows = plane.b != plane.a && d[plane.b] > 1 ? d[plane.b] : 1;
  const report::RasterImage img = report::renderCellMap(d[plane.a], rows, [&](int u, int v) {
    if (plane.projected >= 0) {
      long c = 0, n = 0;
      forCell(grid, plane, u, v, [&](long p) {
        c += map.reachable(off + p);
        ++n;
      });
      return report::viridis(n ? double(c) / n : 0.0);
    }
    report::Rgb col;
    forCell(grid, plane, u, v, [&](long p) { col = report::categorical(map.status[off + p]); });
    return col;
  });
  report::MapFigure fig = mapAxes(grid, plane, title);
  if (plane.projected >= 0)
    fig.scale =
        report::ColourScale{report::viridis, 0, 1,
                            "fraction of the cells along " + std::string(kAxis[plane.projected]) +
                                " that are reachable"};
  else
    fig.legend = statusLegend(counts);
  return writeFigure(out, stem, img, fig);
}

// Axes of a grid's image plane (x to the right, y upwards; a 1-row image has no y extent).
report::MapFigure mapAxes(const TaskGrid& g, const ImagePlane& p, std::string title) {
  report::MapFigure f;
  f.title = std::move(title);
  const auto d = g.dims();
  const AxisRange& a = g.axes[p.a];
  f.x = report::cellAxis(std::string(kAxis[p.a]) + " [m]", a.from, a.to, a.step);
  if (p.b != p.a && d[p.b] > 1) {
    const AxisRange& b = g.axes[p.b];
    f.y = report::cellAxis(std::string(kAxis[p.b]) + " [m]", b.from, b.to, b.step);
  } else {
    f.y = report::MapAxis{"", 0, 0};
  }
  return f;
}

// Legend of the status map: the statuses that occur in it.
std::vector<report::LegendEntry> statusLegend(const std::array<long, kReachStatusCount>& counts) {
  std::vector<report::LegendEntry> l;
  for (int k = 0; k < kReachStatusCount; ++k)
    if (counts[k] > 0) l.push_back({report::categorical(k), describe(static_cast<ReachStatus>(k))});
  return l;
}

std::vector<io::FieldStrings> poseFieldData(const PoseSweep& s, const TaskGrid* g) {
  std::vector<std::string> units{
      "position: m",
      "reachable: 1",
      "status: 1",
      "position_error_m: m",
      "orientation_error_rad: rad",
      "manipulability: m^3 (sqrt(det(J_t J_t^T)) of the rows the task constrains, eq. 5.59: "
      "3 position rows, plus the 2 angular rows perpendicular to the tool axis or all 3 for "
      "the full pose, weighed by a characteristic length of 1 m)",
      "joint_limit_margin: rad (m for prismatic joints)",
      "starts: 1",
      "q: rad (m for prismatic joints)"};
  if (g) {
    units.push_back("manipulability_translation: m^3 (the 3 position rows alone)");
    if (g->task_space.hasOrientation())
      units.push_back("manipulability_rotation: 1 (the angular rows alone)");
  }
  if (s.obstacles) units.push_back("obstacle_distance: m");
  if (s.collision) units.insert(units.end(), {"min_distance: m", "colliding_pair: 1"});
  if (g && g->orientations.size() > 1) {
    units.push_back("reachable_orientations: 1");
    for (int k = 0; k < static_cast<int>(g->orientations.size()); ++k)
      units.push_back("suffix " + suffix(*g, k) + ": orientation " + orientationText(*g, k));
  }
  std::vector<std::string> legend;
  for (int k = 0; k < kReachStatusCount; ++k)
    legend.push_back("status " + std::to_string(k) + ": " + toString(static_cast<ReachStatus>(k)) +
                     " (" + describe(static_cast<ReachStatus>(k)) + ")");
  legend.push_back(
      "manipulability: NaN where status != 0 (no solution); q, errors and margins there are the "
      "best attempt's");
  if (s.collision) {
    legend.push_back("colliding_pair -1: none");
    for (std::size_t i = 0; i < s.pair_names.size(); ++i)
      legend.push_back("colliding_pair " + std::to_string(i) + ": " + s.pair_names[i]);
  }
  return io::fieldData(units, legend);
}

bool writeBestRobot(Writer& out, const std::string& rel, const Model& model, const PoseSweep& s) {
  long best = -1;
  for (long i = 0; i < s.size; ++i)
    if (s.reachable(i) && (best < 0 || s.manipulability[i] > s.manipulability[best])) best = i;
  if (best < 0) return false;
  const Eigen::Map<const Eigen::VectorXd> q(s.q.data() + best * s.dof, s.dof);
  io::PolyDataSet robot = scene::robotPolyData(model, q);
  robot.field_data.push_back({"pose",
                              {"the reachable pose of the largest manipulability, index " +
                               std::to_string(best + s.offset)}});
  io::writeVtp(out.path(rel), robot);
  out.add(rel);
  return true;
}

// The self-collision and obstacle-collision columns of the report tables (when checked).
void insertCollisionColumns(const ReachConfig& cfg, std::vector<std::string>& row, int at,
                            const Stats& st) {
  // A design evaluated without collisions (no volumes) shows "n/a": its share is not comparable.
  auto share = [&](ReachStatus k) {
    return st.collision ? report::percent(st.n ? double(st.status[int(k)]) / st.n : 0)
                        : std::string("n/a (no volumes)");
  };
  if (!cfg.collision.obstacles.empty())
    row.insert(row.begin() + at, share(ReachStatus::ObstacleCollision));
  if (cfg.collision.self) row.insert(row.begin() + at, share(ReachStatus::SelfCollision));
}
void insertCollisionColumns(const ReachConfig& cfg, std::vector<std::string>& header, int at) {
  if (!cfg.collision.obstacles.empty()) header.insert(header.begin() + at, ">obstacle collision");
  if (cfg.collision.self) header.insert(header.begin() + at, ">self-collision");
}

const char* ssvTypeName(SsvType t) {
  return t == SsvType::Point ? "sphere" : t == SsvType::Line ? "capsule" : "triangle";
}
ordered_json obstacleJson(const collision::Obstacle& o) {
  ordered_json pts = ordered_json::array();
  for (int i = 0; i < static_cast<int>(o.type); ++i)
    pts.push_back({o.p_W[i].x(), o.p_W[i].y(), o.p_W[i].z()});
  return {
      {"name", o.name}, {"type", ssvTypeName(o.type)}, {"points_m", pts}, {"radius_m", o.radius_m}};
}
std::vector<std::string> obstacleRow(const collision::Obstacle& o) {
  std::string pts;
  for (int i = 0; i < static_cast<int>(o.type); ++i)
    pts += (i ? ", (" : "(") + report::fixed(o.p_W[i].x(), 3) + ", " +
           report::fixed(o.p_W[i].y(), 3) + ", " + report::fixed(o.p_W[i].z(), 3) + ")";
  return {o.name, ssvTypeName(o.type), pts, report::fixed(o.radius_m * 1e3, 1)};
}

}  // namespace armstudy::reach_report
