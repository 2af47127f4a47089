#include "dexterity/dexterity_audit.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "common/errors.hpp"
#include "study/shared_loop.hpp"

namespace armstudy::dexterity {

namespace {

constexpr char kAuditMagic[] = "armstudy-dexterity-audit-v3";

}  // namespace

std::vector<int> drawCells(int n, int cells, std::uint64_t seed) {
  const std::vector<long> d = drawIndices(n, cells, seed);
  return std::vector<int>(d.begin(), d.end());
}

namespace {

// The map's side of each audited row (known to every process): the cell and the map's result.
void fillMapSide(const DexterityMap& map, const StemGrid& g, const std::vector<int>& cells,
                 DexterityAudit& a) {
  const int G = g.gamma_rad.count;
  for (std::size_t k = 0; k < cells.size(); ++k) {
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
  }
}

}  // namespace

DexterityAudit auditDexterityCells(const Model& model, const DexterityOptions& options,
                                   const DexterityMap& map, const std::vector<int>& cells,
                                   int starts, std::uint64_t seed, int threads,
                                   const UnitRunner* runner) {
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
  fillMapSide(map, g, cells, a);
  // The searches, shared among the processes of a distributed run (a cell per chunk: each is
  // `starts` searches); the best objective travels in H_audit until every row is in.
  SharedLoop loop;
  loop.id = "dexterity-audit/" + map.design;
  loop.items = static_cast<long>(cells.size());
  loop.chunk = 1;
  loop.compute = [&](const std::vector<SharedLoop::Chunk>& mine) {
    const std::vector<long> items = SharedLoop::itemsOf(mine);
    const long n = static_cast<long>(items.size());
#pragma omp parallel num_threads(nt)
    {
      KinematicsWorkspace ws(model);
      IkWorkspace ik_ws(model);
      ik::ObjectiveContext ctx(model, ws);
      collision::CollisionWorkspace cws(model);
      collision::CollisionWorkspace* cw = options.collisionFor(model).enabled() ? &cws : nullptr;
      JointVector q0(model.dof());
#pragma omp for schedule(dynamic, 1)
      for (long m = 0; m < n; ++m) {
        AuditCell& row = a.rows[static_cast<std::size_t>(items[static_cast<std::size_t>(m)])];
        const StemGrid::Cell cell = g.cell(row.index % G, row.index / G);
        double best = std::numeric_limits<double>::infinity();
        for (int s = 0; s < starts; ++s) {
          randomConfiguration(model, seed, static_cast<std::uint64_t>(row.index), s, q0);
          CellResult cand;
          const bool landed =
              cellFromSeed(model, ws, ik_ws, ctx, objective, options, cell, q0, cand, cw, false);
          row.descent.add(cand.descent);
          if (!landed) continue;
          ++row.on_pose;
          if (!cand.reachable) continue;
          ++row.solutions;
          if (cand.H_opt < best) {
            best = cand.H_opt;
            measureCell(model, ws, options, cell, cand);
            row.manipulability_audit = cand.opt.manipulability;
          }
        }
        row.H_audit = best;
      }
    }
  };
  loop.pack = [&](std::size_t, const ItemRange& r) {
    UnitWriter w(kAuditMagic);
    for (long t = r.begin; t < r.end; ++t) {
      const AuditCell& row = a.rows[static_cast<std::size_t>(t)];
      w.put<std::int32_t>(row.on_pose);
      w.put<std::int32_t>(row.solutions);
      w.put(row.manipulability_audit);
      w.put(row.H_audit);
      putTally(w, row.descent);
    }
    return w.bytes();
  };
  loop.unpack = [&](std::size_t, const ItemRange& r, const std::string& bytes) {
    UnitReader rd(bytes, kAuditMagic);
    for (long t = r.begin; t < r.end; ++t) {
      AuditCell& row = a.rows[static_cast<std::size_t>(t)];
      row.on_pose = rd.get<std::int32_t>();
      row.solutions = rd.get<std::int32_t>();
      row.manipulability_audit = rd.get<double>();
      row.H_audit = rd.get<double>();
      getTally(rd, row.descent);
    }
    ARMSTUDY_CHECK(rd.finished(), "the audit's rows arrive whole");
  };
  runSharedLoop(runner, loop);
  for (AuditCell& row : a.rows) {
    row.audit_reachable = row.solutions > 0;
    if (!row.audit_reachable) row.H_audit = std::numeric_limits<double>::quiet_NaN();
    row.gap = row.map_reachable && row.audit_reachable
                  ? (row.H_map - row.H_audit) / std::max(std::abs(row.H_audit), 1e-12)
                  : std::numeric_limits<double>::quiet_NaN();
  }
  for (const AuditCell& r : a.rows) {
    a.descent.add(r.descent);
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
                                 const DexterityMap& map, int threads, const UnitRunner* runner) {
  return auditDexterityCells(
      model, options, map, drawCells(options.grid.size(), options.audit_cells, options.audit_seed),
      options.audit_starts, options.audit_seed, threads, runner);
}

}  // namespace armstudy::dexterity
