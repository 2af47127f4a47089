#include "stages/reach/reach_counts.hpp"

namespace armstudy::reach_counts {

namespace {

double per(double total, long n) { return n > 0 ? total / static_cast<double>(n) : 0.0; }

// The statuses a descent can end with (TorqueLimit is the dynamics stage's).
constexpr ReachStatus kEnded[] = {
    ReachStatus::Reachable,     ReachStatus::OutOfReach,
    ReachStatus::JointLimits,   ReachStatus::RepresentationSingularity,
    ReachStatus::SelfCollision, ReachStatus::ObstacleCollision};

void addKind(const std::string& p, const SolveTally& t, std::vector<StageCount>& out) {
  out.push_back({p + "descents", static_cast<double>(t.descents)});
  out.push_back({p + "changed", static_cast<double>(t.changed)});
  out.push_back({p + "iterations", static_cast<double>(t.iterations)});
  out.push_back({p + "kernel_evaluations", static_cast<double>(t.kernel_evaluations)});
  out.push_back({p + "iterations_per_descent", per(t.iterations, t.descents), false});
  out.push_back(
      {p + "kernel_evaluations_per_descent", per(t.kernel_evaluations, t.descents), false});
  for (const ReachStatus st : kEnded)
    out.push_back(
        {p + "ended_" + toString(st), static_cast<double>(t.ended[static_cast<std::size_t>(st)])});
}

void addEscapes(const std::string& p, const ik::DescentTally& t, std::vector<StageCount>& out) {
  out.push_back({p + "descents", static_cast<double>(t.descents)});
  out.push_back({p + "changed", static_cast<double>(t.changed)});
  out.push_back({p + "iterations", static_cast<double>(t.iterations)});
  out.push_back({p + "kernel_evaluations", static_cast<double>(t.kernel_evaluations)});
  out.push_back({p + "objective_evaluations", static_cast<double>(t.objective_evaluations)});
  out.push_back({p + "iterations_per_descent", per(t.iterations, t.descents), false});
  for (int k = 0; k < 3; ++k)
    out.push_back({p + "stopped_" + ik::toString(static_cast<ik::NullspaceStatus>(k)),
                   static_cast<double>(t.stopped[k])});
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
  out.push_back({p + "descents", static_cast<double>(all.descents)});
  out.push_back({p + "changed", static_cast<double>(all.changed)});
  out.push_back({p + "iterations", static_cast<double>(all.iterations)});
  out.push_back({p + "kernel_evaluations", static_cast<double>(all.kernel_evaluations)});
}

}  // namespace armstudy::reach_counts
