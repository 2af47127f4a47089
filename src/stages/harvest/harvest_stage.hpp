#pragma once
// The [harvest] study stage (docs/dynamics.md, "Harvest torque study"): approaches to the fruits of
// a sampled greenhouse row are planned (thesis 5.3.2), tracked with the null-space IK, sent through
// inverse dynamics and the drive chain at 1 kHz, and checked against the drive limits with and
// without friction; a task grid gives the static holding load and the drive-limited region.
//
//   [harvest]
//   designs = ["final_prototype_9dof"]   # optional, default: every design of the study
//   rate = 1000                          # samples per second (tracking and dynamics) [Hz]
//   temperature = 40                     # drive temperature for friction [deg C], optional
//   tool_beta = "90 deg"                 # R_tool = Ry(tool_beta): planner tool x -> design TCP z
//   start_offset = ["-150 mm", "0 mm", "0 mm"]  # start TCP relative to (stem x, stem y, fruit z)
//   plot_fruits = 2                      # fruits per design with profile plots (SVG)
//   [harvest.row]       seed, stems, fruits_per_stem, first_stem_y, fruit_z_mean, fruit_z_sd
//   [harvest.approach]  the [approach] keys (entry_radius, s_a, s_e, duration, ...)
//   [harvest.objective] joint_limits = 0.1, manipulability = 1.0 (weights of eq. 5.51)
//   [harvest.grid]      x, y, z: value or {from, to, step}; gamma (tool heading, default 0)
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dynamics/drive_feasibility.hpp"
#include "model/model.hpp"
#include "study/checkpoint.hpp"
#include "study/stage.hpp"
#include "tasks/task_grid.hpp"
#include "trajectory/approach_planner.hpp"
#include "trajectory/greenhouse_row.hpp"

namespace armstudy {
namespace io {
class TableReader;
}

namespace harvest {

struct HarvestGrid {
  std::array<AxisRange, 3> axes;  // x, y, z [m]
  double gamma_rad = 0;           // tool heading about z (0: tool along +x, towards the row)
};

struct HarvestOptions {
  std::vector<std::string> designs;  // empty = all designs of the study
  double rate_Hz = defaults::kHarvestRate_Hz;
  double temperature_C = defaults::kHarvestTemperature_C;
  double tool_beta_rad = defaults::kHarvestToolBeta_rad;
  Eigen::Vector3d start_offset = Eigen::Vector3d(-0.15, 0.0, 0.0);
  int plot_fruits = 2;
  GreenhouseRowOptions row;
  ApproachPlannerOptions approach;
  double w_joint_limits = 0.1, w_manipulability = 1.0;
  std::optional<HarvestGrid> grid;
  std::string validate() const;  // empty when valid
};

// Reads the [harvest] table. Throws InputError (file, line, key) on bad input; `designs` are the
// study's design names (every listed name must exist).
HarvestOptions readHarvestOptions(io::TableReader& r, const SectionInput& in);

// One fruit's result for one design.
struct FruitResult {
  int fruit = 0;
  Eigen::Vector3d p_fruit_W = Eigen::Vector3d::Zero();
  std::string status;  // "ok", or the planning / tracking status
  double max_position_error_m = 0, max_orientation_error_rad = 0;
  int limit_joint = -1;  // the joint whose limit stopped the tracking (-1: none)
  double limit_q = 0;    // that limit (q_min or q_max), rad or m
  DriveFeasibility with_friction, without_friction;  // profiles kept only for plotted fruits
  bool evaluated() const { return status == "ok"; }
};

struct GridPointResult {
  bool reachable = false;
  HoldingLoad holding;
};

struct DesignResult {
  std::string design;
  std::vector<FruitResult> fruits;
  std::vector<GridPointResult> grid;
};

// Which fruits (approaches) and holding-grid points evaluateHarvestDesign computes, as ranges of
// indices (non-empty, within the row's fruits / the grid's points), and whom it tells when a range
// is complete: called once per range from the thread that finished it (concurrently for distinct
// ranges), with the range's index and the design result, whose entries of that range are final.
using RangeDone = std::function<void(std::size_t range, const DesignResult& partial)>;
struct HarvestWork {
  std::vector<ItemRange> fruits, grid;
  RangeDone fruits_done, grid_done;  // may be empty
};

// Evaluates one design (threads: OpenMP over fruits and grid points; results are independent of
// the thread count). Fruits and grid points are independent of each other: with `work`, only the
// listed ranges are computed (the others keep default entries), each bit-identical to a full run.
DesignResult evaluateHarvestDesign(const Model& model, const HarvestOptions& options,
                                   const GreenhouseRow& row, int threads,
                                   const HarvestWork* work = nullptr);

// Checkpoint units of a design result: the fruits / grid points of one range as bytes (every
// field, profiles included, bit for bit), and back into a result of the same size (false, result
// unchanged, when the bytes are not such a unit or do not fit; else `range` receives its range).
std::string serializeFruits(const DesignResult& d, const ItemRange& range);
bool deserializeFruits(const std::string& bytes, DesignResult& d, ItemRange& range);
std::string serializeGridPoints(const DesignResult& d, const ItemRange& range);
bool deserializeGridPoints(const std::string& bytes, DesignResult& d, ItemRange& range);

// Runs the stage for the selected designs and writes under <output_dir>/harvest/: per design
// <design>_fruits.csv, <design>_fruit<k>_profile.csv (plotted fruits), SVG plots,
// <design>_holding.vti and PNG maps; report.md and summary.json. Metrics "harvest/<design>/...".
// Work units: one design x a range of fruits (defaults::kHarvestUnitFruits) or holding-grid
// points (defaults::kHarvestUnitGridPoints; ctx.options.unit_items overrides both), ids
// harvest/<design>/fruits_<b>-<e> and harvest/<design>/grid_<b>-<e>, run through ctx.units.
// With `results`, each design's result is appended there (tests).
StageResult runHarvestStage(const StageContext& ctx, const HarvestOptions& options,
                            std::vector<DesignResult>* results = nullptr);

}  // namespace harvest
}  // namespace armstudy
