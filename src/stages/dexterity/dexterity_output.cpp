#include "stages/dexterity/dexterity_output.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "common/angles.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"
#include "io/files.hpp"
#include "metrics/measure_declarations.hpp"
#include "report/image.hpp"
#include "report/plot.hpp"
#include "stages/dexterity/dexterity_status.hpp"
#include "stages/dexterity/dexterity_summary.hpp"
#include "study/rendered_part.hpp"
#include "study/scene.hpp"
#include "study/writer.hpp"

namespace armstudy::dexterity {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Unreachable cells in the heatmap images.
constexpr report::Rgb kUnreachableGrey{160, 160, 160};

}  // namespace

const MeasureFields& MapFields::of(const std::string& name) const {
  const auto decl = metrics::measureDeclarations();
  for (std::size_t k = 0; k < decl.size(); ++k)
    if (name == decl[k].name) return measures.at(k);
  ARMSTUDY_CHECK(false, "MapFields::of: no declared measure " + name);
  return measures.front();
}

MapFields mapFields(const DexterityMap& map) {
  MapFields f;
  const std::size_t N = map.cells.size();
  const auto decl = metrics::measureDeclarations();
  f.measures.resize(decl.size());
  for (auto* v : {&f.reachable, &f.H_plain, &f.H_opt, &f.nullspace_iterations}) v->assign(N, kNaN);
  for (std::size_t k = 0; k < decl.size(); ++k)
    if (decl[k].on_maps) f.measures[k].plain.assign(N, kNaN), f.measures[k].opt.assign(N, kNaN);
  std::vector<unsigned char> valid(N, 0);
  for (std::size_t i = 0; i < N; ++i) {
    const CellResult& c = map.cells[i];
    f.reachable[i] = c.reachable ? 1.0 : 0.0;
    if (!c.reachable) continue;
    valid[i] = 1;
    for (std::size_t k = 0; k < decl.size(); ++k)
      if (decl[k].on_maps) {
        f.measures[k].plain[i] = c.plain.*decl[k].value;
        f.measures[k].opt[i] = c.opt.*decl[k].value;
      }
    f.H_plain[i] = c.H_plain;
    f.H_opt[i] = c.H_opt;
    f.nullspace_iterations[i] = c.nullspace_iterations;
  }
  // Normalisation as thesis Fig. 3.6: 1 = the best value found in this map (either
  // configuration), so plain and optimised maps share one scale.
  std::vector<unsigned char> vboth(valid);
  vboth.insert(vboth.end(), valid.begin(), valid.end());
  for (std::size_t k = 0; k < decl.size(); ++k) {
    if (!decl[k].on_maps || !decl[k].normalised) continue;
    MeasureFields& m = f.measures[k];
    std::vector<double> both(m.plain);
    both.insert(both.end(), m.opt.begin(), m.opt.end());
    m.best = metrics::normaliseToBest(both, vboth, kNaN);
    m.plain_norm.assign(both.begin(), both.begin() + N);
    m.opt_norm.assign(both.begin() + N, both.end());
  }
  return f;
}

FieldStats fieldStats(const DexterityMap& map, const std::vector<double>& field) {
  FieldStats s;
  const int G = map.grid.gamma_rad.count;
  for (std::size_t i = 0; i < field.size(); ++i) {
    const double v = field[i];
    if (std::isnan(v)) continue;
    const double g = map.grid.gamma_rad.value(static_cast<int>(i) % G);
    const double z = map.grid.z_m.value(static_cast<int>(i) / G);
    if (!s.any || v < s.min) s.min = v, s.gamma_at_min = g, s.z_at_min = z;
    if (!s.any || v > s.max) s.max = v, s.gamma_at_max = g, s.z_at_max = z;
    s.any = true;
  }
  return s;
}

namespace {

// Heatmap image of a (gamma, z) field: gamma to the right, z upwards, viridis over [0, hi], grey
// where the cell is unreachable (NaN), with the colour bar below.
report::RasterImage heatmapCells(const DexterityMap& map, const std::vector<double>& v, double hi) {
  const int G = map.grid.gamma_rad.count, Z = map.grid.z_m.count;
  const double span = hi > 0 ? hi : 1.0;
  return report::renderCellMap(G, Z, [&](int i, int j) {
    const double x = v[static_cast<std::size_t>(map.grid.index(i, j))];
    return std::isnan(x) ? kUnreachableGrey : report::viridis(x / span);
  });
}

// The same map as a figure: gamma [deg] to the right, z [m] upwards, colour bar 0..hi.
report::Drawing heatmapFigure(const DexterityMap& map, const report::RasterImage& cells, double hi,
                              const std::string& title, const std::string& scale_label) {
  const AxisRange& ga = map.grid.gamma_rad;
  const AxisRange& za = map.grid.z_m;
  report::MapFigure f;
  f.title = title;
  f.x = report::cellAxis("gamma [deg]", ga.min * kRadToDeg, ga.max * kRadToDeg,
                         ga.step() * kRadToDeg);
  f.y = report::cellAxis("z [m]", za.min, za.max, za.step());
  f.scale = report::ColourScale{report::viridis, 0, hi > 0 ? hi : 1.0, scale_label};
  f.legend = {{kUnreachableGrey, "not reachable"}};
  return report::mapFigure(cells, f, report::Format::svg_and_png);
}

nlohmann::ordered_json statsJson(const FieldStats& s) {
  if (!s.any) return nullptr;
  return {{"min", s.min}, {"min_at_gamma_rad", s.gamma_at_min}, {"min_at_z_m", s.z_at_min},
          {"max", s.max}, {"max_at_gamma_rad", s.gamma_at_max}, {"max_at_z_m", s.z_at_max}};
}

// One design's map, in work units of whole rows (see runDexterityStage): units saved by an
// interrupted run are loaded, the others computed; both are joined by cell index (so the order
// units finished in does not matter), then the search across rows runs on the whole map.
DexterityMap unitMap(const StageContext& ctx, const Model& m, const DexterityOptions& options,
                     long& units_resumed) {
  const long per =
      ctx.options.unit_items > 0 ? ctx.options.unit_items : defaults::kDexterityUnitCells;
  const std::vector<ItemRange> ranges = splitRange(
      options.grid.z_m.count, std::max(1L, per / std::max(1, options.grid.gamma_rad.count)));
  DexterityMap loaded;
  loaded.dof = m.dof();
  loaded.grid = options.grid;
  loaded.cells.resize(options.grid.size());
  std::vector<ItemRange> done;
  std::optional<DexterityMap> computed;
  auto load = [&](std::size_t k, const std::string& bytes) {
    ItemRange got;
    if (!(deserializeRows(bytes, loaded, got) && got.begin == ranges[k].begin &&
          got.end == ranges[k].end))
      return false;
    done.push_back(ranges[k]);
    return true;
  };
  auto compute = [&](const std::vector<std::size_t>&, const std::vector<ItemRange>& todo,
                     const RangeDone& unit_done) {
    // A later call replaces an earlier one's units (UnitBatch).
    computed = computeDexterityRows(m, options, todo, ctx.threads,
                                    [&](std::size_t j, const DexterityMap& partial) {
                                      unit_done(j, serializeRows(partial, todo[j]));
                                    });
  };
  units_resumed += ctx.units.run(
      rangeUnitBatch(unitIds("dexterity/" + m.name + "/rows_", ranges), ranges, load, compute));
  DexterityMap map =
      computed ? std::move(*computed) : computeDexterityRows(m, options, {}, ctx.threads);
  const int G = options.grid.gamma_rad.count;
  for (const ItemRange& u : done)
    std::move(loaded.cells.begin() + u.begin * G, loaded.cells.begin() + u.end * G,
              map.cells.begin() + u.begin * G);
  // The search across rows needs every row: it runs once all units are in (deterministic, so a
  // resumed run ends in the same map).
  searchDexterityMap(m, options, map, ctx.threads, &ctx.units);
  return map;
}

// The means over a map's reachable cells: its reachable share and mean optimised and plain
// manipulability (0 when no cell is reachable).
struct MapMeans {
  double reachable_fraction = 0, manipulability_optimised = 0, manipulability_plain = 0;
};
MapMeans mapMeans(const DexterityMap& map) {
  double sum_opt = 0, sum_plain = 0;
  for (const CellResult& c : map.cells) {
    if (!c.reachable) continue;
    sum_opt += c.opt.manipulability;
    sum_plain += c.plain.manipulability;
  }
  const int r = map.reachable();
  return {map.cells.empty() ? 0.0 : double(r) / map.cells.size(), r ? sum_opt / r : 0.0,
          r ? sum_plain / r : 0.0};
}

// Summary metrics of one map for regression checks.
void addMapMetrics(StudyMetrics& dm, const DexterityMap& map) {
  const std::string prefix = "dexterity/" + map.design;
  std::vector<std::uint8_t> flags(map.cells.size());
  for (std::size_t i = 0; i < map.cells.size(); ++i) flags[i] = map.cells[i].reachable;
  const MapMeans m = mapMeans(map);
  dm.scalars[prefix + "/reachable_fraction"] = m.reachable_fraction;
  dm.scalars[prefix + "/manipulability_mean_optimised"] = m.manipulability_optimised;
  dm.scalars[prefix + "/manipulability_mean_plain"] = m.manipulability_plain;
  dm.flags[prefix + "/reachable"] = flags;
}

const char* const kSub = "dexterity";  // the stage's output folder

// The tops of the colour scales the stage's designs share, per declared measure with a figure:
// its largest optimised value over every design's map (and plain value, for a normalised measure,
// whose plain and optimised maps share one scale), and the tops passed in from outside the run
// (RunOptions::shared_scale_tops, keyed by sharedScaleKey), so that a colour means the same value
// in each design's figure.
struct SharedScales {
  std::vector<double> top;  // per metrics::kMeasures entry
};
std::string sharedScaleKey(const metrics::MeasureDeclaration& d) {
  return std::string("dexterity/") + d.name;
}
SharedScales sharedScales(const std::vector<MapFields>& fields,
                          const std::map<std::string, double>& outside) {
  const auto decl = metrics::measureDeclarations();
  SharedScales sc;
  sc.top.assign(decl.size(), 0.0);
  for (std::size_t k = 0; k < decl.size(); ++k)
    if (const auto it = outside.find(sharedScaleKey(decl[k])); it != outside.end())
      sc.top[k] = it->second;
  auto top = [](double& hi, const std::vector<double>& v) {
    for (double x : v)
      if (!std::isnan(x)) hi = std::max(hi, x);
  };
  for (const MapFields& f : fields)
    for (std::size_t k = 0; k < decl.size(); ++k) {
      if (!decl[k].on_maps || !decl[k].figure_label) continue;
      top(sc.top[k], f.measures[k].opt);
      if (decl[k].normalised) top(sc.top[k], f.measures[k].plain);
    }
  return sc;
}

// Writes the heatmap figures (.svg and the same as .png) of each declared measure with a figure
// (normalised, plain and optimised, for a normalised measure; the optimised value on the scale the
// designs share) and reachability; returns the .svg name per image key.
std::map<std::string, std::string> writeHeatmaps(const DexterityMap& map, const MapFields& f,
                                                 const SharedScales& sc,
                                                 metrics::MeasureSpace space, Writer& out) {
  struct Img {
    std::string key;
    const std::vector<double>* v;
    double hi;
    std::string label;
  };
  std::vector<Img> imgs;
  const auto decl = metrics::measureDeclarations();
  for (std::size_t k = 0; k < decl.size(); ++k) {
    const metrics::MeasureDeclaration& d = decl[k];
    if (!d.on_maps || !d.figure_label) continue;
    const MeasureFields& m = f.measures[k];
    const std::string name = d.name, label = d.figure_label;
    if (d.normalised) {
      imgs.push_back({name + "_optimised_normalised", &m.opt_norm, 1.0,
                      "normalised " + label + ", optimised [1]"});
      imgs.push_back(
          {name + "_plain_normalised", &m.plain_norm, 1.0, "normalised " + label + ", plain [1]"});
    }
    imgs.push_back({name + "_optimised", &m.opt, sc.top[k],
                    label + ", optimised [" + metrics::figureUnitIn(d, space) + "]"});
  }
  imgs.push_back({"reachable", &f.reachable, 1.0, "reachable [1 = yes, 0 = no]"});
  std::map<std::string, std::string> png;  // what the report shows: the .svg figures
  long reachable = 0;
  for (double r : f.reachable) reachable += r > 0;
  // No cell reached: every value map would be all grey; designMarkdown says so instead.
  if (reachable == 0) return png;
  for (const Img& im : imgs) {
    // A reachable map of one value (every cell reachable, or none) would be one colour: the
    // report's status cell says it in words instead.
    if (im.v == &f.reachable &&
        (reachable == 0 || reachable == static_cast<long>(f.reachable.size())))
      continue;
    // <design>_<key>.svg: the figure with axes and colour bar; .png: the same figure.
    const std::string name = map.design + "_" + im.key;
    const report::RasterImage cells = heatmapCells(map, *im.v, im.hi);
    const report::Drawing fig = heatmapFigure(map, cells, im.hi, map.design, im.label);
    out.text(std::string(kSub) + "/" + name + ".svg", fig.svg);
    out.text(std::string(kSub) + "/" + name + ".png", fig.png);
    png[im.key] = name + ".svg";
  }
  return png;
}

// The design's entry of summary.json, without the audit.
nlohmann::ordered_json designJson(const Model& m, const DexterityOptions& options,
                                  const DexterityMap& map, const MapFields& f,
                                  const MapSummary& s) {
  nlohmann::ordered_json d;
  d["design"] = m.name;
  d["dof"] = m.dof();
  d["cells"] = map.cells.size();
  d["reachable"] = s.R;
  d["reachable_gamma_negative"] = s.reach_neg;
  d["reachable_gamma_non_negative"] = s.reach_pos;
  const auto orNull = [&](double v) {
    return s.R ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
  };
  d["best_manipulability"] = orNull(f.manipulability().best);
  d["manipulability_optimised_normalised"] = statsJson(s.mo);
  d["manipulability_plain_normalised"] = statsJson(s.mp);
  d["transmission_optimised"] = statsJson(s.beta_s);
  d["transmission_plain"] = statsJson(s.bp);
  d["mean_normalised_plain"] = orNull(s.mean_p);
  d["mean_normalised_optimised"] = orNull(s.mean_o);
  if (s.valley_row >= 0 && map.grid.z_m.count >= 3)
    d["valley"] = {{"z_m", map.grid.z_m.value(s.valley_row)},
                   {"row_mean_normalised", s.valley_norm},
                   {"row_mean", s.valley_abs},
                   {"at_edge", s.valley_row == 0 || s.valley_row == map.grid.z_m.count - 1}};
  if (s.R == 0) d["warnings"] = {"reaches none of the stem cells"};
  const MapSearchSummary& se = map.search;
  d["search"] = {{"seeding_cells", se.seeding_cells},
                 {"seed_starts", options.seed_starts},
                 {"multistart_tries", se.multistart_tries},
                 {"multistart_improved", se.multistart_improved},
                 {"propagation_rounds", se.rounds},
                 {"neighbour_tries", se.neighbour_tries},
                 {"neighbour_improved", se.neighbour_improved},
                 {"collision_cells", se.collision_cells},
                 {"collision_tries", se.collision_tries},
                 {"collision_freed", se.collision_freed},
                 {"converged", se.converged}};
  return d;
}

// A design's part of the stage that every process computes alike: its summary numbers, its
// summary entry without the audit, the row sweep's report section and the audit.
struct DesignWork {
  MapSummary s;
  StatusCounts counts;
  nlohmann::ordered_json d;
  std::vector<std::string> comparison_row;
  report::Document row_sweep;
  std::vector<RowHalves> row;  // the row sweep's halves (empty without a row)
  std::optional<DexterityAudit> audit;
};

DesignWork designWork(const StageContext& ctx, const DexterityOptions& options, const Model& m,
                      const DexterityMap& map, const MapFields& f) {
  DesignWork w;
  w.s = summarise(map, f, options.grid);
  w.counts = statusCounts(map);
  w.comparison_row = comparisonRow(m, map, f, w.s, manipulabilityUnit(options.measure_space));
  w.d = designJson(m, options, map, f, w.s);
  addStatusJson(map, w.counts, w.d);
  w.row_sweep = rowSweep(m, options, map, ctx.threads, w.d, w.row);
  if (options.audit_cells > 0)
    w.audit = auditDexterityMap(m, options, map, ctx.threads, &ctx.units);
  return w;
}

DesignAnswerFacts answerFacts(const DexterityOptions& options, const DexterityMap& map,
                              const DesignWork& w) {
  const MapMeans m = mapMeans(map);
  return {m.manipulability_optimised, m.reachable_fraction, valleyHeight(options.grid, w.s), w.row};
}

// Renders a design's files (VTK, heat maps, status map, audit cells) into the study's output
// folder and returns its report section and summary entry with the files' names, packed.
std::string renderDesign(const StageContext& ctx, const DexterityOptions& options, const Model& m,
                         const DexterityMap& map, const MapFields& f, const SharedScales& scales,
                         const DesignWork& w) {
  Writer out(ctx.resultsDir());
  const std::string dir = (std::filesystem::path(ctx.resultsDir()) / kSub).string();
  for (const std::string& name :
       writeMapVtk(map, f, m, options.measure_space, options.ellipsoids, dir))
    out.add(std::string(kSub) + "/" + name);
  std::map<std::string, std::string> png =
      writeHeatmaps(map, f, scales, options.measure_space, out);
  png["status"] = writeStatusMap(map, kSub, out);
  RenderedPart part;
  part.jd = w.d;
  part.doc = designSection(m, options, map, f, w.s, png);
  part.doc.append(statusSection(map, w.counts)).append(w.row_sweep);
  if (w.audit) part.doc.append(writeAudit(m, options, *w.audit, kSub, out, part.jd));
  return packRenderedPart(part, out);
}

}  // namespace

// A design's stem map for the study's 3-D view: the cells' TCP positions on the cylinder around
// the stem with their status and optimised manipulability, and the arm at the cell of the largest.
report::ViewCloud viewCloud(const Model& m, const DexterityMap& map, const MapFields& f,
                            const std::string& unit) {
  report::ViewCloud c;
  c.name = "stem map: " + map.design;
  c.value_unit = unit;
  c.value_quantity = unit == "m^3" ? "manipulability (3 position rows)"
                                   : "manipulability (position and orientation rows)";
  const double arc = map.grid.radius_m * map.grid.gamma_rad.step(), dz = map.grid.z_m.step();
  c.point_size_m = std::max(0.005, std::min(arc > 0 ? arc : dz, dz > 0 ? dz : arc));
  c.status_names = statusNamesShownOnMaps();
  int best = -1;
  for (int j = 0; j < map.grid.z_m.count; ++j)
    for (int i = 0; i < map.grid.gamma_rad.count; ++i) {
      const int idx = map.grid.index(i, j);
      const Eigen::Vector3d p = map.grid.cell(i, j).target.p_WT;
      c.p_W.push_back({p.x(), p.y(), p.z()});
      c.status.push_back(static_cast<int>(map.cells[idx].status));
      c.value.push_back(f.manipulability().opt[idx]);
      if (!std::isnan(f.manipulability().opt[idx]) &&
          (best < 0 || f.manipulability().opt[idx] > f.manipulability().opt[best]))
        best = idx;
    }
  if (best >= 0) {
    const CellResult& cell = map.cells[best];
    for (const Eigen::Vector3d& p :
         scene::skeletonPoints(m, cell.optimised ? cell.q_opt : cell.q_plain))
      c.arm_W.push_back({p.x(), p.y(), p.z()});
    c.arm_caption = "arm: " + map.design +
                    " at the stem map's cell of the largest optimised manipulability (" +
                    formatFixedOr(f.manipulability().opt[best], 4, "-") + ").";
  } else {
    c.arm_caption = "arm: " + map.design + " reaches no cell of the stem map.";
  }
  return c;
}

namespace {

// Progressive maps (RunOptions::preview_stride = k): each design's map on every k-th gamma and z
// value, its chained rows alone (no map search), drawn as the first normalised measure's figure to
// dexterity/preview/<design>.svg and .png by the process that owns the design, and announced
// through RunOptions::on_preview. Computed apart from the full map, which does not depend on it.
// Returns the files written, relative to the output folder.
std::vector<std::string> writePreviews(const StageContext& ctx, const DexterityOptions& options) {
  const int k = ctx.options.preview_stride;
  DexterityOptions coarse = options;
  coarse.grid.gamma_rad = options.grid.gamma_rad.every(k);
  coarse.grid.z_m = options.grid.z_m.every(k);
  coarse.seed_starts = coarse.propagation_rounds = coarse.collision_starts = 0;
  const auto decl = metrics::measureDeclarations();
  const auto shown = std::find_if(decl.begin(), decl.end(), [](const auto& d) {
    return d.on_maps && d.normalised && d.figure_label;
  });
  ARMSTUDY_CHECK(shown != decl.end(), "a stem map preview needs a normalised measure");
  const std::string label = std::string("normalised ") + shown->figure_label + ", optimised [1]";
  const std::string title_end =
      " (preview: 1 in " + std::to_string(k) + " cells along gamma and z, before the map search)";
  const std::vector<std::string> parts =
      renderShared(&ctx.units, std::string("preview/") + kSub, ctx.study.designs.size(),
                   ctx.threads, [&](std::size_t di) {
                     const DexterityMap map = computeDexterityRows(
                         ctx.study.designs[di].model, coarse, {{0, coarse.grid.z_m.count}}, 1);
                     const MapFields f = mapFields(map);
                     const report::Drawing fig = heatmapFigure(
                         map, heatmapCells(map, f.measures[shown - decl.begin()].opt_norm, 1.0),
                         1.0, map.design + title_end, label);
                     Writer out(ctx.resultsDir());
                     const std::string name = std::string(kSub) + "/preview/" + map.design;
                     out.text(name + ".svg", fig.svg);
                     out.text(name + ".png", fig.png);
                     if (ctx.options.on_preview) ctx.options.on_preview(out.path(name + ".png"));
                     return packRenderedPart(RenderedPart{}, out);
                   });
  std::vector<std::string> files;
  for (const std::string& bytes : parts) {
    RenderedPart part;
    unpackRenderedPart(bytes, part, files);
  }
  return files;
}

}  // namespace

// Computes each design's map through the work units and writes its files, report section and
// summary entry, then the comparison table, summary.json and report.md.
StageResult runDexterityStage(const StageContext& all_ctx, const DexterityOptions& options,
                              std::vector<DexterityMap>* maps) {
  // The designs this stage evaluates ([dexterity] designs), in study order, with their tool axes.
  const Study selected = options.designs.select(all_ctx.study);
  const StageContext ctx = all_ctx.forStudy(selected);
  const auto t0 = std::chrono::steady_clock::now();
  StageResult sum;
  const std::string sub = kSub;
  Writer out(ctx.output_dir);
  nlohmann::ordered_json js = settingsJson(options);
  report::Document doc = reportIntro(options);
  if (ctx.options.preview_stride > 0) sum.previews = writePreviews(ctx, options);
  // Every design's map first: the figures share colour scales over all of them.
  std::vector<DexterityMap> design_maps;
  std::vector<MapFields> fields;
  for (const StudyDesign& sd : ctx.study.designs) {
    design_maps.push_back(unitMap(ctx, sd.model, options, sum.units_resumed));
    addMapMetrics(sum.metrics, design_maps.back());
    sum.timings.push_back(
        {"dexterity/" + design_maps.back().design + "/wall", design_maps.back().seconds});
    fields.push_back(mapFields(design_maps.back()));
  }
  const SharedScales own = sharedScales(fields, {});
  const auto decl = metrics::measureDeclarations();
  for (std::size_t k = 0; k < decl.size(); ++k)
    if (decl[k].on_maps && decl[k].figure_label)
      sum.scale_tops[sharedScaleKey(decl[k])] = own.top[k];
  const SharedScales scales = sharedScales(fields, ctx.options.shared_scale_tops);
  // The 3-D view: the stem (and the row's plants, when collisions are checked) with each map.
  StemRow stem;
  stem.stem = true;
  sum.view_solids = report::viewSolids(rowObstacles(options.grid, stem));
  const std::vector<report::ViewSolid> plants = report::viewSolids(options.collision.obstacles);
  sum.view_solids.insert(sum.view_solids.end(), plants.begin(), plants.end());
  for (std::size_t di = 0; di < design_maps.size(); ++di)
    sum.view.push_back(viewCloud(ctx.study.designs[di].model, design_maps[di], fields[di],
                                 manipulabilityUnit(options.measure_space)));
  // What every process computes alike, in design order (the audits are loops shared among them).
  std::vector<DesignWork> work;
  for (std::size_t di = 0; di < design_maps.size(); ++di) {
    work.push_back(
        designWork(ctx, options, ctx.study.designs[di].model, design_maps[di], fields[di]));
    const DexterityMap& dm = design_maps[di];
    addDescentCounts("dexterity/" + dm.design, dm,
                     work.back().audit ? &*work.back().audit : nullptr,
                     dm.seconds - dm.search.seconds, sum.counts);
  }
  // Each design's files, rendered by the process that owns it (study/rendered_part.hpp).
  const std::vector<std::string> parts =
      renderShared(&ctx.units, std::string("files/") + kSub, design_maps.size(), ctx.threads,
                   [&](std::size_t di) {
                     return renderDesign(ctx, options, ctx.study.designs[di].model, design_maps[di],
                                         fields[di], scales, work[di]);
                   });
  std::vector<DesignAnswerFacts> facts;
  for (std::size_t di = 0; di < work.size(); ++di)
    facts.push_back(answerFacts(options, design_maps[di], work[di]));
  std::vector<std::string> files;
  for (std::size_t di = 0; di < design_maps.size(); ++di) {
    RenderedPart part;
    unpackRenderedPart(parts[di], part, files);
    doc.append(part.doc);
    js["designs"].push_back(std::move(part.jd));
    if (maps) maps->push_back(std::move(design_maps[di]));
  }
  for (const std::string& f : files) out.add(f);
  dexterityAnswer(ctx.study, options, facts, sum);
  std::vector<std::vector<std::string>> rows;
  for (const DesignWork& w : work) rows.push_back(w.comparison_row);
  doc.append(comparisonSection(ctx.study, options, std::move(rows)));
  out.text(sub + "/summary.json", js.dump(2) + "\n");
  out.report(sub + "/report.md", std::move(doc));
  sum.files = out.files();
  sum.reports = out.reports();
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sum;
}

}  // namespace armstudy::dexterity
