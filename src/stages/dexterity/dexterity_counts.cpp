#include "stages/dexterity/dexterity_output.hpp"
#include "study/descent_counts.hpp"

// The descent counts of a dexterity map, written beside the manifest's timings.
namespace armstudy::dexterity {

namespace {

void addKind(const std::string& p, const ik::DescentTally& t, double seconds,
             std::vector<StageCount>& out) {
  addTallyCounts(p, t, out);
  out.push_back({p + "skipped_proven", static_cast<double>(t.skipped)});
  out.push_back({p + "objective_evaluations", static_cast<double>(t.objective_evaluations)});
  out.push_back({p + "iterations_per_descent", perCount(t.iterations, t.descents), false});
  out.push_back(
      {p + "kernel_evaluations_per_descent", perCount(t.kernel_evaluations, t.descents), false});
  out.push_back({p + "mean_step", perCount(t.step_sum, t.iterations), false});
  out.push_back({p + "mean_last_step", perCount(t.last_step_sum, t.descents), false});
  addStoppedCounts(p, t, out);
  out.push_back({p + "us_per_descent", perCount(1e6 * seconds, t.descents), false});
}

}  // namespace

void addDescentCounts(const std::string& prefix, const DexterityMap& map,
                      const DexterityAudit* audit, double chain_seconds,
                      std::vector<StageCount>& out) {
  const MapSearchSummary& s = map.search;
  const std::string p = prefix + "/descents/";
  ik::DescentTally all;
  double seconds = chain_seconds + s.seed_seconds + s.neighbour_seconds + s.collision_seconds;
  addKind(p + "chain/", s.chain, chain_seconds, out);
  addKind(p + "seed/", s.seed, s.seed_seconds, out);
  addKind(p + "neighbour/", s.neighbour, s.neighbour_seconds, out);
  addKind(p + "collision/", s.collision, s.collision_seconds, out);
  for (const ik::DescentTally* t : {&s.chain, &s.seed, &s.neighbour, &s.collision}) all.add(*t);
  if (audit) {
    addKind(p + "audit/", audit->descent, audit->seconds, out);
    all.add(audit->descent);
    seconds += audit->seconds;
  }
  out.push_back({p + "descents", static_cast<double>(all.descents)});
  out.push_back({p + "changed", static_cast<double>(all.changed)});
  out.push_back({p + "skipped_proven", static_cast<double>(all.skipped)});
  out.push_back({p + "kernel_evaluations", static_cast<double>(all.kernel_evaluations)});
  out.push_back({p + "us_per_descent", perCount(1e6 * seconds, all.descents), false});
}

}  // namespace armstudy::dexterity
