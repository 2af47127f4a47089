#pragma once
// The reach map audit (docs/reachability.md, "The audit"): poses drawn at random
// (seeded) from a grid, each searched from many random configurations within the joint limits,
// independently of the sweep (no warm starts, no neighbours): every start is one solve of the
// reachability solver from that configuration, and a solution counts when it is within the
// tolerances and, in collision-aware sweeps, clear of every checked pair. A status other than
// reachable is contradicted when the audit finds such a solution.
#include <array>
#include <cstdint>
#include <vector>

#include "reach/reach_sweep.hpp"

namespace armstudy {

struct ReachAuditPose {
  long index = 0;
  ReachStatus map_status = ReachStatus::OutOfReach;
  int solutions = 0;               // starts that ended in a (collision-free) solution
  double manipulability_map = 0;   // at the map's solution (reachable poses)
  double manipulability_best = 0;  // the largest the audit found
  SolveTally tally;                // its starts' pose solves (ended: in collision per the check)
};

struct ReachAudit {
  int poses = 0, starts = 0;
  std::uint64_t seed = 0;
  std::array<int, kReachStatusCount> by_status{};     // audited poses per map status
  std::array<int, kReachStatusCount> contradicted{};  // ... of which the audit found a solution
  int audit_missed = 0;  // map reachable, audit found none (the map's solution is the witness)
  int manipulability_compared = 0;  // reachable poses where the audit found solutions too
  int manipulability_within_5pct =
      0;  // ... whose map manipulability is >= 95 % of the audit's best
  double seconds = 0;
  SolveTally descents;               // over all rows
  std::vector<ReachAuditPose> rows;  // ascending pose index
  int contradictedTotal() const;
};

// Audits `sweep` (the whole sweep of `grid`, solved with `options` and `collision`) on `poses`
// poses drawn with `seed` (all when poses >= grid size), `starts` starts each. Poses the map
// calls reachable get every start (to compare manipulability); others stop at the first solution.
// Deterministic for any thread count. `runner`: the run's unit runner, which shares the audited
// poses among the processes of a distributed run (null: this process alone).
ReachAudit auditGridSweep(const Model& model, const TaskGrid& grid, const IkOptions& options,
                          const SweepCollision& collision, const PoseSweep& sweep, int poses,
                          int starts, std::uint64_t seed, int threads,
                          const UnitRunner* runner = nullptr);

}  // namespace armstudy
