#pragma once
// Outputs of the dexterity stage (docs/dexterity.md): per design a VTK ImageData heat map over
// (gamma, z), VTK PolyData ellipsoid glyph data (plain and optimised), PNG images; per study a
// summary JSON and a Markdown report. Every file is written atomically.
#include <string>
#include <vector>

#include "dexterity/dexterity_audit.hpp"
#include "dexterity/dexterity_map.hpp"
#include "study/stage.hpp"

namespace armstudy::dexterity {

// Statistics of one field over the reachable cells.
struct FieldStats {
  bool any = false;
  double min = 0, max = 0;
  double gamma_at_min = 0, z_at_min = 0, gamma_at_max = 0, z_at_max = 0;
};

// One declared measure's per-cell values (metrics/measure_declarations.hpp) at the plain and the
// optimised posture; for a measure declared normalised also both divided by `best`, the largest
// value of the map over both postures (1 = best found in this map). Empty for a measure not on
// the maps.
struct MeasureFields {
  std::vector<double> plain, opt, plain_norm, opt_norm;
  double best = 0;
};

// The per-cell fields the outputs carry; NaN where the cell is unreachable.
struct MapFields {
  std::vector<double> reachable;
  std::vector<MeasureFields> measures;  // one per metrics::kMeasures entry, in its order
  std::vector<double> H_plain, H_opt, nullspace_iterations;
  // The fields of the declared measure `name` (one of metrics::kMeasures).
  const MeasureFields& of(const std::string& name) const;
  const MeasureFields& manipulability() const { return of("manipulability"); }
  const MeasureFields& transmission() const { return of("transmission"); }
};
MapFields mapFields(const DexterityMap& map);
FieldStats fieldStats(const DexterityMap& map, const std::vector<double>& field);

// Writes the map's VTK files into dir and returns their names relative to it (docs/dexterity.md):
// <design>.vti over (gamma [rad], z [m]); <design>_cylinder.vts, the same arrays on the cylinder
// around the stem in world metres; <design>_robot_best.vtp, the arm at the best optimised
// manipulability (when a cell is reachable); with `ellipsoids`,
// <design>_ellipsoids_{plain|optimised}.vtp (reachable cells only). `model` is the map's design.
std::vector<std::string> writeMapVtk(const DexterityMap& map, const MapFields& f,
                                     const Model& model, metrics::MeasureSpace space,
                                     bool ellipsoids, const std::string& dir);

// The cells of rows [rows.begin, rows.end) as checkpoint unit bytes (every field, bit for bit),
// and back into a map of the same grid and design size: false, with the map unchanged, when the
// bytes are not such a unit or do not fit the map; else `rows` receives the unit's rows.
std::string serializeRows(const DexterityMap& map, const ItemRange& rows);
bool deserializeRows(const std::string& bytes, DexterityMap& map, ItemRange& rows);

// Runs the stage for every design of the study and writes everything under
// <output_dir>/dexterity/. Each design's map is cut into work units of whole z rows (about
// ctx.options.unit_items cells, at least one row; 0 = defaults::kDexterityUnitCells), ids
// dexterity/<design>/rows_<b>-<e>, run through ctx.units (loaded when an interrupted run saved
// them). Metrics: dexterity/<design>/... With `maps`, the maps are appended there (tests,
// benchmark).
StageResult runDexterityStage(const StageContext& ctx, const DexterityOptions& options,
                              std::vector<DexterityMap>* maps = nullptr);

// The approachable cells of the near and far half of the circle at one spacing of the row sweep
// (summary.json `row_sweep`; spacing < 0: no stems, 0: the map's own stem only).
struct RowHalves {
  double spacing_m = 0;
  long near_reachable = 0, near_cells = 0, far_reachable = 0, far_cells = 0;
  std::string near_limited_by, far_limited_by;
};
// What the answer says of one design.
struct DesignAnswerFacts {
  double manipulability_mean_optimised = 0;  // over the reachable cells (0: none)
  double reachable_fraction = 0;
  double valley_z_m = 0;       // NaN: no valley inside the grid
  std::vector<RowHalves> row;  // empty without [dexterity.row]; the map's own spacing first
};
// The stage's answer (StageResult::answer) from its designs' facts: the designs ranked by the mean
// optimised manipulability over the cells each reaches, with their reachable shares and the height
// of each map's valley. Designs whose means lie within the audit's tolerance
// (defaults::kAuditTolerance, relative) of the highest are level: the map does not resolve a
// smaller difference. With a row around the stem, per design which half of the plant it can
// approach (thesis section 3.2.1). A design that reaches no cell is a warning. `facts` follows
// the study's designs.
void dexterityAnswer(const Study& study, const DexterityOptions& options,
                     const std::vector<DesignAnswerFacts>& facts, StageResult& sum);

// The map's null-space descents by kind (chain, seed, neighbour, collision, audit; `audit` may be
// null) as counts "<prefix>/descents/<kind>/...": descents, changed (adopted by a cell),
// iterations, kernel evaluations and objective evaluations per descent, mean and last step, how
// they stopped, µs per descent (from the kind's wall time); then the map's totals.
// `chain_seconds`: the chained rows' wall time.
void addDescentCounts(const std::string& prefix, const DexterityMap& map,
                      const DexterityAudit* audit, double chain_seconds,
                      std::vector<StageCount>& out);

}  // namespace armstudy::dexterity
