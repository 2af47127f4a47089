#include "stages/tracking/tracking_stage.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "collision/collision_term.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"
#include "common/parallel_for.hpp"
#include "io/files.hpp"
#include "io/vtk_io.hpp"
#include "model/model_notes.hpp"
#include "report/markdown.hpp"
#include "report/plot.hpp"
#include "study/scene.hpp"
#include "study/writer.hpp"

namespace armstudy::tracking {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

namespace {
constexpr double kPathRate_Hz = 100.0;  // TCP path points per second in the .vtp
constexpr double kPlotRate_Hz = 200.0;  // plotted samples per second in the SVGs
constexpr int kCircleSegments = 36;     // wireframe circles of the obstacles in the .vtp
constexpr int kMotionSteps = 31;        // robot time steps per run in the .pvd series
}  // namespace

// ---------------------------------------------------------------------------------------------
// Outputs
// ---------------------------------------------------------------------------------------------

namespace {

ordered_json finiteOrNull(double v) {
  return std::isfinite(v) ? ordered_json(v) : ordered_json(nullptr);
}

std::string pairText(const RunResult& r, int pair) { return pair >= 0 ? r.pair_names[pair] : ""; }

std::string runLabel(RunKind k) { return k == RunKind::Plain ? "without H_c" : "with H_c"; }

void writeRunCsv(const Model& model, const TrackingEntry& e, const RunResult& r,
                 const std::string& path) {
  const bool obstacles = !e.obstacles.empty();
  const bool orientation = e.task != PoseTaskKind::Position;
  std::ostringstream s;
  s << "t_s";
  for (const Joint& j : model.joints) s << ",q_" << j.name;
  s << ",x_m,y_m,z_m,position_error_m";
  if (orientation) s << ",orientation_error_rad";
  if (obstacles) s << ",obstacle_distance_m,obstacle_pair";
  s << ",self_distance_m,self_pair\n";
  for (const RunSample& rs : r.samples) {
    s << formatGOr(rs.t, 10, "");
    for (int i = 0; i < model.dof(); ++i) s << "," << formatGOr(rs.q[i], 10, "");
    s << "," << formatGOr(rs.p_WT.x(), 10, "") << "," << formatGOr(rs.p_WT.y(), 10, "") << ","
      << formatGOr(rs.p_WT.z(), 10, "") << "," << formatGOr(rs.position_error_m, 10, "");
    if (orientation) s << "," << formatGOr(rs.orientation_error_rad, 10, "");
    if (obstacles)
      s << "," << formatGOr(rs.obstacle_distance_m, 10, "") << "," << pairText(r, rs.obstacle_pair);
    s << "," << formatGOr(rs.self_distance_m, 10, "") << "," << pairText(r, rs.self_pair) << "\n";
  }
  writeFileAtomic(path, s.str());
}

// ParaView scene of one run: parts 0 = reference line, 1 = TCP path, 2 = arm skeletons (base,
// joint-frame origins, TCP) at `snapshots` times, 3 = obstacles (core, plus three great circles of
// the radius around every core point).
struct PolyBuilder {
  io::PolyDataSet poly;
  std::vector<double> time, part, contact, radius;
  int add(const Eigen::Vector3d& p, double t, int prt, bool in_contact, double r) {
    poly.points.push_back(p);
    time.push_back(t);
    part.push_back(prt);
    contact.push_back(in_contact ? 1 : 0);
    radius.push_back(r);
    return static_cast<int>(poly.points.size()) - 1;
  }
  void finish() {
    poly.point_arrays = {{"time", io::ArrayType::Float64, 1, time},
                         {"part", io::ArrayType::Int32, 1, part},
                         {"in_contact", io::ArrayType::UInt8, 1, contact},
                         {"radius", io::ArrayType::Float64, 1, radius}};
  }
};

bool inContact(const RunSample& s) { return s.obstacle_distance_m < 0 || s.self_distance_m < 0; }

void writeRunVtp(const Model& model, const TrackingEntry& e, const LineReference& line,
                 const RunResult& r, const std::string& path) {
  PolyBuilder b;
  b.poly.lines.push_back(
      {b.add(line.p0_W, 0, 0, false, 0), b.add(line.p1_W, e.duration_s, 0, false, 0)});
  const int n = static_cast<int>(r.samples.size());
  const int stride = std::max(1, static_cast<int>(std::lround(e.rate_Hz / kPathRate_Hz)));
  std::vector<int> path_ids;
  for (int k = 0; k < n; k += stride)
    path_ids.push_back(b.add(r.samples[k].p_WT, r.samples[k].t, 1, inContact(r.samples[k]), 0));
  if (n > 0 && (n - 1) % stride != 0)
    path_ids.push_back(
        b.add(r.samples[n - 1].p_WT, r.samples[n - 1].t, 1, inContact(r.samples[n - 1]), 0));
  if (path_ids.size() >= 2) b.poly.lines.push_back(path_ids);

  KinematicsWorkspace ws(model);
  const Eigen::Vector3d p_base(model.base.x, model.base.y, model.base.z);
  const int shots = n == 0 ? 0 : std::min(e.snapshots, n);
  for (int k = 0; k < shots; ++k) {
    const int idx =
        shots == 1 ? 0 : static_cast<int>(std::lround(double(k) * (n - 1) / (shots - 1)));
    const RunSample& s = r.samples[idx];
    forwardKinematics(model, ws, s.q);
    const bool c = inContact(s);
    std::vector<int> ids{b.add(p_base, s.t, 2, c, 0)};
    for (int i = 0; i < model.dof(); ++i) ids.push_back(b.add(ws.p_WF[i], s.t, 2, c, 0));
    ids.push_back(b.add(ws.p_WT, s.t, 2, c, 0));
    b.poly.lines.push_back(ids);
  }

  for (const collision::Obstacle& o : e.obstacles) {
    const int np = o.type == SsvType::Point ? 1 : (o.type == SsvType::Line ? 2 : 3);
    std::vector<int> core;
    for (int c = 0; c < np; ++c) {
      core.push_back(b.add(o.p_W[c], 0, 3, false, o.radius_m));
      for (int plane = 0; plane < 3; ++plane) {
        const Eigen::Vector3d u = Eigen::Vector3d::Unit(plane),
                              v = Eigen::Vector3d::Unit((plane + 1) % 3);
        std::vector<int> circle;
        for (int k = 0; k < kCircleSegments; ++k) {
          const double a = 2 * std::numbers::pi * k / kCircleSegments;
          circle.push_back(b.add(o.p_W[c] + o.radius_m * (std::cos(a) * u + std::sin(a) * v), 0, 3,
                                 false, o.radius_m));
        }
        circle.push_back(circle.front());
        b.poly.lines.push_back(circle);
      }
    }
    if (np == 2) b.poly.lines.push_back(core);
    if (np == 3) b.poly.triangles.push_back({core[0], core[1], core[2]});
  }
  b.finish();
  b.poly.field_data =
      io::fieldData({"position: m", "time: s", "part: 1", "in_contact: 1", "radius: m"},
                    {"part 0: reference line", "part 1: TCP path",
                     "part 2: arm skeleton (base, joint frames, TCP)",
                     "part 3: obstacle (core and three great circles of its radius)",
                     "in_contact 0: clear", "in_contact 1: an obstacle or self distance below 0"});
  io::writeVtp(path, b.poly);
}

report::PlotSeries plotSeries(const RunResult& r, double rate_Hz, const std::string& label,
                              double RunSample::*field, double scale) {
  report::PlotSeries s;
  s.label = label;
  const int n = static_cast<int>(r.samples.size());
  const int stride = std::max(1, static_cast<int>(std::lround(rate_Hz / kPlotRate_Hz)));
  for (int k = 0; k < n; ++k) {
    if (k % stride != 0 && k != n - 1) continue;
    s.x.push_back(r.samples[k].t);
    s.y.push_back(r.samples[k].*field * scale);
  }
  return s;
}

ordered_json runJson(const Model& model, const TrackingEntry& e, const RunResult& r) {
  ordered_json j;
  j["run"] = toString(r.kind);
  j["status"] = ik::toString(r.status);
  j["completed"] = r.completed();
  j["limit_joint"] =
      r.limit_joint >= 0 ? ordered_json(model.joints[r.limit_joint].name) : ordered_json(nullptr);
  j["samples"] = r.samples.size();
  j["end_time_s"] = r.samples.empty() ? 0.0 : r.samples.back().t;
  j["collision_free"] = r.collisionFree();
  j["first_contact_s"] =
      r.first_contact_s ? ordered_json(*r.first_contact_s) : ordered_json(nullptr);
  j["first_contact_pair"] =
      r.first_contact_s ? ordered_json(pairText(r, r.first_contact_pair)) : ordered_json(nullptr);
  if (!e.obstacles.empty()) {
    j["min_obstacle_distance_m"] = finiteOrNull(r.min_obstacle_distance_m);
    j["min_obstacle_pair"] = pairText(r, r.min_obstacle_pair);
    j["min_obstacle_time_s"] = r.min_obstacle_time_s;
  }
  j["min_self_distance_m"] = finiteOrNull(r.min_self_distance_m);
  j["min_self_pair"] = pairText(r, r.min_self_pair);
  j["min_self_time_s"] = r.min_self_time_s;
  j["max_position_error_m"] = r.max_position_error_m;
  j["final_position_error_m"] = r.final_position_error_m;
  if (e.task != PoseTaskKind::Position)
    j["max_orientation_error_rad"] = r.max_orientation_error_rad;
  j["max_joint_speed"] = r.max_joint_speed;
  j["max_joint_speed_ratio"] = r.max_speed_ratio;
  j["max_joint_speed_ratio_joint"] = r.max_speed_joint >= 0
                                         ? ordered_json(model.joints[r.max_speed_joint].name)
                                         : ordered_json(nullptr);
  return j;
}

// The design model of every entry, in entry order.
std::vector<const Model*> entryModels(const StageContext& ctx,
                                      const std::vector<TrackingEntry>& entries) {
  std::vector<const Model*> models;
  for (const TrackingEntry& e : entries) {
    const Model* m = nullptr;
    for (const StudyDesign& d : ctx.study.designs)
      if (d.model.name == e.design) m = &d.model;
    ARMSTUDY_CHECK(m, "tracking entry '" + e.name + "' names a design the study does not have");
    models.push_back(m);
  }
  return models;
}

// Runs (or loads from the checkpoint store) the plain and H_c runs of every entry as work units
// into entry_results; returns the number of units loaded instead of computed.
long runUnits(const StageContext& ctx, const std::vector<TrackingEntry>& entries,
              const std::vector<const Model*>& models, const std::vector<LineReference>& lines,
              std::vector<EntryResult>& entry_results) {
  // Work units: (entry, run), each sequential and independent of the others.
  auto runOf = [&](std::size_t u) -> RunResult& {
    return u % 2 == 0 ? entry_results[u / 2].plain : entry_results[u / 2].with_hc;
  };
  auto kindOf = [](std::size_t u) { return u % 2 == 0 ? RunKind::Plain : RunKind::WithHc; };
  UnitBatch batch;
  for (std::size_t u = 0; u < 2 * entries.size(); ++u)
    batch.ids.push_back("tracking/" + entries[u / 2].name + "/" + toString(kindOf(u)));
  batch.load = [&](std::size_t u, const std::string& bytes) {
    RunResult r;
    if (!deserializeRun(bytes, r) || r.kind != kindOf(u)) return false;
    runOf(u) = std::move(r);
    return true;
  };
  batch.compute = [&](const std::vector<std::size_t>& todo, const UnitBatch::Done& done) {
    // Errors (e.g. a full disk while saving) are rethrown after the loop.
    parallelFor(static_cast<int>(todo.size()), ctx.threads, [&](int k) {
      const std::size_t u = todo[k];
      runOf(u) = evaluateTrackingRun(*models[u / 2], entries[u / 2], lines[u / 2], kindOf(u));
      done(u, serializeRun(runOf(u)));
    });
  };
  return ctx.units.run(batch);
}

// Writes one run's CSV, ParaView scene and robot motion series, and adds its metrics to M.
void writeRunFiles(const Model& model, const TrackingEntry& e, const EntryResult& er,
                   const RunResult& r, Writer& out, StudyMetrics& M) {
  const std::string rb = e.name + "_" + toString(r.kind);
  writeRunCsv(model, e, r, out.path("tracking/" + rb + ".csv"));
  out.add("tracking/" + rb + ".csv");
  writeRunVtp(model, e, er.line, r, out.path("tracking/" + rb + ".vtp"));
  out.add("tracking/" + rb + ".vtp");
  std::vector<scene::MotionStep> steps;
  for (int k : scene::evenSamples(static_cast<int>(r.samples.size()), kMotionSteps))
    steps.push_back({r.samples[k].t, r.samples[k].q});
  scene::writeMotion(out, "tracking/" + rb, model, steps);
  const std::string mp = "tracking/" + e.name + "/" + toString(r.kind) + "/";
  M.scalars[mp + "completed"] = r.completed() ? 1.0 : 0.0;
  M.scalars[mp + "collision_free"] = r.collisionFree() ? 1.0 : 0.0;
  if (!e.obstacles.empty()) M.scalars[mp + "min_obstacle_distance_m"] = r.min_obstacle_distance_m;
  if (std::isfinite(r.min_self_distance_m))
    M.scalars[mp + "min_self_distance_m"] = r.min_self_distance_m;
  M.scalars[mp + "max_tcp_error_m"] = r.max_position_error_m;
  M.scalars[mp + "final_tcp_error_m"] = r.final_position_error_m;
  M.scalars[mp + "max_joint_speed_ratio"] = r.max_speed_ratio;
}

// What the distance plot of an entry shows: the obstacle distance, or without obstacles the self
// distance.
std::string distanceWhat(const TrackingEntry& e) {
  return e.obstacles.empty() ? "self-collision distance" : "obstacle distance";
}

// Writes an entry's plots: obstacle (or self) distance and TCP error of both runs over time.
void writeEntryPlots(const TrackingEntry& e, const EntryResult& er, Writer& out) {
  const bool obst = !e.obstacles.empty();
  double RunSample::*dist = obst ? &RunSample::obstacle_distance_m : &RunSample::self_distance_m;
  const std::string what = distanceWhat(e);
  report::PlotSpec dplot;
  dplot.title = e.name + ": " + what;
  dplot.x_label = "t [s]";
  dplot.panels.resize(1);
  dplot.panels[0].y_label = what + " [mm]";
  for (const RunResult* r : {&er.plain, &er.with_hc})
    dplot.panels[0].series.push_back(plotSeries(*r, e.rate_Hz, runLabel(r->kind), dist, 1e3));
  dplot.panels[0].lines.push_back({0.0, "contact (d = 0)", true, report::Rgb{214, 39, 40}});
  out.text("tracking/" + e.name + "_distance.svg", report::plot(dplot).svg);
  report::PlotSpec eplot;
  eplot.title = e.name + ": TCP position error";
  eplot.x_label = "t [s]";
  eplot.panels.resize(1);
  eplot.panels[0].y_label = "TCP position error [mm]";
  for (const RunResult* r : {&er.plain, &er.with_hc})
    eplot.panels[0].series.push_back(
        plotSeries(*r, e.rate_Hz, runLabel(r->kind), &RunSample::position_error_m, 1e3));
  out.text("tracking/" + e.name + "_tcp_error.svg", report::plot(eplot).svg);
}

// An entry's report section: its settings, the table of both runs, the plots and file names.
report::Document entryReport(const Model& model, const TrackingEntry& e, const EntryResult& er) {
  const bool obst = !e.obstacles.empty();
  const std::string& base = e.name;
  std::ostringstream md;
  std::string obstacle_list;
  for (const auto& o : e.obstacles)
    obstacle_list += (obstacle_list.empty() ? "" : ", ") + o.name + " (" + toString(o.type) +
                     ", r = " + report::fixed(o.radius_m, 3) + " m)";
  const Eigen::Vector3d& p0 = er.line.p0_W;
  const Eigen::Vector3d& p1 = er.line.p1_W;
  md << "Design `" << e.design << "`, " << toString(e.task) << " task, TCP from ("
     << report::fixed(p0.x(), 3) << ", " << report::fixed(p0.y(), 3) << ", "
     << report::fixed(p0.z(), 3) << ") m to (" << report::fixed(p1.x(), 3) << ", "
     << report::fixed(p1.y(), 3) << ", " << report::fixed(p1.z(), 3) << ") m in "
     << report::fixed(e.duration_s, 2) << " s at " << report::fixed(e.rate_Hz, 0)
     << " Hz; null-space gain alpha = " << e.redundancy.alpha
     << "/s, drift gain K = " << e.redundancy.drift_gain << "/s"
     << (e.w_joint_limits > 0 ? ", H_j weight " + report::fixed(e.w_joint_limits, 3)
                              : std::string())
     << (e.w_manipulability > 0 ? ", H_m1 weight " + report::fixed(e.w_manipulability, 3)
                                : std::string())
     << ". Obstacles: " << (obstacle_list.empty() ? "none" : obstacle_list)
     << ". H_c: d_a = " << report::fixed(e.avoidance.potential.safety_distance_m, 3)
     << " m, t = " << e.avoidance.potential.blend_t << ", H_0 = " << e.avoidance.potential.h0
     << ", weight " << e.avoidance.weight << ", "
     << (e.avoidance.potential.self ? "self pairs and obstacles" : "obstacles only") << ".";
  std::vector<std::vector<std::string>> rows;
  for (const RunResult* r : {&er.plain, &er.with_hc}) {
    const std::string contact = r->first_contact_s
                                    ? report::fixed(*r->first_contact_s, 3) + " s (" +
                                          pairText(*r, r->first_contact_pair) + ")"
                                    : "none";
    rows.push_back({runLabel(r->kind), r->statusText(model),
                    obst ? formatFixedOr(r->min_obstacle_distance_m * 1e3, 1, "-") + " (" +
                               pairText(*r, r->min_obstacle_pair) +
                               ", t = " + report::fixed(r->min_obstacle_time_s, 2) + " s)"
                         : "-",
                    formatFixedOr(r->min_self_distance_m * 1e3, 1, "-") + " (" +
                        pairText(*r, r->min_self_pair) + ")",
                    contact, report::scientific(r->max_position_error_m, 2),
                    report::scientific(r->final_position_error_m, 2),
                    r->max_speed_joint >= 0 ? report::percent(r->max_speed_ratio, 0) + " (" +
                                                  model.joints[r->max_speed_joint].name + ")"
                                            : "-"});
  }
  report::Document doc;
  doc.heading(2, e.name)
      .paragraph(md.str())
      .table({"run", "status", ">min obstacle distance [mm]", ">min self distance [mm]",
              "first contact", ">max TCP error [m]", ">final TCP error [m]",
              ">peak joint speed / limit"},
             rows)
      .paragraph(
          "The IK is kinematic: joint speeds are not limited; the last column is the largest "
          "|qdot_i| / max_velocity_i of the design over the run (above 100 %: the drives could "
          "not follow).")
      .figures({{distanceWhat(e), base + "_distance.svg"}, {"TCP error", base + "_tcp_error.svg"}})
      .paragraph("Per-sample data: `" + base + "_plain.csv`, `" + base +
                 "_with_hc.csv`; ParaView scenes (reference line, TCP path, arm skeletons, "
                 "obstacles; colour by `in_contact` or `time`): `" +
                 base + "_plain.vtp`, `" + base + "_with_hc.vtp`.");
  return doc;
}

// The entry's answer (StageResult::answer): each run's status, first contact and closest approach.
std::string entryAnswer(const Model& model, const TrackingEntry& e, const EntryResult& er) {
  std::string a = "`" + e.name + "` (`" + e.design + "`):";
  for (const RunResult* r : {&er.plain, &er.with_hc}) {
    a += std::string(r == &er.plain ? " " : "; ") + runLabel(r->kind) + ": " +
         r->statusText(model) + ", " +
         (r->first_contact_s ? "first contact at " + report::fixed(*r->first_contact_s, 3) +
                                   " s (" + pairText(*r, r->first_contact_pair) + ")"
                             : "no contact");
    if (!e.obstacles.empty())
      a += ", closest to the obstacles " + formatFixedOr(r->min_obstacle_distance_m * 1e3, 1, "-") +
           " mm";
  }
  return a + ".";
}

// An entry's record in summary.json: its settings and both runs.
ordered_json entryJson(const Model& model, const TrackingEntry& e, const EntryResult& er) {
  const Eigen::Vector3d& p0 = er.line.p0_W;
  const Eigen::Vector3d& p1 = er.line.p1_W;
  ordered_json ej;
  ej["name"] = e.name;
  ej["design"] = e.design;
  ej["task_space"] = toString(e.task);
  ej["q0"] = std::vector<double>(e.q0.data(), e.q0.data() + e.q0.size());
  ej["p0_W"] = {p0.x(), p0.y(), p0.z()};
  ej["p1_W"] = {p1.x(), p1.y(), p1.z()};
  ej["duration_s"] = e.duration_s;
  ej["rate_Hz"] = e.rate_Hz;
  ej["obstacles"] = ordered_json::array();
  for (const auto& o : e.obstacles) ej["obstacles"].push_back(o.name);
  ej["nullspace"] = {{"gain_per_s", e.redundancy.alpha},
                     {"drift_gain_per_s", e.redundancy.drift_gain},
                     {"joint_weights", e.redundancy.joint_weights},
                     {"damping_lambda0", e.redundancy.damping_lambda0},
                     {"damping_m0", e.redundancy.damping_m0},
                     {"joint_limits", e.w_joint_limits},
                     {"joint_limit_activation", e.joint_limit_activation},
                     {"manipulability", e.w_manipulability}};
  ej["avoidance"] = {{"safety_distance_m", e.avoidance.potential.safety_distance_m},
                     {"weight", e.avoidance.weight},
                     {"blend", e.avoidance.potential.blend_t},
                     {"h0", e.avoidance.potential.h0},
                     {"self", e.avoidance.potential.self},
                     {"environment", e.avoidance.potential.environment}};
  ej["runs"] = {runJson(model, e, er.plain), runJson(model, e, er.with_hc)};
  return ej;
}

}  // namespace

// Runs both runs of every entry as work units, then writes the per-run files, the per-entry
// plots, report.md and summary.json.
StageResult runTrackingStage(const StageContext& ctx, const std::vector<TrackingEntry>& entries,
                             std::vector<EntryResult>* results) {
  const auto t0 = std::chrono::steady_clock::now();
  StageResult sum;
  const std::vector<const Model*> models = entryModels(ctx, entries);
  const int ne = static_cast<int>(entries.size());
  std::vector<EntryResult> entry_results(ne);
  std::vector<LineReference> lines(ne);
  for (int i = 0; i < ne; ++i) {
    lines[i] = lineReference(*models[i], entries[i]);
    entry_results[i].name = entries[i].name;
    entry_results[i].line = lines[i];
  }
  sum.units_resumed = runUnits(ctx, entries, models, lines, entry_results);

  fs::create_directories(fs::path(ctx.output_dir) / "tracking");
  Writer out(ctx.output_dir);  // files under tracking/
  report::Document doc;
  doc.heading(1, "Straight-line tracking past obstacles: " + ctx.study.name)
      .paragraph(
          "Thesis Fig. 5.13 (section 5.4.3): the TCP follows a straight line at constant speed "
          "with the null-space IK (Algorithm 5.3, drift compensation eq. 5.50, explicit Euler eq. "
          "5.49). Each entry runs twice: without and with the collision-avoidance potential H_c "
          "(eq. 5.53-5.57) in the null-space objective (eq. 5.51). Distances are those of the "
          "swept-sphere volumes (negative = overlap; docs/collision.md). Details: "
          "docs/tracking.md.");
  ordered_json js;
  js["study"] = ctx.study.name;
  js["entries"] = ordered_json::array();
  for (int i = 0; i < ne; ++i) {
    const TrackingEntry& e = entries[i];
    const Model& model = *models[i];
    const EntryResult& er = entry_results[i];
    for (const RunResult* r : {&er.plain, &er.with_hc})
      writeRunFiles(model, e, er, *r, out, sum.metrics);
    writeEntryPlots(e, er, out);
    doc.append(entryReport(model, e, er));
    js["entries"].push_back(entryJson(model, e, er));
    sum.answer.push_back(entryAnswer(model, e, er));
    for (report::ViewCloud& c : trackingViewClouds(model, e, er)) sum.view.push_back(std::move(c));
    for (const report::ViewSolid& s : report::viewSolids(e.obstacles)) sum.view_solids.push_back(s);
    if (er.plain.limit_joint >= 0 || er.with_hc.limit_joint >= 0)  // a stop at a joint limit
      for (const std::string& a : notes::about(model, notes::kJointLimits))
        if (std::find(sum.assumptions.begin(), sum.assumptions.end(),
                      "`" + model.name + "`: " + a) == sum.assumptions.end())
          sum.assumptions.push_back("`" + model.name + "`: " + a);
  }
  if (!sum.view.empty()) {
    sum.view_about =
        "The points are the TCP's path of each run in the world frame, coloured by the smallest "
        "distance between the arm's volumes and the obstacles (between its own links without "
        "obstacles; negative = overlap) or by contact; the arm stands at the run's closest "
        "approach.";
    sum.view_value_label = "distance";
  }
  out.report("tracking/report.md", std::move(doc));
  out.text("tracking/summary.json", js.dump(2) + "\n");
  sum.files = out.files();
  sum.reports = out.reports();
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (results) *results = std::move(entry_results);
  return sum;
}

}  // namespace armstudy::tracking
