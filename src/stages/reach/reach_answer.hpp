#pragma once
// The reach stage's answer (private to stages/reach): which design reaches most and is more
// dexterous, from the stage's summary and the grid's maps.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "report/document.hpp"
#include "stages/reach/reach_report.hpp"

namespace armstudy::reach_report {

// One design on a grid or pose list, as the answer compares it.
struct DesignCoverage {
  std::string design;
  long reachable = 0, joint_limits = 0;  // poses reachable, and blocked by joint limits
  double fraction = 0;                   // reachable / poses
  long boundary = 0;  // reachable poses beside an unreachable one (boundaryPoses; 0 on a list)
};
// The poses of a grid only one design of a pair reaches.
struct PairCoverage {
  std::string a, b;
  long a_only = 0, b_only = 0;
};
// The dexterity of a pair where both reach (dexterityComparison): the mean manipulability of each
// and the more dexterous one, "" when the parts disagree.
struct PairVerdict {
  std::string a, b, better;
  double mean_a = 0, mean_b = 0;
  long both = 0;  // poses both reach
};
// A design's largest reach found on a grid against its reference_reach_m.
struct ReachAgainstReference {
  std::string design;
  double reference_m = 0;
  double found_m = 0;  // < 0: no pose reached
  double resolution_m = 0;
};
// A grid or pose list as the answer sees it.
struct CoverageFacts {
  std::string what;  // "grid `<name>`", "pose list `<name>`"
  long poses = 0;
  std::vector<DesignCoverage> designs;
  std::vector<PairCoverage> pairs;
  std::vector<PairVerdict> verdicts;
  std::vector<ReachAgainstReference> references;
};
// What the stage's answer rests on: its grids, then its pose lists, and the designs evaluated
// without collision volumes while the study checks collisions.
struct ReachFacts {
  std::vector<CoverageFacts> sets;
  std::vector<std::string> without_volumes;
};

// The stage's answer and warnings (StageResult::answer/warnings) from its facts: per grid and
// pose list, which design reaches most and by how much, and the dexterity verdicts where both
// reach; a design that reaches nothing is a warning.
void reachAnswer(const ReachFacts& facts, std::vector<std::string>& answer,
                 std::vector<std::string>& warnings);

// Dexterity of design pairs on the poses both reach: mean manipulability and its translational and
// rotational parts of each, and a verdict that ranks the pair only when the combined value and
// both parts agree. Appends a table and a list of verdicts to doc and the verdicts to `verdicts`;
// returns the summary.json block. The
// designs' parts are computed on `threads` threads each.
nlohmann::ordered_json dexterityComparison(
    const std::vector<const Model*>& models, const TaskGrid& g,
    const std::vector<PoseSweep>& sweeps,
    const std::vector<std::pair<std::size_t, std::size_t>>& pairs, int threads,
    report::Document& doc, std::vector<PairVerdict>& verdicts);

}  // namespace armstudy::reach_report
