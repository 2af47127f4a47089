#pragma once
// The descent counts of a reach map (private to stages/reach), written beside the manifest's
// timings: <prefix>/descents/<kind>/... for the chains (chain), the map search's phases
// (propagation, collision_starts, box, best), the audit (audit) and the collision escape's
// null-space descents among all of them (escape), then the map's totals.
#include <string>
#include <vector>

#include "reach/reach_audit.hpp"
#include "reach/reach_sweep.hpp"
#include "study/stage.hpp"

namespace armstudy::reach_counts {

// `audit` may be null (no audit).
void addDescentCounts(const std::string& prefix, const PoseSweep& map,
                      const SweepSearchSummary& search, const ReachAudit* audit,
                      std::vector<StageCount>& out);

}  // namespace armstudy::reach_counts
