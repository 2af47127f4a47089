#include "dexterity/dexterity_map.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <exception>
#include <limits>

#include "common/errors.hpp"

namespace armstudy::dexterity {

std::string DexterityOptions::validate() const {
  const std::string g = grid.validate();
  if (!g.empty()) return g;
  for (double w : {w_joint_limits, w_manipulability, w_transmission})
    if (!std::isfinite(w) || w < 0) return "objective weights must be finite and >= 0";
  if (!(joint_limit_activation > 0 && joint_limit_activation < 0.5))
    return "joint_limit_activation must lie in (0, 0.5)";
  if (fixed_direction) {
    const double nrm = direction_W.norm();
    if (!std::isfinite(nrm) || nrm == 0) return "transmission direction u must not be zero";
    if (std::abs(nrm - 1.0) > 1e-6) return "transmission direction u must be a unit vector";
  }
  for (double w : joint_weights)
    if (!std::isfinite(w) || w <= 0) return "joint weights must be finite and > 0";
  if (!(position_tolerance_m > 0) || !(orientation_tolerance_rad > 0))
    return "tolerances must be > 0";
  if (cold_starts < 1) return "cold_starts must be >= 1";
  if (solve.max_iterations < 1) return "solver max_iterations must be >= 1";
  return nullspace.validate();
}

std::string DexterityOptions::validateFor(const Model& model) const {
  const std::string v = validate();
  if (!v.empty()) return v;
  if (!joint_weights.empty() && static_cast<int>(joint_weights.size()) != model.dof())
    return "joint_weights has " + std::to_string(joint_weights.size()) + " entries but design '" +
           model.name + "' has " + std::to_string(model.dof()) + " joints";
  if (model.dof() < ik::taskDim(grid.task))
    return "design '" + model.name + "' has fewer joints than the task has components";
  return "";
}

ik::WeightedObjective DexterityOptions::buildObjective(const Model& model) const {
  ik::WeightedObjective obj;  // eq. (5.51); zero weights are dropped
  obj.add(w_joint_limits, std::make_shared<ik::JointLimitTerm>(model, joint_limit_activation));
  obj.add(w_manipulability, std::make_shared<ik::ManipulabilityTerm>(measure_space));
  obj.add(w_transmission, std::make_shared<ik::TransmissionTerm>(measure_space));
  return obj;
}

int DexterityMap::reachable() const {
  int r = 0;
  for (const auto& c : cells) r += c.reachable ? 1 : 0;
  return r;
}

IkTarget reachTarget(const ik::PoseTarget& t) {
  IkTarget r;
  r.task_space = TaskSpace::position();
  r.w_d.head<3>() = t.p_WT;
  switch (t.kind) {
    case ik::PoseTaskKind::Position: break;
    case ik::PoseTaskKind::PositionAxis:
      r.tool_axis = true;
      r.z_d_W = t.R_WT.col(2);
      break;
    case ik::PoseTaskKind::FullPose: {
      r.task_space = TaskSpace::fullPose();
      const CardanAngles c = cardanFromRotation(t.R_WT);
      r.w_d.tail<3>() << c.alpha, c.beta, c.gamma;
      break;
    }
  }
  return r;
}

CellResult solveCell(const Model& model, KinematicsWorkspace& ws, IkWorkspace& ik_ws,
                     ik::ObjectiveContext& ctx, const ik::WeightedObjective& objective,
                     const DexterityOptions& options, const StemGrid::Cell& cell,
                     std::uint64_t cell_id, const JointVector* warm_plain,
                     const JointVector* warm_opt) {
  CellResult r;
  const int n = model.dof();
  ik::RedundancyOptions ro;
  ro.joint_weights = options.joint_weights;
  const JointVector w_inv = ro.weightInverse(n);
  const Eigen::Vector3d u = options.fixed_direction ? options.direction_W : cell.u_W;
  auto accept = [&](const ik::PoseSolveResult& s) {
    return s.error.position_m <= options.position_tolerance_m &&
           s.error.orientation_rad <= options.orientation_tolerance_rad;
  };
  auto cost = [](const ik::PoseSolveResult& s) {
    return s.error.position_m + defaults::kOrientationLength_m * s.error.orientation_rad;
  };
  ik::PoseSolveResult best;
  best.q = warm_plain ? *warm_plain : JointVector::Zero(n);
  best.error.position_m = best.error.orientation_rad = std::numeric_limits<double>::infinity();
  if (warm_plain) {
    ++r.starts;
    best = ik::solvePose(model, ws, cell.target, *warm_plain, w_inv, options.solve);
  }
  if (!accept(best)) {
    // The reachability solver (thesis eq. 3.2), then the local solve polishes its solution to the
    // tight tolerance of options.solve.
    IkOptions io;
    io.position_tolerance_m = options.position_tolerance_m;
    io.orientation_tolerance_rad = options.orientation_tolerance_rad;
    io.max_starts = options.cold_starts;
    io.classify_failures = false;
    const IkResult ir = solvePose(model, ik_ws, reachTarget(cell.target), io, cell_id, warm_plain);
    r.starts += ir.starts;
    const ik::PoseSolveResult s = ik::solvePose(model, ws, cell.target, ir.q, w_inv, options.solve);
    if (cost(s) < cost(best)) best = s;
  }
  r.q_plain = best.q;
  r.position_error_m = best.error.position_m;
  r.orientation_error_rad = best.error.orientation_rad;
  r.reachable = accept(best);
  if (!r.reachable) {
    r.q_opt = r.q_plain;
    return r;
  }
  ctx.u_W = u;
  forwardKinematicsAndJacobian(model, ws, r.q_plain);
  r.plain = metrics::tcpMeasures(ws, options.measure_space, u, true);
  r.ellipsoid_plain = metrics::translationalEllipsoid(ws);
  ctx.prepare(r.q_plain);
  r.H_plain = objective.evaluate(ctx, nullptr);
  r.q_opt = r.q_plain;
  r.opt = r.plain;
  r.ellipsoid_opt = r.ellipsoid_plain;
  r.H_opt = r.H_plain;
  if (n > ik::taskDim(cell.target.kind) && !objective.empty()) {
    JointVector start = r.q_plain;
    if (warm_opt) {
      const ik::PoseSolveResult s = ik::solvePose(model, ws, cell.target, *warm_opt, w_inv, options.solve);
      if (s.error.position_m <= options.nullspace.pose_tolerance &&
          s.error.orientation_rad <= options.nullspace.pose_tolerance)
        start = s.q;
    }
    ik::NullspaceResult o =
        ik::optimiseAtPose(model, ws, ctx, cell.target, start, objective, w_inv, options.nullspace);
    if (start != r.q_plain && !(o.H_final <= r.H_plain)) {
      // The chained start led to a worse local optimum: optimise from the plain solution instead,
      // so the optimised configuration is never worse than the plain one.
      o = ik::optimiseAtPose(model, ws, ctx, cell.target, r.q_plain, objective, w_inv, options.nullspace);
    }
    r.optimised = o.status != ik::NullspaceStatus::NotOnPose;
    r.nullspace_status = o.status;
    r.nullspace_iterations = o.iterations;
    r.q_opt = o.q;
    r.H_opt = o.H_final;
    forwardKinematicsAndJacobian(model, ws, r.q_opt);
    r.opt = metrics::tcpMeasures(ws, options.measure_space, u, true);
    r.ellipsoid_opt = metrics::translationalEllipsoid(ws);
  }
  return r;
}

DexterityMap computeDexterityMap(const Model& model, const DexterityOptions& options, int threads) {
  std::vector<ItemRange> all;
  if (options.grid.z_m.count > 0) all.push_back({0, options.grid.z_m.count});
  return computeDexterityRows(model, options, all, threads);
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
  std::exception_ptr failure;
  const int n_work = static_cast<int>(work.size());
#pragma omp parallel num_threads(map.threads)
  {
    KinematicsWorkspace ws(model);
    IkWorkspace ik_ws(model);
    ik::ObjectiveContext ctx(model, ws);
#pragma omp for schedule(dynamic, 1)
    for (int w = 0; w < n_work; ++w) {
      const auto [k, iz] = work[w];
      // One row = one circle around the stem, solved in gamma order with warm starts.
      JointVector prev_plain, prev_opt;
      bool have_prev = false;
      for (int ig = 0; ig < cols; ++ig) {
        const StemGrid::Cell cell = options.grid.cell(ig, iz);
        CellResult r = solveCell(model, ws, ik_ws, ctx, objective, options, cell,
                                 static_cast<std::uint64_t>(options.grid.index(ig, iz)),
                                 have_prev ? &prev_plain : nullptr, have_prev ? &prev_opt : nullptr);
        have_prev = r.reachable;
        if (r.reachable) {
          prev_plain = r.q_plain;
          prev_opt = r.q_opt;
        }
        map.cells[options.grid.index(ig, iz)] = std::move(r);
      }
      if (countdown.itemDone(k) && on_done) {
        try {
          on_done(k, map);
        } catch (...) {
#pragma omp critical(armstudy_dexterity_failure)
          if (!failure) failure = std::current_exception();
        }
      }
    }
  }
  if (failure) std::rethrow_exception(failure);
  map.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return map;
}

}  // namespace armstudy::dexterity
