#include "stages/harvest/harvest_units.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "common/errors.hpp"
#include "dynamics/approach_tracking.hpp"
#include "io/approach_io.hpp"
#include "io/files.hpp"
#include "io/toml_reader.hpp"
#include "io/vtk_io.hpp"
#include "report/image.hpp"
#include "report/markdown.hpp"

namespace armstudy::harvest {

namespace fs = std::filesystem;
using io::TableReader;
using nlohmann::ordered_json;
// ---------------------------------------------------------------------------------------------
// Checkpoint units
// ---------------------------------------------------------------------------------------------

namespace {

constexpr char kFruitsMagic[] = "armstudy-harvest-fruits-v2";
constexpr char kGridMagic[] = "armstudy-harvest-grid-v1";

// Per-sample rows of equal width: count, width, values.
void rowsField(UnitWriter& w, const std::vector<JointVector>& rows) {
  w.put<std::uint64_t>(rows.size());
  w.put<std::int64_t>(rows.empty() ? 0 : rows.front().size());
  for (const JointVector& r : rows)
    for (Eigen::Index i = 0; i < r.size(); ++i) w.put(r[i]);
}
void rowsField(UnitReader& r, std::vector<JointVector>& rows) {
  const auto n = r.get<std::uint64_t>();
  const auto width = r.get<std::int64_t>();
  if (!r.ok() || width < 0 || width > defaults::kMaxDof || (n > 0 && width == 0) ||
      n > (1ULL << 32)) {
    r.fail();
    return;
  }
  rows.assign(n, JointVector::Zero(width));
  for (JointVector& row : rows)
    for (Eigen::Index i = 0; r.ok() && i < width; ++i) row[i] = r.get<double>();
}

// A drive-feasibility result, both ways (study/checkpoint.hpp).
template <class Io, class Feasibility>
void feasibilityFields(Io& io, Feasibility& d) {
  unitValue<std::uint8_t>(io, d.feasible);
  unitValue<std::int32_t>(io, d.failing_joint);
  unitEnum<std::int32_t>(io, d.failing_quantity, kDriveQuantityCount);
  unitValue<double>(io, d.failure_time_s);
  unitCount(io, d.joints, defaults::kMaxDof);
  for (auto& j : d.joints) {
    unitField(io, j.joint);
    unitValue<std::uint8_t>(io, j.has_drive);
    for (auto* v : {&j.peak_effort, &j.peak_motor_torque_Nm}) unitValue<double>(io, *v);
    for (auto& c : j.checks) {
      for (auto* v : {&c.value, &c.limit, &c.margin, &c.first_exceeded_s})
        unitValue<double>(io, *v);
      for (auto* flag : {&c.checked, &c.exceeded}) unitValue<std::uint8_t>(io, *flag);
      unitValue<std::int32_t>(io, c.first_exceeded_k);
    }
  }
  for (auto* rows : {&d.effort, &d.motor_torque, &d.current, &d.motor_speed, &d.voltage})
    rowsField(io, *rows);
  auto& used = d.options_used;
  unitValue<std::uint8_t>(io, used.friction);
  unitValue<double>(io, used.temperature_C);
  for (auto* flag : {&used.keep_profiles, &used.drive_rotor_inertia})
    unitValue<std::uint8_t>(io, *flag);
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

// A unit of the items `range` of `all`: the head, then each item's `fields`.
template <class T, class Fields>
std::string serializeRange(const char* magic, const std::vector<T>& all, const ItemRange& range,
                           Fields fields) {
  UnitWriter w(magic);
  putHead(w, static_cast<long>(all.size()), range);
  for (long i = range.begin; i < range.end; ++i) fields(w, all[i]);
  return w.bytes();
}
// Places the items of a unit in `all` (sized already); false when the unit does not fit.
template <class T, class Fields>
bool deserializeRange(const std::string& bytes, const char* magic, std::vector<T>& all,
                      ItemRange& range, Fields fields) {
  UnitReader r(bytes, magic);
  ItemRange got;
  if (!getHead(r, static_cast<long>(all.size()), got)) return false;
  std::vector<T> items(static_cast<std::size_t>(got.size()));
  for (T& x : items) fields(r, x);
  if (!r.finished()) return false;
  std::move(items.begin(), items.end(), all.begin() + got.begin);
  range = got;
  return true;
}

constexpr auto kFruitFields = [](auto& io, auto& f) {
  unitValue<std::int32_t>(io, f.fruit);
  unitField(io, f.p_fruit_W);
  unitField(io, f.status);
  for (auto* v : {&f.max_position_error_m, &f.max_orientation_error_rad}) unitValue<double>(io, *v);
  unitValue<std::int32_t>(io, f.limit_joint);
  unitValue<double>(io, f.limit_q);
  for (auto* d : {&f.with_friction, &f.without_friction}) feasibilityFields(io, *d);
};

constexpr auto kGridPointFields = [](auto& io, auto& p) {
  unitValue<std::uint8_t>(io, p.reachable);
  for (auto* m : {&p.holding.effort, &p.holding.current_A, &p.holding.current_ratio})
    unitField(io, *m);
  unitValue<std::uint8_t>(io, p.holding.feasible);
  unitValue<std::int32_t>(io, p.holding.limiting_joint);
  unitValue<double>(io, p.holding.max_ratio);
};

}  // namespace

std::string serializeFruits(const DesignResult& d, const ItemRange& range) {
  return serializeRange(kFruitsMagic, d.fruits, range, kFruitFields);
}

bool deserializeFruits(const std::string& bytes, DesignResult& d, ItemRange& range) {
  return deserializeRange(bytes, kFruitsMagic, d.fruits, range, kFruitFields);
}

std::string serializeGridPoints(const DesignResult& d, const ItemRange& range) {
  return serializeRange(kGridMagic, d.grid, range, kGridPointFields);
}

bool deserializeGridPoints(const std::string& bytes, DesignResult& d, ItemRange& range) {
  return deserializeRange(bytes, kGridMagic, d.grid, range, kGridPointFields);
}

// One design's result in work units (fruits and holding-grid points in ranges of unit_items,
// 0 = defaults), run through ctx.units: units saved by an interrupted run are loaded, the rest
// evaluated in one parallel loop and saved as soon as done; both are joined by index.
DesignResult unitDesign(const StageContext& ctx, const Model& model, const HarvestOptions& options,
                        const GreenhouseRow& row, long& units_resumed) {
  const long unit_items = ctx.options.unit_items;
  const long nf = static_cast<long>(row.fruits.size());
  long np = 0;
  if (options.grid)
    np = long(options.grid->axes[0].count()) * options.grid->axes[1].count() *
         options.grid->axes[2].count();
  const std::vector<ItemRange> fruit_units =
      splitRange(nf, unit_items > 0 ? unit_items : defaults::kHarvestUnitFruits);
  const std::vector<ItemRange> grid_units =
      splitRange(np, unit_items > 0 ? unit_items : defaults::kHarvestUnitGridPoints);
  const std::size_t F = fruit_units.size();
  std::vector<std::string> ids = unitIds("harvest/" + model.name + "/fruits_", fruit_units);
  for (const std::string& id : unitIds("harvest/" + model.name + "/grid_", grid_units))
    ids.push_back(id);
  std::vector<ItemRange> ranges = fruit_units;
  ranges.insert(ranges.end(), grid_units.begin(), grid_units.end());
  DesignResult loaded;
  loaded.fruits.resize(nf);
  loaded.grid.resize(np);
  std::vector<ItemRange> fruits_loaded, grid_loaded;
  auto load = [&](std::size_t k, const std::string& bytes) {
    ItemRange got;
    const bool ok =
        k < F ? deserializeFruits(bytes, loaded, got) : deserializeGridPoints(bytes, loaded, got);
    if (!ok || got.begin != ranges[k].begin || got.end != ranges[k].end) return false;
    (k < F ? fruits_loaded : grid_loaded).push_back(ranges[k]);
    return true;
  };
  HarvestWork work;
  std::vector<std::size_t> fruit_ids, grid_ids;
  std::optional<DesignResult> computed;
  auto compute = [&](const std::vector<std::size_t>& units, const std::vector<ItemRange>& todo,
                     const armstudy::RangeDone& done) {
    // A later call replaces an earlier one's units (UnitBatch).
    work.fruits.clear();
    work.grid.clear();
    fruit_ids.clear();
    grid_ids.clear();
    for (std::size_t j = 0; j < units.size(); ++j) {
      (units[j] < F ? work.fruits : work.grid).push_back(todo[j]);
      (units[j] < F ? fruit_ids : grid_ids).push_back(j);
    }
    work.fruits_done = [&](std::size_t j, const DesignResult& d) {
      done(fruit_ids[j], serializeFruits(d, work.fruits[j]));
    };
    work.grid_done = [&](std::size_t j, const DesignResult& d) {
      done(grid_ids[j], serializeGridPoints(d, work.grid[j]));
    };
    computed = evaluateHarvestDesign(model, options, row, ctx.threads, &work);
  };
  units_resumed += ctx.units.run(rangeUnitBatch(ids, ranges, load, compute));
  DesignResult d = computed ? std::move(*computed)
                            : evaluateHarvestDesign(model, options, row, ctx.threads, &work);
  for (const ItemRange& u : fruits_loaded)
    std::move(loaded.fruits.begin() + u.begin, loaded.fruits.begin() + u.end,
              d.fruits.begin() + u.begin);
  for (const ItemRange& u : grid_loaded)
    std::move(loaded.grid.begin() + u.begin, loaded.grid.begin() + u.end, d.grid.begin() + u.begin);
  return d;
}

}  // namespace armstudy::harvest
