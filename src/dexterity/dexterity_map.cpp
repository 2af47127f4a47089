#include "dexterity/dexterity_map.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>

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

JointVector coldStart(const Model& model, int k) {
  const int n = model.dof();
  JointVector q(n);
  // splitmix64 on (k, i): portable and independent of the standard library's engines.
  auto mix = [](std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
  };
  for (int i = 0; i < n; ++i) {
    const auto& l = model.joints[i].limits;
    const double mid = 0.5 * (l.q_min + l.q_max);
    if (k == 0) {
      q[i] = mid;
    } else {
      const double r = (mix(static_cast<std::uint64_t>(k) * 131 + i) >> 11) * 0x1.0p-53;
      q[i] = mid + (r - 0.5) * 0.8 * (l.q_max - l.q_min);  // inner 80 % of the range
    }
  }
  return q;
}

CellResult solveCell(const Model& model, KinematicsWorkspace& ws, ik::ObjectiveContext& ctx,
                     const ik::WeightedObjective& objective, const DexterityOptions& options,
                     const StemGrid::Cell& cell, const JointVector* warm_plain,
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
  ik::PoseSolveResult best;
  best.error.position_m = best.error.orientation_rad = std::numeric_limits<double>::infinity();
  if (warm_plain) {
    ++r.starts;
    best = ik::solvePose(model, ws, cell.target, *warm_plain, w_inv, options.solve);
  }
  for (int k = 0; !accept(best) && k < options.cold_starts; ++k) {
    ++r.starts;
    ik::PoseSolveResult s = ik::solvePose(model, ws, cell.target, coldStart(model, k), w_inv, options.solve);
    if (s.error.position_m + defaults::kOrientationLength_m * s.error.orientation_rad <
        best.error.position_m + defaults::kOrientationLength_m * best.error.orientation_rad)
      best = s;
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
  const int rows = options.grid.z_m.count, cols = options.grid.gamma_rad.count;
#pragma omp parallel num_threads(map.threads)
  {
    KinematicsWorkspace ws(model);
    ik::ObjectiveContext ctx(model, ws);
#pragma omp for schedule(dynamic, 1)
    for (int iz = 0; iz < rows; ++iz) {
      // One row = one circle around the stem, solved in gamma order with warm starts.
      JointVector prev_plain, prev_opt;
      bool have_prev = false;
      for (int ig = 0; ig < cols; ++ig) {
        const StemGrid::Cell cell = options.grid.cell(ig, iz);
        CellResult r = solveCell(model, ws, ctx, objective, options, cell,
                                 have_prev ? &prev_plain : nullptr, have_prev ? &prev_opt : nullptr);
        have_prev = r.reachable;
        if (r.reachable) {
          prev_plain = r.q_plain;
          prev_opt = r.q_opt;
        }
        map.cells[options.grid.index(ig, iz)] = std::move(r);
      }
    }
  }
  map.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return map;
}

}  // namespace armstudy::dexterity
