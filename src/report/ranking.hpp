// Rankings that name a winner only when the study can tell: a difference inside what the study
// resolves (the audit's tolerance, a grid's spacing, the noise) is a tie, not a win.
#pragma once

#include <cstddef>
#include <vector>

namespace armstudy::report {

// How many leading entries of `best_first` (sorted, best first; larger is better) are level with
// the first: those whose distance to it is at most `resolution` (same unit as the values).
// Always at least 1 for a non-empty list.
inline std::size_t levelWithFirst(const std::vector<double>& best_first, double resolution) {
  std::size_t n = best_first.empty() ? 0 : 1;
  while (n < best_first.size() && best_first[0] - best_first[n] <= resolution) ++n;
  return n;
}

}  // namespace armstudy::report
