#include "dexterity/dexterity_audit.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "common/errors.hpp"

namespace armstudy::dexterity {

std::vector<int> drawCells(int n, int cells, std::uint64_t seed) {
  const std::vector<long> d = drawIndices(n, cells, seed);
  return std::vector<int>(d.begin(), d.end());
}

DexterityAudit auditDexterityCells(const Model& model, const DexterityOptions& options,
                                   const DexterityMap& map, const std::vector<int>& cells,
                                   int starts, std::uint64_t seed, int threads) {
  const auto t0 = std::chrono::steady_clock::now();
  const StemGrid& g = options.grid;
  ARMSTUDY_CHECK(static_cast<int>(map.cells.size()) == g.size(),
                 "dexterity map does not match its grid");
  DexterityAudit a;
  a.cells = static_cast<int>(cells.size());
  a.starts = starts;
  a.seed = seed;
  a.rows.resize(cells.size());
  const ik::WeightedObjective objective = options.buildObjective(model);
  const int G = g.gamma_rad.count;
  const int nt = threads > 0 ? threads : omp_get_max_threads();
#pragma omp parallel num_threads(nt)
  {
    KinematicsWorkspace ws(model);
    ik::ObjectiveContext ctx(model, ws);
    collision::CollisionWorkspace cws(model);
    collision::CollisionWorkspace* cw = options.collisionFor(model).enabled() ? &cws : nullptr;
    JointVector q0(model.dof());
#pragma omp for schedule(dynamic, 1)
    for (int k = 0; k < static_cast<int>(cells.size()); ++k) {
      const int idx = cells[k];
      ARMSTUDY_CHECK(idx >= 0 && idx < g.size(), "audit cell out of range");
      const StemGrid::Cell cell = g.cell(idx % G, idx / G);
      AuditCell& row = a.rows[k];
      row.index = idx;
      row.gamma_rad = cell.gamma;
      row.z_m = cell.z;
      const CellResult& m = map.cells[idx];
      row.map_reachable = m.reachable;
      row.map_status = m.status;
      row.H_map = m.H_opt;
      row.manipulability_map = m.opt.manipulability;
      double best = std::numeric_limits<double>::infinity();
      for (int s = 0; s < starts; ++s) {
        randomConfiguration(model, seed, static_cast<std::uint64_t>(idx), s, q0);
        CellResult cand;
        if (!cellFromSeed(model, ws, ctx, objective, options, cell, q0, cand, cw)) continue;
        ++row.on_pose;
        if (!cand.reachable) continue;
        ++row.solutions;
        if (cand.H_opt < best) {
          best = cand.H_opt;
          row.manipulability_audit = cand.opt.manipulability;
        }
      }
      row.audit_reachable = row.solutions > 0;
      row.H_audit = row.audit_reachable ? best : std::numeric_limits<double>::quiet_NaN();
      row.gap = row.map_reachable && row.audit_reachable
                    ? (row.H_map - row.H_audit) / std::max(std::abs(row.H_audit), 1e-12)
                    : std::numeric_limits<double>::quiet_NaN();
    }
  }
  for (const AuditCell& r : a.rows) {
    if (r.map_reachable && r.audit_reachable) {
      ++a.both_reachable;
      a.within_1pct += r.gap <= 0.01 ? 1 : 0;
      a.within_5pct += r.gap <= 0.05 ? 1 : 0;
      if (r.gap > a.worst_gap) {
        a.worst_gap = r.gap;
        a.worst_index = r.index;
      }
    }
    a.reach_contradicted += !r.map_reachable && r.audit_reachable ? 1 : 0;
    const int st = static_cast<int>(r.map_status);
    ++a.verdicts[st];
    // A verdict is contradicted by a posture it says does not exist: a collision-free one for
    // "in collision", any posture on the pose for "joint limits" / "out of reach".
    const bool in_collision = r.map_status == ReachStatus::SelfCollision ||
                              r.map_status == ReachStatus::ObstacleCollision;
    if (!r.map_reachable && (in_collision ? r.audit_reachable : r.on_pose > 0))
      ++a.contradicted[st];
    a.audit_missed += r.map_reachable && !r.audit_reachable ? 1 : 0;
  }
  a.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return a;
}

DexterityAudit auditDexterityMap(const Model& model, const DexterityOptions& options,
                                 const DexterityMap& map, int threads) {
  return auditDexterityCells(
      model, options, map, drawCells(options.grid.size(), options.audit_cells, options.audit_seed),
      options.audit_starts, options.audit_seed, threads);
}

}  // namespace armstudy::dexterity
