#pragma once
// The manifest counts of a map search's local descents (StageResult::counts), shared by the stages
// that tally them: names "<p>descents", "<p>changed", ... with p a prefix ending in '/'.
#include <string>
#include <vector>

#include "ik/nullspace.hpp"
#include "study/stage.hpp"

namespace armstudy {

// total / n, 0 without n: a mean per descent or per iteration.
inline double perCount(double total, long n) {
  return n > 0 ? total / static_cast<double>(n) : 0.0;
}

// The counts every descent tally has (ik::DescentTally, the reach sweep's SolveTally): descents,
// those whose outcome a result took, their iterations and their kernel evaluations.
template <class Tally>
void addTallyCounts(const std::string& p, const Tally& t, std::vector<StageCount>& out) {
  out.push_back({p + "descents", static_cast<double>(t.descents)});
  out.push_back({p + "changed", static_cast<double>(t.changed)});
  out.push_back({p + "iterations", static_cast<double>(t.iterations)});
  out.push_back({p + "kernel_evaluations", static_cast<double>(t.kernel_evaluations)});
}

// How the null-space descents of t ended: "<p>stopped_<status>" per ik::NullspaceStatus.
inline void addStoppedCounts(const std::string& p, const ik::DescentTally& t,
                             std::vector<StageCount>& out) {
  for (int k = 0; k < 3; ++k)
    out.push_back({p + "stopped_" + ik::toString(static_cast<ik::NullspaceStatus>(k)),
                   static_cast<double>(t.stopped[k])});
}

}  // namespace armstudy
