#include "stages/reach/reach_grid_pieces.hpp"

#include <algorithm>
#include <array>
#include <nlohmann/json.hpp>

#include "io/vtk_io.hpp"
#include "reach/boundary_surface.hpp"
#include "report/markdown.hpp"
#include "study/rendered_part.hpp"

namespace armstudy {

using nlohmann::ordered_json;

using namespace reach_report;

namespace {

// The map search's work and the audit of design di: summary entries and report lines.
void searchAndAuditEntries(const GridRendering& gr, std::size_t di, ordered_json& jd,
                           report::Document& doc) {
  const PoseSweep& map = gr.res.maps[di];
  const SweepSearchSummary& search = gr.res.searches[di];
  jd["search"] = {{"propagation_rounds", search.rounds},
                  {"neighbour_tries", search.neighbour_tries},
                  {"neighbour_updates", search.neighbour_updates},
                  {"collision_multistart_poses", search.multistart_poses},
                  {"collision_multistart_tries", search.multistart_tries},
                  {"collision_multistart_freed", search.multistart_freed},
                  {"best_manipulability_rounds", search.best_rounds},
                  {"best_manipulability_updates", search.best_updates},
                  {"converged", search.converged}};
  std::string search_text = "Map search (" + map.design + "): " + std::to_string(search.rounds) +
                            (search.rounds == 1 ? " neighbour-propagation round changed "
                                                : " neighbour-propagation rounds changed ") +
                            std::to_string(search.neighbour_updates) +
                            (search.neighbour_updates == 1 ? " status" : " statuses");
  if (map.collision)
    search_text +=
        "; " + std::to_string(search.multistart_poses) + " poses still in collision got " +
        std::to_string(gr.cfg.search.collision_starts) + " seeded starts each (" +
        std::to_string(search.multistart_freed) +
        " found collision-free). A pose is `self_collision` / "
        "`obstacle_collision` only when no collision-free solution was found in all its starts "
        "(array "
        "`starts` of the .vti: the sweep's starts, escapes, neighbour seeds and seeded starts, "
        "capped at 255)";
  doc.paragraph(search_text + ".");
  if (gr.cfg.audit_poses <= 0) return;
  const ReachAudit& audit = gr.res.audits[di];
  ordered_json ja;
  ja["poses"] = audit.poses;
  ja["starts_per_pose"] = audit.starts;
  ja["seed"] = audit.seed;
  ordered_json jb = ordered_json::object(), jc = ordered_json::object();
  for (int k = 0; k < kReachStatusCount; ++k) {
    jb[toString(static_cast<ReachStatus>(k))] = audit.by_status[k];
    jc[toString(static_cast<ReachStatus>(k))] = audit.contradicted[k];
  }
  ja["audited_by_status"] = jb;
  ja["contradicted_by_status"] = jc;
  ja["contradicted"] = audit.contradictedTotal();
  ja["reachable_but_audit_found_none"] = audit.audit_missed;
  ja["manipulability_compared"] = audit.manipulability_compared;
  ja["manipulability_within_5pct_of_audit_best"] = audit.manipulability_within_5pct;
  jd["audit"] = ja;
  const int sc = static_cast<int>(ReachStatus::SelfCollision),
            oc = static_cast<int>(ReachStatus::ObstacleCollision);
  doc.paragraph(
      "Audit (" + map.design + "): " + std::to_string(audit.poses) +
      " poses drawn at random (seed " + std::to_string(audit.seed) + "), " +
      std::to_string(audit.starts) +
      " random starts each, without the sweep's warm starts or neighbours: " +
      std::to_string(audit.contradictedTotal()) + " statuses contradicted (a solution" +
      (map.collision ? " clear of collisions" : "") + " found where the map has none; " +
      std::to_string(audit.contradicted[sc]) + " of " + std::to_string(audit.by_status[sc]) +
      " self_collision, " + std::to_string(audit.contradicted[oc]) + " of " +
      std::to_string(audit.by_status[oc]) + " obstacle_collision), " +
      std::to_string(audit.audit_missed) +
      " reachable poses where the audit found no solution; manipulability at the map's solution "
      "within 5 % "
      "of the best the audit found at " +
      std::to_string(audit.manipulability_within_5pct) + " of " +
      std::to_string(audit.manipulability_compared) + " reachable poses.");
}

// VTK image data of design di: one array per quantity and orientation.
void writeDesignVti(const GridRendering& gr, std::size_t di,
                    const std::vector<ManipulabilityParts>& mparts, Writer& out, ordered_json& jd) {
  const PoseSweep& map = gr.res.maps[di];
  const TaskGrid& grid = gr.grid;
  io::ImageGrid img;
  img.dims = gr.res.dims;
  img.origin = {grid.axes[0].from, grid.axes[1].from, grid.axes[2].from};
  img.spacing = {grid.axes[0].step, grid.axes[1].step, grid.axes[2].step};
  for (int k = 0; k < gr.res.orientation_count; ++k) {
    addPoseArrays(img.point_arrays, map, &grid, gr.res.positions, k, suffix(grid, k));
    addPartArrays(img.point_arrays, map, mparts, grid, gr.res.positions, k, suffix(grid, k));
  }
  if (gr.res.orientation_count > 1)
    img.point_arrays.push_back(arrayOf("reachable_orientations", io::ArrayType::UInt8, nullptr,
                                       gr.res.positions, 0, 1, [&](long p, int) {
                                         int c = 0;
                                         for (int k = 0; k < gr.res.orientation_count; ++k)
                                           c += map.reachable(k * gr.res.positions + p);
                                         return double(c);
                                       }));
  img.field_data = poseFieldData(map, &grid);
  const std::string rel = gr.res.folder + "/" + map.design + ".vti";
  io::writeVti(out.path(rel), img);
  out.add(rel);
  jd["vti"] = rel;
  writeBestRobot(out, gr.res.folder + "/" + map.design + "_robot_best.vtp",
                 gr.ctx.study.designs[di].model, map);
}

// The main piece of design di: its summary entry, report lines, table rows, VTK map and best robot.
void renderMain(const GridRendering& gr, std::size_t di, Writer& out, RenderedPart& part) {
  const TaskGrid& grid = gr.grid;
  const PoseSweep& map = gr.res.maps[di];
  const StudyDesign& sd = gr.ctx.study.designs[di];
  Stats all;
  std::vector<Stats> per(gr.res.orientation_count);
  const std::vector<ManipulabilityParts> mparts = manipulabilityParts(sd.model, grid, map, 1);
  for (long i = 0; i < grid.size(); ++i) {
    const Eigen::Vector3d p = grid.position(grid.pointOf(i));
    all.add(map, i, p);
    per[grid.orientationOf(i)].add(map, i, p);
    if (map.reachable(i)) {
      all.addParts(mparts[static_cast<std::size_t>(i)]);
      per[grid.orientationOf(i)].addParts(mparts[static_cast<std::size_t>(i)]);
    }
  }
  ordered_json jd;
  jd["design"] = map.design;
  jd["variant_of"] = sd.base_name;
  ordered_json ov = ordered_json::object();
  for (const auto& [k, v] : sd.overrides) ov[k] = v;
  jd["overrides"] = ov;
  jd.update(all.json());
  jd["boundary_poses"] = boundaryPoses(grid, map);
  ordered_json jper = ordered_json::array();
  const auto share = [](const Stats& st, ReachStatus k) {
    return report::percent(st.n ? double(st.status[static_cast<int>(k)]) / st.n : 0);
  };
  for (int k = 0; k < gr.res.orientation_count; ++k) {
    ordered_json e = per[k].json();
    e["orientation"] = orientationText(grid, k);
    jper.push_back(e);
    part.rows.push_back(
        {map.design, orientationText(grid, k), report::percent(per[k].fraction()),
         share(per[k], ReachStatus::JointLimits), share(per[k], ReachStatus::OutOfReach),
         share(per[k], ReachStatus::RepresentationSingularity), per[k].extent.text()});
    if (!usesCardanAngles(grid.task_space)) part.rows.back().erase(part.rows.back().begin() + 5);
    insertCollisionColumns(gr.cfg, part.rows.back(), 3, per[k]);
  }
  jd["per_orientation"] = jper;
  searchAndAuditEntries(gr, di, jd, part.doc);
  if (gr.cfg.outputs.vtk) writeDesignVti(gr, di, mparts, out, jd);
  part.jd = std::move(jd);
}

// The surface pieces of design di: its boundary surface in orientation k (3-D grids).
void renderSurface(const GridRendering& gr, std::size_t di, int k, Writer& out,
                   RenderedPart& part) {
  const TaskGrid& grid = gr.grid;
  if (!(gr.cfg.outputs.surface && grid.spatialDimension() == 3)) return;
  const PoseSweep& map = gr.res.maps[di];
  const double cell_volume_m3 = grid.axes[0].step * grid.axes[1].step * grid.axes[2].step;
  std::vector<Eigen::Vector3d> pts;
  for (long p = 0; p < gr.res.positions; ++p)
    if (map.reachable(k * gr.res.positions + p)) pts.push_back(grid.position(p));
  const BoundarySurface bs = alphaShapeSurface(
      pts, gridAlphaRadius({grid.axes[0].step, grid.axes[1].step, grid.axes[2].step}));
  io::PolyDataSet poly;
  poly.points = bs.vertices;
  poly.triangles = bs.triangles;
  poly.field_data = io::fieldData(
      {"position: m"},
      {"surface: boundary of the reachable grid points (" + orientationText(grid, k) + ")"});
  const std::string rel = gr.res.folder + "/" + map.design + "_surface" + suffix(grid, k) + ".vtp";
  io::writeVtp(out.path(rel), poly);
  out.add(rel);
  part.jd = {{"orientation", orientationText(grid, k)},
             {"file", rel},
             {"alpha_shape_volume_m3", bs.volume_m3},
             {"voxel_volume_m3", cell_volume_m3 * static_cast<double>(pts.size())},
             {"triangles", bs.triangles.size()}};
}

// The largest manipulability any design reaches on the grid (all orientations): the top of the
// one colour scale every design's manipulability figure of the grid shares, so that a colour
// means the same value in each of them.
double sharedManipulabilityMax(const GridRendering& gr) {
  double manipulability_max_m3 = 0;
  for (const PoseSweep& map : gr.res.maps)
    for (long i = 0; i < gr.grid.size(); ++i)
      if (map.reachable(i))
        manipulability_max_m3 = std::max(manipulability_max_m3, map.manipulability[i]);
  return manipulability_max_m3;
}

// The manipulability figure of design di in orientation k (2-D grids), colour
// 0..manipulability_max_m3 (shared by the grid's designs), appended to `images`.
void manipulabilityFigure(const GridRendering& gr, std::size_t di, int k,
                          double manipulability_max_m3, Writer& out, report::Document& images) {
  const TaskGrid& grid = gr.grid;
  const PoseSweep& map = gr.res.maps[di];
  const long off = static_cast<long>(k) * gr.res.positions;
  report::RasterImage m_img = report::renderCellMap(
      gr.res.dims[gr.layout.plane.a], gr.layout.image_rows, [&](int u, int v) {
        report::Rgb col{230, 230, 230};
        forCell(grid, gr.layout.plane, u, v, [&](long p) {
          if (map.reachable(off + p))
            col = report::viridis(map.manipulability[off + p] / manipulability_max_m3);
        });
        return col;
      });
  report::MapFigure mfig =
      mapAxes(grid, gr.layout.plane, map.design + ", " + orientationText(grid, k));
  mfig.scale = report::ColourScale{report::viridis, 0, manipulability_max_m3,
                                   "manipulability of the task rows, eq. 5.59 [" +
                                       taskManipulabilityUnit(grid.task_space) + "]"};
  mfig.legend = {{report::Rgb{230, 230, 230}, "unreachable"}};
  const std::string mrel = writeFigure(
      out, "reach/images/" + grid.name + "__" + map.design + suffix(grid, k) + "_manipulability",
      m_img, mfig);
  images.figures(
      {{"manipulability", mrel}},
      "Manipulability sqrt(det(J_t J_t^T)) of the task rows (eq. 5.59) at the solution, " +
          map.design + ", " + orientationText(grid, k) + "; viridis from 0 (dark) to " +
          report::scientific(manipulability_max_m3) + " " +
          taskManipulabilityUnit(grid.task_space) +
          " (yellow), the same scale for every design of the grid, grey = unreachable.");
}

// The figures pieces of design di: the status (or reachable-fraction) and manipulability figures of
// orientation k.
void renderImages(const GridRendering& gr, std::size_t di, int k, Writer& out, RenderedPart& part) {
  if (!gr.cfg.outputs.images) return;
  const TaskGrid& grid = gr.grid;
  const ImagePlane& plane = gr.layout.plane;
  const PoseSweep& map = gr.res.maps[di];
  report::Document& images = part.images;
  Stats per_k;  // the orientation's poses in index order, as the summary entry counts them
  for (long p = 0; p < gr.res.positions; ++p) {
    const long i = static_cast<long>(k) * gr.res.positions + p;
    per_k.add(map, i, grid.position(grid.pointOf(i)));
  }
  const double manipulability_max_m3 = sharedManipulabilityMax(gr);
  // A status map whose cells all have one status would be one colour: a sentence says it instead.
  if (plane.projected < 0) {
    long n = 0;
    for (long c : per_k.status) n += c;
    for (int st = 0; st < kReachStatusCount; ++st)
      if (n > 0 && per_k.status[st] == n) {
        images.paragraph("*" + map.design + ", " + orientationText(grid, k) + ": 100 % of the " +
                         std::to_string(n) + " cells " + describe(static_cast<ReachStatus>(st)) +
                         " (no map drawn).*");
        // (Nothing reachable: the manipulability map would be one colour too.)
        if (manipulability_max_m3 > 0 && st == static_cast<int>(ReachStatus::Reachable))
          manipulabilityFigure(gr, di, k, manipulability_max_m3, out, images);
        return;
      }
  }
  const std::string title = map.design + ", " + orientationText(grid, k);
  const std::string rel =
      writeStatusFigure(out, "reach/images/" + grid.name + "__" + map.design + suffix(grid, k),
                        grid, plane, map, k, per_k.status, title);
  images.figures({{title, rel}}, title + ": " + report::percent(per_k.fraction()) + " reachable. " +
                                     imageCaptionAxes(grid, plane) + ".");
  if (plane.projected < 0 && manipulability_max_m3 > 0)
    manipulabilityFigure(gr, di, k, manipulability_max_m3, out, images);
}

// The comparison images of the pair (a, b), one per orientation.
void renderPair(const GridRendering& gr, std::size_t a, std::size_t b, Writer& out,
                report::Document& pair_imgs) {
  const TaskGrid& grid = gr.grid;
  const std::vector<PoseSweep>& sweeps = gr.res.maps;
  for (int k = 0; k < gr.res.orientation_count; ++k) {
    const long off = static_cast<long>(k) * gr.res.positions;
    // Both, only a, only b, neither; a map of one of them would be one colour: said in words.
    std::array<long, 4> in{};
    for (long p = 0; p < gr.res.positions; ++p) {
      const bool ra = sweeps[a].reachable(off + p), rb = sweeps[b].reachable(off + p);
      ++in[ra && rb ? 0 : ra ? 1 : rb ? 2 : 3];
    }
    const std::string names[4] = {"reached by both", "reached only by " + sweeps[a].design,
                                  "reached only by " + sweeps[b].design, "reached by neither"};
    const auto sole = std::find(in.begin(), in.end(), gr.res.positions);
    if (gr.res.positions > 0 && sole != in.end()) {
      pair_imgs.paragraph("*" + sweeps[a].design + " vs " + sweeps[b].design + ", " +
                          orientationText(grid, k) + ": 100 % of the " +
                          std::to_string(gr.res.positions) + " cells " + names[sole - in.begin()] +
                          " (no map drawn).*");
      continue;
    }
    report::RasterImage img = report::renderCellMap(
        gr.res.dims[gr.layout.plane.a], gr.layout.image_rows, [&](int u, int v) {
          report::Rgb col;
          forCell(grid, gr.layout.plane, u, v, [&](long p) {
            const bool ra = sweeps[a].reachable(off + p), rb = sweeps[b].reachable(off + p);
            col = ra && rb ? report::categorical(0)
                  : ra     ? report::categorical(5)
                  : rb     ? report::categorical(2)
                           : report::categorical(1);
          });
          return col;
        });
    report::MapFigure cfig =
        mapAxes(grid, gr.layout.plane,
                sweeps[a].design + " vs " + sweeps[b].design + ", " + orientationText(grid, k));
    cfig.legend = {{report::categorical(0), "both"},
                   {report::categorical(5), "only " + sweeps[a].design},
                   {report::categorical(2), "only " + sweeps[b].design},
                   {report::categorical(1), "neither"}};
    const std::string rel = writeFigure(out,
                                        "reach/images/" + grid.name + "__" + sweeps[a].design +
                                            "__vs__" + sweeps[b].design + suffix(grid, k),
                                        img, cfig);
    pair_imgs.figures({{sweeps[a].design + " vs " + sweeps[b].design, rel}},
                      orientationText(grid, k) + ": reached by both (green), only " +
                          sweeps[a].design + " (blue), only " + sweeps[b].design +
                          " (orange), neither (light grey). " +
                          imageCaptionAxes(grid, gr.layout.plane) + ".");
  }
}

// Renders piece `it` (a design's piece, or a pair's images), writes its files into the study's
// output folder and returns its part and the files' names as bytes.
std::string renderPiece(const GridRendering& gr, std::size_t it) {
  Writer w(gr.ctx.resultsDir());
  RenderedPart part;
  const GridPiece piece = gr.layout.piece(it);
  switch (piece.kind) {
    case GridPiece::Kind::Main:
      renderMain(gr, piece.design, w, part);
      break;
    case GridPiece::Kind::Surface:
      renderSurface(gr, piece.design, piece.orientation, w, part);
      break;
    case GridPiece::Kind::Figures:
      renderImages(gr, piece.design, piece.orientation, w, part);
      break;
    case GridPiece::Kind::PairImages: {
      const auto [a, b] = gr.res.pairs[gr.layout.image_pairs[piece.pair]];
      renderPair(gr, a, b, w, part.images);
      break;
    }
  }
  return packRenderedPart(part, w);
}

}  // namespace

GridPiece GridPieces::piece(std::size_t it) const {
  GridPiece piece;
  if (it >= designPieces()) {
    piece.kind = GridPiece::Kind::PairImages;
    piece.pair = it - designPieces();
    return piece;
  }
  const auto per_design = static_cast<std::size_t>(piecesPerDesign());
  piece.design = it / per_design;
  const int within = static_cast<int>(it % per_design);
  if (within == 0) return piece;
  piece.kind = within <= orientation_count ? GridPiece::Kind::Surface : GridPiece::Kind::Figures;
  piece.orientation = within <= orientation_count ? within - 1 : within - 1 - orientation_count;
  return piece;
}

GridPieces gridPieces(const ReachGridResults& res, const ReachConfig& cfg) {
  GridPieces pieces;
  pieces.plane = imagePlane(res.taskGrid());
  const ImagePlane& plane = pieces.plane;
  pieces.image_rows = plane.b != plane.a && res.dims[plane.b] > 1 ? res.dims[plane.b] : 1;
  pieces.orientation_count = res.orientation_count;
  pieces.design_count = res.designCount();
  for (std::size_t p = 0; p < res.pairs.size(); ++p)
    if (res.designCount() <= kMaxPairImageDesigns || res.pairs[p].first == 0)
      pieces.image_pairs.push_back(p);
  pieces.pair_images = res.designCount() >= 2 && cfg.outputs.images && plane.projected < 0;
  return pieces;
}

std::vector<std::string> renderGridPieces(const StageContext& ctx, const ReachConfig& cfg,
                                          const ReachGridResults& res, const GridPieces& pieces) {
  const GridRendering gr{ctx, cfg, res, res.taskGrid(), pieces};
  return renderShared(&ctx.units, "files/" + res.taskGrid().name, pieces.count(), ctx.threads,
                      [&gr](std::size_t it) { return renderPiece(gr, it); });
}

}  // namespace armstudy
