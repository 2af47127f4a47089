#include "stages/reach/reach_counts.hpp"

#include "study/descent_counts.hpp"

namespace armstudy::reach_counts {

namespace {

void addKind(const std::string& p, const SolveTally& t, std::vector<StageCount>& out) {
  addTallyCounts(p, t, out);
  out.push_back({p + "iterations_per_descent", perCount(t.iterations, t.descents), false});
  out.push_back(
      {p + "kernel_evaluations_per_descent", perCount(t.kernel_evaluations, t.descents), false});
  for (int k = 0; k < kReachStatusCount; ++k) {
    const auto st = static_cast<ReachStatus>(k);
    if (st != ReachStatus::TorqueLimit)  // the dynamics stage's; a descent never ends with it
      out.push_back({p + "ended_" + toString(st), static_cast<double>(t.ended[k])});
  }
}

void addEscapes(const std::string& p, const ik::DescentTally& t, std::vector<StageCount>& out) {
  addTallyCounts(p, t, out);
  out.push_back({p + "objective_evaluations", static_cast<double>(t.objective_evaluations)});
  out.push_back({p + "iterations_per_descent", perCount(t.iterations, t.descents), false});
  addStoppedCounts(p, t, out);
}

}  // namespace

void addDescentCounts(const std::string& prefix, const PoseSweep& map,
                      const SweepSearchSummary& search, const ReachAudit* audit,
                      std::vector<StageCount>& out) {
  const std::string p = prefix + "/descents/";
  const std::pair<const char*, const SolveTally*> kinds[] = {
      {"chain", &map.chain},
      {"propagation", &search.propagation},
      {"collision_starts", &search.collision_starts},
      {"box", &search.box},
      {"best", &search.best},
      {"audit", audit ? &audit->descents : nullptr}};
  SolveTally all;
  for (const auto& [kind, tally] : kinds) {
    if (!tally) continue;
    addKind(p + kind + "/", *tally, out);
    all.add(*tally);
  }
  addEscapes(p + "escape/", all.escape, out);
  addTallyCounts(p, all, out);
}

}  // namespace armstudy::reach_counts
