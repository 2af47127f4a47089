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

namespace {
struct PairDexterity {
  long both = 0;
  double w[2] = {0, 0}, t[2] = {0, 0}, r[2] = {0, 0};  // means over the poses both reach
};
// +1 when every ratio b/a is above 1 (b better), -1 when every one is below, 0 otherwise.
int agreement(const std::vector<double>& ratios) {
  bool up = true, down = true;
  for (double x : ratios) {
    up &= x > 1;
    down &= x < 1;
  }
  return up ? 1 : (down ? -1 : 0);
}
}  // namespace

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

namespace {
// "`a` reaches the most, 95.6 % (`b` 81.8 %, `c` 0.0 %)" over one grid's or list's designs. On a
// grid, designs are level with the first when their difference in reachable poses is at most half
// the two designs' boundary poses (`boundary_poses`: the reach boundary is known to within one grid
// spacing); `pairs` (the comparison's a_only/b_only counts) then says what each reaches alone.
std::string coverageSentence(const ordered_json& designs, const ordered_json& pairs, long poses,
                             const std::string& what, std::vector<std::string>& warnings) {
  struct Entry {
    double fraction;
    std::string design;
    long reachable, boundary;
  };
  std::vector<Entry> f;
  for (const auto& d : designs) {
    f.push_back({d.value("fraction", 0.0), d.value("design", std::string()),
                 d.value("reachable", 0L), d.value("boundary_poses", 0L)});
    if (f.back().reachable == 0)
      warnings.push_back("`" + f.back().design + "` reaches none of the " + std::to_string(poses) +
                         " poses of " + what + ".");
  }
  std::stable_sort(f.begin(), f.end(),
                   [](const Entry& a, const Entry& b) { return a.fraction > b.fraction; });
  if (f.empty()) return "";
  const std::string of = " of the " + std::to_string(poses) + " poses of " + what;
  if (f.size() == 1)
    return "`" + f[0].design + "` reaches " + report::percent(f[0].fraction) + of + ".";
  auto level = [&](const Entry& e) {
    return report::percent(e.fraction) == report::percent(f[0].fraction) ||
           2 * (f[0].reachable - e.reachable) <= f[0].boundary + e.boundary;
  };
  std::size_t k = 0;
  std::string top, rest;
  for (; k < f.size() && level(f[k]); ++k)
    top += std::string(k ? ", " : "") + "`" + f[k].design + "` " + report::percent(f[k].fraction);
  for (std::size_t j = k; j < f.size(); ++j)
    rest +=
        std::string(j > k ? ", " : "") + "`" + f[j].design + "` " + report::percent(f[j].fraction);
  std::string a;
  if (k == 1)
    a = "`" + f[0].design + "` reaches the most" + of + ", " + report::percent(f[0].fraction);
  else
    a = std::string(k == f.size() ? "Level" : "Level at the top") + of + ": " + top;
  if (k < f.size()) a += (k == 1 ? " (then " : "; then ") + rest + (k == 1 ? ")" : "");
  if (k > 1) {
    const long diff = f[0].reachable - f[k - 1].reachable;
    a += ". The difference, " + std::to_string(diff) + " poses, is inside the grid's resolution (" +
         "half the poses on the reach boundaries, where one grid spacing decides)";
    for (const auto& pr : pairs)
      for (std::size_t x = 0; x < k; ++x)
        for (std::size_t y = x + 1; y < k; ++y)
          if ((pr.value("a", "") == f[x].design && pr.value("b", "") == f[y].design) ||
              (pr.value("a", "") == f[y].design && pr.value("b", "") == f[x].design))
            a += "; only `" + pr.value("a", std::string()) + "` reaches " +
                 std::to_string(pr.value("a_only", 0L)) + ", only `" +
                 pr.value("b", std::string()) + "` " + std::to_string(pr.value("b_only", 0L));
  }
  return a + ".";
}
// Each design's largest reach found against its reference_reach_m (summary.json
// `reference_reach`): a sentence of the answer, and a warning when they differ by more than the
// grid resolves (one step).
void referenceReachAnswer(const ordered_json& refs, const std::string& what,
                          std::vector<std::string>& answer, std::vector<std::string>& warnings) {
  for (const auto& r : refs) {
    const std::string design = "`" + r.value("design", std::string()) + "`";
    const double ref = r.value("reference_reach_m", 0.0), res = r.value("resolution_m", 0.0);
    const std::string ref_text = report::fixed(ref * 1e3, 0) + " mm";
    if (!r.contains("largest_reach_found_m") || r["largest_reach_found_m"].is_null()) {
      warnings.push_back(design + " reaches no pose of " + what +
                         ": its reach cannot be compared " + "with the reference " + ref_text +
                         ".");
      continue;
    }
    const double found = r["largest_reach_found_m"].get<double>(), diff = found - ref;
    const std::string sign = diff >= 0 ? "+" : "";
    const std::string text = design + " largest reach found on " + what + ": " +
                             report::fixed(found * 1e3, 0) + " mm against the reference " +
                             ref_text + " (" + sign + report::fixed(diff * 1e3, 0) + " mm, " +
                             sign + report::fixed(100 * diff / ref, 1) + " %; the grid resolves " +
                             report::fixed(res * 1e3, 0) + " mm)";
    answer.push_back(text + ".");
    if (std::abs(diff) > res)
      warnings.push_back(text +
                         ": the difference is larger than the grid resolves; check the "
                         "reference's definition (base axis to flange or to the TCP) and "
                         "the design's tool.");
  }
}
}  // namespace

void reachAnswer(const ordered_json& summary, std::vector<std::string>& answer,
                 std::vector<std::string>& warnings) {
  for (const char* kind : {"grids", "pose_lists"}) {
    if (!summary.contains(kind)) continue;
    for (const auto& g : summary[kind]) {
      const std::string what =
          std::string(kind[0] == 'g' ? "grid `" : "pose list `") + g.value("name", "") + "`";
      const long poses = g.value("poses", 0L);
      const ordered_json pairs = g.contains("comparison") && g["comparison"].contains("pairs")
                                     ? g["comparison"]["pairs"]
                                     : ordered_json::array();
      std::string a =
          coverageSentence(g.value("designs", ordered_json::array()), pairs, poses, what, warnings);
      if (a.empty()) continue;
      a[0] = a[0] == '`' ? a[0] : static_cast<char>(std::toupper(static_cast<unsigned char>(a[0])));
      std::string verdicts;
      if (g.contains("comparison") && g["comparison"].contains("dexterity"))
        for (const auto& v : g["comparison"]["dexterity"]) {
          if (!v.contains("better") || v["better"].is_null()) continue;
          const bool a_better = v.value("a", "") == v["better"].get<std::string>();
          const auto& m = v["manipulability_mean"];
          const double ratio = a_better ? m[0].get<double>() / m[1].get<double>()
                                        : m[1].get<double>() / m[0].get<double>();
          verdicts += std::string(verdicts.empty() ? "" : "; ") + "`" +
                      v.value(a_better ? "a" : "b", "") + "` " + formatG(ratio, 3) + "x `" +
                      v.value(a_better ? "b" : "a", "") + "` (" +
                      std::to_string(v.value("poses_both_reach", 0L)) + " poses)";
        }
      if (!verdicts.empty())
        a += " More dexterous where both reach (manipulability of the task's rows, ranked only "
             "where its translational "
             "and rotational parts agree): " +
             verdicts + ".";
      answer.push_back(a);
      if (g.contains("reference_reach"))
        referenceReachAnswer(g["reference_reach"], what, answer, warnings);
    }
  }
  if (summary.contains("designs_without_collision_volumes") &&
      !summary["designs_without_collision_volumes"].empty()) {
    std::string names;
    for (const auto& n : summary["designs_without_collision_volumes"])
      names += std::string(names.empty() ? "" : ", ") + "`" + n.get<std::string>() + "`";
    warnings.push_back(
        names +
        " evaluated without self-collision and obstacles (no collision volumes): their "
        "reachable shares are not comparable with the others'.");
  }
}

nlohmann::ordered_json dexterityComparison(
    const std::vector<const Model*>& models, const TaskGrid& g,
    const std::vector<PoseSweep>& sweeps,
    const std::vector<std::pair<std::size_t, std::size_t>>& pairs, int threads, std::string& md) {
  std::vector<std::vector<ManipulabilityParts>> parts;
  for (std::size_t d = 0; d < sweeps.size(); ++d)
    parts.push_back(manipulabilityParts(*models[d], g, sweeps[d], threads));
  const bool rot = g.task_space.hasOrientation();
  ordered_json out = ordered_json::array();
  std::vector<std::vector<std::string>> rows;
  std::string verdicts;
  for (const auto& [a, b] : pairs) {
    PairDexterity pd;
    for (long i = 0; i < g.size(); ++i) {
      if (!(sweeps[a].reachable(i) && sweeps[b].reachable(i))) continue;
      ++pd.both;
      const std::size_t u = static_cast<std::size_t>(i);
      const std::size_t ab[2] = {a, b};
      for (int s = 0; s < 2; ++s) {
        pd.w[s] += sweeps[ab[s]].manipulability[u];
        pd.t[s] += parts[ab[s]][u].translation;
        pd.r[s] += parts[ab[s]][u].rotation;
      }
    }
    const std::string &na = sweeps[a].design, &nb = sweeps[b].design;
    ordered_json j = {{"a", na}, {"b", nb}, {"poses_both_reach", pd.both}};
    if (pd.both == 0) {
      out.push_back(j);
      continue;
    }
    for (int s = 0; s < 2; ++s) {
      pd.w[s] /= pd.both;
      pd.t[s] /= pd.both;
      pd.r[s] /= pd.both;
    }
    const double rw = pd.w[1] / pd.w[0], rt = pd.t[1] / pd.t[0], rr = rot ? pd.r[1] / pd.r[0] : rt;
    const int agree = agreement({rw, rt, rr});
    j["manipulability_mean"] = {pd.w[0], pd.w[1]};
    j["translation_mean"] = {pd.t[0], pd.t[1]};
    if (rot) j["rotation_mean"] = {pd.r[0], pd.r[1]};
    j["better"] =
        agree > 0 ? ordered_json(nb) : (agree < 0 ? ordered_json(na) : ordered_json(nullptr));
    out.push_back(j);
    auto ratio = [](double x) {
      return x >= 1 ? report::fixed(x, 2) + "x" : "1/" + report::fixed(1 / x, 2) + "x";
    };
    std::vector<std::string> row{na,
                                 nb,
                                 std::to_string(pd.both),
                                 report::fixed(pd.w[0], 3) + " / " + report::fixed(pd.w[1], 3),
                                 ratio(rw),
                                 ratio(rt)};
    if (rot) row.push_back(ratio(rr));
    rows.push_back(row);
    if (agree != 0) {
      const std::string& better = agree > 0 ? nb : na;
      const std::string& worse = agree > 0 ? na : nb;
      const double f = agree > 0 ? rw : 1 / rw;
      verdicts += "- `" + better + "` is more dexterous than `" + worse + "` on the " +
                  std::to_string(pd.both) + " poses both reach: " + report::fixed(f, 2) +
                  "x the manipulability" +
                  (rot ? ", and better in both its translational and rotational parts.\n" : ".\n");
    } else {
      verdicts += "- `" + na + "` vs `" + nb + "`: no ranking; the combined value favours `" +
                  (rw > 1 ? nb : na) + "` but the translational part favours `" +
                  (rt > 1 ? nb : na) + "` and the rotational part `" + (rr > 1 ? nb : na) +
                  "` (the combined value depends on the 1 m that weighs the angular rows).\n";
    }
  }
  if (rows.empty()) return out;
  std::vector<std::string> header{
      "A", "B", ">poses both reach", ">manipulability A / B", ">B/A", ">B/A translation"};
  if (rot) header.push_back(">B/A rotation");
  md +=
      "Dexterity where both reach (means over the poses both designs reach; manipulability of the "
      "rows the task "
      "constrains, " +
      std::string(rot ? "the angular rows weighed by a characteristic length of 1 m; translation: "
                        "the 3 position "
                        "rows alone [m^3]; rotation: the angular rows alone [1]"
                      : "the 3 position rows [m^3]") +
      "; a pair is ranked only when all agree):\n\n" + report::markdownTable(header, rows) + "\n" +
      verdicts + "\n";
  return out;
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
