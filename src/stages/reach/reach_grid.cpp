#include "stages/reach/reach_grid.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "io/vtk_io.hpp"
#include "report/markdown.hpp"
#include "stages/reach/reach_answer.hpp"
#include "stages/reach/reach_grid_pieces.hpp"
#include "stages/reach/reach_grid_results.hpp"
#include "stages/reach/reach_report.hpp"
#include "study/rendered_part.hpp"
#include "study/scene.hpp"

namespace armstudy {

using nlohmann::ordered_json;

using namespace reach_report;

namespace {

// What the grid's report is made from: what its pieces were rendered from, and their rendered
// parts; `out` lists the files in the order they were written.
struct GridReport : GridRendering {
  const std::vector<std::string>& parts;
  Writer& out;
  CoverageFacts& facts;  // what the answer says of the grid
};

ordered_json gridHeader(const TaskGrid& grid, report::Document& doc) {
  const std::array<int, 3> dims = grid.dims();
  ordered_json jg;
  jg["name"] = grid.name;
  jg["task_space"] = grid.task_space.toString();
  jg["dims"] = {dims[0], dims[1], dims[2]};
  jg["origin_m"] = {grid.axes[0].from, grid.axes[1].from, grid.axes[2].from};
  jg["spacing_m"] = {grid.axes[0].step, grid.axes[1].step, grid.axes[2].step};
  ordered_json jo = ordered_json::array();
  for (const Orientation& o : grid.orientations)
    jo.push_back({{"alpha_rad", o.alpha}, {"beta_rad", o.beta}, {"gamma_rad", o.gamma}});
  jg["orientations"] = jo;
  jg["poses"] = grid.size();
  if (!grid.reference.empty()) jg["reference"] = grid.reference;
  doc.heading(2, "Grid `" + grid.name + "`")
      .paragraph("Task space " + grid.task_space.toString() + "; x " + axisText(grid.axes[0]) +
                 ", y " + axisText(grid.axes[1]) + ", z " + axisText(grid.axes[2]) + "; " +
                 std::to_string(grid.orientations.size()) + " orientation(s); " +
                 std::to_string(grid.size()) + " poses per design.");
  return jg;
}

// Joins each design's pieces in order: its summary entry (with the surfaces), report and figure
// blocks and table rows, and lists the files their processes wrote. Returns the designs' summary
// entries.
ordered_json joinDesignParts(const GridReport& rep, report::Document& doc, report::Document& images,
                             std::vector<std::vector<std::string>>& rows) {
  ordered_json jdesigns = ordered_json::array();
  std::vector<std::string> design_files;
  for (std::size_t di = 0; di < rep.res.designCount(); ++di) {
    RenderedPart part;
    unpackRenderedPart(rep.parts[rep.layout.mainPiece(di)], part, design_files);
    ordered_json jsurf = ordered_json::array();
    for (int k = 0; k < rep.res.orientation_count; ++k) {
      RenderedPart surface;
      unpackRenderedPart(rep.parts[rep.layout.surfacePiece(di, k)], surface, design_files);
      if (!surface.jd.is_null()) jsurf.push_back(std::move(surface.jd));
    }
    if (rep.cfg.outputs.surface && rep.grid.spatialDimension() == 3)
      part.jd["surface"] = std::move(jsurf);
    for (int k = 0; k < rep.res.orientation_count; ++k) {
      RenderedPart figures;
      unpackRenderedPart(rep.parts[rep.layout.figuresPiece(di, k)], figures, design_files);
      part.images.append(figures.images);
    }
    jdesigns.push_back(std::move(part.jd));
    doc.append(part.doc);
    images.append(part.images);
    for (auto& row : part.rows) rows.push_back(std::move(row));
  }
  for (const std::string& f : design_files) rep.out.add(f);
  return jdesigns;
}

// Each design's reachable poses, those blocked by joint limits and its boundary poses on the grid.
void designCoverage(const ReachGridResults& res, CoverageFacts& facts) {
  const TaskGrid& grid = res.taskGrid();
  facts.what = "grid `" + grid.name + "`";
  facts.poses = grid.size();
  for (const PoseSweep& map : res.maps) {
    DesignCoverage d{map.design};
    for (long i = 0; i < grid.size(); ++i) {
      d.reachable += map.reachable(i);
      d.joint_limits += map.status[i] == static_cast<int>(ReachStatus::JointLimits);
    }
    d.fraction = grid.size() ? static_cast<double>(d.reachable) / grid.size() : 0.0;
    d.boundary = boundaryPoses(grid, map);
    facts.designs.push_back(std::move(d));
  }
}

// The grid's tables: statuses per design and orientation, reachable volumes (3-D grids), and the
// reference statement next to this model's numbers.
void gridTables(const GridReport& rep, const ordered_json& jdesigns,
                const std::vector<std::vector<std::string>>& rows, report::Document& doc) {
  std::vector<std::string> header = {"design",
                                     "orientation",
                                     ">reachable",
                                     ">joint limits",
                                     ">out of reach",
                                     ">repr. singular",
                                     "extent of the reachable poses"};
  if (!usesCardanAngles(rep.grid.task_space)) header.erase(header.begin() + 5);
  insertCollisionColumns(rep.cfg, header, 3);
  doc.table(header, rows);
  if (rep.grid.spatialDimension() == 3 && rep.cfg.outputs.surface) {
    std::vector<std::vector<std::string>> srows;
    for (const auto& jd : jdesigns)
      for (const auto& sf : jd["surface"])
        srows.push_back({jd["design"].get<std::string>(), sf["orientation"].get<std::string>(),
                         report::fixed(sf["alpha_shape_volume_m3"].get<double>(), 4),
                         report::fixed(sf["voxel_volume_m3"].get<double>(), 4),
                         sf["file"].get<std::string>()});
    doc.paragraph(
           "Reachable volume (boundary surface: CGAL 3-D alpha shape of the reachable grid "
           "points; the voxel estimate counts one grid cell per reachable point):")
        .table({"design", "orientation", ">alpha shape [m^3]", ">voxels [m^3]", "surface"}, srows);
  }
  if (rep.grid.reference.empty()) return;
  std::string model = "**This model:** ";
  for (std::size_t di = 0; di < rep.res.maps.size(); ++di) {
    const auto& jd = jdesigns[di];
    model += "`" + rep.res.maps[di].design + "` reaches " +
             report::percent(jd["fraction"].get<double>()) + " of the grid's poses";
    Stats all;
    for (long i = 0; i < rep.grid.size(); ++i)
      all.add(rep.res.maps[di], i, rep.grid.position(rep.grid.pointOf(i)));
    model += " (extent " + all.extent.text() + ")" + (di + 1 < rep.res.maps.size() ? "; " : ".");
  }
  doc.paragraph("**Reference:** " + rep.grid.reference).paragraph(model);
}

// Designs that reach none of the grid's poses: a warning in the report, in summary.json and on
// stderr (a base placed in the wrong unit, a grid beside the arm).
void warnUnreached(const GridReport& rep, const ordered_json& jdesigns, ordered_json& jg,
                   report::Document& doc) {
  ordered_json none = ordered_json::array();
  for (const auto& jd : jdesigns)
    if (jd["reachable"].get<long>() == 0) none.push_back(jd["design"]);
  if (none.empty()) return;
  std::string names;
  for (const auto& n : none) names += (names.empty() ? "`" : ", `") + n.get<std::string>() + "`";
  const std::string text = names + (none.size() > 1 ? " reach" : " reaches") + " none of the " +
                           std::to_string(rep.grid.size()) + " poses of grid `" + rep.grid.name +
                           "`: check the design's base placement and its units against the grid";
  doc.paragraph("**Warning:** " + text + ".");
  jg["designs_reaching_nothing"] = none;
  rep.ctx.warn(text);
}

// The largest reach found on the grid (the farthest reachable pose from the design's base z axis)
// against each design's reference_reach_m: a table in the report and summary.json.
void compareReferenceReach(const GridReport& rep, ordered_json& jg, report::Document& doc) {
  std::vector<std::vector<std::string>> rows;
  ordered_json jr = ordered_json::array();
  for (std::size_t di = 0; di < rep.res.designCount(); ++di) {
    const StudyDesign& sd = rep.ctx.study.designs[di];
    if (!(sd.reference_reach_m > 0)) continue;
    const Eigen::Isometry3d T_BW = sd.model.T_WB.inverse();
    double found = -1;
    for (long i = 0; i < rep.grid.size(); ++i)
      if (rep.res.maps[di].reachable(i)) {
        const Eigen::Vector3d p_B = T_BW * rep.grid.position(rep.grid.pointOf(i));
        found = std::max(found, std::hypot(p_B.x(), p_B.y()));
      }
    const double ref = sd.reference_reach_m, diff = found - ref;
    double resolution = 0;  // the largest reach is known to within one step of the grid
    for (const AxisRange& a : rep.grid.axes)
      if (a.count() > 1) resolution = std::max(resolution, a.step);
    rows.push_back({sd.model.name, report::fixed(ref, 3), found < 0 ? "-" : report::fixed(found, 3),
                    found < 0
                        ? "-"
                        : (diff >= 0 ? "+" : "") + report::fixed(diff * 1e3, 0) + " mm (" +
                              (diff >= 0 ? "+" : "") + report::fixed(100 * diff / ref, 1) + " %)"});
    rep.facts.references.push_back({sd.model.name, ref, found, resolution});
    jr.push_back(
        {{"design", sd.model.name},
         {"reference_reach_m", ref},
         {"largest_reach_found_m", found < 0 ? ordered_json(nullptr) : ordered_json(found)},
         {"difference_m", found < 0 ? ordered_json(nullptr) : ordered_json(diff)},
         {"resolution_m", resolution}});
  }
  if (rows.empty()) return;
  doc.paragraph(
         "Largest reach found (the farthest reachable pose of this grid from the design's base z "
         "axis) against the design's `reference_reach_m`:")
      .table({"design", ">reference [m]", ">largest found [m]", ">difference"}, rows);
  jg["reference_reach"] = jr;
}

// comparison.vti: which designs reach each pose (bit mask and count per orientation).
void writeComparisonVti(const GridReport& rep, ordered_json& jcmp) {
  const TaskGrid& grid = rep.grid;
  const std::vector<PoseSweep>& sweeps = rep.res.maps;
  io::ImageGrid img;
  img.dims = rep.res.dims;
  img.origin = {grid.axes[0].from, grid.axes[1].from, grid.axes[2].from};
  img.spacing = {grid.axes[0].step, grid.axes[1].step, grid.axes[2].step};
  for (int k = 0; k < rep.res.orientation_count; ++k) {
    img.point_arrays.push_back(arrayOf("reached_by_mask" + suffix(grid, k), io::ArrayType::Int32,
                                       &grid, rep.res.positions, k, 1, [&](long i, int) {
                                         long m = 0;
                                         for (std::size_t di = 0; di < sweeps.size(); ++di)
                                           if (sweeps[di].reachable(i)) m |= 1L << di;
                                         return double(m);
                                       }));
    img.point_arrays.push_back(arrayOf("reached_by_count" + suffix(grid, k), io::ArrayType::UInt8,
                                       &grid, rep.res.positions, k, 1, [&](long i, int) {
                                         int c = 0;
                                         for (const auto& s : sweeps) c += s.reachable(i);
                                         return double(c);
                                       }));
  }
  std::vector<std::string> legend;
  for (std::size_t di = 0; di < sweeps.size(); ++di)
    legend.push_back("reached_by_mask bit " + std::to_string(di) + " (value " +
                     std::to_string(1L << di) + "): " + sweeps[di].design);
  img.field_data = io::fieldData(
      {"position: m", "reached_by_mask: 1 (bit mask)", "reached_by_count: 1"}, legend);
  const std::string rel = rep.res.folder + "/comparison.vti";
  io::writeVti(rep.out.path(rel), img);
  rep.out.add(rel);
  jcmp["vti"] = rel;
  ordered_json bits = ordered_json::array();
  for (const auto& s : sweeps) bits.push_back(s.design);
  jcmp["mask_bits"] = bits;
}

// Best design / variant per base design (e.g. the best base placement): summary entries and rows.
ordered_json bestVariants(const GridReport& rep, const ordered_json& jdesigns,
                          std::vector<std::vector<std::string>>& brow) {
  ordered_json best = ordered_json::array();
  std::vector<std::string> bases;
  for (const auto& sd : rep.ctx.study.designs)
    if (std::find(bases.begin(), bases.end(), sd.base_name) == bases.end())
      bases.push_back(sd.base_name);
  for (const std::string& base : bases) {
    int count = 0, best_i = -1;
    double best_f = -1;
    bool base_sweep = false;
    for (std::size_t di = 0; di < rep.res.maps.size(); ++di) {
      if (rep.ctx.study.designs[di].base_name != base) continue;
      ++count;
      for (const auto& [k, v] : rep.ctx.study.designs[di].overrides)
        base_sweep |= k.rfind("base.", 0) == 0;
      const double f = jdesigns[di]["fraction"].get<double>();
      if (f > best_f) {
        best_f = f;
        best_i = static_cast<int>(di);
      }
    }
    if (count < 2) continue;
    best.push_back({{"base_design", base},
                    {"best", rep.res.maps[best_i].design},
                    {"fraction", best_f},
                    {"varies_base_placement", base_sweep}});
    brow.push_back(
        {base, rep.res.maps[best_i].design, report::percent(best_f), base_sweep ? "yes" : "no"});
  }
  return best;
}

// The comparison of designs on this grid: comparison.vti, per pair which poses each reaches and
// the pair's images, dexterity where both reach, the best variant per base design.
ordered_json compareDesigns(const GridReport& rep, const ordered_json& jdesigns,
                            report::Document& doc) {
  ordered_json jcmp;
  if (rep.cfg.outputs.vtk && rep.res.maps.size() <= 30) writeComparisonVti(rep, jcmp);
  doc.heading(3, "Comparison of designs on `" + rep.grid.name + "`");
  std::vector<std::vector<std::string>> crow;
  ordered_json jpairs = ordered_json::array();
  report::Document pair_imgs;
  std::vector<std::string> pair_files;
  for (std::size_t p = 0; p < rep.res.pairs.size(); ++p) {
    const auto [a, b] = rep.res.pairs[p];
    long n_a = 0, n_b = 0, both = 0, neither = 0;
    for (long i = 0; i < rep.grid.size(); ++i) {
      const bool ra = rep.res.maps[a].reachable(i), rb = rep.res.maps[b].reachable(i);
      n_a += ra && !rb;
      n_b += rb && !ra;
      both += ra && rb;
      neither += !ra && !rb;
    }
    rep.facts.pairs.push_back({rep.res.maps[a].design, rep.res.maps[b].design, n_a, n_b});
    jpairs.push_back({{"a", rep.res.maps[a].design},
                      {"b", rep.res.maps[b].design},
                      {"a_only", n_a},
                      {"b_only", n_b},
                      {"both", both},
                      {"neither", neither}});
    const double N = static_cast<double>(rep.grid.size());
    crow.push_back({rep.res.maps[a].design, rep.res.maps[b].design, report::percent(n_a / N),
                    report::percent(n_b / N), report::percent(both / N),
                    report::percent(neither / N)});
    const auto img = std::find(rep.layout.image_pairs.begin(), rep.layout.image_pairs.end(), p);
    if (rep.layout.pair_images &&
        img != rep.layout.image_pairs.end()) {  // the images the render loop made
      RenderedPart part;
      unpackRenderedPart(rep.parts[rep.layout.pairPiece(img - rep.layout.image_pairs.begin())],
                         part, pair_files);
      pair_imgs.append(part.images);
    }
  }
  for (const std::string& f : pair_files) rep.out.add(f);
  jcmp["pairs"] = jpairs;
  std::vector<std::vector<std::string>> brow;
  jcmp["best_variant"] = bestVariants(rep, jdesigns, brow);
  doc.paragraph("Per pose, which designs reach it (all orientations together):")
      .table({"A", "B", ">A only", ">B only", ">both", ">neither"}, crow);
  jcmp["dexterity"] = dexterityComparison(rep.res.models, rep.grid, rep.res.maps, rep.res.pairs,
                                          rep.ctx.threads, doc, rep.facts.verdicts);
  if (!brow.empty())
    doc.paragraph(
           "Best variant per base design (the most reachable poses; with base.* overrides this "
           "is the best base placement):")
        .table({"base design", "best variant", ">reachable", "base placement varied"}, brow);
  doc.append(pair_imgs);
  return jcmp;
}

// The view's status of a grid position over its orientations: reachable in one of them, else
// reachable only in contact with an obstacle, else only in self-collision, else the first
// orientation's status (not drawn).
int positionStatus(const ReachGridResults& res, const PoseSweep& map, long p) {
  const int order[] = {static_cast<int>(ReachStatus::Reachable),
                       static_cast<int>(ReachStatus::ObstacleCollision),
                       static_cast<int>(ReachStatus::SelfCollision)};
  for (const int want : order)
    for (int k = 0; k < res.orientation_count; ++k)
      if (map.status[static_cast<long>(k) * res.positions + p] == want) return want;
  return map.status[p];
}

// The grid's maps for the study's 3-D view: per design, the grid positions with their status and
// largest manipulability over the orientations, and the arm at the reachable pose of the largest
// manipulability.
std::vector<report::ViewCloud> viewClouds(const ReachGridResults& res) {
  std::vector<report::ViewCloud> clouds;
  double step_m = INFINITY;
  for (int a = 0; a < 3; ++a)
    if (res.dims[a] > 1) step_m = std::min(step_m, res.taskGrid().axes[a].step);
  for (std::size_t di = 0; di < res.designCount(); ++di) {
    const PoseSweep& map = res.maps[di];
    report::ViewCloud c;
    c.name = "grid " + res.taskGrid().name + ": " + map.design;
    // Maps share a colour scale only with maps of the same task rows.
    const TaskSpace& task = res.taskGrid().task_space;
    const int position_rows = int(task.selected[0]) + int(task.selected[1]) + int(task.selected[2]);
    c.value_unit = "m^" + std::to_string(position_rows);
    const int rows = task.dim();
    c.value_quantity = rows == position_rows
                           ? "manipulability (" + std::to_string(rows) + " position rows)"
                           : "manipulability (" + std::to_string(rows) + " task rows, " +
                                 std::to_string(rows - position_rows) + " angular weighed by 1 m)";
    c.point_size_m = std::isfinite(step_m) ? step_m : 0.02;
    c.status_names = statusNamesShownOnMaps();
    long best = -1;
    for (long p = 0; p < res.positions; ++p) {
      const Eigen::Vector3d x = res.taskGrid().position(p);
      c.p_W.push_back({x.x(), x.y(), x.z()});
      c.status.push_back(positionStatus(res, map, p));
      double v = NAN;
      for (int k = 0; k < res.orientation_count; ++k) {
        const long i = static_cast<long>(k) * res.positions + p;
        if (!map.reachable(i)) continue;
        v = std::isnan(v) ? map.manipulability[i] : std::max(v, map.manipulability[i]);
        if (best < 0 || map.manipulability[i] > map.manipulability[best]) best = i;
      }
      c.value.push_back(v);
    }
    if (best >= 0) {
      const Eigen::Map<const Eigen::VectorXd> q(map.q.data() + best * map.dof, map.dof);
      for (const Eigen::Vector3d& x : scene::skeletonPoints(*res.models[di], q))
        c.arm_W.push_back({x.x(), x.y(), x.z()});
      c.arm_caption = "arm: " + map.design +
                      " at the grid's reachable pose of the largest "
                      "manipulability (" +
                      report::scientific(map.manipulability[best]) + " " +
                      taskManipulabilityUnit(task) + ").";
    } else {
      c.arm_caption = "arm: " + map.design + " reaches no pose of the grid.";
    }
    clouds.push_back(std::move(c));
  }
  return clouds;
}

}  // namespace

ordered_json reportGrid(const StageContext& ctx, const ReachConfig& cfg, const TaskGrid& grid,
                        Progress& progress, StageResult& sum, Writer& out, report::Document& doc,
                        CoverageFacts& facts) {
  ordered_json jg = gridHeader(grid, doc);
  const ReachGridResults res = solveReachGrid(ctx, cfg, grid, progress, sum);
  const auto t0 = std::chrono::steady_clock::now();
  const GridPieces pieces = gridPieces(res, cfg);
  const std::vector<std::string> parts = renderGridPieces(ctx, cfg, res, pieces);
  const GridReport rep{{ctx, cfg, res, grid, pieces}, parts, out, facts};
  std::vector<std::vector<std::string>> rows;
  report::Document images;
  const ordered_json jdesigns = joinDesignParts(rep, doc, images, rows);
  sum.timings.push_back(
      {res.folder + "/files",
       std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()});
  jg["designs"] = jdesigns;
  designCoverage(res, facts);
  warnUnreached(rep, jdesigns, jg, doc);
  gridTables(rep, jdesigns, rows, doc);
  compareReferenceReach(rep, jg, doc);
  doc.append(images);
  if (res.designCount() >= 2) jg["comparison"] = compareDesigns(rep, jdesigns, doc);
  for (report::ViewCloud& c : viewClouds(res)) sum.view.push_back(std::move(c));
  return jg;
}

}  // namespace armstudy
