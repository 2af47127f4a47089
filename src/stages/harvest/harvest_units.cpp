#include "stages/harvest/harvest_units.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "common/errors.hpp"
#include "dynamics/approach_tracking.hpp"
#include "io/files.hpp"
#include "io/toml_reader.hpp"
#include "io/vtk_io.hpp"
#include "report/image.hpp"
#include "report/markdown.hpp"
#include "io/approach_io.hpp"

namespace armstudy::harvest {

namespace fs = std::filesystem;
using io::TableReader;
using nlohmann::ordered_json;
// ---------------------------------------------------------------------------------------------
// Checkpoint units
// ---------------------------------------------------------------------------------------------

namespace {

constexpr char kFruitsMagic[] = "armstudy-harvest-fruits-v1";
constexpr char kGridMagic[] = "armstudy-harvest-grid-v1";

// Per-sample rows of equal width: count, width, values.
void putRows(UnitWriter& w, const std::vector<JointVector>& rows) {
  w.put<std::uint64_t>(rows.size());
  w.put<std::int64_t>(rows.empty() ? 0 : rows.front().size());
  for (const JointVector& r : rows)
    for (Eigen::Index i = 0; i < r.size(); ++i) w.put(r[i]);
}
void getRows(UnitReader& r, std::vector<JointVector>& rows) {
  const auto n = r.get<std::uint64_t>();
  const auto width = r.get<std::int64_t>();
  if (!r.ok() || width < 0 || width > defaults::kMaxDof || (n > 0 && width == 0) || n > (1ULL << 32)) {
    r.fail();
    return;
  }
  rows.assign(n, JointVector::Zero(width));
  for (JointVector& row : rows)
    for (Eigen::Index i = 0; r.ok() && i < width; ++i) row[i] = r.get<double>();
}

void putFeasibility(UnitWriter& w, const DriveFeasibility& d) {
  w.put<std::uint8_t>(d.feasible);
  w.put<std::int32_t>(d.failing_joint);
  w.put<std::int32_t>(static_cast<std::int32_t>(d.failing_quantity));
  w.put(d.failure_time_s);
  w.put<std::uint64_t>(d.joints.size());
  for (const JointDriveSummary& j : d.joints) {
    w.putString(j.joint);
    w.put<std::uint8_t>(j.has_drive);
    w.put(j.peak_effort);
    w.put(j.peak_motor_torque_Nm);
    for (const QuantityCheck& c : j.checks) {
      for (double v : {c.value, c.limit, c.margin, c.first_exceeded_s}) w.put(v);
      w.put<std::uint8_t>(c.checked);
      w.put<std::uint8_t>(c.exceeded);
      w.put<std::int32_t>(c.first_exceeded_k);
    }
  }
  for (const auto* rows : {&d.effort, &d.motor_torque, &d.current, &d.motor_speed, &d.voltage}) putRows(w, *rows);
  w.put<std::uint8_t>(d.options_used.friction);
  w.put(d.options_used.temperature_C);
  w.put<std::uint8_t>(d.options_used.keep_profiles);
  w.put<std::uint8_t>(d.options_used.drive_rotor_inertia);
}

void getFeasibility(UnitReader& r, DriveFeasibility& d) {
  d.feasible = r.get<std::uint8_t>() != 0;
  d.failing_joint = r.get<std::int32_t>();
  const auto q = r.get<std::int32_t>();
  if (q < 0 || q >= kDriveQuantityCount) r.fail();
  d.failing_quantity = static_cast<DriveQuantity>(q);
  d.failure_time_s = r.get<double>();
  const auto nj = r.get<std::uint64_t>();
  if (nj > static_cast<std::uint64_t>(defaults::kMaxDof)) r.fail();
  d.joints.assign(r.ok() ? nj : 0, JointDriveSummary{});
  for (JointDriveSummary& j : d.joints) {
    j.joint = r.getString();
    j.has_drive = r.get<std::uint8_t>() != 0;
    j.peak_effort = r.get<double>();
    j.peak_motor_torque_Nm = r.get<double>();
    for (QuantityCheck& c : j.checks) {
      for (double* v : {&c.value, &c.limit, &c.margin, &c.first_exceeded_s}) *v = r.get<double>();
      c.checked = r.get<std::uint8_t>() != 0;
      c.exceeded = r.get<std::uint8_t>() != 0;
      c.first_exceeded_k = r.get<std::int32_t>();
    }
  }
  for (auto* rows : {&d.effort, &d.motor_torque, &d.current, &d.motor_speed, &d.voltage}) getRows(r, *rows);
  d.options_used.friction = r.get<std::uint8_t>() != 0;
  d.options_used.temperature_C = r.get<double>();
  d.options_used.keep_profiles = r.get<std::uint8_t>() != 0;
  d.options_used.drive_rotor_inertia = r.get<std::uint8_t>() != 0;
}

// Header of a unit: the design's result sizes and the range; false when it does not fit `size`.
void putHead(UnitWriter& w, long size, const ItemRange& range) {
  for (long v : {size, range.begin, range.end}) w.put<std::int64_t>(v);
}
bool getHead(UnitReader& r, long size, ItemRange& range) {
  const auto n = r.get<std::int64_t>(), b = r.get<std::int64_t>(), e = r.get<std::int64_t>();
  range = {b, e};
  return r.ok() && n == size && 0 <= b && b < e && e <= n;
}

}  // namespace

std::string serializeFruits(const DesignResult& d, const ItemRange& range) {
  UnitWriter w(kFruitsMagic);
  putHead(w, static_cast<long>(d.fruits.size()), range);
  for (long i = range.begin; i < range.end; ++i) {
    const FruitResult& f = d.fruits[i];
    w.put<std::int32_t>(f.fruit);
    w.putMatrix(f.p_fruit_W);
    w.putString(f.status);
    w.put(f.max_position_error_m);
    w.put(f.max_orientation_error_rad);
    putFeasibility(w, f.with_friction);
    putFeasibility(w, f.without_friction);
  }
  return w.bytes();
}

bool deserializeFruits(const std::string& bytes, DesignResult& d, ItemRange& range) {
  UnitReader r(bytes, kFruitsMagic);
  ItemRange got;
  if (!getHead(r, static_cast<long>(d.fruits.size()), got)) return false;
  std::vector<FruitResult> fruits(static_cast<std::size_t>(got.size()));
  for (FruitResult& f : fruits) {
    f.fruit = r.get<std::int32_t>();
    r.getMatrix(f.p_fruit_W);
    f.status = r.getString();
    f.max_position_error_m = r.get<double>();
    f.max_orientation_error_rad = r.get<double>();
    getFeasibility(r, f.with_friction);
    getFeasibility(r, f.without_friction);
  }
  if (!r.finished()) return false;
  std::move(fruits.begin(), fruits.end(), d.fruits.begin() + got.begin);
  range = got;
  return true;
}

std::string serializeGridPoints(const DesignResult& d, const ItemRange& range) {
  UnitWriter w(kGridMagic);
  putHead(w, static_cast<long>(d.grid.size()), range);
  for (long i = range.begin; i < range.end; ++i) {
    const GridPointResult& p = d.grid[i];
    w.put<std::uint8_t>(p.reachable);
    w.putMatrix(p.holding.effort);
    w.putMatrix(p.holding.current_A);
    w.putMatrix(p.holding.current_ratio);
    w.put<std::uint8_t>(p.holding.feasible);
    w.put<std::int32_t>(p.holding.limiting_joint);
    w.put(p.holding.max_ratio);
  }
  return w.bytes();
}

bool deserializeGridPoints(const std::string& bytes, DesignResult& d, ItemRange& range) {
  UnitReader r(bytes, kGridMagic);
  ItemRange got;
  if (!getHead(r, static_cast<long>(d.grid.size()), got)) return false;
  std::vector<GridPointResult> points(static_cast<std::size_t>(got.size()));
  for (GridPointResult& p : points) {
    p.reachable = r.get<std::uint8_t>() != 0;
    r.getMatrix(p.holding.effort);
    r.getMatrix(p.holding.current_A);
    r.getMatrix(p.holding.current_ratio);
    p.holding.feasible = r.get<std::uint8_t>() != 0;
    p.holding.limiting_joint = r.get<std::int32_t>();
    p.holding.max_ratio = r.get<double>();
  }
  if (!r.finished()) return false;
  std::move(points.begin(), points.end(), d.grid.begin() + got.begin);
  range = got;
  return true;
}

// One design's result in work units (fruits and holding-grid points in ranges of unit_items,
// 0 = defaults), run through ctx.units: units saved by an interrupted run are loaded, the rest
// evaluated in one parallel loop and saved as soon as done; both are joined by index.
DesignResult unitDesign(const StageContext& ctx, const Model& model, const HarvestOptions& options,
                        const GreenhouseRow& row, long& units_resumed) {
  const long unit_items = ctx.options.unit_items;
  const long nf = static_cast<long>(row.fruits.size());
  long np = 0;
  if (options.grid) np = long(options.grid->axes[0].count()) * options.grid->axes[1].count() * options.grid->axes[2].count();
  const std::vector<ItemRange> fruit_units =
      splitRange(nf, unit_items > 0 ? unit_items : defaults::kHarvestUnitFruits);
  const std::vector<ItemRange> grid_units =
      splitRange(np, unit_items > 0 ? unit_items : defaults::kHarvestUnitGridPoints);
  const std::size_t F = fruit_units.size();
  auto range = [&](std::size_t k) { return k < F ? fruit_units[k] : grid_units[k - F]; };
  UnitBatch batch;
  for (const ItemRange& r : fruit_units) batch.ids.push_back("harvest/" + model.name + "/fruits_" + r.text());
  for (const ItemRange& r : grid_units) batch.ids.push_back("harvest/" + model.name + "/grid_" + r.text());
  DesignResult loaded;
  loaded.fruits.resize(nf);
  loaded.grid.resize(np);
  std::vector<ItemRange> fruits_loaded, grid_loaded;
  batch.load = [&](std::size_t k, const std::string& bytes) {
    ItemRange got;
    const bool ok = k < F ? deserializeFruits(bytes, loaded, got) : deserializeGridPoints(bytes, loaded, got);
    if (!ok || got.begin != range(k).begin || got.end != range(k).end) return false;
    (k < F ? fruits_loaded : grid_loaded).push_back(range(k));
    return true;
  };
  HarvestWork work;
  std::vector<std::size_t> fruit_ids, grid_ids;
  std::optional<DesignResult> computed;
  batch.compute = [&](const std::vector<std::size_t>& todo, const UnitBatch::Done& done) {
    // A later call replaces an earlier one's units (UnitBatch).
    work.fruits.clear();
    work.grid.clear();
    fruit_ids.clear();
    grid_ids.clear();
    for (std::size_t k : todo) {
      (k < F ? work.fruits : work.grid).push_back(range(k));
      (k < F ? fruit_ids : grid_ids).push_back(k);
    }
    work.fruits_done = [&](std::size_t j, const DesignResult& d) { done(fruit_ids[j], serializeFruits(d, work.fruits[j])); };
    work.grid_done = [&](std::size_t j, const DesignResult& d) { done(grid_ids[j], serializeGridPoints(d, work.grid[j])); };
    computed = evaluateHarvestDesign(model, options, row, ctx.threads, &work);
  };
  units_resumed += ctx.units.run(batch);
  DesignResult d = computed ? std::move(*computed) : evaluateHarvestDesign(model, options, row, ctx.threads, &work);
  for (const ItemRange& u : fruits_loaded)
    std::move(loaded.fruits.begin() + u.begin, loaded.fruits.begin() + u.end, d.fruits.begin() + u.begin);
  for (const ItemRange& u : grid_loaded)
    std::move(loaded.grid.begin() + u.begin, loaded.grid.begin() + u.end, d.grid.begin() + u.begin);
  return d;
}

}  // namespace armstudy::harvest
