#pragma once
// The dexterity map audit (docs/dexterity.md, "How far is the map from an independent search"):
// cells drawn at random (seeded), each searched from many random configurations within the joint
// limits that do not use the map's path (no chaining, no neighbours): every start is solved onto
// the cell's pose and optimised in the null space with the map's own objective and settings; the
// best objective found is compared with the map's.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dexterity/dexterity_map.hpp"

namespace armstudy::dexterity {

struct AuditCell {
  int index = 0;  // grid.index(i_gamma, i_z)
  double gamma_rad = 0, z_m = 0;
  ReachStatus map_status = ReachStatus::OutOfReach;
  bool map_reachable = false, audit_reachable = false;      // audit: a collision-free posture found
  double H_map = 0, H_audit = 0;                            // objective (eq. 5.51, lower is better)
  double manipulability_map = 0, manipulability_audit = 0;  // at the optimised configurations
  double gap = 0;            // (H_map - H_audit) / |H_audit|: > 0 where the audit found better
  int solutions = 0;         // starts that reached the pose collision-free
  int on_pose = 0;           // starts that reached the pose (in collision or not)
  ik::DescentTally descent;  // the null-space descents of its starts
};

struct DexterityAudit {
  int cells = 0, starts = 0;
  std::uint64_t seed = 0;
  int both_reachable = 0;
  int within_1pct = 0, within_5pct = 0;  // of both_reachable: gap <= 1 % / 5 %
  int reach_contradicted = 0;            // map: unreachable, audit: a solution (a wrong verdict)
  int audit_missed = 0;  // map: reachable, audit: none (the map's solution is a witness)
  // Per map status (ReachStatus): cells with that verdict, and those the audit contradicted (a
  // collision-free posture for SelfCollision / ObstacleCollision, any posture on the pose for
  // OutOfReach / JointLimits).
  std::array<int, kReachStatusCount> verdicts{}, contradicted{};
  double worst_gap = 0;
  int worst_index = -1;
  ik::DescentTally descent;  // over all rows, in row order
  double seconds = 0;
  std::vector<AuditCell> rows;  // in cell index order
  // Share of the cells the map and audit both reach that are within `tol` (1 when none).
  double shareWithin1Percent() const {
    return both_reachable ? double(within_1pct) / both_reachable : 1.0;
  }
};

// `cells` distinct cell indices of [0, n) drawn with `seed`, ascending (all when cells >= n).
std::vector<int> drawCells(int n, int cells, std::uint64_t seed);

// Audits `map` (computed with `options`) on options.audit_cells cells with options.audit_starts
// starts each (seed options.audit_seed). Deterministic for any thread and process count: the
// cells are a loop the processes of `runner` share (null: this process alone).
DexterityAudit auditDexterityMap(const Model& model, const DexterityOptions& options,
                                 const DexterityMap& map, int threads,
                                 const UnitRunner* runner = nullptr);

// The cells given explicitly (tests: every cell of a small grid).
DexterityAudit auditDexterityCells(const Model& model, const DexterityOptions& options,
                                   const DexterityMap& map, const std::vector<int>& cells,
                                   int starts, std::uint64_t seed, int threads,
                                   const UnitRunner* runner = nullptr);

}  // namespace armstudy::dexterity
