#include "stages/reach/reach_grid.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string_view>
#include <cmath>
#include <nlohmann/json.hpp>

#include "collision/reach_collision.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "io/vtk_io.hpp"
#include "reach/boundary_surface.hpp"
#include "reach/reach_audit.hpp"
#include "report/markdown.hpp"
#include "stages/reach/reach_report.hpp"
#include "stages/reach/reach_units.hpp"
#include "study/checkpoint.hpp"
#include "study/interleave.hpp"

namespace armstudy {

using nlohmann::ordered_json;

namespace {
constexpr std::string_view kDesignPartMagic = "armstudy-reach-design-parts-1";
}  // namespace
using namespace reach_report;
using namespace reach_units;

ordered_json reportGrid(const StageContext& ctx, const ReachConfig& cfg, const TaskGrid& g, Progress& progress,
                        StageResult& sum, Writer& out, std::string& md) {
  const Study& study = ctx.study;
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

  // Every design's units in one pool (one hand-out and exchange in a distributed run).
  std::vector<const Model*> models;
  for (const StudyDesign& sd : study.designs) models.push_back(&sd.model);
  std::vector<PoseSweep> sweeps = solveGridDesigns(ctx, sum, "reach/" + g.name, models, g, cfg, progress);
  // Across units, once all are in: statuses that do not depend on the traversal (issue 12). The
  // designs' searches advance together, one step each per shared loop (study/interleave.hpp).
  const std::size_t nd = study.designs.size();
  std::vector<SweepSearchSummary> searches(nd);
  std::vector<InterleavedProgram> programs;
  for (std::size_t di = 0; di < nd; ++di)
    programs.push_back([&, di](const UnitRunner* r) {
      searches[di] = searchGridSweep(study.designs[di].model, g, cfg.ik, ctx.threads, cfg.collisionFor(study.designs[di].model), cfg.search,
                                     sweeps[di], r);
    });
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  auto t0 = Clock::now();
  // A distributed run may search the designs in rank groups: a design's search then travels as its
  // summary and changed rows to the ranks that did not run it. A search's predicted cost: its
  // reachable poses (the best-manipulability rounds visit them), a tenth as much for an arm of six
  // joints or fewer (defaults::kSearchWeightNonRedundant; assumption, docs/distributed.md "Rank
  // groups"), plus one (a design that reaches nothing still gets a group of its own when there are
  // enough groups).
  ProgramResults results;
  results.weight = [&](std::size_t di) {
    return 1.0 + double(sweeps[di].countReachable()) *
                     (study.designs[di].model.dof() > 6 ? 1.0 : defaults::kSearchWeightNonRedundant);
  };
  results.pack = [&](std::size_t di) { return packSearchResult(sweeps[di], searches[di]); };
  results.unpack = [&](std::size_t di, const std::string& bytes) {
    unpackSearchResult(bytes, sweeps[di], searches[di]);
  };
  runInterleaved(&ctx.units, programs, &results);
  // One wall time for the grid's searches (they ran together; each search's own wall time would
  // include the waits for the others).
  sum.timings.push_back({"reach/" + g.name + "/search", seconds(t0)});
  for (std::size_t di = 0; di < nd; ++di)
    addUnitMetrics(sum.metrics, "reach/" + g.name + "/" + study.designs[di].model.name, sweeps[di]);
  // The audits (issue 12), interleaved alike.
  std::vector<ReachAudit> audits(nd);
  if (cfg.audit_poses > 0) {
    programs.clear();
    for (std::size_t di = 0; di < nd; ++di)
      programs.push_back([&, di](const UnitRunner* r) {
        audits[di] = auditGridSweep(study.designs[di].model, g, cfg.ik, cfg.collisionFor(study.designs[di].model), sweeps[di], cfg.audit_poses,
                                    cfg.audit_starts, cfg.audit_seed, ctx.threads, r);
      });
    t0 = Clock::now();
    runInterleaved(&ctx.units, programs);
    sum.timings.push_back({"reach/" + g.name + "/audit", seconds(t0)});
  }
  // Each design's files, figures and report lines, and each compared pair's images, rendered by the
  // process that owns it (a loop shared among the processes of a distributed run, one design or
  // pair per chunk): the files go to a
  // scratch folder inside the store (<output>/.partial/render/), their bytes travel with the
  // design's summary entry (CBOR) and report lines, and process 0 then writes them in design order
  // (the others list them only), so the files and their order are those of a single process.
  t0 = Clock::now();
  const ImagePlane plane = imagePlane(g);
  // A design's files come in pieces, each a chunk of the shared loop below, so that a costly
  // design spreads over several ranks: piece 0 is its summary entry, report lines, VTK map and
  // best robot; pieces 1..no the boundary surface of each orientation (3-D grids); pieces
  // no+1..2no the figures of each orientation. Joined in piece order, their files are in the
  // order one call would write them.
  const int pieces = 1 + 2 * no;
  auto renderMain = [&](std::size_t di, Writer& out, DesignPart& part) {
    std::string& md = part.md;
    std::vector<std::vector<std::string>>& rows = part.rows;
    const PoseSweep& s = sweeps[di];
    const StudyDesign& sd = study.designs[di];
    Stats all;
    std::vector<Stats> per(no);
    const std::vector<ManipulabilityParts> mparts = manipulabilityParts(sd.model, g, s);
    for (long i = 0; i < g.size(); ++i) {
      const Eigen::Vector3d p = g.position(g.pointOf(i));
      all.add(s, i, p);
      per[g.orientationOf(i)].add(s, i, p);
      if (s.reachable(i)) {
        all.addParts(mparts[static_cast<std::size_t>(i)]);
        per[g.orientationOf(i)].addParts(mparts[static_cast<std::size_t>(i)]);
      }
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
      if (!usesCardanAngles(g.task_space)) rows.back().erase(rows.back().begin() + 5);
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
    if (s.collision)
      md += "; " + std::to_string(se.multistart_poses) + " poses still in collision got " +
            std::to_string(cfg.search.collision_starts) + " seeded starts each (" +
            std::to_string(se.multistart_freed) + " found collision-free). A pose is `self_collision` / "
            "`obstacle_collision` only when no collision-free solution was found in all its starts (array "
            "`starts` of the .vti: the sweep's starts, escapes, neighbour seeds and seeded starts, capped at 255)";
    md += ".\n\n";
    if (cfg.audit_poses > 0) {
      const ReachAudit& au = audits[di];
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
            (s.collision ? " clear of collisions" : "") + " found where the map has none; " +
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
      for (int k = 0; k < no; ++k) {
        addPoseArrays(img.point_arrays, s, &g, points, k, suffix(g, k));
        addPartArrays(img.point_arrays, s, mparts, g, points, k, suffix(g, k));
      }
      if (no > 1)
        img.point_arrays.push_back(arrayOf("reachable_orientations", io::ArrayType::UInt8, nullptr, points, 0, 1,
                                           [&](long p, int) {
                                             int c = 0;
                                             for (int k = 0; k < no; ++k) c += s.reachable(k * points + p);
                                             return double(c);
                                           }));
      img.field_data = poseFieldData(s, &g);
      const std::string rel = gdir + "/" + s.design + ".vti";
      io::writeVti(out.path(rel), img);
      out.add(rel);
      jd["vti"] = rel;
      writeBestRobot(out, gdir + "/" + s.design + "_robot_best.vtp", sd.model, s);
    }
    part.jd = std::move(jd);
  };
  auto renderSurface = [&](std::size_t di, int k, Writer& out, DesignPart& part) {
    if (!(cfg.outputs.surface && g.spatialDimension() == 3)) return;
    const PoseSweep& s = sweeps[di];
    const double voxel = g.axes[0].step * g.axes[1].step * g.axes[2].step;
    std::vector<Eigen::Vector3d> pts;
    for (long p = 0; p < points; ++p)
      if (s.reachable(k * points + p)) pts.push_back(g.position(p));
    const BoundarySurface bs =
        alphaShapeSurface(pts, gridAlphaRadius({g.axes[0].step, g.axes[1].step, g.axes[2].step}));
    io::PolyDataSet poly;
    poly.points = bs.vertices;
    poly.triangles = bs.triangles;
    poly.field_data = io::fieldData({"position: m"}, {"surface: boundary of the reachable grid points (" +
                                                      orientationText(g, k) + ")"});
    const std::string rel = gdir + "/" + s.design + "_surface" + suffix(g, k) + ".vtp";
    io::writeVtp(out.path(rel), poly);
    out.add(rel);
    part.jd = {{"orientation", orientationText(g, k)},
               {"file", rel},
               {"alpha_shape_volume_m3", bs.volume_m3},
               {"voxel_volume_m3", voxel * static_cast<double>(pts.size())},
               {"triangles", bs.triangles.size()}};
  };
  auto renderImages = [&](std::size_t di, int k, Writer& out, DesignPart& part) {
    if (!cfg.outputs.images) return;
    const PoseSweep& s = sweeps[di];
    std::string& images_md = part.images_md;
    Stats per_k;  // the orientation's poses in index order, as the summary entry counts them
    for (long p = 0; p < points; ++p) {
      const long i = static_cast<long>(k) * points + p;
      per_k.add(s, i, g.position(g.pointOf(i)));
    }
    const int nu = d[plane.a], nv = plane.b != plane.a && d[plane.b] > 1 ? d[plane.b] : 1;
    double mmax = 0;
    for (long i = 0; i < g.size(); ++i)
      if (s.reachable(i)) mmax = std::max(mmax, s.manipulability[i]);
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
      fig.legend = statusLegend(per_k.status);
    const std::string rel =
        writeFigure(out, "reach/images/" + g.name + "__" + s.design + suffix(g, k), status_img, fig);
    images_md += "![" + s.design + ", " + orientationText(g, k) + "](" + rel + ")\n\n*" + s.design + ", " +
                 orientationText(g, k) + ": " + report::percent(per_k.fraction()) + " reachable. " +
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
      mfig.scale = report::ColourScale{report::viridis, 0, mmax, "manipulability of the task rows, eq. 5.59 [m^3]"};
      mfig.legend = {{report::Rgb{230, 230, 230}, "unreachable"}};
      const std::string mrel = writeFigure(out, 
          "reach/images/" + g.name + "__" + s.design + suffix(g, k) + "_manipulability", m_img, mfig);
      images_md += "![manipulability](" + mrel + ")\n\n*Manipulability sqrt(det(J_t J_t^T)) of the task rows (eq. 5.59) at the solution, " +
                   s.design + ", " + orientationText(g, k) + "; viridis from 0 (dark) to " +
                   report::scientific(mmax) + " (yellow), grey = unreachable.*\n\n";
    }
  };
  // The pairs of designs compared on this grid (many designs: the first against each other) and
  // their comparison images, rendered in the same shared loop as the designs' files (one pair per
  // chunk after the designs' chunks), then written in pair order with the comparison below.
  const std::size_t max_pairs_designs = 4;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t a = 0; a < nd; ++a)
    for (std::size_t b = a + 1; b < nd; ++b)
      if (!(nd > max_pairs_designs && a > 0)) pairs.emplace_back(a, b);
  const bool pair_images = nd >= 2 && cfg.outputs.images && plane.projected < 0;
  auto renderPair = [&](std::size_t a, std::size_t b, Writer& out, std::string& pair_imgs) {
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
                   orientationText(g, k) + ": reached by both (green), only " + sweeps[a].design + " (blue), only " +
                   sweeps[b].design + " (orange), neither (light grey). " + imageCaptionAxes(g, plane) + ".*\n\n";
    }
  };
  const std::size_t design_items = nd * static_cast<std::size_t>(pieces);
  const std::size_t n_items = design_items + (pair_images ? pairs.size() : 0);
  // Per design piece, then per pair: files, entry and lines as bytes.
  std::vector<std::string> parts(n_items);
  SharedLoop render;
  render.id = "files/" + g.name;
  render.items = static_cast<long>(n_items);
  render.chunk = 1;
  render.compute = [&](const std::vector<SharedLoop::Chunk>& mine) {
    for (const long item : SharedLoop::itemsOf(mine)) {
      const auto it = static_cast<std::size_t>(item);
      const std::string scratch = out.path(".partial/render/" + g.name + "-" + std::to_string(item));
      std::filesystem::remove_all(scratch);
      Writer w(scratch);
      DesignPart part;
      if (it < design_items) {
        const std::size_t di = it / static_cast<std::size_t>(pieces);
        const int piece = static_cast<int>(it % static_cast<std::size_t>(pieces));
        if (piece == 0)
          renderMain(di, w, part);
        else if (piece <= no)
          renderSurface(di, piece - 1, w, part);
        else
          renderImages(di, piece - 1 - no, w, part);
      } else {
        const auto [a, b] = pairs[it - design_items];
        renderPair(a, b, w, part.md);
      }
      std::string bytes = packDesignPart(part, w);
      std::filesystem::remove_all(scratch);
      parts[it] = std::move(bytes);
    }
  };
  render.pack = [&](std::size_t, const ItemRange& r) {
    UnitWriter b(kDesignPartMagic);
    for (long di = r.begin; di < r.end; ++di) b.putString(parts[static_cast<std::size_t>(di)]);
    return b.bytes();
  };
  render.unpack = [&](std::size_t, const ItemRange& r, const std::string& bytes) {
    UnitReader rd(bytes, kDesignPartMagic);
    for (long di = r.begin; di < r.end; ++di) parts[static_cast<std::size_t>(di)] = rd.getString();
    ARMSTUDY_CHECK(rd.finished(), "a design's files arrive whole");
  };
  runSharedLoop(&ctx.units, render);
  {
    std::error_code ec;  // the scratch folders' parents, when empty (the store may hold units)
    std::filesystem::remove(out.path(".partial/render"), ec);
    std::filesystem::remove(out.path(".partial"), ec);
  }
  // A rank other than 0 is done with the grid here: what follows (the designs' summary entries,
  // report lines and files, the comparison) only rank 0 writes, and nothing in it is shared. The
  // other ranks go on to the next grid's units while rank 0 writes (docs/distributed.md "Files").
  if (!ctx.writes_results) return jg;
  // Writes the rendered files (in the background), or on a rank other than 0 only lists them: its
  // scratch copies would not be read.
  auto writeRendered = [&](std::vector<std::pair<std::string, std::string>> files) {
    if (ctx.writes_results) {
      out.textLater(std::move(files));
    } else {
      for (const auto& f : files) out.add(f.first);
    }
  };
  std::vector<std::vector<std::string>> rows;
  ordered_json jdesigns = ordered_json::array();
  std::string images_md;
  // The files are written on a background thread (Writer::textLater) while the stage goes on: the
  // next grid's units need not wait for the disk. The stage flushes before it returns.
  std::vector<std::pair<std::string, std::string>> design_files;
  for (std::size_t di = 0; di < nd; ++di) {
    DesignPart part;
    const std::size_t first = di * static_cast<std::size_t>(pieces);
    unpackDesignPart(parts[first], part, design_files);
    ordered_json jsurf = ordered_json::array();
    for (int k = 0; k < no; ++k) {
      DesignPart surface;
      unpackDesignPart(parts[first + 1 + static_cast<std::size_t>(k)], surface, design_files);
      if (!surface.jd.is_null()) jsurf.push_back(std::move(surface.jd));
    }
    if (cfg.outputs.surface && g.spatialDimension() == 3) part.jd["surface"] = std::move(jsurf);
    for (int k = 0; k < no; ++k) {
      DesignPart figures;
      unpackDesignPart(parts[first + 1 + static_cast<std::size_t>(no + k)], figures, design_files);
      part.images_md += figures.images_md;
    }
    jdesigns.push_back(std::move(part.jd));
    md += part.md;
    images_md += part.images_md;
    for (auto& row : part.rows) rows.push_back(std::move(row));
  }
  writeRendered(std::move(design_files));
  sum.timings.push_back({"reach/" + g.name + "/files", seconds(t0)});
  jg["designs"] = jdesigns;
  std::vector<std::string> header = {"design", "orientation", ">reachable", ">joint limits", ">out of reach",
                                     ">repr. singular", "extent of the reachable poses"};
  if (!usesCardanAngles(g.task_space)) header.erase(header.begin() + 5);
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
      std::vector<std::string> legend;
      for (std::size_t di = 0; di < sweeps.size(); ++di)
        legend.push_back("reached_by_mask bit " + std::to_string(di) + " (value " + std::to_string(1L << di) +
                         "): " + sweeps[di].design);
      img.field_data = io::fieldData({"position: m", "reached_by_mask: 1 (bit mask)", "reached_by_count: 1"}, legend);
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
    ordered_json jpairs = ordered_json::array();
    std::string pair_imgs;
    std::vector<std::pair<std::string, std::string>> pair_files;
    for (std::size_t p = 0; p < pairs.size(); ++p) {
      const auto [a, b] = pairs[p];
      long n_a = 0, n_b = 0, both = 0, neither = 0;
      for (long i = 0; i < g.size(); ++i) {
        const bool ra = sweeps[a].reachable(i), rb = sweeps[b].reachable(i);
        n_a += ra && !rb;
        n_b += rb && !ra;
        both += ra && rb;
        neither += !ra && !rb;
      }
      jpairs.push_back({{"a", sweeps[a].design}, {"b", sweeps[b].design}, {"a_only", n_a}, {"b_only", n_b},
                        {"both", both}, {"neither", neither}});
      const double N = static_cast<double>(g.size());
      crow.push_back({sweeps[a].design, sweeps[b].design, report::percent(n_a / N), report::percent(n_b / N),
                      report::percent(both / N), report::percent(neither / N)});
      if (pair_images) {  // the images the render loop made
        DesignPart part;
        unpackDesignPart(parts[design_items + p], part, pair_files);
        pair_imgs += part.md;
      }
    }
    writeRendered(std::move(pair_files));
    jcmp["pairs"] = jpairs;
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
    std::string dexterity_md;
    jcmp["dexterity"] = dexterityComparison(models, g, sweeps, pairs, dexterity_md);
    jg["comparison"] = jcmp;
    md += "Per pose, which designs reach it (all orientations together):\n\n" +
          report::markdownTable({"A", "B", ">A only", ">B only", ">both", ">neither"}, crow) + "\n" + dexterity_md;
    if (!brow.empty())
      md += "Best variant per base design (the most reachable poses; with base.* overrides this is the best base placement):\n\n" +
            report::markdownTable({"base design", "best variant", ">reachable", "base placement varied"}, brow) + "\n";
    md += pair_imgs;
  }
  return jg;
}

}  // namespace armstudy
