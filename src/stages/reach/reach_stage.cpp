#include "stages/reach/reach_stage.hpp"

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <set>

#include "common/errors.hpp"
#include "io/vtk_io.hpp"
#include "model/model_notes.hpp"
#include "report/arm_drawing.hpp"
#include "report/markdown.hpp"
#include "stages/reach/reach_answer.hpp"
#include "stages/reach/reach_counts.hpp"
#include "stages/reach/reach_grid.hpp"
#include "stages/reach/reach_preview.hpp"
#include "stages/reach/reach_report.hpp"
#include "stages/reach/reach_units.hpp"
#include "study/stage_designs.hpp"

namespace armstudy {

using nlohmann::ordered_json;
using namespace reach_report;
using namespace reach_units;

namespace {

// The settings block of summary.json.
ordered_json settingsJson(const ReachConfig& cfg) {
  ordered_json j = {{"position_tolerance_m", cfg.ik.position_tolerance_m},
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
  ordered_json jobs = ordered_json::array();
  for (const collision::Obstacle& o : cfg.collision.obstacles) jobs.push_back(obstacleJson(o));
  j["obstacles"] = jobs;
  return j;
}

// The report's opening: the title, the study's description, the tolerances, the task and each
// design's tool axis.
report::Document taskSection(const Study& study, const ReachConfig& cfg) {
  report::Document doc;
  doc.heading(1, "Reachability: study `" + study.name + "`");
  if (!study.description.empty()) doc.paragraph(study.description);
  doc.paragraph(
      "Thesis eq. (3.2): a pose is reachable when a configuration within the joint limits puts the "
      "TCP within " +
      report::fixed(cfg.ik.position_tolerance_m * 1e3, 2) + " mm and " +
      report::fixed(cfg.ik.orientation_tolerance_rad * kRadToDeg, 2) + " deg of it (up to " +
      std::to_string(cfg.ik.max_starts) + " deterministic starts, seed " +
      std::to_string(cfg.ik.seed) +
      "). See docs/reachability.md for the solver, the failure reasons and the file formats.");
  std::string task = "Task: each design's tool axis (named in its design file or study entry) ";
  for (std::size_t di = 0; di < study.designs.size(); ++di) {
    const Eigen::Vector3d& a = study.designs[di].model.tool_axis_T;
    task += std::string(di ? ", " : "") + "`" + study.designs[di].model.name + "` TCP (" +
            report::fixed(a.x(), 3) + ", " + report::fixed(a.y(), 3) + ", " +
            report::fixed(a.z(), 3) + ")";
  }
  doc.paragraph(
      task +
      ". The spraying task (eq. 3.1) puts the TCP at the point with the tool axis along d = "
      "Rx(alpha) Rz(gamma) e_y (+y at alpha = gamma = 0) and the roll about it free; "
      "manipulability is sqrt(det(J_t J_t^T)) of the 3 position rows and the 2 angular rows "
      "perpendicular to the tool axis (eq. 5.59; the angular rows weighed by a characteristic "
      "length of 1 m; summary.json and the .vti files give the translational and rotational parts "
      "beside it).");
  return doc;
}

// The designs evaluated without collisions (no volumes) while the study checks them: a warning at
// the top of the report, in summary.json and on stderr.
void warnWithoutVolumes(const StageContext& ctx, const ReachConfig& cfg, ordered_json& jr,
                        report::Document& doc, ReachFacts& facts) {
  const bool self_on = cfg.collision.self, obst_on = !cfg.collision.obstacles.empty();
  std::string without;
  for (const StudyDesign& sd : ctx.study.designs)
    if (sd.model.collision.empty())
      without += std::string(without.empty() ? "" : ", ") + "`" + sd.model.name + "`";
  if (!(self_on || obst_on) || without.empty()) return;
  doc.paragraph("**Warning:** " + without +
                " evaluated without self-collision and obstacles: no collision volumes (a design "
                "file without [[collision]] entries, or a URDF whose links have no collision "
                "geometry); their rows say \"n/a\" in the collision columns and their reachable "
                "shares are not comparable with the others'.");
  for (const StudyDesign& sd : ctx.study.designs)
    if (sd.model.collision.empty()) facts.without_volumes.push_back(sd.model.name);
  jr["designs_without_collision_volumes"] = facts.without_volumes;
  ctx.warn(without + " evaluated without self-collision and obstacles (no collision volumes)");
}

// The links (base and the body after each joint) of `m` that carry collision volumes.
int linksWithVolumes(const Model& m) {
  std::set<int> links;
  for (const CollisionVolume& v : m.collision.volumes) links.insert(v.link);
  return static_cast<int>(links.size());
}

// Designs whose links lack collision volumes (a URDF's meshes not found, links without
// <collision>): a warning naming them, at the top of the report, in the answer's warnings and on
// stderr, whether self-collision is on (it then covers fewer links) or off.
void warnPartialCollision(const StageContext& ctx, const ReachConfig& cfg, report::Document& doc,
                          std::vector<std::string>& warnings) {
  for (const StudyDesign& sd : ctx.study.designs) {
    const Model& m = sd.model;
    const std::vector<std::string> missing = notes::all(m, notes::kNoCollision);
    if (missing.empty()) continue;
    std::string links;
    for (const std::string& l : missing) links += (links.empty() ? "" : ", ") + l;
    const int with = linksWithVolumes(m), all = m.dof() + 1;
    const bool checked = cfg.collision.self && !m.collision.empty();
    const std::string w =
        "`" + m.name + "`: " + std::to_string(all - with) + " of " + std::to_string(all) +
        " links have no collision volume: " + links + "; " +
        (checked ? "self-collision covers the other " + std::to_string(with) + " links only"
                 : std::string("self-collision is off for this design"));
    doc.paragraph("**Warning:** " + w + ".");
    warnings.push_back(w);
    ctx.warn(w);
  }
}

// The design assumption lines about joint limits of each design with poses blocked by them (the
// "joint limits" count rests on them), as "`<design>`: <line>".
void jointLimitAssumptions(const Study& study, const ReachFacts& facts,
                           std::vector<std::string>& out) {
  std::set<std::string> blocked;
  for (const CoverageFacts& set : facts.sets)
    for (const DesignCoverage& d : set.designs)
      if (d.joint_limits > 0) blocked.insert(d.design);
  for (const StudyDesign& sd : study.designs)
    if (blocked.count(sd.model.name))
      for (const std::string& a : notes::about(sd.model, notes::kJointLimits))
        out.push_back("`" + sd.model.name + "`: " + a);
}

// The map colours, and what the collision and obstacle checks mean.
report::Document checksSection(const std::vector<StudyDesign>& designs, const ReachConfig& cfg) {
  const bool self_on = cfg.collision.self, obst_on = !cfg.collision.obstacles.empty();
  // Only a literal selection of Cardan angles can be representation singular.
  bool cardan = false;
  for (const TaskGrid& g : cfg.grids) cardan |= usesCardanAngles(g.task_space);
  for (const PoseList& l : cfg.pose_lists) cardan |= usesCardanAngles(l.task_space);
  const auto colour = [](int status) {  // "bluish green (#009e73)"
    const report::Rgb c = report::categorical(status);
    return report::colourName(c) + " (" + report::hex(c) + ")";
  };
  report::Document doc;
  doc.paragraph("Map colours: " + colour(0) + " reachable, " + colour(1) + " out of reach, " +
                colour(2) + " blocked by joint limits" +
                (cardan ? ", " + colour(3) + " representation singularity" : "") +
                (self_on ? ", " + colour(4) + " reachable only in self-collision" : "") +
                (obst_on ? ", " + colour(6) + " reachable only in contact with an obstacle" : "") +
                ".");
  if (self_on) {
    std::string cover;
    for (const StudyDesign& sd : designs)
      cover += std::string(cover.empty() ? "" : ", ") + "`" + sd.model.name + "` " +
               std::to_string(linksWithVolumes(sd.model)) + " of " +
               std::to_string(sd.model.dof() + 1);
    doc.paragraph("Self-collision: on for the links with collision volumes (" + cover +
                  " links). A pose counts as reachable only with a collision-free solution (every "
                  "self-collision distance of the design's swept-sphere volumes > 0, other "
                  "postures tried through the redundancy); poses reachable only in collision are "
                  "counted separately, with the colliding pair in summary.json.");
  }
  if (obst_on) {
    doc.paragraph("Obstacles: " + std::to_string(cfg.collision.obstacles.size()) +
                  " in the task frame, checked against every link's swept-sphere volumes; a pose "
                  "counts as reachable only with a solution clear of them (field "
                  "`obstacle_distance`: the arm's clearance from the nearest obstacle at the "
                  "solution).");
    std::vector<std::vector<std::string>> orows;
    for (const collision::Obstacle& o : cfg.collision.obstacles) orows.push_back(obstacleRow(o));
    doc.table({"obstacle", "type", "points (task frame) [m]", ">radius [mm]"}, orows);
  }
  return doc;
}

// The designs evaluated, each drawn at its zero pose (reach/images/arm_<design>.svg), as a report
// section; nothing without images.
report::Document designDrawings(const StageContext& ctx, const ReachConfig& cfg, Writer& out) {
  report::Document doc;
  if (!cfg.outputs.images) return doc;
  doc.heading(2, "The designs");
  for (const StudyDesign& sd : ctx.study.designs) {
    const std::string file = report::zeroPoseFileName(sd.model.name);
    out.text("reach/images/" + file, report::zeroPoseSvg(sd.model));
    doc.append(report::zeroPoseFigure(sd.model.name, "images/" + file));
  }
  return doc;
}

// One design on a pose list: its sweep and search, summary entry, .vtp and best robot, table row.
ordered_json poseListDesign(const StageContext& ctx, const ReachConfig& cfg, const PoseList& l,
                            const StudyDesign& sd, Progress& progress, StageResult& sum,
                            Writer& out, std::vector<std::string>& row, CoverageFacts& facts) {
  const std::string unit = "reach/" + l.name + "/" + sd.model.name;
  PoseSweep s = solvePoseList(ctx, sum, unit, sd.model, l, cfg, progress);
  // Poses in collision get the seeded starts too (a list has no neighbours).
  const SweepSearchSummary ss = searchPoseListSweep(
      sd.model, l, cfg.ik, ctx.threads, cfg.collisionFor(sd.model), cfg.search, s, &ctx.units);
  sum.timings.push_back({unit + "/search", ss.seconds});
  reach_counts::addDescentCounts(unit, s, ss, nullptr, sum.counts);
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
    poly.field_data = poseFieldData(s, nullptr);
    poly.field_data[1].values.push_back("line: 1");
    const std::string rel = "reach/" + l.name + "/" + s.design + ".vtp";
    io::writeVtp(out.path(rel), poly);
    out.add(rel);
    jd["vtp"] = rel;
    writeBestRobot(out, "reach/" + l.name + "/" + s.design + "_robot_best.vtp", sd.model, s);
  }
  facts.designs.push_back({s.design, st.reachable,
                           st.status[static_cast<int>(ReachStatus::JointLimits)], st.fraction()});
  row = {s.design, report::percent(st.fraction()),
         report::percent(st.n ? double(st.status[2]) / st.n : 0),
         report::percent(st.n ? double(st.status[1]) / st.n : 0), st.extent.text()};
  insertCollisionColumns(cfg, row, 2, st);
  return jd;
}

// A pose list: every design on it, its summary block and report section.
ordered_json reportPoseList(const StageContext& ctx, const ReachConfig& cfg, const PoseList& l,
                            Progress& progress, StageResult& sum, Writer& out,
                            report::Document& doc, CoverageFacts& facts) {
  ordered_json jl;
  jl["name"] = l.name;
  jl["file"] = l.file;
  jl["task_space"] = l.task_space.toString();
  jl["poses"] = l.poses.size();
  facts.what = "pose list `" + l.name + "`";
  facts.poses = static_cast<long>(l.poses.size());
  doc.heading(2, "Pose list `" + l.name + "`")
      .paragraph(std::to_string(l.poses.size()) + " poses from `" + l.file + "`, task space " +
                 l.task_space.toString() + ".");
  std::vector<std::vector<std::string>> rows;
  ordered_json jdesigns = ordered_json::array();
  for (const StudyDesign& sd : ctx.study.designs) {
    rows.emplace_back();
    jdesigns.push_back(poseListDesign(ctx, cfg, l, sd, progress, sum, out, rows.back(), facts));
  }
  jl["designs"] = jdesigns;
  std::vector<std::string> header = {"design", ">reachable", ">joint limits", ">out of reach",
                                     "extent"};
  insertCollisionColumns(cfg, header, 2);
  doc.table(header, rows);
  return jl;
}

}  // namespace

StageResult runReachStage(const StageContext& all_ctx, const ReachConfig& cfg) {
  const auto t0 = std::chrono::steady_clock::now();
  StageResult sum;
  if (!cfg.enabled) return sum;
  // The designs this stage evaluates ([reach] designs), in study order, with their tool axes.
  const Study selected = StageDesigns{cfg.designs, cfg.tool_axes}.select(all_ctx.study);
  const StageContext ctx = all_ctx.forStudy(selected);
  const Study& study = ctx.study;
  ARMSTUDY_CHECK(cfg.validate().empty(), cfg.validate());
  Writer out(ctx.output_dir);
  long total = 0;
  for (const TaskGrid& g : cfg.grids) total += g.size() * static_cast<long>(study.designs.size());
  for (const PoseList& l : cfg.pose_lists)
    total += static_cast<long>(l.poses.size() * study.designs.size());
  Progress progress(total, ctx.options.progress, "reachability " + study.name);

  ordered_json js;
  js["study"] = study.name;
  ordered_json jr;
  jr["settings"] = settingsJson(cfg);
  report::Document doc = taskSection(study, cfg);
  ReachFacts facts;
  warnWithoutVolumes(ctx, cfg, jr, doc, facts);
  std::vector<std::string> partial;
  warnPartialCollision(ctx, cfg, doc, partial);
  doc.append(checksSection(study.designs, cfg));
  doc.append(designDrawings(ctx, cfg, out));
  if (ctx.options.preview_stride > 0) sum.previews = writeReachPreviews(ctx, cfg);
  ordered_json jgrids = ordered_json::array();
  for (const TaskGrid& g : cfg.grids) {
    facts.sets.emplace_back();
    jgrids.push_back(reportGrid(ctx, cfg, g, progress, sum, out, doc, facts.sets.back()));
  }
  jr["grids"] = jgrids;
  ordered_json jlists = ordered_json::array();
  for (const PoseList& l : cfg.pose_lists) {
    facts.sets.emplace_back();
    jlists.push_back(reportPoseList(ctx, cfg, l, progress, sum, out, doc, facts.sets.back()));
  }
  jr["pose_lists"] = jlists;
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  reachAnswer(facts, sum.answer, sum.warnings);
  jointLimitAssumptions(study, facts, sum.assumptions);
  sum.warnings.insert(sum.warnings.begin(), partial.begin(), partial.end());
  js["reach"] = jr;
  out.text("summary.json", js.dump(2) + "\n");
  out.report("reach/report.md", std::move(doc));
  sum.files = out.files();
  sum.reports = out.reports();
  return sum;
}

}  // namespace armstudy
