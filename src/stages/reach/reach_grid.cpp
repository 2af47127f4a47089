#include "stages/reach/reach_grid.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string_view>

#include "collision/reach_collision.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "common/parallel_for.hpp"
#include "io/vtk_io.hpp"
#include "reach/boundary_surface.hpp"
#include "reach/reach_audit.hpp"
#include "report/markdown.hpp"
#include "stages/reach/reach_report.hpp"
#include "stages/reach/reach_units.hpp"
#include "study/checkpoint.hpp"
#include "study/interleave.hpp"
#include "study/rendered_part.hpp"
#include "study/scene.hpp"

namespace armstudy {

using nlohmann::ordered_json;

using namespace reach_report;
using namespace reach_units;

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Designs compared pairwise (tables, dexterity) up to this many; beyond, the first against each
// other. Pair images (one per orientation and pair) for all pairs up to kMaxPairImageDesigns
// designs; beyond, for the first against each other.
constexpr std::size_t kMaxPairsDesigns = 12;
constexpr std::size_t kMaxPairImageDesigns = 4;

// One grid's run, phase by phase: sweep and search (solveGrid), audit (auditGrid), render each
// design's and pair's files in a shared loop (renderGrid), then, on the process that writes the
// results, the report: the designs' entries and tables (writeGridReport) and the comparison of
// designs (compareDesigns).
struct GridRun {
  GridRun(const StageContext& c, const ReachConfig& rc, const TaskGrid& tg, StageResult& s,
          Writer& w)
      : ctx(c),
        study(c.study),
        cfg(rc),
        g(tg),
        sum(s),
        out(w),
        d(tg.dims()),
        points(tg.points()),
        no(static_cast<int>(tg.orientations.size())),
        nd(c.study.designs.size()),
        gdir("reach/" + tg.name),
        plane(imagePlane(tg)),
        pieces(1 + 2 * no) {
    for (const StudyDesign& sd : study.designs) models.push_back(&sd.model);
    // The pairs of designs compared on this grid (many designs: the first against each other).
    for (std::size_t a = 0; a < nd; ++a)
      for (std::size_t b = a + 1; b < nd; ++b)
        if (!(nd > kMaxPairsDesigns && a > 0)) {
          if (nd <= kMaxPairImageDesigns || a == 0) image_pairs.push_back(pairs.size());
          pairs.emplace_back(a, b);
        }
    pair_images = nd >= 2 && cfg.outputs.images && plane.projected < 0;
  }
  const StageContext& ctx;
  const Study& study;
  const ReachConfig& cfg;
  const TaskGrid& g;
  StageResult& sum;
  Writer& out;
  const std::array<int, 3> d;
  const long points;
  const int no;
  const std::size_t nd;
  const std::string gdir;
  const ImagePlane plane;
  // A design's files come in pieces, each a chunk of the shared render loop, so that a costly
  // design spreads over several ranks: piece 0 is its summary entry, report lines, VTK map and
  // best robot; pieces 1..no the boundary surface of each orientation (3-D grids); pieces
  // no+1..2no the figures of each orientation. Joined in piece order, their files are in the
  // order one call would write them.
  const int pieces;
  std::vector<const Model*> models;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  std::vector<std::size_t> image_pairs;  // the pairs (indices into pairs) that get images
  bool pair_images = false;
  std::vector<PoseSweep> sweeps;
  std::vector<SweepSearchSummary> searches;
  std::vector<ReachAudit> audits;
  std::vector<std::string>
      parts;  // per design piece, then per pair: files, entry and lines as bytes
  std::size_t designItems() const { return nd * static_cast<std::size_t>(pieces); }
  int imageRows() const { return plane.b != plane.a && d[plane.b] > 1 ? d[plane.b] : 1; }
};

ordered_json gridHeader(const TaskGrid& g, std::string& md) {
  const auto d = g.dims();
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
  md += "Task space " + g.task_space.toString() + "; x " + axisText(g.axes[0]) + ", y " +
        axisText(g.axes[1]) + ", z " + axisText(g.axes[2]) + "; " +
        std::to_string(g.orientations.size()) + " orientation(s); " + std::to_string(g.size()) +
        " poses per design.\n\n";
  return jg;
}

// Every design's units in one pool (one hand-out and exchange in a distributed run), then across
// units, once all are in, the map search: statuses that do not depend on the traversal. The
// designs' searches advance together, one step each per shared loop (study/interleave.hpp).
void solveGrid(GridRun& r, Progress& progress) {
  r.sweeps = solveGridDesigns(r.ctx, r.sum, r.gdir, r.models, r.g, r.cfg, progress);
  r.searches.assign(r.nd, {});
  std::vector<InterleavedProgram> programs;
  for (std::size_t di = 0; di < r.nd; ++di)
    programs.push_back([&r, di](const UnitRunner* runner) {
      const Model& m = r.study.designs[di].model;
      r.searches[di] = searchGridSweep(m, r.g, r.cfg.ik, r.ctx.threads, r.cfg.collisionFor(m),
                                       r.cfg.search, r.sweeps[di], runner);
    });
  const auto t0 = Clock::now();
  // A distributed run may search the designs in rank groups: a design's search then travels as its
  // summary and changed rows to the ranks that did not run it. A search's predicted cost: its
  // reachable poses (the best-manipulability rounds visit them), a tenth as much for an arm of six
  // joints or fewer (defaults::kSearchWeightNonRedundant; assumption, docs/distributed.md "Rank
  // groups"), plus one (a design that reaches nothing still gets a group of its own when there are
  // enough groups).
  ProgramResults results;
  results.weight = [&r](std::size_t di) {
    return 1.0 +
           double(r.sweeps[di].countReachable()) *
               (r.study.designs[di].model.dof() > 6 ? 1.0 : defaults::kSearchWeightNonRedundant);
  };
  results.pack = [&r](std::size_t di) { return packSearchResult(r.sweeps[di], r.searches[di]); };
  results.unpack = [&r](std::size_t di, const std::string& bytes) {
    unpackSearchResult(bytes, r.sweeps[di], r.searches[di]);
  };
  runInterleaved(&r.ctx.units, programs, &results);
  // One wall time for the grid's searches (they ran together; each search's own wall time would
  // include the waits for the others).
  r.sum.timings.push_back({r.gdir + "/search", secondsSince(t0)});
  for (std::size_t di = 0; di < r.nd; ++di)
    addUnitMetrics(r.sum.metrics, r.gdir + "/" + r.study.designs[di].model.name, r.sweeps[di]);
}

// The audits (docs/reachability.md "The audit"), interleaved like the searches.
void auditGrid(GridRun& r) {
  r.audits.assign(r.nd, {});
  if (r.cfg.audit_poses <= 0) return;
  std::vector<InterleavedProgram> programs;
  for (std::size_t di = 0; di < r.nd; ++di)
    programs.push_back([&r, di](const UnitRunner* runner) {
      const Model& m = r.study.designs[di].model;
      r.audits[di] =
          auditGridSweep(m, r.g, r.cfg.ik, r.cfg.collisionFor(m), r.sweeps[di], r.cfg.audit_poses,
                         r.cfg.audit_starts, r.cfg.audit_seed, r.ctx.threads, runner);
    });
  const auto t0 = Clock::now();
  runInterleaved(&r.ctx.units, programs);
  r.sum.timings.push_back({r.gdir + "/audit", secondsSince(t0)});
}

// The map search's work and the audit of design di: summary entries and report lines.
void searchAndAuditEntries(const GridRun& r, std::size_t di, ordered_json& jd, std::string& md) {
  const PoseSweep& s = r.sweeps[di];
  const SweepSearchSummary& se = r.searches[di];
  jd["search"] = {{"propagation_rounds", se.rounds},
                  {"neighbour_tries", se.neighbour_tries},
                  {"neighbour_updates", se.neighbour_updates},
                  {"collision_multistart_poses", se.multistart_poses},
                  {"collision_multistart_tries", se.multistart_tries},
                  {"collision_multistart_freed", se.multistart_freed},
                  {"best_manipulability_rounds", se.best_rounds},
                  {"best_manipulability_updates", se.best_updates},
                  {"converged", se.converged}};
  md += "Map search (" + s.design + "): " + std::to_string(se.rounds) +
        (se.rounds == 1 ? " neighbour-propagation round changed "
                        : " neighbour-propagation rounds changed ") +
        std::to_string(se.neighbour_updates) +
        (se.neighbour_updates == 1 ? " status" : " statuses");
  if (s.collision)
    md += "; " + std::to_string(se.multistart_poses) + " poses still in collision got " +
          std::to_string(r.cfg.search.collision_starts) + " seeded starts each (" +
          std::to_string(se.multistart_freed) +
          " found collision-free). A pose is `self_collision` / "
          "`obstacle_collision` only when no collision-free solution was found in all its starts "
          "(array "
          "`starts` of the .vti: the sweep's starts, escapes, neighbour seeds and seeded starts, "
          "capped at 255)";
  md += ".\n\n";
  if (r.cfg.audit_poses <= 0) return;
  const ReachAudit& au = r.audits[di];
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
  const int sc = static_cast<int>(ReachStatus::SelfCollision),
            oc = static_cast<int>(ReachStatus::ObstacleCollision);
  md += "Audit (" + s.design + "): " + std::to_string(au.poses) + " poses drawn at random (seed " +
        std::to_string(au.seed) + "), " + std::to_string(au.starts) +
        " random starts each, without the sweep's warm starts or neighbours: " +
        std::to_string(au.contradictedTotal()) + " statuses contradicted (a solution" +
        (s.collision ? " clear of collisions" : "") + " found where the map has none; " +
        std::to_string(au.contradicted[sc]) + " of " + std::to_string(au.by_status[sc]) +
        " self_collision, " + std::to_string(au.contradicted[oc]) + " of " +
        std::to_string(au.by_status[oc]) + " obstacle_collision), " +
        std::to_string(au.audit_missed) +
        " reachable poses where the audit found no solution; manipulability at the map's solution "
        "within 5 % "
        "of the best the audit found at " +
        std::to_string(au.manipulability_within_5pct) + " of " +
        std::to_string(au.manipulability_compared) + " reachable poses.\n\n";
}

// VTK image data of design di: one array per quantity and orientation.
void writeDesignVti(const GridRun& r, std::size_t di,
                    const std::vector<ManipulabilityParts>& mparts, Writer& out, ordered_json& jd) {
  const PoseSweep& s = r.sweeps[di];
  const TaskGrid& g = r.g;
  io::ImageGrid img;
  img.dims = r.d;
  img.origin = {g.axes[0].from, g.axes[1].from, g.axes[2].from};
  img.spacing = {g.axes[0].step, g.axes[1].step, g.axes[2].step};
  for (int k = 0; k < r.no; ++k) {
    addPoseArrays(img.point_arrays, s, &g, r.points, k, suffix(g, k));
    addPartArrays(img.point_arrays, s, mparts, g, r.points, k, suffix(g, k));
  }
  if (r.no > 1)
    img.point_arrays.push_back(arrayOf("reachable_orientations", io::ArrayType::UInt8, nullptr,
                                       r.points, 0, 1, [&](long p, int) {
                                         int c = 0;
                                         for (int k = 0; k < r.no; ++k)
                                           c += s.reachable(k * r.points + p);
                                         return double(c);
                                       }));
  img.field_data = poseFieldData(s, &g);
  const std::string rel = r.gdir + "/" + s.design + ".vti";
  io::writeVti(out.path(rel), img);
  out.add(rel);
  jd["vti"] = rel;
  writeBestRobot(out, r.gdir + "/" + s.design + "_robot_best.vtp", r.study.designs[di].model, s);
}

// Piece 0 of design di: its summary entry, report lines, table rows, VTK map and best robot.
void renderMain(const GridRun& r, std::size_t di, Writer& out, RenderedPart& part) {
  const TaskGrid& g = r.g;
  const PoseSweep& s = r.sweeps[di];
  const StudyDesign& sd = r.study.designs[di];
  Stats all;
  std::vector<Stats> per(r.no);
  const std::vector<ManipulabilityParts> mparts = manipulabilityParts(sd.model, g, s, 1);
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
  jd["boundary_poses"] = boundaryPoses(g, s);
  ordered_json jper = ordered_json::array();
  const auto share = [](const Stats& st, ReachStatus k) {
    return report::percent(st.n ? double(st.status[static_cast<int>(k)]) / st.n : 0);
  };
  for (int k = 0; k < r.no; ++k) {
    ordered_json e = per[k].json();
    e["orientation"] = orientationText(g, k);
    jper.push_back(e);
    part.rows.push_back(
        {s.design, orientationText(g, k), report::percent(per[k].fraction()),
         share(per[k], ReachStatus::JointLimits), share(per[k], ReachStatus::OutOfReach),
         share(per[k], ReachStatus::RepresentationSingularity), per[k].extent.text()});
    if (!usesCardanAngles(g.task_space)) part.rows.back().erase(part.rows.back().begin() + 5);
    insertCollisionColumns(r.cfg, part.rows.back(), 3, per[k]);
  }
  jd["per_orientation"] = jper;
  searchAndAuditEntries(r, di, jd, part.md);
  if (r.cfg.outputs.vtk) writeDesignVti(r, di, mparts, out, jd);
  part.jd = std::move(jd);
}

// Pieces 1..no of design di: the boundary surface of orientation k (3-D grids).
void renderSurface(const GridRun& r, std::size_t di, int k, Writer& out, RenderedPart& part) {
  const TaskGrid& g = r.g;
  if (!(r.cfg.outputs.surface && g.spatialDimension() == 3)) return;
  const PoseSweep& s = r.sweeps[di];
  const double voxel = g.axes[0].step * g.axes[1].step * g.axes[2].step;
  std::vector<Eigen::Vector3d> pts;
  for (long p = 0; p < r.points; ++p)
    if (s.reachable(k * r.points + p)) pts.push_back(g.position(p));
  const BoundarySurface bs =
      alphaShapeSurface(pts, gridAlphaRadius({g.axes[0].step, g.axes[1].step, g.axes[2].step}));
  io::PolyDataSet poly;
  poly.points = bs.vertices;
  poly.triangles = bs.triangles;
  poly.field_data = io::fieldData(
      {"position: m"},
      {"surface: boundary of the reachable grid points (" + orientationText(g, k) + ")"});
  const std::string rel = r.gdir + "/" + s.design + "_surface" + suffix(g, k) + ".vtp";
  io::writeVtp(out.path(rel), poly);
  out.add(rel);
  part.jd = {{"orientation", orientationText(g, k)},
             {"file", rel},
             {"alpha_shape_volume_m3", bs.volume_m3},
             {"voxel_volume_m3", voxel * static_cast<double>(pts.size())},
             {"triangles", bs.triangles.size()}};
}

// The largest manipulability any design reaches on the grid (all orientations): the top of the
// one colour scale every design's manipulability figure of the grid shares, so that a colour
// means the same value in each of them.
double sharedManipulabilityMax(const GridRun& r) {
  double mmax = 0;
  for (const PoseSweep& s : r.sweeps)
    for (long i = 0; i < r.g.size(); ++i)
      if (s.reachable(i)) mmax = std::max(mmax, s.manipulability[i]);
  return mmax;
}

// The manipulability figure of design di in orientation k (2-D grids), colour 0..mmax (shared by
// the grid's designs).
std::string manipulabilityFigure(const GridRun& r, std::size_t di, int k, double mmax,
                                 Writer& out) {
  const TaskGrid& g = r.g;
  const PoseSweep& s = r.sweeps[di];
  const long off = static_cast<long>(k) * r.points;
  report::RasterImage m_img =
      report::renderCellMap(r.d[r.plane.a], r.imageRows(), [&](int u, int v) {
        report::Rgb col{230, 230, 230};
        forCell(g, r.plane, u, v, [&](long p) {
          if (s.reachable(off + p)) col = report::viridis(s.manipulability[off + p] / mmax);
        });
        return col;
      });
  report::MapFigure mfig = mapAxes(g, r.plane, s.design + ", " + orientationText(g, k));
  mfig.scale = report::ColourScale{
      report::viridis, 0, mmax,
      "manipulability of the task rows, eq. 5.59 [" + taskManipulabilityUnit(g.task_space) + "]"};
  mfig.legend = {{report::Rgb{230, 230, 230}, "unreachable"}};
  const std::string mrel = writeFigure(
      out, "reach/images/" + g.name + "__" + s.design + suffix(g, k) + "_manipulability", m_img,
      mfig);
  return "![manipulability](" + mrel +
         ")\n\n*Manipulability sqrt(det(J_t J_t^T)) of the task rows (eq. 5.59) at the solution, " +
         s.design + ", " + orientationText(g, k) + "; viridis from 0 (dark) to " +
         report::scientific(mmax) + " " + taskManipulabilityUnit(g.task_space) +
         " (yellow), the same scale for every design of the grid" + ", grey = unreachable.*\n\n";
}

// Pieces no+1..2no of design di: the status (or reachable-fraction) and manipulability figures of
// orientation k.
void renderImages(const GridRun& r, std::size_t di, int k, Writer& out, RenderedPart& part) {
  if (!r.cfg.outputs.images) return;
  const TaskGrid& g = r.g;
  const ImagePlane& plane = r.plane;
  const PoseSweep& s = r.sweeps[di];
  std::string& images_md = part.images_md;
  Stats per_k;  // the orientation's poses in index order, as the summary entry counts them
  for (long p = 0; p < r.points; ++p) {
    const long i = static_cast<long>(k) * r.points + p;
    per_k.add(s, i, g.position(g.pointOf(i)));
  }
  const double mmax = sharedManipulabilityMax(r);
  const long off = static_cast<long>(k) * r.points;
  // A status map whose cells all have one status would be one colour: a sentence says it instead.
  if (plane.projected < 0) {
    long n = 0;
    for (long c : per_k.status) n += c;
    for (int st = 0; st < kReachStatusCount; ++st)
      if (n > 0 && per_k.status[st] == n) {
        images_md += "*" + s.design + ", " + orientationText(g, k) + ": 100 % of the " +
                     std::to_string(n) + " cells " + describe(static_cast<ReachStatus>(st)) +
                     " (no map drawn).*\n\n";
        // (Nothing reachable: the manipulability map would be one colour too.)
        if (mmax > 0 && st == static_cast<int>(ReachStatus::Reachable))
          images_md += manipulabilityFigure(r, di, k, mmax, out);
        return;
      }
  }
  report::RasterImage status_img =
      report::renderCellMap(r.d[plane.a], r.imageRows(), [&](int u, int v) {
        if (plane.projected >= 0) {
          long c = 0, n = 0;
          forCell(g, plane, u, v, [&](long p) {
            c += s.reachable(off + p);
            ++n;
          });
          return report::viridis(n ? double(c) / n : 0.0);
        }
        report::Rgb col;
        forCell(g, plane, u, v, [&](long p) { col = report::categorical(s.status[off + p]); });
        return col;
      });
  report::MapFigure fig = mapAxes(g, plane, s.design + ", " + orientationText(g, k));
  if (plane.projected >= 0)
    fig.scale =
        report::ColourScale{report::viridis, 0, 1,
                            "fraction of the cells along " + std::string(kAxis[plane.projected]) +
                                " that are reachable"};
  else
    fig.legend = statusLegend(per_k.status);
  const std::string rel =
      writeFigure(out, "reach/images/" + g.name + "__" + s.design + suffix(g, k), status_img, fig);
  images_md += "![" + s.design + ", " + orientationText(g, k) + "](" + rel + ")\n\n*" + s.design +
               ", " + orientationText(g, k) + ": " + report::percent(per_k.fraction()) +
               " reachable. " + imageCaptionAxes(g, plane) + ".*\n\n";
  if (plane.projected < 0 && mmax > 0) images_md += manipulabilityFigure(r, di, k, mmax, out);
}

// The comparison images of the pair (a, b), one per orientation.
void renderPair(const GridRun& r, std::size_t a, std::size_t b, Writer& out,
                std::string& pair_imgs) {
  const TaskGrid& g = r.g;
  const std::vector<PoseSweep>& sweeps = r.sweeps;
  for (int k = 0; k < r.no; ++k) {
    const long off = static_cast<long>(k) * r.points;
    // Both, only a, only b, neither; a map of one of them would be one colour: said in words.
    std::array<long, 4> in{};
    for (long p = 0; p < r.points; ++p) {
      const bool ra = sweeps[a].reachable(off + p), rb = sweeps[b].reachable(off + p);
      ++in[ra && rb ? 0 : ra ? 1 : rb ? 2 : 3];
    }
    const std::string names[4] = {"reached by both", "reached only by " + sweeps[a].design,
                                  "reached only by " + sweeps[b].design, "reached by neither"};
    const auto sole = std::find(in.begin(), in.end(), r.points);
    if (r.points > 0 && sole != in.end()) {
      pair_imgs += "*" + sweeps[a].design + " vs " + sweeps[b].design + ", " +
                   orientationText(g, k) + ": 100 % of the " + std::to_string(r.points) +
                   " cells " + names[sole - in.begin()] + " (no map drawn).*\n\n";
      continue;
    }
    report::RasterImage img =
        report::renderCellMap(r.d[r.plane.a], r.imageRows(), [&](int u, int v) {
          report::Rgb col;
          forCell(g, r.plane, u, v, [&](long p) {
            const bool ra = sweeps[a].reachable(off + p), rb = sweeps[b].reachable(off + p);
            col = ra && rb ? report::categorical(0)
                  : ra     ? report::categorical(5)
                  : rb     ? report::categorical(2)
                           : report::categorical(1);
          });
          return col;
        });
    report::MapFigure cfig = mapAxes(
        g, r.plane, sweeps[a].design + " vs " + sweeps[b].design + ", " + orientationText(g, k));
    cfig.legend = {{report::categorical(0), "both"},
                   {report::categorical(5), "only " + sweeps[a].design},
                   {report::categorical(2), "only " + sweeps[b].design},
                   {report::categorical(1), "neither"}};
    const std::string rel = writeFigure(out,
                                        "reach/images/" + g.name + "__" + sweeps[a].design +
                                            "__vs__" + sweeps[b].design + suffix(g, k),
                                        img, cfig);
    pair_imgs += "![" + sweeps[a].design + " vs " + sweeps[b].design + "](" + rel + ")\n\n*" +
                 orientationText(g, k) + ": reached by both (green), only " + sweeps[a].design +
                 " (blue), only " + sweeps[b].design + " (orange), neither (light grey). " +
                 imageCaptionAxes(g, r.plane) + ".*\n\n";
  }
}

// Renders item `it` of the shared loop (a design's piece, or a pair's images), writes its files
// into the study's output folder and returns its part and the files' names as bytes.
std::string renderItem(const GridRun& r, std::size_t it) {
  Writer w(r.ctx.resultsDir());
  RenderedPart part;
  if (it < r.designItems()) {
    const std::size_t di = it / static_cast<std::size_t>(r.pieces);
    const int piece = static_cast<int>(it % static_cast<std::size_t>(r.pieces));
    if (piece == 0)
      renderMain(r, di, w, part);
    else if (piece <= r.no)
      renderSurface(r, di, piece - 1, w, part);
    else
      renderImages(r, di, piece - 1 - r.no, w, part);
  } else {
    const auto [a, b] = r.pairs[r.image_pairs[it - r.designItems()]];
    renderPair(r, a, b, w, part.md);
  }
  return packRenderedPart(part, w);
}

// Each design's files, figures and report lines, and each compared pair's images, rendered by the
// process that owns it (a loop shared among the processes of a distributed run, one piece or pair
// per chunk, study/rendered_part.hpp), which writes the files into the study's output folder
// itself: only their names travel, with the design's summary entry and report lines, and every
// process lists them in design order, so the files and their order are those of a single process.
void renderGrid(GridRun& r) {
  const std::size_t n_items = r.designItems() + (r.pair_images ? r.image_pairs.size() : 0);
  r.parts = renderShared(&r.ctx.units, "files/" + r.g.name, n_items, r.ctx.threads,
                         [&r](std::size_t it) { return renderItem(r, it); });
}

// Joins each design's pieces in order: its summary entry (with the surfaces), report and image
// lines and table rows, and lists the files their processes wrote. Returns the designs' summary
// entries.
ordered_json joinDesignParts(GridRun& r, std::string& md, std::string& images_md,
                             std::vector<std::vector<std::string>>& rows) {
  ordered_json jdesigns = ordered_json::array();
  std::vector<std::string> design_files;
  for (std::size_t di = 0; di < r.nd; ++di) {
    RenderedPart part;
    const std::size_t first = di * static_cast<std::size_t>(r.pieces);
    unpackRenderedPart(r.parts[first], part, design_files);
    ordered_json jsurf = ordered_json::array();
    for (int k = 0; k < r.no; ++k) {
      RenderedPart surface;
      unpackRenderedPart(r.parts[first + 1 + static_cast<std::size_t>(k)], surface, design_files);
      if (!surface.jd.is_null()) jsurf.push_back(std::move(surface.jd));
    }
    if (r.cfg.outputs.surface && r.g.spatialDimension() == 3) part.jd["surface"] = std::move(jsurf);
    for (int k = 0; k < r.no; ++k) {
      RenderedPart figures;
      unpackRenderedPart(r.parts[first + 1 + static_cast<std::size_t>(r.no + k)], figures,
                         design_files);
      part.images_md += figures.images_md;
    }
    jdesigns.push_back(std::move(part.jd));
    md += part.md;
    images_md += part.images_md;
    for (auto& row : part.rows) rows.push_back(std::move(row));
  }
  for (const std::string& f : design_files) r.out.add(f);
  return jdesigns;
}

// The grid's tables: statuses per design and orientation, reachable volumes (3-D grids), and the
// reference statement next to this model's numbers.
void gridTables(const GridRun& r, const ordered_json& jdesigns,
                const std::vector<std::vector<std::string>>& rows, std::string& md) {
  std::vector<std::string> header = {"design",
                                     "orientation",
                                     ">reachable",
                                     ">joint limits",
                                     ">out of reach",
                                     ">repr. singular",
                                     "extent of the reachable poses"};
  if (!usesCardanAngles(r.g.task_space)) header.erase(header.begin() + 5);
  insertCollisionColumns(r.cfg, header, 3);
  md += report::markdownTable(header, rows);
  md += "\n";
  if (r.g.spatialDimension() == 3 && r.cfg.outputs.surface) {
    std::vector<std::vector<std::string>> srows;
    for (const auto& jd : jdesigns)
      for (const auto& sf : jd["surface"])
        srows.push_back({jd["design"].get<std::string>(), sf["orientation"].get<std::string>(),
                         report::fixed(sf["alpha_shape_volume_m3"].get<double>(), 4),
                         report::fixed(sf["voxel_volume_m3"].get<double>(), 4),
                         sf["file"].get<std::string>()});
    md +=
        "Reachable volume (boundary surface: CGAL 3-D alpha shape of the reachable grid points; "
        "the voxel estimate counts one grid cell per reachable point):\n\n" +
        report::markdownTable(
            {"design", "orientation", ">alpha shape [m^3]", ">voxels [m^3]", "surface"}, srows) +
        "\n";
  }
  if (r.g.reference.empty()) return;
  md += "**Reference:** " + r.g.reference + "\n\n**This model:** ";
  for (std::size_t di = 0; di < r.sweeps.size(); ++di) {
    const auto& jd = jdesigns[di];
    md += "`" + r.sweeps[di].design + "` reaches " + report::percent(jd["fraction"].get<double>()) +
          " of the grid's poses";
    Stats all;
    for (long i = 0; i < r.g.size(); ++i) all.add(r.sweeps[di], i, r.g.position(r.g.pointOf(i)));
    md += " (extent " + all.extent.text() + ")" + (di + 1 < r.sweeps.size() ? "; " : ".\n\n");
  }
}

// Designs that reach none of the grid's poses: a warning in the report, in summary.json and on
// stderr (a base placed in the wrong unit, a grid beside the arm).
void warnUnreached(const GridRun& r, const ordered_json& jdesigns, ordered_json& jg,
                   std::string& md) {
  ordered_json none = ordered_json::array();
  for (const auto& jd : jdesigns)
    if (jd["reachable"].get<long>() == 0) none.push_back(jd["design"]);
  if (none.empty()) return;
  std::string names;
  for (const auto& n : none) names += (names.empty() ? "`" : ", `") + n.get<std::string>() + "`";
  const std::string text = names + (none.size() > 1 ? " reach" : " reaches") + " none of the " +
                           std::to_string(r.g.size()) + " poses of grid `" + r.g.name +
                           "`: check the design's base placement and its units against the grid";
  md += "**Warning:** " + text + ".\n\n";
  jg["designs_reaching_nothing"] = none;
  std::fprintf(stderr, "armstudy: warning: %s\n", text.c_str());
}

// The largest reach found on the grid (the farthest reachable pose from the design's base z axis)
// against each design's reference_reach_m: a table in the report and summary.json.
void compareReferenceReach(const GridRun& r, ordered_json& jg, std::string& md) {
  std::vector<std::vector<std::string>> rows;
  ordered_json jr = ordered_json::array();
  for (std::size_t di = 0; di < r.nd; ++di) {
    const StudyDesign& sd = r.study.designs[di];
    if (!(sd.reference_reach_m > 0)) continue;
    const Eigen::Isometry3d T_BW = sd.model.T_WB.inverse();
    double found = -1;
    for (long i = 0; i < r.g.size(); ++i)
      if (r.sweeps[di].reachable(i)) {
        const Eigen::Vector3d p_B = T_BW * r.g.position(r.g.pointOf(i));
        found = std::max(found, std::hypot(p_B.x(), p_B.y()));
      }
    const double ref = sd.reference_reach_m, diff = found - ref;
    double resolution = 0;  // the largest reach is known to within one step of the grid
    for (const AxisRange& a : r.g.axes)
      if (a.count() > 1) resolution = std::max(resolution, a.step);
    rows.push_back({sd.model.name, report::fixed(ref, 3), found < 0 ? "-" : report::fixed(found, 3),
                    found < 0
                        ? "-"
                        : (diff >= 0 ? "+" : "") + report::fixed(diff * 1e3, 0) + " mm (" +
                              (diff >= 0 ? "+" : "") + report::fixed(100 * diff / ref, 1) + " %)"});
    jr.push_back(
        {{"design", sd.model.name},
         {"reference_reach_m", ref},
         {"largest_reach_found_m", found < 0 ? ordered_json(nullptr) : ordered_json(found)},
         {"difference_m", found < 0 ? ordered_json(nullptr) : ordered_json(diff)},
         {"resolution_m", resolution}});
  }
  if (rows.empty()) return;
  md +=
      "Largest reach found (the farthest reachable pose of this grid from the design's base z "
      "axis) "
      "against the design's `reference_reach_m`:\n\n" +
      report::markdownTable({"design", ">reference [m]", ">largest found [m]", ">difference"},
                            rows) +
      "\n";
  jg["reference_reach"] = jr;
}

// comparison.vti: which designs reach each pose (bit mask and count per orientation).
void writeComparisonVti(const GridRun& r, ordered_json& jcmp) {
  const TaskGrid& g = r.g;
  const std::vector<PoseSweep>& sweeps = r.sweeps;
  io::ImageGrid img;
  img.dims = r.d;
  img.origin = {g.axes[0].from, g.axes[1].from, g.axes[2].from};
  img.spacing = {g.axes[0].step, g.axes[1].step, g.axes[2].step};
  for (int k = 0; k < r.no; ++k) {
    img.point_arrays.push_back(arrayOf("reached_by_mask" + suffix(g, k), io::ArrayType::Int32, &g,
                                       r.points, k, 1, [&](long i, int) {
                                         long m = 0;
                                         for (std::size_t di = 0; di < sweeps.size(); ++di)
                                           if (sweeps[di].reachable(i)) m |= 1L << di;
                                         return double(m);
                                       }));
    img.point_arrays.push_back(arrayOf("reached_by_count" + suffix(g, k), io::ArrayType::UInt8, &g,
                                       r.points, k, 1, [&](long i, int) {
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
  const std::string rel = r.gdir + "/comparison.vti";
  io::writeVti(r.out.path(rel), img);
  r.out.add(rel);
  jcmp["vti"] = rel;
  ordered_json bits = ordered_json::array();
  for (const auto& s : sweeps) bits.push_back(s.design);
  jcmp["mask_bits"] = bits;
}

// Best design / variant per base design (e.g. the best base placement): summary entries and rows.
ordered_json bestVariants(const GridRun& r, const ordered_json& jdesigns,
                          std::vector<std::vector<std::string>>& brow) {
  ordered_json best = ordered_json::array();
  std::vector<std::string> bases;
  for (const auto& sd : r.study.designs)
    if (std::find(bases.begin(), bases.end(), sd.base_name) == bases.end())
      bases.push_back(sd.base_name);
  for (const std::string& base : bases) {
    int count = 0, best_i = -1;
    double best_f = -1;
    bool base_sweep = false;
    for (std::size_t di = 0; di < r.sweeps.size(); ++di) {
      if (r.study.designs[di].base_name != base) continue;
      ++count;
      for (const auto& [k, v] : r.study.designs[di].overrides)
        base_sweep |= k.rfind("base.", 0) == 0;
      const double f = jdesigns[di]["fraction"].get<double>();
      if (f > best_f) {
        best_f = f;
        best_i = static_cast<int>(di);
      }
    }
    if (count < 2) continue;
    best.push_back({{"base_design", base},
                    {"best", r.sweeps[best_i].design},
                    {"fraction", best_f},
                    {"varies_base_placement", base_sweep}});
    brow.push_back(
        {base, r.sweeps[best_i].design, report::percent(best_f), base_sweep ? "yes" : "no"});
  }
  return best;
}

// The comparison of designs on this grid: comparison.vti, per pair which poses each reaches and
// the pair's images, dexterity where both reach, the best variant per base design.
ordered_json compareDesigns(GridRun& r, const ordered_json& jdesigns, std::string& md) {
  ordered_json jcmp;
  if (r.cfg.outputs.vtk && r.sweeps.size() <= 30) writeComparisonVti(r, jcmp);
  md += "### Comparison of designs on `" + r.g.name + "`\n\n";
  std::vector<std::vector<std::string>> crow;
  ordered_json jpairs = ordered_json::array();
  std::string pair_imgs;
  std::vector<std::string> pair_files;
  for (std::size_t p = 0; p < r.pairs.size(); ++p) {
    const auto [a, b] = r.pairs[p];
    long n_a = 0, n_b = 0, both = 0, neither = 0;
    for (long i = 0; i < r.g.size(); ++i) {
      const bool ra = r.sweeps[a].reachable(i), rb = r.sweeps[b].reachable(i);
      n_a += ra && !rb;
      n_b += rb && !ra;
      both += ra && rb;
      neither += !ra && !rb;
    }
    jpairs.push_back({{"a", r.sweeps[a].design},
                      {"b", r.sweeps[b].design},
                      {"a_only", n_a},
                      {"b_only", n_b},
                      {"both", both},
                      {"neither", neither}});
    const double N = static_cast<double>(r.g.size());
    crow.push_back({r.sweeps[a].design, r.sweeps[b].design, report::percent(n_a / N),
                    report::percent(n_b / N), report::percent(both / N),
                    report::percent(neither / N)});
    const auto img = std::find(r.image_pairs.begin(), r.image_pairs.end(), p);
    if (r.pair_images && img != r.image_pairs.end()) {  // the images the render loop made
      RenderedPart part;
      unpackRenderedPart(r.parts[r.designItems() + (img - r.image_pairs.begin())], part,
                         pair_files);
      pair_imgs += part.md;
    }
  }
  for (const std::string& f : pair_files) r.out.add(f);
  jcmp["pairs"] = jpairs;
  std::vector<std::vector<std::string>> brow;
  jcmp["best_variant"] = bestVariants(r, jdesigns, brow);
  std::string dexterity_md;
  jcmp["dexterity"] =
      dexterityComparison(r.models, r.g, r.sweeps, r.pairs, r.ctx.threads, dexterity_md);
  md += "Per pose, which designs reach it (all orientations together):\n\n" +
        report::markdownTable({"A", "B", ">A only", ">B only", ">both", ">neither"}, crow) + "\n" +
        dexterity_md;
  if (!brow.empty())
    md +=
        "Best variant per base design (the most reachable poses; with base.* overrides this is the "
        "best base placement):\n\n" +
        report::markdownTable(
            {"base design", "best variant", ">reachable", "base placement varied"}, brow) +
        "\n";
  md += pair_imgs;
  return jcmp;
}

}  // namespace

// The view's status of a grid position over its orientations: reachable in one of them, else
// reachable only in contact with an obstacle, else only in self-collision, else the first
// orientation's status (not drawn).
int positionStatus(const GridRun& r, const PoseSweep& s, long p) {
  const int order[] = {static_cast<int>(ReachStatus::Reachable),
                       static_cast<int>(ReachStatus::ObstacleCollision),
                       static_cast<int>(ReachStatus::SelfCollision)};
  for (const int want : order)
    for (int k = 0; k < r.no; ++k)
      if (s.status[static_cast<long>(k) * r.points + p] == want) return want;
  return s.status[p];
}

// The grid's maps for the study's 3-D view: per design, the grid positions with their status and
// largest manipulability over the orientations, and the arm at the reachable pose of the largest
// manipulability.
void addViewClouds(const GridRun& r) {
  double step = INFINITY;
  for (int a = 0; a < 3; ++a)
    if (r.d[a] > 1) step = std::min(step, r.g.axes[a].step);
  for (std::size_t di = 0; di < r.nd; ++di) {
    const PoseSweep& s = r.sweeps[di];
    report::ViewCloud c;
    c.name = "grid " + r.g.name + ": " + s.design;
    // Maps share a colour scale only with maps of the same task rows.
    const int position_rows = int(r.g.task_space.selected[0]) + int(r.g.task_space.selected[1]) +
                              int(r.g.task_space.selected[2]);
    c.value_unit = "m^" + std::to_string(position_rows);
    const int rows = r.g.task_space.dim();
    c.value_quantity = rows == position_rows
                           ? "manipulability (" + std::to_string(rows) + " position rows)"
                           : "manipulability (" + std::to_string(rows) + " task rows, " +
                                 std::to_string(rows - position_rows) + " angular weighed by 1 m)";
    c.point_size_m = std::isfinite(step) ? step : 0.02;
    c.status_names = statusNamesShownOnMaps();
    long best = -1;
    for (long p = 0; p < r.points; ++p) {
      const Eigen::Vector3d x = r.g.position(p);
      c.p_W.push_back({x.x(), x.y(), x.z()});
      c.status.push_back(positionStatus(r, s, p));
      double v = NAN;
      for (int k = 0; k < r.no; ++k) {
        const long i = static_cast<long>(k) * r.points + p;
        if (!s.reachable(i)) continue;
        v = std::isnan(v) ? s.manipulability[i] : std::max(v, s.manipulability[i]);
        if (best < 0 || s.manipulability[i] > s.manipulability[best]) best = i;
      }
      c.value.push_back(v);
    }
    if (best >= 0) {
      const Eigen::Map<const Eigen::VectorXd> q(s.q.data() + best * s.dof, s.dof);
      for (const Eigen::Vector3d& x : scene::skeletonPoints(*r.models[di], q))
        c.arm_W.push_back({x.x(), x.y(), x.z()});
      c.arm_caption = "arm: " + s.design +
                      " at the grid's reachable pose of the largest "
                      "manipulability (" +
                      report::scientific(s.manipulability[best]) + " " +
                      taskManipulabilityUnit(r.g.task_space) + ").";
    } else {
      c.arm_caption = "arm: " + s.design + " reaches no pose of the grid.";
    }
    r.sum.view.push_back(std::move(c));
  }
}

ordered_json reportGrid(const StageContext& ctx, const ReachConfig& cfg, const TaskGrid& g,
                        Progress& progress, StageResult& sum, Writer& out, std::string& md) {
  GridRun r(ctx, cfg, g, sum, out);
  ordered_json jg = gridHeader(g, md);
  solveGrid(r, progress);
  auditGrid(r);
  auto t0 = Clock::now();
  renderGrid(r);
  // A rank other than 0 is done with the grid here: what follows (the designs' summary entries,
  // report lines and files, the comparison) only rank 0 writes, and nothing in it is shared. The
  // other ranks go on to the next grid's units while rank 0 writes (docs/distributed.md "Files").
  if (!ctx.writes_results) return jg;
  std::vector<std::vector<std::string>> rows;
  std::string images_md;
  const ordered_json jdesigns = joinDesignParts(r, md, images_md, rows);
  sum.timings.push_back({r.gdir + "/files", secondsSince(t0)});
  jg["designs"] = jdesigns;
  warnUnreached(r, jdesigns, jg, md);
  gridTables(r, jdesigns, rows, md);
  compareReferenceReach(r, jg, md);
  md += images_md;
  if (r.sweeps.size() >= 2) jg["comparison"] = compareDesigns(r, jdesigns, md);
  addViewClouds(r);
  return jg;
}

}  // namespace armstudy
