#include "stages/reach/reach_stage.hpp"
#include "reach/reach_audit.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "collision/reach_collision.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "io/files.hpp"
#include "io/vtk_io.hpp"
#include "reach/boundary_surface.hpp"
#include "reach/reach_sweep.hpp"
#include "report/image.hpp"
#include "report/markdown.hpp"

namespace armstudy {

using nlohmann::ordered_json;
namespace fs = std::filesystem;

namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
const char* kAxis[3] = {"x", "y", "z"};

struct Extent {
  std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  bool empty() const { return !(lo[0] <= hi[0]); }
  void add(const Eigen::Vector3d& p) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
  ordered_json json() const {
    if (empty()) return nullptr;
    ordered_json j;
    for (int a = 0; a < 3; ++a) j[std::string(kAxis[a]) + "_m"] = {lo[a], hi[a]};
    return j;
  }
  std::string text() const {
    if (empty()) return "none";
    std::string s;
    for (int a = 0; a < 3; ++a) {
      if (a) s += ", ";
      s += std::string(kAxis[a]) + " " + report::fixed(lo[a], 2) + ".." + report::fixed(hi[a], 2);
    }
    return s + " m";
  }
};

struct Stats {
  long n = 0, reachable = 0;
  std::array<long, kReachStatusCount> status{};
  Extent extent;
  double manip_sum = 0, manip_min = INFINITY, manip_max = 0;
  bool collision = false, obstacles = false;
  std::map<std::string, long> colliding_pairs;  // poses reachable only in collision, per pair
  double min_distance = INFINITY;               // smallest distance over the reachable poses
  double min_obstacle_distance = INFINITY;      //   ... to an obstacle
  void add(const PoseSweep& s, long i, const Eigen::Vector3d& p) {
    ++n;
    ++status[s.status[i]];
    if (s.collision) {
      collision = true;
      const int c = s.colliding_pair[i];
      if (c >= 0) ++colliding_pairs[s.pair_names[c]];
      if (s.reachable(i)) min_distance = std::min(min_distance, s.min_distance_m[i]);
    }
    if (s.obstacles) {
      obstacles = true;
      if (s.reachable(i)) min_obstacle_distance = std::min(min_obstacle_distance, s.obstacle_distance_m[i]);
    }
    if (s.reachable(i)) {
      ++reachable;
      extent.add(p);
      manip_sum += s.manipulability[i];
      manip_min = std::min(manip_min, s.manipulability[i]);
      manip_max = std::max(manip_max, s.manipulability[i]);
    }
  }
  double fraction() const { return n ? static_cast<double>(reachable) / n : 0.0; }
  ordered_json json() const {
    ordered_json j;
    j["poses"] = n;
    j["reachable"] = reachable;
    j["fraction"] = fraction();
    ordered_json sc = ordered_json::object();
    for (int k = 0; k < kReachStatusCount; ++k) sc[toString(static_cast<ReachStatus>(k))] = status[k];
    j["status_counts"] = sc;
    j["extent"] = extent.json();
    if (reachable)
      j["manipulability"] = {{"mean", manip_sum / reachable}, {"min", manip_min}, {"max", manip_max}};
    if (collision) {
      ordered_json cp = ordered_json::object();
      for (const auto& [name, count] : colliding_pairs) cp[name] = count;
      j["colliding_pairs"] = cp;
      j["min_distance_m"] = reachable && std::isfinite(min_distance) ? ordered_json(min_distance) : ordered_json(nullptr);
    }
    if (obstacles)
      j["min_obstacle_distance_m"] = reachable && std::isfinite(min_obstacle_distance)
                                         ? ordered_json(min_obstacle_distance)
                                         : ordered_json(nullptr);
    return j;
  }
};

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
  return report::fixed(a.from, 3) + ".." + report::fixed(a.to, 3) + " m step " + report::fixed(a.step, 3) +
         " m (" + std::to_string(a.count()) + ")";
}

std::string suffix(const TaskGrid& g, int k) {
  return g.orientations.size() > 1 ? "_o" + std::to_string(k) : "";
}

// The two image axes of a grid: the first two multi-valued axes (2-D), or for 3-D grids the two
// axes other than the one with the fewest values (that one is projected out).
struct ImagePlane {
  int a = 0, b = 1, projected = -1;
};
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

long pointIndex(const TaskGrid& g, int i, int j, int k) {
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

std::string imageCaptionAxes(const TaskGrid& g, const ImagePlane& p) {
  const auto d = g.dims();
  std::string s = std::string(kAxis[p.a]) + " " + report::fixed(g.axes[p.a].from, 2) + ".." +
                  report::fixed(g.axes[p.a].to, 2) + " m to the right";
  if (d[p.b] > 1)
    s += ", " + std::string(kAxis[p.b]) + " " + report::fixed(g.axes[p.b].from, 2) + ".." +
         report::fixed(g.axes[p.b].to, 2) + " m upwards";
  if (p.projected >= 0)
    s += "; fraction of the " + std::to_string(d[p.projected]) + " cells along " + kAxis[p.projected] +
         " that are reachable (viridis: dark = none, yellow = all)";
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
    for (int c = 0; c < components; ++c) a.values[static_cast<std::size_t>(p) * components + c] = value(offset + p, c);
  return a;
}

void addPoseArrays(std::vector<io::NamedArray>& out, const PoseSweep& s, const TaskGrid* g,
                   long points, int k, const std::string& sfx) {
  using io::ArrayType;
  out.push_back(arrayOf("reachable" + sfx, ArrayType::UInt8, g, points, k, 1,
                        [&](long i, int) { return s.reachable(i) ? 1.0 : 0.0; }));
  out.push_back(arrayOf("status" + sfx, ArrayType::UInt8, g, points, k, 1, [&](long i, int) { return s.status[i]; }));
  out.push_back(arrayOf("position_error_m" + sfx, ArrayType::Float64, g, points, k, 1,
                        [&](long i, int) { return s.position_error_m[i]; }));
  out.push_back(arrayOf("orientation_error_rad" + sfx, ArrayType::Float64, g, points, k, 1,
                        [&](long i, int) { return s.orientation_error_rad[i]; }));
  out.push_back(arrayOf("manipulability" + sfx, ArrayType::Float64, g, points, k, 1,
                        [&](long i, int) { return s.manipulability[i]; }));
  out.push_back(arrayOf("joint_limit_margin" + sfx, ArrayType::Float64, g, points, k, 1,
                        [&](long i, int) { return s.joint_limit_margin[i]; }));
  out.push_back(arrayOf("starts" + sfx, ArrayType::UInt8, g, points, k, 1, [&](long i, int) { return s.starts[i]; }));
  out.push_back(arrayOf("q" + sfx, ArrayType::Float64, g, points, k, s.dof,
                        [&](long i, int c) { return s.q[static_cast<std::size_t>(i) * s.dof + c]; }));
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

// The raw map as <stem>.png and the figure with axes and legend as <stem>.svg; returns the .svg
// path (what the report shows).
std::string writeFigure(Writer& out, const std::string& stem, const report::RasterImage& img,
                        const report::MapFigure& fig) {
  report::writePng(out.path(stem + ".png"), img);
  out.add(stem + ".png");
  out.text(stem + ".svg", report::svgMapFigure(img, fig));
  return stem + ".svg";
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
  const char* text[kReachStatusCount] = {"reachable", "out of reach", "blocked by joint limits",
                                         "representation singularity", "only in self-collision", "torque",
                                         "only in contact with an obstacle"};
  std::vector<report::LegendEntry> l;
  for (int k = 0; k < kReachStatusCount; ++k)
    if (counts[k] > 0) l.push_back({report::categorical(k), text[k]});
  return l;
}

// A chunk's result as bytes for the checkpoint store: its place in the sweep and every per-pose
// column, no timings.
constexpr char kUnitMagic[] = "armstudy-reach-unit-v5";

std::string serializeSweep(const PoseSweep& s) {
  UnitWriter w(kUnitMagic);
  w.put<std::int64_t>(s.dof);
  w.put<std::int64_t>(s.offset);
  w.put<std::int64_t>(s.size);
  w.putVector(s.status);
  w.putVector(s.starts);
  w.putVector(s.position_error_m);
  w.putVector(s.orientation_error_rad);
  w.putVector(s.manipulability);
  w.putVector(s.joint_limit_margin);
  w.putVector(s.q);
  w.putVector(s.q_alt);
  w.put<std::uint8_t>(s.collision);
  w.put<std::uint8_t>(s.obstacles);
  w.putVector(s.min_distance_m);
  w.putVector(s.colliding_pair);
  w.putVector(s.obstacle_distance_m);
  w.put<std::uint64_t>(s.pair_names.size());
  for (const std::string& n : s.pair_names) w.putString(n);
  return w.bytes();
}

bool deserializeSweep(const std::string& b, const std::string& design, PoseSweep& s) {
  UnitReader r(b, kUnitMagic);
  s = PoseSweep{};
  s.design = design;
  s.dof = static_cast<int>(r.get<std::int64_t>());
  s.offset = r.get<std::int64_t>();
  s.size = r.get<std::int64_t>();
  r.getVector(s.status);
  r.getVector(s.starts);
  r.getVector(s.position_error_m);
  r.getVector(s.orientation_error_rad);
  r.getVector(s.manipulability);
  r.getVector(s.joint_limit_margin);
  r.getVector(s.q);
  r.getVector(s.q_alt);
  s.collision = r.get<std::uint8_t>() != 0;
  s.obstacles = r.get<std::uint8_t>() != 0;
  r.getVector(s.min_distance_m);
  r.getVector(s.colliding_pair);
  r.getVector(s.obstacle_distance_m);
  const auto names = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; r.ok() && k < names; ++k) s.pair_names.push_back(r.getString());
  if (!r.finished() || s.size < 0 || s.dof < 0) return false;
  const auto n = static_cast<std::size_t>(s.size);
  const std::size_t nc = s.collision ? n : 0, no = s.obstacles ? n : 0;
  return s.status.size() == n && s.starts.size() == n && s.position_error_m.size() == n &&
         s.orientation_error_rad.size() == n && s.manipulability.size() == n && s.joint_limit_margin.size() == n &&
         s.q.size() == n * s.dof && s.q_alt.size() == n * s.dof && s.min_distance_m.size() == nc && s.colliding_pair.size() == nc &&
         s.obstacle_distance_m.size() == no;
}

long posesOf(const TaskGrid& g) { return g.size(); }
long posesOf(const PoseList& l) { return static_cast<long>(l.poses.size()); }

// One design's sweep of a grid or pose list, as checkpoint units of `unit_poses` poses (rounded to
// whole sweep units, at least one): units saved by an interrupted run are loaded, the others
// solved in one parallel sweep and each saved as soon as it is done; the sweep is assembled from
// the units in index order. Unit ids: <prefix>/units_<first>-<end> (a range of sweep units). A
// saved unit that does not fit (place, size, design size, collision columns) is solved again.
template <class Source, class SweepRanges>
PoseSweep solveUnits(const StageContext& ctx, StageResult& sum, const std::string& prefix,
                     const Model& model, const Source& source, const SweepCollision& collision, Progress& progress,
                     SweepRanges&& sweep_ranges) {
  const long len = sweepUnitLength(source), poses = posesOf(source);
  const std::vector<std::string> pair_names =
      collision.enabled() ? collision::collisionPairNames(model, collision.obstacles, collision.self)
                          : std::vector<std::string>{};
  const long unit_poses = ctx.options.unit_items > 0 ? ctx.options.unit_items : defaults::kReachUnitPoses;
  const std::vector<ItemRange> ranges = splitRange(sweepUnitCount(source), std::max(1L, unit_poses / len));
  std::vector<PoseSweep> chunks, solved;
  UnitBatch batch;
  for (const ItemRange& r : ranges) batch.ids.push_back(prefix + "/units_" + r.text());
  batch.load = [&](std::size_t k, const std::string& bytes) {
    PoseSweep c;
    const long first = ranges[k].begin * len, n = std::min(poses, ranges[k].end * len) - first;
    if (!(deserializeSweep(bytes, model.name, c) && c.offset == first && c.size == n && c.dof == model.dof() &&
          c.collision == collision.enabled() && c.obstacles == !collision.obstacles.empty() &&
          c.pair_names == pair_names))
      return false;
    progress.advance(n);
    chunks.push_back(std::move(c));
    return true;
  };
  batch.compute = [&](const std::vector<std::size_t>& todo, const UnitBatch::Done& done) {
    std::vector<ItemRange> todo_ranges;
    for (std::size_t k : todo) todo_ranges.push_back(ranges[k]);
    solved = sweep_ranges(todo_ranges, [&](std::size_t j, const PoseSweep& c) { done(todo[j], serializeSweep(c)); });
  };
  sum.units_resumed += ctx.units.run(batch);
  if (solved.empty() && !chunks.empty()) return assembleSweep(std::move(chunks), poses);
  double wall = 0, t_reach = 0, t_unreach = 0;
  long nr = 0, n = 0;
  for (PoseSweep& c : solved) {
    wall = std::max(wall, c.wall_seconds);
    t_reach += c.solve_seconds_reachable;
    t_unreach += c.solve_seconds_unreachable;
    nr += c.countReachable();
    n += c.size;
    chunks.push_back(std::move(c));
  }
  sum.timings.push_back({prefix + "/wall", wall});
  sum.timings.push_back({prefix + "/per_reachable_pose", nr ? t_reach / nr : 0.0});
  sum.timings.push_back({prefix + "/per_unreachable_pose", n > nr ? t_unreach / (n - nr) : 0.0});
  return assembleSweep(std::move(chunks), poses);
}

// The self-collision and obstacle-collision columns of the report tables (when checked).
void insertCollisionColumns(const ReachConfig& cfg, std::vector<std::string>& row, int at, const Stats& st) {
  auto share = [&](ReachStatus k) { return report::percent(st.n ? double(st.status[int(k)]) / st.n : 0); };
  if (!cfg.collision.obstacles.empty()) row.insert(row.begin() + at, share(ReachStatus::ObstacleCollision));
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
  for (int i = 0; i < static_cast<int>(o.type); ++i) pts.push_back({o.p_W[i].x(), o.p_W[i].y(), o.p_W[i].z()});
  return {{"name", o.name}, {"type", ssvTypeName(o.type)}, {"points_m", pts}, {"radius_m", o.radius_m}};
}
std::vector<std::string> obstacleRow(const collision::Obstacle& o) {
  std::string pts;
  for (int i = 0; i < static_cast<int>(o.type); ++i)
    pts += (i ? ", (" : "(") + report::fixed(o.p_W[i].x(), 3) + ", " + report::fixed(o.p_W[i].y(), 3) + ", " +
           report::fixed(o.p_W[i].z(), 3) + ")";
  return {o.name, ssvTypeName(o.type), pts, report::fixed(o.radius_m * 1e3, 1)};
}

// Summary metrics of one unit for baselines and checks.
void addUnitMetrics(StudyMetrics& m, const std::string& prefix, const PoseSweep& s) {
  const long nr = s.countReachable();
  m.scalars[prefix + "/reachable_fraction"] = s.size ? double(nr) / s.size : 0.0;
  double sum_m = 0;
  std::vector<std::uint8_t> flags(s.size);
  for (long i = 0; i < s.size; ++i) {
    flags[i] = s.reachable(i);
    if (flags[i]) sum_m += s.manipulability[i];
  }
  m.scalars[prefix + "/manipulability_mean"] = nr ? sum_m / nr : 0.0;
  m.flags[prefix + "/reachable"] = flags;
}

}  // namespace

StageResult runReachStage(const StageContext& ctx, const ReachConfig& cfg) {
  const auto t0 = std::chrono::steady_clock::now();
  StageResult sum;
  const Study& study = ctx.study;
  if (!cfg.enabled) return sum;
  ARMSTUDY_CHECK(cfg.validate().empty(), cfg.validate());
  Writer out(ctx.output_dir);
  long total = 0;
  for (const TaskGrid& g : cfg.grids) total += g.size() * static_cast<long>(study.designs.size());
  for (const PoseList& l : cfg.pose_lists) total += static_cast<long>(l.poses.size() * study.designs.size());
  Progress progress(total, ctx.options.progress, "reachability " + study.name);

  ordered_json js;
  js["study"] = study.name;
  ordered_json jr;
  jr["settings"] = {{"position_tolerance_m", cfg.ik.position_tolerance_m},
                    {"orientation_tolerance_rad", cfg.ik.orientation_tolerance_rad},
                    {"orientation_tolerance_deg", cfg.ik.orientation_tolerance_rad * kRadToDeg},
                    {"starts", cfg.ik.max_starts},
                    {"classify", cfg.ik.classify_failures},
                    {"classify_starts", cfg.ik.classify_starts},
                    {"seed", cfg.ik.seed},
                    {"algorithm", toString(cfg.ik.algorithm)},
                    {"self_collision", cfg.collision.self},
                    {"nullspace_escape", cfg.collision.nullspace_escape},
                    {"search_propagation_rounds", cfg.search.propagation_rounds},
                    {"search_collision_starts", cfg.search.collision_starts},
                    {"search_best_manipulability", cfg.search.best_manipulability},
                    {"search_seed", cfg.search.seed},
                    {"sweep_order", cfg.ik.sweep_descending ? "descending" : "ascending"}};
  {
    ordered_json jobs = ordered_json::array();
    for (const collision::Obstacle& o : cfg.collision.obstacles) jobs.push_back(obstacleJson(o));
    jr["settings"]["obstacles"] = jobs;
  }
  std::string md = "# Reachability: study `" + study.name + "`\n\n";
  if (!study.description.empty()) md += study.description + "\n\n";
  md += "Thesis eq. (3.2): a pose is reachable when a configuration within the joint limits puts the TCP within " +
        report::fixed(cfg.ik.position_tolerance_m * 1e3, 2) + " mm and " +
        report::fixed(cfg.ik.orientation_tolerance_rad * kRadToDeg, 2) +
        " deg of it (up to " + std::to_string(cfg.ik.max_starts) +
        " deterministic starts, seed " + std::to_string(cfg.ik.seed) +
        "). See docs/reachability.md for the solver, the failure reasons and the file formats.\n\n";
  const bool self_on = cfg.collision.self, obst_on = !cfg.collision.obstacles.empty();
  md += "Map colours: " + report::hex(report::categorical(0)) + " reachable, " +
        report::hex(report::categorical(1)) + " out of reach, " + report::hex(report::categorical(2)) +
        " blocked by joint limits, " + report::hex(report::categorical(3)) +
        " representation singularity" +
        (self_on ? ", " + report::hex(report::categorical(4)) + " reachable only in self-collision" : "") +
        (obst_on ? ", " + report::hex(report::categorical(6)) + " reachable only in contact with an obstacle" : "") +
        " (green, light grey, orange, purple" + (self_on ? ", red" : "") + (obst_on ? ", brown" : "") + ").\n\n";
  if (self_on)
    md += "Self-collision: on. A pose counts as reachable only with a collision-free solution (every self-collision "
          "distance of the design's swept-sphere volumes > 0, other postures tried through the redundancy); poses "
          "reachable only in collision are counted separately, with the colliding pair in summary.json.\n\n";
  if (obst_on) {
    md += "Obstacles: " + std::to_string(cfg.collision.obstacles.size()) +
          " in the task frame, checked against every link's swept-sphere volumes; a pose counts as reachable only "
          "with a solution clear of them (field `obstacle_distance`: the arm's clearance from the nearest "
          "obstacle at the solution).\n\n";
    std::vector<std::vector<std::string>> orows;
    for (const collision::Obstacle& o : cfg.collision.obstacles) orows.push_back(obstacleRow(o));
    md += report::markdownTable({"obstacle", "type", "points (task frame) [m]", ">radius [mm]"}, orows) + "\n";
  }

  ordered_json jgrids = ordered_json::array();
  for (const TaskGrid& g : cfg.grids) {
    const auto d = g.dims();
    const long points = g.points();
    const int no = static_cast<int>(g.orientations.size());
    const std::string gdir = "reach/" + g.name;
    ordered_json jg;
    jg["name"] = g.name;
    jg["task_space"] = g.task_space.toString();
    jg["dims"] = {d[0], d[1], d[2]};
    jg["origin_m"] = {g.axes[0].from, g.axes[1].from, g.axes[2].from};
    jg["spacing_m"] = {g.axes[0].step, g.axes[1].step, g.axes[2].step};
    ordered_json jo = ordered_json::array();
    for (const Orientation& o : g.orientations)
      jo.push_back({{"alpha_rad", o.alpha}, {"beta_rad", o.beta}, {"gamma_rad", o.gamma}});
    jg["orientations"] = jo;
    jg["poses"] = g.size();
    if (!g.reference.empty()) jg["reference"] = g.reference;

    md += "## Grid `" + g.name + "`\n\n";
    md += "Task space " + g.task_space.toString() + "; x " + axisText(g.axes[0]) + ", y " + axisText(g.axes[1]) +
          ", z " + axisText(g.axes[2]) + "; " + std::to_string(no) + " orientation(s); " +
          std::to_string(g.size()) + " poses per design.\n\n";

    std::vector<PoseSweep> sweeps;
    std::vector<SweepSearchSummary> searches;
    for (const StudyDesign& sd : study.designs) {
      const std::string unit = "reach/" + g.name + "/" + sd.model.name;
      sweeps.push_back(solveUnits(ctx, sum, unit, sd.model, g, cfg.collision, progress, [&](const auto& ranges, const auto& done) {
        return sweepGridRanges(sd.model, g, ranges, cfg.ik, ctx.threads, &progress, cfg.collision, done);
      }));
      // Across units, once all are in: statuses that do not depend on the traversal (issue 12).
      const SweepSearchSummary ss =
          searchGridSweep(sd.model, g, cfg.ik, ctx.threads, cfg.collision, cfg.search, sweeps.back());
      searches.push_back(ss);
      sum.timings.push_back({unit + "/search", ss.seconds});
      addUnitMetrics(sum.metrics, unit, sweeps.back());
    }

    std::vector<std::vector<std::string>> rows;
    ordered_json jdesigns = ordered_json::array();
    const ImagePlane plane = imagePlane(g);
    std::string images_md;
    for (std::size_t di = 0; di < sweeps.size(); ++di) {
      const PoseSweep& s = sweeps[di];
      const StudyDesign& sd = study.designs[di];
      Stats all;
      std::vector<Stats> per(no);
      for (long i = 0; i < g.size(); ++i) {
        const Eigen::Vector3d p = g.position(g.pointOf(i));
        all.add(s, i, p);
        per[g.orientationOf(i)].add(s, i, p);
      }
      ordered_json jd;
      jd["design"] = s.design;
      jd["variant_of"] = sd.base_name;
      ordered_json ov = ordered_json::object();
      for (const auto& [k, v] : sd.overrides) ov[k] = v;
      jd["overrides"] = ov;
      jd.update(all.json());
      ordered_json jper = ordered_json::array();
      for (int k = 0; k < no; ++k) {
        ordered_json e = per[k].json();
        e["orientation"] = orientationText(g, k);
        jper.push_back(e);
        rows.push_back({s.design, orientationText(g, k), report::percent(per[k].fraction()),
                        report::percent(per[k].n ? double(per[k].status[2]) / per[k].n : 0),
                        report::percent(per[k].n ? double(per[k].status[1]) / per[k].n : 0),
                        report::percent(per[k].n ? double(per[k].status[3]) / per[k].n : 0),
                        per[k].extent.text()});
        insertCollisionColumns(cfg, rows.back(), 3, per[k]);
      }
      jd["per_orientation"] = jper;
      const SweepSearchSummary& se = searches[di];
      jd["search"] = {{"propagation_rounds", se.rounds},
                      {"neighbour_tries", se.neighbour_tries},
                      {"neighbour_updates", se.neighbour_updates},
                      {"collision_multistart_poses", se.multistart_poses},
                      {"collision_multistart_tries", se.multistart_tries},
                      {"collision_multistart_freed", se.multistart_freed},
                      {"best_manipulability_rounds", se.best_rounds},
                      {"best_manipulability_updates", se.best_updates},
                      {"converged", se.converged}};
      md += "Map search (" + s.design + "): " + std::to_string(se.rounds) + " neighbour-propagation rounds changed " +
            std::to_string(se.neighbour_updates) + " statuses";
      if (cfg.collision.enabled())
        md += "; " + std::to_string(se.multistart_poses) + " poses still in collision got " +
              std::to_string(cfg.search.collision_starts) + " seeded starts each (" +
              std::to_string(se.multistart_freed) + " found collision-free). A pose is `self_collision` / "
              "`obstacle_collision` only when no collision-free solution was found in all its starts (array "
              "`starts` of the .vti: the sweep's starts, escapes, neighbour seeds and seeded starts, capped at 255)";
      md += ".\n\n";
      if (cfg.audit_poses > 0) {
        const ReachAudit au = auditGridSweep(sd.model, g, cfg.ik, cfg.collision, s, cfg.audit_poses, cfg.audit_starts,
                                             cfg.audit_seed, ctx.threads);
        ordered_json ja;
        ja["poses"] = au.poses;
        ja["starts_per_pose"] = au.starts;
        ja["seed"] = au.seed;
        ordered_json jb = ordered_json::object(), jc = ordered_json::object();
        for (int k = 0; k < kReachStatusCount; ++k) {
          jb[toString(static_cast<ReachStatus>(k))] = au.by_status[k];
          jc[toString(static_cast<ReachStatus>(k))] = au.contradicted[k];
        }
        ja["audited_by_status"] = jb;
        ja["contradicted_by_status"] = jc;
        ja["contradicted"] = au.contradictedTotal();
        ja["reachable_but_audit_found_none"] = au.audit_missed;
        ja["manipulability_compared"] = au.manipulability_compared;
        ja["manipulability_within_5pct_of_audit_best"] = au.manipulability_within_5pct;
        jd["audit"] = ja;
        const int sc = static_cast<int>(ReachStatus::SelfCollision), oc = static_cast<int>(ReachStatus::ObstacleCollision);
        md += "Audit (" + s.design + "): " + std::to_string(au.poses) + " poses drawn at random (seed " +
              std::to_string(au.seed) + "), " + std::to_string(au.starts) +
              " random starts each, without the sweep's warm starts or neighbours: " +
              std::to_string(au.contradictedTotal()) + " statuses contradicted (a solution" +
              (cfg.collision.enabled() ? " clear of collisions" : "") + " found where the map has none; " +
              std::to_string(au.contradicted[sc]) + " of " + std::to_string(au.by_status[sc]) +
              " self_collision, " + std::to_string(au.contradicted[oc]) + " of " + std::to_string(au.by_status[oc]) +
              " obstacle_collision), " + std::to_string(au.audit_missed) +
              " reachable poses where the audit found no solution; manipulability at the map's solution within 5 % "
              "of the best the audit found at " + std::to_string(au.manipulability_within_5pct) + " of " +
              std::to_string(au.manipulability_compared) + " reachable poses.\n\n";
      }

      // VTK image data: one array per quantity and orientation.
      if (cfg.outputs.vtk) {
        io::ImageGrid img;
        img.dims = d;
        img.origin = {g.axes[0].from, g.axes[1].from, g.axes[2].from};
        img.spacing = {g.axes[0].step, g.axes[1].step, g.axes[2].step};
        for (int k = 0; k < no; ++k) addPoseArrays(img.point_arrays, s, &g, points, k, suffix(g, k));
        if (no > 1)
          img.point_arrays.push_back(arrayOf("reachable_orientations", io::ArrayType::UInt8, nullptr, points, 0, 1,
                                             [&](long p, int) {
                                               int c = 0;
                                               for (int k = 0; k < no; ++k) c += s.reachable(k * points + p);
                                               return double(c);
                                             }));
        const std::string rel = gdir + "/" + s.design + ".vti";
        io::writeVti(out.path(rel), img);
        out.add(rel);
        jd["vti"] = rel;
      }
      // Boundary surface of the reachable region (3-D grids).
      if (cfg.outputs.surface && g.spatialDimension() == 3) {
        ordered_json jsurf = ordered_json::array();
        const double voxel = g.axes[0].step * g.axes[1].step * g.axes[2].step;
        for (int k = 0; k < no; ++k) {
          std::vector<Eigen::Vector3d> pts;
          for (long p = 0; p < points; ++p)
            if (s.reachable(k * points + p)) pts.push_back(g.position(p));
          const BoundarySurface bs =
              alphaShapeSurface(pts, gridAlphaRadius({g.axes[0].step, g.axes[1].step, g.axes[2].step}));
          io::PolyDataSet poly;
          poly.points = bs.vertices;
          poly.triangles = bs.triangles;
          const std::string rel = gdir + "/" + s.design + "_surface" + suffix(g, k) + ".vtp";
          io::writeVtp(out.path(rel), poly);
          out.add(rel);
          jsurf.push_back({{"orientation", orientationText(g, k)},
                           {"file", rel},
                           {"alpha_shape_volume_m3", bs.volume_m3},
                           {"voxel_volume_m3", voxel * static_cast<double>(pts.size())},
                           {"triangles", bs.triangles.size()}});
          md += "";
        }
        jd["surface"] = jsurf;
      }
      // Images.
      if (cfg.outputs.images) {
        const int nu = d[plane.a], nv = plane.b != plane.a && d[plane.b] > 1 ? d[plane.b] : 1;
        double mmax = 0;
        for (long i = 0; i < g.size(); ++i)
          if (s.reachable(i)) mmax = std::max(mmax, s.manipulability[i]);
        for (int k = 0; k < no; ++k) {
          const long off = static_cast<long>(k) * points;
          report::RasterImage status_img = report::renderCellMap(nu, nv, [&](int u, int v) {
            if (plane.projected >= 0) {
              long c = 0, n = 0;
              forCell(g, plane, u, v, [&](long p) { c += s.reachable(off + p); ++n; });
              return report::viridis(n ? double(c) / n : 0.0);
            }
            report::Rgb col;
            forCell(g, plane, u, v, [&](long p) { col = report::categorical(s.status[off + p]); });
            return col;
          });
          report::MapFigure fig = mapAxes(g, plane, s.design + ", " + orientationText(g, k));
          if (plane.projected >= 0)
            fig.scale = report::ColourScale{report::viridis, 0, 1,
                                            "fraction of the cells along " + std::string(kAxis[plane.projected]) +
                                                " that are reachable"};
          else
            fig.legend = statusLegend(per[k].status);
          const std::string rel =
              writeFigure(out, "reach/images/" + g.name + "__" + s.design + suffix(g, k), status_img, fig);
          images_md += "![" + s.design + ", " + orientationText(g, k) + "](" + rel + ")\n\n*" + s.design + ", " +
                       orientationText(g, k) + ": " + report::percent(per[k].fraction()) + " reachable. " +
                       imageCaptionAxes(g, plane) + ".*\n\n";
          if (plane.projected < 0 && mmax > 0) {
            report::RasterImage m_img = report::renderCellMap(nu, nv, [&](int u, int v) {
              report::Rgb col{230, 230, 230};
              forCell(g, plane, u, v, [&](long p) {
                if (s.reachable(off + p)) col = report::viridis(s.manipulability[off + p] / mmax);
              });
              return col;
            });
            report::MapFigure mfig = mapAxes(g, plane, s.design + ", " + orientationText(g, k));
            mfig.scale = report::ColourScale{report::viridis, 0, mmax, "manipulability (eq. 5.59)"};
            mfig.legend = {{report::Rgb{230, 230, 230}, "unreachable"}};
            const std::string mrel = writeFigure(out, 
                "reach/images/" + g.name + "__" + s.design + suffix(g, k) + "_manipulability", m_img, mfig);
            images_md += "![manipulability](" + mrel + ")\n\n*Manipulability sqrt(det(J_w J_w^T)) (eq. 5.59) at the solution, " +
                         s.design + ", " + orientationText(g, k) + "; viridis from 0 (dark) to " +
                         report::scientific(mmax) + " (yellow), grey = unreachable.*\n\n";
          }
        }
      }
      jdesigns.push_back(jd);
    }
    jg["designs"] = jdesigns;
    std::vector<std::string> header = {"design", "orientation", ">reachable", ">joint limits", ">out of reach",
                                       ">repr. singular", "extent of the reachable poses"};
    insertCollisionColumns(cfg, header, 3);
    md += report::markdownTable(header, rows);
    md += "\n";
    if (g.spatialDimension() == 3 && cfg.outputs.surface) {
      std::vector<std::vector<std::string>> srows;
      for (const auto& jd : jdesigns)
        for (const auto& sf : jd["surface"])
          srows.push_back({jd["design"].get<std::string>(), sf["orientation"].get<std::string>(),
                           report::fixed(sf["alpha_shape_volume_m3"].get<double>(), 4),
                           report::fixed(sf["voxel_volume_m3"].get<double>(), 4), sf["file"].get<std::string>()});
      md += "Reachable volume (boundary surface: CGAL 3-D alpha shape of the reachable grid points; the voxel estimate counts one grid cell per reachable point):\n\n" +
            report::markdownTable({"design", "orientation", ">alpha shape [m^3]", ">voxels [m^3]", "surface"}, srows) + "\n";
    }
    if (!g.reference.empty()) {
      md += "**Reference:** " + g.reference + "\n\n**This model:** ";
      for (std::size_t di = 0; di < sweeps.size(); ++di) {
        const auto& jd = jdesigns[di];
        md += "`" + sweeps[di].design + "` reaches " + report::percent(jd["fraction"].get<double>()) +
              " of the grid's poses";
        Stats all;
        for (long i = 0; i < g.size(); ++i) all.add(sweeps[di], i, g.position(g.pointOf(i)));
        md += " (extent " + all.extent.text() + ")" + (di + 1 < sweeps.size() ? "; " : ".\n\n");
      }
    }
    md += images_md;

    // Comparison of designs on this grid.
    if (sweeps.size() >= 2) {
      ordered_json jcmp;
      if (cfg.outputs.vtk && sweeps.size() <= 30) {
        io::ImageGrid img;
        img.dims = d;
        img.origin = {g.axes[0].from, g.axes[1].from, g.axes[2].from};
        img.spacing = {g.axes[0].step, g.axes[1].step, g.axes[2].step};
        for (int k = 0; k < no; ++k) {
          img.point_arrays.push_back(arrayOf("reached_by_mask" + suffix(g, k), io::ArrayType::Int32, &g, points, k, 1,
                                             [&](long i, int) {
                                               long m = 0;
                                               for (std::size_t di = 0; di < sweeps.size(); ++di)
                                                 if (sweeps[di].reachable(i)) m |= 1L << di;
                                               return double(m);
                                             }));
          img.point_arrays.push_back(arrayOf("reached_by_count" + suffix(g, k), io::ArrayType::UInt8, &g, points, k, 1,
                                             [&](long i, int) {
                                               int c = 0;
                                               for (const auto& s : sweeps) c += s.reachable(i);
                                               return double(c);
                                             }));
        }
        const std::string rel = gdir + "/comparison.vti";
        io::writeVti(out.path(rel), img);
        out.add(rel);
        jcmp["vti"] = rel;
        ordered_json bits = ordered_json::array();
        for (const auto& s : sweeps) bits.push_back(s.design);
        jcmp["mask_bits"] = bits;
      }
      md += "### Comparison of designs on `" + g.name + "`\n\n";
      std::vector<std::vector<std::string>> crow;
      ordered_json pairs = ordered_json::array();
      std::string pair_imgs;
      const std::size_t max_pairs_designs = 4;
      for (std::size_t a = 0; a < sweeps.size(); ++a)
        for (std::size_t b = a + 1; b < sweeps.size(); ++b) {
          if (sweeps.size() > max_pairs_designs && a > 0) continue;  // many designs: first vs each
          long n_a = 0, n_b = 0, both = 0, neither = 0;
          for (long i = 0; i < g.size(); ++i) {
            const bool ra = sweeps[a].reachable(i), rb = sweeps[b].reachable(i);
            n_a += ra && !rb;
            n_b += rb && !ra;
            both += ra && rb;
            neither += !ra && !rb;
          }
          pairs.push_back({{"a", sweeps[a].design}, {"b", sweeps[b].design}, {"a_only", n_a}, {"b_only", n_b},
                           {"both", both}, {"neither", neither}});
          const double N = static_cast<double>(g.size());
          crow.push_back({sweeps[a].design, sweeps[b].design, report::percent(n_a / N), report::percent(n_b / N),
                          report::percent(both / N), report::percent(neither / N)});
          if (cfg.outputs.images && plane.projected < 0) {
            const int nu = d[plane.a], nv = plane.b != plane.a && d[plane.b] > 1 ? d[plane.b] : 1;
            for (int k = 0; k < no; ++k) {
              const long off = static_cast<long>(k) * points;
              report::RasterImage img = report::renderCellMap(nu, nv, [&](int u, int v) {
                report::Rgb col;
                forCell(g, plane, u, v, [&](long p) {
                  const bool ra = sweeps[a].reachable(off + p), rb = sweeps[b].reachable(off + p);
                  col = ra && rb ? report::categorical(0)
                                 : ra ? report::categorical(5) : rb ? report::categorical(2) : report::categorical(1);
                });
                return col;
              });
              report::MapFigure cfig =
                  mapAxes(g, plane, sweeps[a].design + " vs " + sweeps[b].design + ", " + orientationText(g, k));
              cfig.legend = {{report::categorical(0), "both"},
                             {report::categorical(5), "only " + sweeps[a].design},
                             {report::categorical(2), "only " + sweeps[b].design},
                             {report::categorical(1), "neither"}};
              const std::string rel = writeFigure(out, "reach/images/" + g.name + "__" + sweeps[a].design + "__vs__" +
                                                     sweeps[b].design + suffix(g, k),
                                                 img, cfig);
              pair_imgs += "![" + sweeps[a].design + " vs " + sweeps[b].design + "](" + rel + ")\n\n*" +
                           orientationText(g, k) + ": reached by both (green), only " + sweeps[a].design +
                           " (blue), only " + sweeps[b].design + " (orange), neither (light grey). " +
                           imageCaptionAxes(g, plane) + ".*\n\n";
            }
          }
        }
      jcmp["pairs"] = pairs;
      // Best design / variant per base design (e.g. the best base placement).
      ordered_json best = ordered_json::array();
      std::vector<std::vector<std::string>> brow;
      std::vector<std::string> bases;
      for (const auto& sd : study.designs)
        if (std::find(bases.begin(), bases.end(), sd.base_name) == bases.end()) bases.push_back(sd.base_name);
      for (const std::string& base : bases) {
        int count = 0, best_i = -1;
        double best_f = -1;
        bool base_sweep = false;
        for (std::size_t di = 0; di < sweeps.size(); ++di) {
          if (study.designs[di].base_name != base) continue;
          ++count;
          for (const auto& [k, v] : study.designs[di].overrides) base_sweep |= k.rfind("base.", 0) == 0;
          const double f = jdesigns[di]["fraction"].get<double>();
          if (f > best_f) {
            best_f = f;
            best_i = static_cast<int>(di);
          }
        }
        if (count < 2) continue;
        best.push_back({{"base_design", base}, {"best", sweeps[best_i].design}, {"fraction", best_f},
                        {"varies_base_placement", base_sweep}});
        brow.push_back({base, sweeps[best_i].design, report::percent(best_f), base_sweep ? "yes" : "no"});
      }
      jcmp["best_variant"] = best;
      jg["comparison"] = jcmp;
      md += "Per pose, which designs reach it (all orientations together):\n\n" +
            report::markdownTable({"A", "B", ">A only", ">B only", ">both", ">neither"}, crow) + "\n";
      if (!brow.empty())
        md += "Best variant per base design (the most reachable poses; with base.* overrides this is the best base placement):\n\n" +
              report::markdownTable({"base design", "best variant", ">reachable", "base placement varied"}, brow) + "\n";
      md += pair_imgs;
    }
    jgrids.push_back(jg);
  }
  jr["grids"] = jgrids;

  // Pose lists.
  ordered_json jlists = ordered_json::array();
  for (const PoseList& l : cfg.pose_lists) {
    ordered_json jl;
    jl["name"] = l.name;
    jl["file"] = l.file;
    jl["task_space"] = l.task_space.toString();
    jl["poses"] = l.poses.size();
    md += "## Pose list `" + l.name + "`\n\n" + std::to_string(l.poses.size()) + " poses from `" + l.file +
          "`, task space " + l.task_space.toString() + ".\n\n";
    std::vector<std::vector<std::string>> rows;
    ordered_json jdesigns = ordered_json::array();
    for (const StudyDesign& sd : study.designs) {
      const std::string unit = "reach/" + l.name + "/" + sd.model.name;
      PoseSweep s = solveUnits(ctx, sum, unit, sd.model, l, cfg.collision, progress, [&](const auto& ranges, const auto& done) {
        return sweepPoseListRanges(sd.model, l, ranges, cfg.ik, ctx.threads, &progress, cfg.collision, done);
      });
      // Poses in collision get the seeded starts too (issue 12; a list has no neighbours).
      const SweepSearchSummary ss =
          searchPoseListSweep(sd.model, l, cfg.ik, ctx.threads, cfg.collision, cfg.search, s);
      sum.timings.push_back({unit + "/search", ss.seconds});
      addUnitMetrics(sum.metrics, unit, s);
      Stats st;
      for (long i = 0; i < s.size; ++i) st.add(s, i, l.poses[i].head<3>());
      ordered_json jd;
      jd["design"] = s.design;
      jd.update(st.json());
      jd["search"] = {{"collision_multistart_poses", ss.multistart_poses},
                      {"collision_multistart_tries", ss.multistart_tries},
                      {"collision_multistart_freed", ss.multistart_freed}};
      if (cfg.outputs.vtk) {
        io::PolyDataSet poly;
        poly.vertices = true;
        for (const auto& w : l.poses) poly.points.push_back(w.head<3>());
        addPoseArrays(poly.point_arrays, s, nullptr, s.size, 0, "");
        poly.point_arrays.push_back(arrayOf("line", io::ArrayType::Int32, nullptr, s.size, 0, 1,
                                            [&](long i, int) { return double(l.lines[i]); }));
        const std::string rel = "reach/" + l.name + "/" + s.design + ".vtp";
        io::writeVtp(out.path(rel), poly);
        out.add(rel);
        jd["vtp"] = rel;
      }
      jdesigns.push_back(jd);
      rows.push_back({s.design, report::percent(st.fraction()),
                      report::percent(st.n ? double(st.status[2]) / st.n : 0),
                      report::percent(st.n ? double(st.status[1]) / st.n : 0), st.extent.text()});
      insertCollisionColumns(cfg, rows.back(), 2, st);
    }
    jl["designs"] = jdesigns;
    jlists.push_back(jl);
    std::vector<std::string> header = {"design", ">reachable", ">joint limits", ">out of reach", "extent"};
    insertCollisionColumns(cfg, header, 2);
    md += report::markdownTable(header, rows) + "\n";
  }
  jr["pose_lists"] = jlists;
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  js["reach"] = jr;
  out.text("summary.json", js.dump(2) + "\n");
  out.text("report.md", md);
  sum.files = out.files();
  return sum;
}

}  // namespace armstudy
