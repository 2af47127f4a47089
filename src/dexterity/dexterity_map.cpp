#include "dexterity/dexterity_map.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>

#include "collision/collision_term.hpp"
#include "collision/reach_collision.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "common/first_exception.hpp"
#include "dexterity/stem_collision.hpp"
#include "metrics/measure_declarations.hpp"

namespace armstudy::dexterity {

namespace {

// Every declared measure (metrics/measure_declarations.hpp), in the declared order.
void putMeasures(UnitWriter& w, const metrics::DexterityMeasures& m) {
  for (const metrics::MeasureDeclaration& d : metrics::measureDeclarations()) w.put(m.*d.value);
}
void getMeasures(UnitReader& r, metrics::DexterityMeasures& m) {
  for (const metrics::MeasureDeclaration& d : metrics::measureDeclarations())
    m.*d.value = r.get<double>();
}

}  // namespace

void putCell(UnitWriter& w, const CellResult& c) {
  w.put<std::uint8_t>(c.reachable);
  w.put<std::uint8_t>(c.optimised);
  w.put<std::uint8_t>(static_cast<std::uint8_t>(c.status));
  w.put<std::int32_t>(c.colliding_pair);
  w.put(c.min_distance_m);
  w.putMatrix(c.q_plain);
  w.putMatrix(c.q_opt);
  putMeasures(w, c.plain);
  putMeasures(w, c.opt);
  for (const metrics::Ellipsoid* e : {&c.ellipsoid_plain, &c.ellipsoid_opt}) {
    w.putMatrix(e->axes_W);
    w.putMatrix(e->lengths);
  }
  for (double v : {c.H_plain, c.H_opt, c.position_error_m, c.orientation_error_rad}) w.put(v);
  w.put<std::int32_t>(c.starts);
  w.put<std::int32_t>(c.nullspace_iterations);
  w.put<std::int32_t>(static_cast<std::int32_t>(c.nullspace_status));
  putTally(w, c.descent);
}

void putTally(UnitWriter& w, const ik::DescentTally& t) {
  for (long v : {t.descents, t.changed, t.iterations, t.objective_evaluations, t.kernel_evaluations,
                 t.stopped[0], t.stopped[1], t.stopped[2], t.skipped})
    w.put<std::int64_t>(v);
  w.put(t.step_sum);
  w.put(t.last_step_sum);
}

void getTally(UnitReader& r, ik::DescentTally& t) {
  for (long* v : {&t.descents, &t.changed, &t.iterations, &t.objective_evaluations,
                  &t.kernel_evaluations, &t.stopped[0], &t.stopped[1], &t.stopped[2], &t.skipped})
    *v = static_cast<long>(r.get<std::int64_t>());
  t.step_sum = r.get<double>();
  t.last_step_sum = r.get<double>();
}

void getCell(UnitReader& r, CellResult& c) {
  c.reachable = r.get<std::uint8_t>() != 0;
  c.optimised = r.get<std::uint8_t>() != 0;
  const auto status = r.get<std::uint8_t>();
  if (status >= kReachStatusCount) r.fail();
  c.status = static_cast<ReachStatus>(status);
  c.colliding_pair = r.get<std::int32_t>();
  c.min_distance_m = r.get<double>();
  r.getMatrix(c.q_plain);
  r.getMatrix(c.q_opt);
  getMeasures(r, c.plain);
  getMeasures(r, c.opt);
  for (metrics::Ellipsoid* el : {&c.ellipsoid_plain, &c.ellipsoid_opt}) {
    r.getMatrix(el->axes_W);
    r.getMatrix(el->lengths);
  }
  for (double* v : {&c.H_plain, &c.H_opt, &c.position_error_m, &c.orientation_error_rad})
    *v = r.get<double>();
  c.starts = r.get<std::int32_t>();
  c.nullspace_iterations = r.get<std::int32_t>();
  const auto st = r.get<std::int32_t>();
  if (st < 0 || st > static_cast<int>(ik::NullspaceStatus::NotOnPose)) r.fail();
  c.nullspace_status = static_cast<ik::NullspaceStatus>(st);
  getTally(r, c.descent);
}

const double kMapStationaryGradient = 1e-4;  // [H per rad or m]
const double kMapProofRadius = 0.04;         // [rad or m], below defaults::kMapSameBasin

ik::NullspaceOptions mapDescentOptions() {
  ik::NullspaceOptions o;
  o.quasi_newton = true;
  o.gradient_tolerance = kMapStationaryGradient;
  return o;
}

std::string DexterityOptions::validate() const {
  const std::string g = grid.validate();
  if (!g.empty()) return g;
  for (double w : {w_joint_limits, w_manipulability, w_transmission, w_collision})
    if (!std::isfinite(w) || w < 0) return "objective weights must be finite and >= 0";
  if (!(joint_limit_activation > 0 && joint_limit_activation < 0.5))
    return "joint_limit_activation must lie in (0, 0.5)";
  if (fixed_direction) {
    const double nrm = direction_W.norm();
    if (!std::isfinite(nrm) || nrm == 0) return "transmission direction u must not be zero";
    if (std::abs(nrm - 1.0) > 1e-6) return "transmission direction u must be a unit vector";
  }
  for (double w : joint_weights)
    if (!(w >= defaults::kMinWeight && w <= defaults::kMaxWeight))
      return "joint weights must lie in [1e-6, 1e6]";
  if (!(position_tolerance_m > 0) || !(orientation_tolerance_rad > 0))
    return "tolerances must be > 0";
  if (cold_starts < 1) return "cold_starts must be >= 1";
  if (solve.max_iterations < 1) return "solver max_iterations must be >= 1";
  if (!(collision_safety_distance_m > 0) || !std::isfinite(collision_safety_distance_m))
    return "collision safety distance must be a finite length > 0";
  if (!(collision.clearance_m >= 0) || !std::isfinite(collision.clearance_m))
    return "clearance must be a finite length >= 0";
  return nullspace.validate();
}

std::string DexterityOptions::validateFor(const Model& model) const {
  const std::string v = validate();
  if (!v.empty()) return v;
  if (!joint_weights.empty() && static_cast<int>(joint_weights.size()) != model.dof())
    return "joint_weights has " + std::to_string(joint_weights.size()) + " entries but design '" +
           model.name + "' has " + std::to_string(model.dof()) + " joints";
  if (model.dof() < taskDim(grid.task))
    return "design '" + model.name + "' has fewer joints than the task has components";
  return "";
}

ik::WeightedObjective DexterityOptions::buildObjective(const Model& model) const {
  ik::WeightedObjective obj;  // eq. (5.51); zero weights are dropped
  obj.add(w_joint_limits, std::make_shared<ik::JointLimitTerm>(model, joint_limit_activation));
  obj.add(w_manipulability, std::make_shared<ik::ManipulabilityTerm>(measure_space));
  obj.add(w_transmission, std::make_shared<ik::TransmissionTerm>(measure_space));
  const StemCollision col = collisionFor(model);
  if (w_collision > 0 && col.enabled()) {
    collision::CollisionPotentialOptions po;
    po.safety_distance_m = collision_safety_distance_m;
    po.self = col.self;
    po.environment = !col.obstacles.empty();
    obj.add(w_collision, std::make_shared<collision::CollisionTerm>(po, col.obstacles));
  }
  return obj;
}

IkOptions DexterityOptions::exactSolveOptions() const {
  IkOptions o = solve;
  o.joint_weights = joint_weights;
  return o;
}

int DexterityMap::reachable() const {
  int r = 0;
  for (const auto& c : cells) r += c.reachable ? 1 : 0;
  return r;
}

namespace {

JointVector weightInverse(const DexterityOptions& options, int n) {
  ik::RedundancyOptions ro;
  ro.joint_weights = options.joint_weights;
  return ro.weightInverse(n);
}

bool onPose(const IkResult& s, const DexterityOptions& options) {
  return s.position_error_m <= options.position_tolerance_m &&
         s.orientation_error_rad <= options.orientation_tolerance_rad;
}

// The cell's results once r.q_plain (and its errors) hold a reachable plain solution: the plain
// objective, then (redundant designs) the null-space optimisation from `start` (the plain
// configuration when null), retried from the plain configuration when `start` led to a worse
// optimum, so the optimised configuration is never worse than the plain one. The measures of
// both postures are measureCell's.
void finishCell(const Model& model, KinematicsWorkspace& ws, ik::ObjectiveContext& ctx,
                const ik::WeightedObjective& objective, const DexterityOptions& options,
                const ik::NullspaceOptions& descent, const StemGrid::Cell& cell,
                const JointVector& w_inv, const JointVector* start, CellResult& r) {
  ctx.u_W = options.fixed_direction ? options.direction_W : cell.u_W;
  forwardKinematicsAndJacobian(model, ws, r.q_plain);
  ctx.prepare(r.q_plain);
  r.H_plain = objective.evaluate(ctx, nullptr);
  r.q_opt = r.q_plain;
  r.H_opt = r.H_plain;
  if (model.dof() <= cell.target.rows() || objective.empty()) return;
  const JointVector& from = start ? *start : r.q_plain;
  ik::NullspaceResult o =
      ik::optimiseAtPose(model, ws, ctx, cell.target, from, objective, w_inv, descent);
  r.descent.add(o);
  if (from != r.q_plain && !(o.H_final <= r.H_plain)) {
    o = ik::optimiseAtPose(model, ws, ctx, cell.target, r.q_plain, objective, w_inv, descent);
    r.descent.add(o);
  }
  r.optimised = o.status != ik::NullspaceStatus::NotOnPose;
  r.nullspace_status = o.status;
  r.nullspace_iterations = o.iterations;
  r.q_opt = o.q;
  r.H_opt = o.H_final;
}

// finishCell, then the collision verdict (settleCollision). A quasi-Newton descent that ended in
// contact (the cell then keeps its start) is redone with the steepest directions: where the
// minimum of H on the pose lies in contact, quasi-Newton steps jump into it and steepest steps stop
// short of it (docs/dexterity.md, "What is computed").
void optimiseAndSettle(const Model& model, KinematicsWorkspace& ws, ik::ObjectiveContext& ctx,
                       const ik::WeightedObjective& objective, const DexterityOptions& options,
                       const StemGrid::Cell& cell, const JointVector& w_inv,
                       const JointVector* start, collision::CollisionWorkspace* cws,
                       CellResult& r) {
  const CellResult before = r;
  finishCell(model, ws, ctx, objective, options, options.nullspace, cell, w_inv, start, r);
  const bool descended = r.optimised;
  settleCollision(model, ws, cws, options.collision, r);
  if (!(options.nullspace.quasi_newton && descended && r.reachable && !r.optimised)) return;
  ik::NullspaceOptions steepest = options.nullspace;
  steepest.quasi_newton = false;
  const ik::DescentTally tally = r.descent;
  r = before;
  r.descent = tally;
  finishCell(model, ws, ctx, objective, options, steepest, cell, w_inv, start, r);
  settleCollision(model, ws, cws, options.collision, r);
}

}  // namespace

void measureCell(const Model& model, KinematicsWorkspace& ws, const DexterityOptions& options,
                 const StemGrid::Cell& cell, CellResult& r) {
  const Eigen::Vector3d u = options.fixed_direction ? options.direction_W : cell.u_W;
  forwardKinematicsAndJacobian(model, ws, r.q_plain);
  r.plain = metrics::tcpMeasures(ws, options.measure_space, u, true);
  r.ellipsoid_plain = metrics::translationalEllipsoid(ws);
  if (r.q_opt == r.q_plain) {  // not optimised, or put back to its start
    r.opt = r.plain;
    r.ellipsoid_opt = r.ellipsoid_plain;
    return;
  }
  forwardKinematicsAndJacobian(model, ws, r.q_opt);
  r.opt = metrics::tcpMeasures(ws, options.measure_space, u, true);
  r.ellipsoid_opt = metrics::translationalEllipsoid(ws);
}

bool cellFromSeed(const Model& model, KinematicsWorkspace& ws, IkWorkspace& ik_ws,
                  ik::ObjectiveContext& ctx, const ik::WeightedObjective& objective,
                  const DexterityOptions& options, const StemGrid::Cell& cell,
                  const JointVector& seed, CellResult& out, collision::CollisionWorkspace* cws,
                  bool measure, const JointVector* proven) {
  const JointVector w_inv = weightInverse(options, model.dof());
  const IkResult s = solvePose(model, ik_ws, cell.target, options.exactSolveOptions(), 0, &seed);
  // On the pose as exactly as the null-space stage needs (a seed that only gets within the
  // study's tolerance is no candidate: its optimum would be off the pose).
  if (!(onPose(s, options) && s.position_error_m <= options.nullspace.pose_tolerance &&
        s.orientation_error_rad <= options.nullspace.pose_tolerance))
    return false;
  out = CellResult{};
  if (proven && (s.q - *proven).cwiseAbs().maxCoeff() <= kMapProofRadius) {
    out.descent.skipped = 1;
    return false;
  }
  out.reachable = true;
  out.starts = 1;
  out.q_plain = s.q;
  out.position_error_m = s.position_error_m;
  out.orientation_error_rad = s.orientation_error_rad;
  optimiseAndSettle(model, ws, ctx, objective, options, cell, w_inv, nullptr, cws, out);
  if (measure) measureCell(model, ws, options, cell, out);
  return true;
}

bool provenOptimum(const Model& model, KinematicsWorkspace& ws, ik::ObjectiveContext& ctx,
                   const ik::WeightedObjective& objective, const DexterityOptions& options,
                   const StemGrid::Cell& cell, const CellResult& c) {
  if (!c.reachable || !c.optimised) return false;
  ctx.u_W = options.fixed_direction ? options.direction_W : cell.u_W;
  return ik::projectedGradient(model, ws, ctx, cell.target, c.q_opt, objective,
                               weightInverse(options, model.dof())) <= kMapStationaryGradient;
}

CellResult solveCell(const Model& model, KinematicsWorkspace& ws, IkWorkspace& ik_ws,
                     ik::ObjectiveContext& ctx, const ik::WeightedObjective& objective,
                     const DexterityOptions& options, const StemGrid::Cell& cell,
                     std::uint64_t cell_id, const JointVector* warm_plain,
                     const JointVector* warm_opt, collision::CollisionWorkspace* cws) {
  CellResult r;
  const int n = model.dof();
  const JointVector w_inv = weightInverse(options, n);
  const IkOptions exact = options.exactSolveOptions();
  auto cost = [](const IkResult& s) {
    return s.position_error_m + defaults::kOrientationLength_m * s.orientation_error_rad;
  };
  IkResult best;
  best.q = warm_plain ? *warm_plain : JointVector::Zero(n);
  best.position_error_m = best.orientation_error_rad = std::numeric_limits<double>::infinity();
  if (warm_plain) {
    ++r.starts;
    best = solvePose(model, ik_ws, cell.target, exact, cell_id, warm_plain);
  }
  if (!onPose(best, options)) {
    // The reachability solver (thesis eq. 3.2), then the local solve polishes its solution to the
    // tight tolerance of options.solve.
    IkOptions io;
    io.position_tolerance_m = options.position_tolerance_m;
    io.orientation_tolerance_rad = options.orientation_tolerance_rad;
    io.max_starts = options.cold_starts;
    io.classify_failures = true;  // an unreachable cell's reason: joint limits or out of reach
    const IkResult ir = solvePose(model, ik_ws, cell.target, io, cell_id, warm_plain);
    r.starts += ir.starts;
    r.status = ir.status == ReachStatus::Reachable ? ReachStatus::OutOfReach : ir.status;
    const IkResult s = solvePose(model, ik_ws, cell.target, exact, cell_id, &ir.q);
    if (cost(s) < cost(best)) best = s;
  }
  r.q_plain = best.q;
  r.position_error_m = best.position_error_m;
  r.orientation_error_rad = best.orientation_error_rad;
  r.reachable = onPose(best, options);
  if (!r.reachable) {
    r.q_opt = r.q_plain;
    return r;
  }
  if (cws) escapeCollision(model, ws, ik_ws, *cws, options, cell, cell_id, r);
  // The null-space descent starts from the pose solution nearest the previous cell's optimum.
  JointVector start;
  bool chained = false;
  if (warm_opt && n > cell.target.rows() && !objective.empty()) {
    const IkResult s = solvePose(model, ik_ws, cell.target, exact, cell_id, warm_opt);
    if (s.position_error_m <= options.nullspace.pose_tolerance &&
        s.orientation_error_rad <= options.nullspace.pose_tolerance) {
      start = s.q;
      chained = true;
    }
  }
  optimiseAndSettle(model, ws, ctx, objective, options, cell, w_inv, chained ? &start : nullptr,
                    cws, r);
  measureCell(model, ws, options, cell, r);
  return r;
}

DexterityMap computeDexterityMap(const Model& model, const DexterityOptions& options, int threads) {
  std::vector<ItemRange> all;
  if (options.grid.z_m.count > 0) all.push_back({0, options.grid.z_m.count});
  DexterityMap map = computeDexterityRows(model, options, all, threads);
  searchDexterityMap(model, options, map, threads);
  return map;
}

DexterityMap computeDexterityRows(const Model& model, const DexterityOptions& options,
                                  const std::vector<ItemRange>& row_ranges, int threads,
                                  const RowsDone& on_done) {
  const std::string why = options.validateFor(model);
  ARMSTUDY_CHECK(why.empty(), why);
  const auto t0 = std::chrono::steady_clock::now();
  DexterityMap map;
  map.design = model.name;
  map.dof = model.dof();
  map.grid = options.grid;
  map.cells.resize(options.grid.size());
  map.threads = threads > 0 ? threads : omp_get_max_threads();
  const StemCollision col = options.collisionFor(model);
  map.collision = col.enabled();
  if (map.collision) map.pair_names = collision::collisionPairNames(model, col.obstacles, col.self);
  const ik::WeightedObjective objective = options.buildObjective(model);
  const int cols = options.grid.gamma_rad.count;
  std::vector<std::pair<std::size_t, int>> work;  // (range, row), in order
  for (std::size_t k = 0; k < row_ranges.size(); ++k) {
    const ItemRange& r = row_ranges[k];
    ARMSTUDY_CHECK(0 <= r.begin && r.begin < r.end && r.end <= options.grid.z_m.count,
                   "dexterity row range out of bounds");
    for (long iz = r.begin; iz < r.end; ++iz) work.emplace_back(k, static_cast<int>(iz));
  }
  RangeCountdown countdown(row_ranges);
  FirstException failure;
  const int n_work = static_cast<int>(work.size());
#pragma omp parallel num_threads(map.threads)
  {
    KinematicsWorkspace ws(model);
    IkWorkspace ik_ws(model);
    ik::ObjectiveContext ctx(model, ws);
    collision::CollisionWorkspace cws(model);
    collision::CollisionWorkspace* cw = map.collision ? &cws : nullptr;
#pragma omp for schedule(dynamic, 1)
    for (int w = 0; w < n_work; ++w) {
      const std::size_t k = work[w].first;  // not a structured binding: captured below (clang)
      const int iz = work[w].second;
      // One row = one circle around the stem, solved in gamma order with warm starts.
      JointVector prev_plain, prev_opt;
      bool have_prev = false;
      for (int step = 0; step < cols; ++step) {
        const int ig = options.descending ? cols - 1 - step : step;
        const StemGrid::Cell cell = options.grid.cell(ig, iz);
        CellResult r =
            solveCell(model, ws, ik_ws, ctx, objective, options, cell,
                      static_cast<std::uint64_t>(options.grid.index(ig, iz)),
                      have_prev ? &prev_plain : nullptr, have_prev ? &prev_opt : nullptr, cw);
        have_prev = r.reachable;
        if (r.reachable) {
          prev_plain = r.q_plain;
          prev_opt = r.q_opt;
        }
        map.cells[options.grid.index(ig, iz)] = std::move(r);
      }
      if (countdown.itemDone(k) && on_done) failure.call([&] { on_done(k, map); });
    }
  }
  failure.rethrow();
  map.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return map;
}

}  // namespace armstudy::dexterity
