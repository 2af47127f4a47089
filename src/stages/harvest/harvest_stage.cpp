#include "stages/harvest/harvest_stage.hpp"

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
// Reading
// ---------------------------------------------------------------------------------------------

std::string HarvestOptions::validate() const {
  if (!(rate_Hz > 0) || !std::isfinite(rate_Hz)) return "rate must be positive";
  if (!std::isfinite(temperature_C)) return "temperature must be finite";
  if (!start_offset.allFinite()) return "start offset must be finite";
  if (plot_fruits < 0) return "plot_fruits must be >= 0";
  if (!(w_joint_limits >= 0) || !(w_manipulability >= 0)) return "objective weights must be >= 0";
  std::string err;
  if (!row.validate(err)) return "row: " + err;
  if (!approach.validate(err)) return "approach: " + err;
  if (grid)
    for (const auto& a : grid->axes)
      if (std::string why = a.validate(); !why.empty()) return "grid: " + why;
  return "";
}

namespace {

AxisRange readAxis(TableReader& r, const std::string& key) {
  const toml::node* n = r.node(key);
  if (!n) r.fail(key, "missing axis (a value such as \"1.2 m\" or {from, to, step})");
  AxisRange a;
  if (const toml::table* t = n->as_table()) {
    TableReader tr(*t, r.file(), r.keyPath(key));
    a.from = tr.quantity("from", Dimension::Length);
    a.to = tr.quantity("to", Dimension::Length);
    a.step = tr.quantity("step", Dimension::Length);
    tr.finish();
  } else {
    a.from = a.to = io::nodeQuantity(*n, Dimension::Length, r.file(), r.keyPath(key));
    a.step = 1;
  }
  if (std::string why = a.validate(); !why.empty()) r.fail(key, why);
  return a;
}

}  // namespace

HarvestOptions readHarvestOptions(TableReader& r, const std::vector<std::string>& designs) {
  HarvestOptions o;
  if (r.has("designs")) {
    o.designs = r.stringArray("designs");
    if (o.designs.empty()) r.fail("designs", "empty list of designs");
    for (const auto& d : o.designs)
      if (std::find(designs.begin(), designs.end(), d) == designs.end())
        r.fail("designs", "design '" + d + "' is not part of the study");
  }
  o.rate_Hz = r.number("rate", o.rate_Hz);
  if (!(o.rate_Hz > 0) || o.rate_Hz > 1e5) r.fail("rate", "rate must lie in (0, 100000] Hz");
  o.temperature_C = r.number("temperature", o.temperature_C);
  o.tool_beta_rad = r.quantity("tool_beta", Dimension::Angle, o.tool_beta_rad);
  if (r.has("start_offset")) {
    const toml::array* a = r.array("start_offset");
    if (!a || a->size() != 3) r.fail("start_offset", "expected three lengths [dx, dy, dz]");
    for (int i = 0; i < 3; ++i)
      o.start_offset[i] =
          io::nodeQuantity(*a->get(i), Dimension::Length, r.file(), r.keyPath("start_offset"));
  }
  o.plot_fruits = static_cast<int>(r.integer("plot_fruits", o.plot_fruits));
  if (o.plot_fruits < 0) r.fail("plot_fruits", "must be >= 0");

  if (const toml::table* t = r.table("row")) {
    TableReader rr(*t, r.file(), r.keyPath("row"));
    const long long seed = rr.integer("seed", 1);
    if (seed < 0) rr.fail("seed", "seed must be >= 0");
    o.row.seed = static_cast<std::uint64_t>(seed);
    o.row.stems = static_cast<int>(rr.integer("stems", o.row.stems));
    if (o.row.stems < 1 || o.row.stems > 10000) rr.fail("stems", "stems must lie in [1, 10000]");
    o.row.fruits_per_stem = static_cast<int>(rr.integer("fruits_per_stem", o.row.fruits_per_stem));
    if (o.row.fruits_per_stem < 1 || o.row.fruits_per_stem > 100)
      rr.fail("fruits_per_stem", "fruits_per_stem must lie in [1, 100]");
    o.row.first_stem_y_m = rr.quantity("first_stem_y", Dimension::Length, o.row.first_stem_y_m);
    o.row.fruit_z.mean = rr.quantity("fruit_z_mean", Dimension::Length, o.row.fruit_z.mean);
    o.row.fruit_z.sd = rr.quantity("fruit_z_sd", Dimension::Length, o.row.fruit_z.sd);
    o.row.fruit_z.min = rr.quantity("fruit_z_min", Dimension::Length, o.row.fruit_z.min);
    o.row.fruit_z.max = rr.quantity("fruit_z_max", Dimension::Length, o.row.fruit_z.max);
    o.row.fruit_angle_min_rad =
        rr.quantity("fruit_angle_min", Dimension::Angle, o.row.fruit_angle_min_rad);
    o.row.fruit_angle_max_rad =
        rr.quantity("fruit_angle_max", Dimension::Angle, o.row.fruit_angle_max_rad);
    std::string err;
    if (!o.row.validate(err)) throw InputError(r.file(), rr.line(), r.keyPath("row"), err);
    rr.finish();
  }
  {
    const toml::table* t = r.table("approach");
    if (!t) r.fail("approach", "missing table [harvest.approach] (duration is required)");
    TableReader ar(*t, r.file(), r.keyPath("approach"));
    o.approach = readApproachOptions(ar);
    ar.finish();
  }
  if (const toml::table* t = r.table("objective")) {
    TableReader orr(*t, r.file(), r.keyPath("objective"));
    o.w_joint_limits = orr.number("joint_limits", o.w_joint_limits);
    o.w_manipulability = orr.number("manipulability", o.w_manipulability);
    if (!(o.w_joint_limits >= 0)) orr.fail("joint_limits", "weight must be >= 0");
    if (!(o.w_manipulability >= 0)) orr.fail("manipulability", "weight must be >= 0");
    orr.finish();
  }
  if (const toml::table* t = r.table("grid")) {
    TableReader gr(*t, r.file(), r.keyPath("grid"));
    HarvestGrid g;
    g.axes[0] = readAxis(gr, "x");
    g.axes[1] = readAxis(gr, "y");
    g.axes[2] = readAxis(gr, "z");
    g.gamma_rad = gr.quantity("gamma", Dimension::Angle, 0.0);
    const long pts = static_cast<long>(g.axes[0].count()) * g.axes[1].count() * g.axes[2].count();
    if (pts > 1000000) gr.fail("x", "grid has more than 1e6 points");
    gr.finish();
    o.grid = g;
  }
  const std::string why = o.validate();
  ARMSTUDY_CHECK(why.empty(), "harvest reader and validate disagree: " + why);
  return o;
}

// ---------------------------------------------------------------------------------------------
// Evaluation
// ---------------------------------------------------------------------------------------------

namespace {

Eigen::Matrix3d toolRotation(double beta) {
  return Eigen::AngleAxisd(beta, Eigen::Vector3d::UnitY()).toRotationMatrix();
}

// The (range, item) pairs of `ranges`, in order; every range non-empty and within [0, count).
std::vector<std::pair<std::size_t, long>> workItems(const std::vector<ItemRange>& ranges, long count) {
  std::vector<std::pair<std::size_t, long>> items;
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    ARMSTUDY_CHECK(0 <= ranges[k].begin && ranges[k].begin < ranges[k].end && ranges[k].end <= count,
                   "harvest work range out of bounds");
    for (long i = ranges[k].begin; i < ranges[k].end; ++i) items.emplace_back(k, i);
  }
  return items;
}

ApproachTrackingOptions trackingOptions(const HarvestOptions& o) {
  ApproachTrackingOptions t;
  t.tracking.dt = 1.0 / o.rate_Hz;
  t.tracking.stop_at_joint_limit = true;
  t.R_tool = toolRotation(o.tool_beta_rad);
  return t;
}

}  // namespace

DesignResult evaluateHarvestDesign(const Model& model, const HarvestOptions& options,
                                   const GreenhouseRow& row, int threads, const HarvestWork* work) {
  ARMSTUDY_CHECK(options.validate().empty(), "harvest options must validate");
  DesignResult res;
  res.design = model.name;
  DynamicsOptions dopt;
  dopt.include_rotor_inertia = false;  // the drive chain adds J_rotor (counted once)
  const RigidBodyModel rbm = makeRigidBodyModel(model, dopt);
  ik::WeightedObjective objective;
  if (options.w_joint_limits > 0)
    objective.add(options.w_joint_limits,
                  std::make_shared<ik::JointLimitTerm>(model, defaults::kJointLimitActivation));
  if (options.w_manipulability > 0)
    objective.add(options.w_manipulability,
                  std::make_shared<ik::ManipulabilityTerm>(metrics::MeasureSpace::Translational));
  const ApproachTrackingOptions topt = trackingOptions(options);
  const int nthreads = threads > 0 ? threads : omp_get_max_threads();

  const int nf = static_cast<int>(row.fruits.size());
  res.fruits.resize(nf);
  std::vector<ItemRange> all_fruits;
  if (nf > 0) all_fruits.push_back({0, nf});
  const std::vector<ItemRange>& fruit_ranges = work ? work->fruits : all_fruits;
  std::vector<std::pair<std::size_t, long>> fruit_work = workItems(fruit_ranges, nf);
  RangeCountdown fruit_countdown(fruit_ranges);
  std::exception_ptr failure;
  // Tells `done` (may be empty) that range k is complete; keeps the first exception.
  auto report = [&](const RangeDone& done, std::size_t k) {
    if (!done) return;
    try {
      done(k, res);
    } catch (...) {
#pragma omp critical(armstudy_harvest_failure)
      if (!failure) failure = std::current_exception();
    }
  };
  const long n_fruit_work = static_cast<long>(fruit_work.size());
#pragma omp parallel num_threads(nthreads)
  {
    IkWorkspace ws(model);
    ik::ObjectiveContext ctx(model, ws.kin);
    DynamicsWorkspace dws(rbm);
    // One approach: planned, tracked, through the drive chain with and without friction.
    auto evaluateFruit = [&](int f) {
      const SampledFruit& fr = row.fruits[f];
      FruitResult& out = res.fruits[f];
      out.fruit = f;
      out.p_fruit_W = fr.p_W;
      const Eigen::Vector2d stem = row.stems_xy[fr.stem];
      ApproachProblem pb;
      pb.p_start_W =
          Eigen::Vector3d(stem.x() + options.start_offset.x(), stem.y() + options.start_offset.y(),
                          fr.p_W.z() + options.start_offset.z());
      const Eigen::Vector2d to_stem = stem - pb.p_start_W.head<2>();
      pb.cardan_start = Eigen::Vector3d(0, 0, std::atan2(to_stem.y(), to_stem.x()));
      pb.stem_xy_W = stem;
      pb.fruit_W = fr.p_W;
      pb.reference_xy_W = Eigen::Vector2d::Zero();
      const ApproachTrajectory appr = planApproach(pb, options.approach);
      if (appr.status() != ApproachStatus::Ok) {
        out.status = toString(appr.status());
        return;
      }
      const TrackedApproach tr =
          trackApproach(model, ws, ctx, appr, objective, topt, static_cast<std::uint64_t>(f));
      out.max_position_error_m = tr.max_position_error_m;
      out.max_orientation_error_rad = tr.max_orientation_error_rad;
      if (tr.status != ApproachTrackingStatus::Ok) {
        out.status = tr.status == ApproachTrackingStatus::TrackingFailed
                         ? std::string("tracking_") + ik::toString(tr.tracking_status)
                         : std::string(toString(tr.status));
        return;
      }
      out.status = "ok";
      DriveFeasibilityOptions fo;
      fo.temperature_C = options.temperature_C;
      fo.keep_profiles = true;  // friction share and plots need them (a few MB at most)
      fo.friction = true;
      out.with_friction = evaluateDriveFeasibility(model, rbm, dws, tr.trajectory, fo);
      fo.friction = false;
      out.without_friction = evaluateDriveFeasibility(model, rbm, dws, tr.trajectory, fo);
    };
#pragma omp for schedule(dynamic)
    for (long w = 0; w < n_fruit_work; ++w) {
      const auto [k, f] = fruit_work[w];
      evaluateFruit(static_cast<int>(f));
      if (fruit_countdown.itemDone(k)) report(work ? work->fruits_done : RangeDone{}, k);
    }
  }
  if (failure) std::rethrow_exception(failure);

  if (options.grid) {
    const HarvestGrid& g = *options.grid;
    const long nx = g.axes[0].count(), ny = g.axes[1].count(), nz = g.axes[2].count();
    const long np = nx * ny * nz;
    res.grid.resize(np);
    const Eigen::Matrix3d R_WT =
        Eigen::AngleAxisd(g.gamma_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
        toolRotation(options.tool_beta_rad);
    const CardanAngles c = cardanFromRotation(R_WT);
    IkOptions iko;
    iko.classify_failures = false;
    std::vector<ItemRange> all_points{{0, np}};
    const std::vector<ItemRange>& grid_ranges = work ? work->grid : all_points;
    std::vector<std::pair<std::size_t, long>> grid_work = workItems(grid_ranges, np);
    RangeCountdown grid_countdown(grid_ranges);
    const long n_grid_work = static_cast<long>(grid_work.size());
#pragma omp parallel num_threads(nthreads)
    {
      IkWorkspace ws(model);
      DynamicsWorkspace dws(rbm);
#pragma omp for schedule(dynamic, 8)
      for (long w = 0; w < n_grid_work; ++w) {
        const auto [range, p] = grid_work[w];
        const long i = p % nx, j = (p / nx) % ny, k = p / (nx * ny);
        IkTarget target;
        target.task_space = TaskSpace::fullPose();
        target.w_d << g.axes[0].value(static_cast<int>(i)), g.axes[1].value(static_cast<int>(j)),
            g.axes[2].value(static_cast<int>(k)), c.alpha, c.beta, c.gamma;
        const IkResult r = solvePose(model, ws, target, iko, static_cast<std::uint64_t>(p));
        GridPointResult& gp = res.grid[p];
        gp.reachable = r.reachable();
        if (gp.reachable) gp.holding = holdingLoad(model, rbm, dws, r.q);
        if (grid_countdown.itemDone(range)) report(work ? work->grid_done : RangeDone{}, range);
      }
    }
    if (failure) std::rethrow_exception(failure);
  }
  return res;
}

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

namespace {

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

}  // namespace

// ---------------------------------------------------------------------------------------------
// Outputs
// ---------------------------------------------------------------------------------------------

namespace {

std::string num(double v) {
  if (!std::isfinite(v)) return "nan";
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

bool isRevolute(const Model& model, int i) { return model.joints[i].type == JointType::Revolute; }

std::string marginText(const QuantityCheck& c) {
  return c.checked ? report::percent(c.margin, 1) : "n/a";
}
std::string limitText(const QuantityCheck& c, int decimals) {
  return c.checked ? report::fixed(c.limit, decimals) : "-";
}

// Worst (largest value) check of joint i and quantity q over the evaluated fruits.
struct JointAggregate {
  double peak_effort = 0;
  std::array<QuantityCheck, kDriveQuantityCount> worst;  // with friction
  double peak_current_no_friction = 0;
  double friction_share = 0;  // max over the evaluated fruits of peak |I_f - I_nf| / peak |I_f|
  int exceeded_fruits = 0;    // fruits where any check of this joint failed (with friction)
  bool has_drive = false;
};

std::vector<JointAggregate> aggregate(const Model& model, const DesignResult& d) {
  const int n = model.dof();
  std::vector<JointAggregate> agg(n);
  for (const FruitResult& f : d.fruits) {
    if (!f.evaluated()) continue;
    for (int i = 0; i < n; ++i) {
      const JointDriveSummary& js = f.with_friction.joints[i];
      const JointDriveSummary& jn = f.without_friction.joints[i];
      JointAggregate& a = agg[i];
      a.has_drive = js.has_drive;
      a.peak_effort = std::max(a.peak_effort, js.peak_effort);
      bool any = false;
      for (int q = 0; q < kDriveQuantityCount; ++q) {
        const QuantityCheck& c = js.checks[q];
        QuantityCheck& w = a.worst[q];
        if (c.value >= w.value || !w.checked) {
          const bool first = !w.checked && w.value == 0;
          if (c.value >= w.value || first) w = c;
        }
        any = any || c.exceeded;
      }
      if (any) ++a.exceeded_fruits;
      a.peak_current_no_friction =
          std::max(a.peak_current_no_friction, jn.check(DriveQuantity::PeakCurrent).value);
      if (!f.with_friction.current.empty() && !f.without_friction.current.empty()) {
        double dmax = 0, imax = 0;
        for (size_t k = 0; k < f.with_friction.current.size(); ++k) {
          dmax = std::max(
              dmax, std::abs(f.with_friction.current[k][i] - f.without_friction.current[k][i]));
          imax = std::max(imax, std::abs(f.with_friction.current[k][i]));
        }
        if (imax > 0) a.friction_share = std::max(a.friction_share, dmax / imax);
      }
    }
  }
  return agg;
}

std::string failureText(const Model& model, const DriveFeasibility& r) {
  if (r.feasible) return "feasible";
  return model.joints[r.failing_joint].name + " " + toString(r.failing_quantity) + " at " +
         report::fixed(r.failure_time_s, 3) + " s";
}

void writeFruitCsv(const Model& model, const DesignResult& d, const std::string& path) {
  std::ostringstream s;
  const int n = model.dof();
  s << "fruit,x_m,y_m,z_m,status,feasible,failing_joint,failing_quantity,failure_time_s,"
       "feasible_no_friction,max_position_error_m,max_orientation_error_rad";
  for (int i = 0; i < n; ++i) s << ",peak_current_A_" << model.joints[i].name;
  for (int i = 0; i < n; ++i) s << ",rms_current_A_" << model.joints[i].name;
  for (int i = 0; i < n; ++i) s << ",peak_current_no_friction_A_" << model.joints[i].name;
  s << "\n";
  for (const FruitResult& f : d.fruits) {
    s << f.fruit << "," << num(f.p_fruit_W.x()) << "," << num(f.p_fruit_W.y()) << ","
      << num(f.p_fruit_W.z()) << "," << f.status << ",";
    if (f.evaluated()) {
      const auto& r = f.with_friction;
      s << (r.feasible ? 1 : 0) << "," << (r.feasible ? "" : model.joints[r.failing_joint].name)
        << "," << (r.feasible ? "" : toString(r.failing_quantity)) << ","
        << (r.feasible ? "" : num(r.failure_time_s)) << "," << (f.without_friction.feasible ? 1 : 0)
        << "," << num(f.max_position_error_m) << "," << num(f.max_orientation_error_rad);
      for (int i = 0; i < n; ++i)
        s << "," << num(r.joints[i].check(DriveQuantity::PeakCurrent).value);
      for (int i = 0; i < n; ++i)
        s << "," << num(r.joints[i].check(DriveQuantity::RmsCurrent).value);
      for (int i = 0; i < n; ++i)
        s << "," << num(f.without_friction.joints[i].check(DriveQuantity::PeakCurrent).value);
    } else {
      s << ",,,,,,";
      for (int i = 0; i < 3 * n; ++i) s << ",";
    }
    s << "\n";
  }
  writeFileAtomic(path, s.str());
}

void writeProfileCsv(const Model& model, const FruitResult& f, double dt, const std::string& path) {
  const int n = model.dof();
  const auto& a = f.with_friction;
  const auto& b = f.without_friction;
  std::ostringstream s;
  s << "t_s";
  const char* cols[] = {"effort", "current_A", "current_no_friction_A", "motor_speed_radps",
                        "voltage_V"};
  for (const char* c : cols)
    for (int i = 0; i < n; ++i) s << "," << c << "_" << model.joints[i].name;
  s << "\n";
  for (size_t k = 0; k < a.effort.size(); ++k) {
    s << num(k * dt);
    for (int i = 0; i < n; ++i) s << "," << num(a.effort[k][i]);
    for (int i = 0; i < n; ++i) s << "," << num(a.current[k][i]);
    for (int i = 0; i < n; ++i) s << "," << num(b.current[k][i]);
    for (int i = 0; i < n; ++i) s << "," << num(a.motor_speed[k][i]);
    for (int i = 0; i < n; ++i) s << "," << num(a.voltage[k][i]);
    s << "\n";
  }
  writeFileAtomic(path, s.str());
}

// Every `stride`-th sample (plots stay small).
std::vector<report::Series> profileSeries(const Model& model, const std::vector<JointVector>& rows,
                                          double dt, const std::string& suffix, int stride) {
  std::vector<report::Series> out;
  for (int i = 0; i < model.dof(); ++i) {
    report::Series s;
    s.label = model.joints[i].name + suffix;
    for (size_t k = 0; k < rows.size(); k += stride) {
      s.x.push_back(k * dt);
      s.y.push_back(rows[k][i]);
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace

StageResult runHarvestStage(const StageContext& ctx, const HarvestOptions& options,
                            std::vector<DesignResult>* results) {
  const auto t0 = std::chrono::steady_clock::now();
  StageResult sum;
  const fs::path dir = fs::path(ctx.output_dir) / "harvest";
  fs::create_directories(dir);
  auto rel = [](const std::string& name) { return "harvest/" + name; };
  const GreenhouseRow row = sampleGreenhouseRow(options.row);
  const double dt = 1.0 / options.rate_Hz;
  const int stride = std::max(1, static_cast<int>(std::lround(options.rate_Hz / 200.0)));

  std::ostringstream md;
  md << "# Harvest torque study: " << ctx.study.name << "\n\n"
     << "Approaches to a greenhouse row sampled from thesis Table 2.2 (seed " << options.row.seed
     << ", " << row.fruits.size() << " fruits on " << row.stems_xy.size()
     << " stems), planned with the heuristic planner of section 5.3.2 (r_e = "
     << report::fixed(options.approach.entry_radius_m, 3) << " m, s_a = " << options.approach.s_a
     << ", s_e = " << options.approach.s_e << ", T = " << options.approach.duration_s
     << " s), tracked with the null-space IK (joint limits weight " << options.w_joint_limits
     << ", manipulability weight " << options.w_manipulability << ") at "
     << report::fixed(options.rate_Hz, 0)
     << " Hz, inverse dynamics and drive chain per joint (docs/dynamics.md). Margins are "
        "(limit - value) / limit; n/a = limit not given in the design.\n\n";

  ordered_json js;
  js["study"] = ctx.study.name;
  js["row"] = {{"seed", options.row.seed},
               {"stems", row.stems_xy.size()},
               {"fruits", row.fruits.size()},
               {"row_to_row_m", row.row_to_row_m}};
  js["approach"] = {{"entry_radius_m", options.approach.entry_radius_m},
                    {"s_a", options.approach.s_a},
                    {"s_e", options.approach.s_e},
                    {"duration_s", options.approach.duration_s}};
  js["rate_Hz"] = options.rate_Hz;
  js["designs"] = ordered_json::array();

  for (const StudyDesign& sd : ctx.study.designs) {
    const Model& model = sd.model;
    if (!options.designs.empty() && std::find(options.designs.begin(), options.designs.end(),
                                              model.name) == options.designs.end())
      continue;
    if (model.inertias.empty())
      throw InputError(
          model.file, 0, "inertia",
          "design '" + model.name + "' has no [[inertia]] data; the harvest stage needs it");
    DesignResult d = unitDesign(ctx, model, options, row, sum.units_resumed);
    const int n = model.dof();
    const std::string base = model.name;
    const std::string mprefix = "dynamics/" + model.name + "/";

    writeFruitCsv(model, d, (dir / (base + "_fruits.csv")).string());
    sum.files.push_back(rel(base + "_fruits.csv"));

    int evaluated = 0, feasible = 0, feasible_nf = 0;
    std::vector<std::uint8_t> flags;
    for (const FruitResult& f : d.fruits) {
      flags.push_back(f.evaluated() && f.with_friction.feasible ? 1 : 0);
      if (!f.evaluated()) continue;
      ++evaluated;
      feasible += f.with_friction.feasible;
      feasible_nf += f.without_friction.feasible;
    }
    const double nfr = std::max<double>(1, static_cast<double>(d.fruits.size()));
    auto& M = sum.metrics;
    M.scalars[mprefix + "evaluated_fraction"] = evaluated / nfr;
    M.scalars[mprefix + "feasible_fraction"] = feasible / nfr;
    M.scalars[mprefix + "feasible_fraction_no_friction"] = feasible_nf / nfr;
    M.flags[mprefix + "fruit_feasible"] = flags;
    const std::vector<JointAggregate> agg = aggregate(model, d);
    for (int i = 0; i < n; ++i) {
      if (!agg[i].has_drive) continue;
      const std::string jp = mprefix + model.joints[i].name + "/";
      M.scalars[jp + "peak_current_A"] = agg[i].worst[0].value;
      M.scalars[jp + "rms_current_A"] = agg[i].worst[1].value;
      M.scalars[jp + "peak_motor_speed_radps"] = agg[i].worst[2].value;
      M.scalars[jp + "peak_current_no_friction_A"] = agg[i].peak_current_no_friction;
    }

    // Plots and profiles of the first fruits.
    std::vector<int> plotted;  // the first plot_fruits evaluated fruits
    for (const FruitResult& f : d.fruits)
      if (f.evaluated() && static_cast<int>(plotted.size()) < options.plot_fruits)
        plotted.push_back(f.fruit);
    for (const FruitResult& f : d.fruits) {
      if (std::find(plotted.begin(), plotted.end(), f.fruit) == plotted.end()) continue;
      const std::string fb = base + "_fruit" + std::to_string(f.fruit);
      writeProfileCsv(model, f, dt, (dir / (fb + "_profile.csv")).string());
      sum.files.push_back(rel(fb + "_profile.csv"));
      writeFileAtomic(
          (dir / (fb + "_effort.svg")).string(),
          report::svgLinePlot(profileSeries(model, f.with_friction.effort, dt, "", stride), "t [s]",
                              "joint torque [N m] / lift force [N]",
                              model.name + " fruit " + std::to_string(f.fruit) + ": Q"));
      writeFileAtomic(
          (dir / (fb + "_current.svg")).string(),
          report::svgLinePlot(
              profileSeries(model, f.with_friction.current, dt, "", stride), "t [s]",
              "motor current [A]",
              model.name + " fruit " + std::to_string(f.fruit) + ": current with friction"));
      // Fig. 4.1: one joint with and without friction (joint 3 as in the thesis).
      const int jf = std::min(2, n - 1);
      auto a = profileSeries(model, f.with_friction.current, dt, " with friction", stride);
      auto b = profileSeries(model, f.without_friction.current, dt, " without friction", stride);
      writeFileAtomic((dir / (fb + "_friction.svg")).string(),
                      report::svgLinePlot({a[jf], b[jf]}, "t [s]", "motor current [A]",
                                          model.name + " fruit " + std::to_string(f.fruit) + ": " +
                                              model.joints[jf].name + " with/without friction"));
      for (const char* s : {"_effort.svg", "_current.svg", "_friction.svg"})
        sum.files.push_back(rel(fb + s));
    }

    // Report: per-fruit and per-joint tables.
    md << "## " << model.name << "\n\n"
       << "Fruits evaluated: " << evaluated << " of " << d.fruits.size()
       << "; feasible with friction: " << feasible << ", without friction: " << feasible_nf
       << ".\n\n";
    std::vector<std::vector<std::string>> rows;
    for (const FruitResult& f : d.fruits) {
      rows.push_back({std::to_string(f.fruit),
                      report::fixed(f.p_fruit_W.x(), 3) + ", " + report::fixed(f.p_fruit_W.y(), 3) +
                          ", " + report::fixed(f.p_fruit_W.z(), 3),
                      f.status, f.evaluated() ? failureText(model, f.with_friction) : "-",
                      f.evaluated() ? failureText(model, f.without_friction) : "-",
                      f.evaluated() ? report::scientific(f.max_position_error_m, 2) : "-"});
    }
    md << report::markdownTable({"fruit", "position [m]", "status", "with friction (fails first)",
                                 "without friction", ">max TCP error [m]"},
                                rows)
       << "\n";
    rows.clear();
    for (int i = 0; i < n; ++i) {
      const JointAggregate& a = agg[i];
      if (!a.has_drive) {
        rows.push_back({model.joints[i].name, report::fixed(a.peak_effort, 2), "no drive", "", "",
                        "", "", "", "", ""});
        continue;
      }
      const auto& pc = a.worst[0];
      const auto& rc = a.worst[1];
      const auto& sc = a.worst[2];
      const auto& vc = a.worst[3];
      rows.push_back({model.joints[i].name, report::fixed(a.peak_effort, 2),
                      report::fixed(pc.value, 2) + " / " + limitText(pc, 1), marginText(pc),
                      report::fixed(rc.value, 2) + " / " + limitText(rc, 1), marginText(rc),
                      report::fixed(sc.value, 0) + " / " + limitText(sc, 0), marginText(sc),
                      report::fixed(vc.value, 1) + " / " + limitText(vc, 0), marginText(vc),
                      report::fixed(a.peak_current_no_friction, 2),
                      report::percent(a.friction_share, 0), std::to_string(a.exceeded_fruits)});
    }
    md << "Per joint, worst over the evaluated fruits (with friction):\n\n"
       << report::markdownTable(
              {"joint", ">peak Q [N m, N]", ">peak I [A] / limit", ">margin", ">RMS I [A] / limit",
               ">margin", ">motor speed [rad/s] / limit", ">margin", ">voltage [V] / limit",
               ">margin", ">peak I no friction [A]", ">friction share", ">fruits over a limit"},
              rows)
       << "\nfriction share = max_t |I_friction - I_frictionless| / max_t |I_friction| over the "
          "evaluated fruits (thesis Fig. 4.1 reports up to 50 % for joint 3).\n\n";
    for (int f : plotted)
      md << "![" << model.name << " fruit " << f << " current](" << base << "_fruit" << f
         << "_current.svg) ![friction](" << base << "_fruit" << f << "_friction.svg)\n\n";

    ordered_json dj;
    dj["design"] = model.name;
    dj["evaluated"] = evaluated;
    dj["feasible"] = feasible;
    dj["feasible_no_friction"] = feasible_nf;
    dj["fruits"] = ordered_json::array();
    for (const FruitResult& f : d.fruits) {
      ordered_json fj = {{"fruit", f.fruit},
                         {"p_W", {f.p_fruit_W.x(), f.p_fruit_W.y(), f.p_fruit_W.z()}},
                         {"status", f.status}};
      if (f.evaluated()) {
        fj["feasible"] = f.with_friction.feasible;
        fj["feasible_no_friction"] = f.without_friction.feasible;
        if (!f.with_friction.feasible) {
          fj["failing_joint"] = model.joints[f.with_friction.failing_joint].name;
          fj["failing_quantity"] = toString(f.with_friction.failing_quantity);
          fj["failure_time_s"] = f.with_friction.failure_time_s;
        }
        fj["max_position_error_m"] = f.max_position_error_m;
      }
      dj["fruits"].push_back(fj);
    }
    dj["joints"] = ordered_json::array();
    for (int i = 0; i < n; ++i) {
      ordered_json jj = {{"joint", model.joints[i].name},
                         {"has_drive", agg[i].has_drive},
                         {"peak_effort", agg[i].peak_effort}};
      for (int q = 0; q < kDriveQuantityCount; ++q) {
        const QuantityCheck& c = agg[i].worst[q];
        ordered_json cj = {{"value", c.value}, {"limit", c.limit}};
        cj["margin"] = c.checked ? ordered_json(c.margin) : ordered_json(nullptr);
        jj[toString(static_cast<DriveQuantity>(q))] = cj;
      }
      jj["peak_current_no_friction"] = agg[i].peak_current_no_friction;
      jj["friction_share"] = agg[i].friction_share;
      dj["joints"].push_back(jj);
    }

    // Holding-load grid.
    if (options.grid) {
      const HarvestGrid& g = *options.grid;
      io::ImageGrid img;
      img.dims = {g.axes[0].count(), g.axes[1].count(), g.axes[2].count()};
      for (int a = 0; a < 3; ++a) {
        img.origin[a] = g.axes[a].from;
        img.spacing[a] = g.axes[a].step;
      }
      const long np = img.points();
      io::NamedArray status{"status", io::ArrayType::Int32, 1, std::vector<double>(np)};
      io::NamedArray ratio{"max_current_ratio", io::ArrayType::Float64, 1, std::vector<double>(np)};
      // The lift carries the whole arm: its holding current hardly depends on the pose, so the map
      // also shows the largest ratio over the revolute joints.
      io::NamedArray ratio_rev{"max_current_ratio_revolute", io::ArrayType::Float64, 1,
                               std::vector<double>(np)};
      io::NamedArray limj{"limiting_joint", io::ArrayType::Int32, 1, std::vector<double>(np)};
      std::vector<io::NamedArray> hold;
      for (int i = 0; i < n; ++i)
        hold.push_back({"holding_" + model.joints[i].name, io::ArrayType::Float64, 1,
                        std::vector<double>(np)});
      int reachable = 0, limited = 0;
      double max_ratio = 0;
      int max_ratio_joint = -1;
      std::vector<int> limiting_count(n, 0);
      const double nan = std::numeric_limits<double>::quiet_NaN();
      for (long p = 0; p < np; ++p) {
        const GridPointResult& gp = d.grid[p];
        if (!gp.reachable) {
          status.values[p] = 0;
          ratio.values[p] = nan;
          ratio_rev.values[p] = nan;
          limj.values[p] = -1;
          for (auto& h : hold) h.values[p] = nan;
          continue;
        }
        ++reachable;
        const bool ok = gp.holding.feasible;
        if (!ok) {
          ++limited;
          ++limiting_count[gp.holding.limiting_joint];
        }
        if (gp.holding.limiting_joint >= 0 && gp.holding.max_ratio > max_ratio) {
          max_ratio = gp.holding.max_ratio;
          max_ratio_joint = gp.holding.limiting_joint;
        }
        status.values[p] = ok ? 1 : 2;
        ratio.values[p] = gp.holding.max_ratio;
        ratio_rev.values[p] = 0;
        for (int i = 0; i < n; ++i)
          if (isRevolute(model, i))
            ratio_rev.values[p] = std::max(ratio_rev.values[p], gp.holding.current_ratio[i]);
        limj.values[p] = gp.holding.limiting_joint;
        for (int i = 0; i < n; ++i) hold[i].values[p] = gp.holding.effort[i];
      }
      img.point_arrays = {status, ratio, ratio_rev, limj};
      for (auto& h : hold) img.point_arrays.push_back(std::move(h));
      io::writeVti((dir / (base + "_holding.vti")).string(), img);
      sum.files.push_back(rel(base + "_holding.vti"));
      M.scalars[mprefix + "holding_reachable_fraction"] = reachable / static_cast<double>(np);
      M.scalars[mprefix + "holding_drive_limited_fraction"] =
          reachable > 0 ? limited / static_cast<double>(reachable) : 0.0;
      M.scalars[mprefix + "holding_max_current_ratio"] = max_ratio;
      md << "Largest static holding current over the reachable grid points: "
         << report::percent(max_ratio, 1) << " of the continuous limit"
         << (max_ratio_joint >= 0 ? " (" + model.joints[max_ratio_joint].name + ")" : std::string())
         << ".\n\n";

      // Maps over the first two axes with more than one value (the first slice of a 3-D grid).
      std::vector<int> axes;
      for (int a = 0; a < 3; ++a)
        if (img.dims[a] > 1) axes.push_back(a);
      if (axes.size() >= 2) {
        const int a0 = axes[0], a1 = axes[1];
        auto index = [&](int u, int v) {
          std::array<long, 3> ijk{0, 0, 0};
          ijk[a0] = u;
          ijk[a1] = v;
          return ijk[0] + img.dims[0] * (ijk[1] + static_cast<long>(img.dims[1]) * ijk[2]);
        };
        const auto statusImg = report::renderCellMap(img.dims[a0], img.dims[a1], [&](int u, int v) {
          const int s = static_cast<int>(status.values[index(u, v)]);
          return s == 0   ? report::Rgb{200, 200, 200}
                 : s == 1 ? report::Rgb{60, 170, 90}
                          : report::Rgb{215, 50, 40};
        });
        // Raw maps (.png) and figures with axes and legends (.svg, shown in the report).
        const char* an[3] = {"x", "y", "z"};
        auto figure = [&](const std::string& title) {
          report::MapFigure f;
          f.title = title;
          f.x = report::cellAxis(std::string(an[a0]) + " [m]", img.origin[a0],
                                 img.origin[a0] + img.spacing[a0] * (img.dims[a0] - 1), img.spacing[a0]);
          f.y = report::cellAxis(std::string(an[a1]) + " [m]", img.origin[a1],
                                 img.origin[a1] + img.spacing[a1] * (img.dims[a1] - 1), img.spacing[a1]);
          return f;
        };
        report::MapFigure status_fig = figure(model.name + ": static holding");
        status_fig.legend = {{report::Rgb{60, 170, 90}, "holdable"},
                             {report::Rgb{215, 50, 40}, "drive limit"},
                             {report::Rgb{200, 200, 200}, "unreachable"}};
        report::writePng((dir / (base + "_holding_map.png")).string(), statusImg);
        writeFileAtomic((dir / (base + "_holding_map.svg")).string(), report::svgMapFigure(statusImg, status_fig));
        const auto ratioImg = report::renderCellMap(img.dims[a0], img.dims[a1], [&](int u, int v) {
          const double r = ratio_rev.values[index(u, v)];
          return std::isfinite(r) ? report::viridis(r / 1.5) : report::Rgb{200, 200, 200};
        });
        report::MapFigure ratio_fig = figure(model.name + ": max |I| / I_continuous (revolute joints)");
        ratio_fig.scale = report::ColourScale{report::viridis, 0, 1.5, "max |I| / I_continuous"};
        ratio_fig.legend = {{report::Rgb{200, 200, 200}, "unreachable"}};
        report::writePng((dir / (base + "_holding_ratio.png")).string(), ratioImg);
        writeFileAtomic((dir / (base + "_holding_ratio.svg")).string(), report::svgMapFigure(ratioImg, ratio_fig));
        for (const char* f : {"_holding_map.png", "_holding_map.svg", "_holding_ratio.png", "_holding_ratio.svg"})
          sum.files.push_back(rel(base + f));
        md << "Static holding (gravity + payload) over the grid, tool heading "
           << report::fixed(g.gamma_rad * 180 / M_PI, 0) << " deg: " << reachable << " of " << np
           << " points reachable, " << limited
           << " of them drive-limited (|I| > continuous current). "
           << "Map axes: " << an[a0] << " to the right, " << an[a1]
           << " upwards; green = holdable, red = drive limit, grey = unreachable. Second map: "
              "max |I| / I_continuous over the revolute joints (viridis, 0 to 1.5; the lift's "
              "ratio is "
              "nearly constant, it carries the whole arm).\n\n"
           << "![holding map](" << base << "_holding_map.svg) ![ratio](" << base
           << "_holding_ratio.svg)\n\n";
      } else {
        md << "Static holding over the grid: " << reachable << " of " << np << " points reachable, "
           << limited << " drive-limited.\n\n";
      }
      std::vector<std::vector<std::string>> lrows;
      for (int i = 0; i < n; ++i)
        if (limiting_count[i] > 0)
          lrows.push_back({model.joints[i].name, std::to_string(limiting_count[i])});
      if (!lrows.empty())
        md << report::markdownTable({"limiting joint", ">grid points"}, lrows) << "\n";
      dj["grid"] = {{"points", np},
                    {"reachable", reachable},
                    {"drive_limited", limited},
                    {"max_current_ratio", max_ratio}};
    }
    js["designs"].push_back(dj);
    if (results) results->push_back(std::move(d));
  }
  writeFileAtomic((dir / "report.md").string(), md.str());
  writeFileAtomic((dir / "summary.json").string(), js.dump(2) + "\n");
  sum.files.push_back(rel("report.md"));
  sum.files.push_back(rel("summary.json"));
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sum;
}

}  // namespace armstudy::harvest
