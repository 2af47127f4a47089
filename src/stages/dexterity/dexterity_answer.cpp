// The dexterity stage's answer block (dexterity_output.hpp, dexterityAnswer).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/defaults.hpp"
#include "common/format.hpp"
#include "metrics/dexterity_measures.hpp"
#include "report/markdown.hpp"
#include "report/ranking.hpp"
#include "stages/dexterity/dexterity_output.hpp"
#include "stages/dexterity/dexterity_status.hpp"

namespace armstudy::dexterity {

namespace {

double ratio(long a, long n) { return n ? double(a) / double(n) : 0.0; }

std::string share(long a, long n) {
  return report::percent(ratio(a, n)) + " (" + std::to_string(a) + " of " + std::to_string(n) +
         " cells)";
}

// Which half of the plant a design can approach (thesis section 3.2.1): the near and far half at
// the map's own spacing with what limits each, without neighbouring stems, and the range over the
// row sweep's spacings.
std::string rowHalvesAnswer(const std::string& design, const std::vector<RowHalves>& row) {
  const RowHalves& m = row[0];
  std::string a = "`" + design + "` can approach the near half of the plant (|gamma| < 90 deg, " +
                  "the robot's side of the row) at " + share(m.near_reachable, m.near_cells) +
                  " and the far half at " + share(m.far_reachable, m.far_cells);
  if (m.spacing_m > 0)
    a += ", with the neighbouring stems at " + formatFixedOr(m.spacing_m, 3, "-") + " m";
  a += " (near half limited by " + m.near_limited_by + ", far half by " + m.far_limited_by + ")";
  double near_lo = 2, near_hi = -1, far_lo = 2, far_hi = -1, s_lo = 1e9, s_hi = -1;
  for (std::size_t k = 1; k < row.size(); ++k) {
    const RowHalves& r = row[k];
    if (r.spacing_m <= 0) {
      a += "; without neighbouring stems " +
           report::percent(ratio(r.near_reachable, r.near_cells)) + " and " +
           report::percent(ratio(r.far_reachable, r.far_cells));
      continue;
    }
    const double n = ratio(r.near_reachable, r.near_cells), f = ratio(r.far_reachable, r.far_cells);
    near_lo = std::min(near_lo, n), near_hi = std::max(near_hi, n);
    far_lo = std::min(far_lo, f), far_hi = std::max(far_hi, f);
    s_lo = std::min(s_lo, r.spacing_m), s_hi = std::max(s_hi, r.spacing_m);
  }
  if (s_hi > 0)
    a += "; with the stems " + formatFixedOr(s_lo, 3, "-") + "-" + formatFixedOr(s_hi, 3, "-") +
         " m apart the near half " + report::percent(near_lo) + "-" + report::percent(near_hi) +
         ", the far half " + report::percent(far_lo) + "-" + report::percent(far_hi);
  return a + ".";
}

}  // namespace

void dexterityAnswer(const Study& study, const DexterityOptions& options,
                     const std::vector<DesignAnswerFacts>& facts, StageResult& sum) {
  struct Row {
    std::string design;
    double mean, reach, valley_z_m;
    std::size_t order;  // the study's design order
  };
  std::vector<Row> rows;
  for (std::size_t di = 0; di < study.designs.size(); ++di) {
    const std::string& name = study.designs[di].model.name;
    rows.push_back({name, facts[di].manipulability_mean_optimised, facts[di].reachable_fraction,
                    facts[di].valley_z_m, di});
    if (rows.back().reach == 0)
      sum.warnings.push_back("`" + name + "` reaches none of the " +
                             std::to_string(options.grid.size()) + " cells around the stem.");
  }
  // The row's question (which half can be approached) first, then the ranking.
  for (std::size_t di = 0; di < study.designs.size(); ++di)
    if (!facts[di].row.empty())
      sum.answer.push_back(rowHalvesAnswer(study.designs[di].model.name, facts[di].row));
  rows.erase(std::remove_if(rows.begin(), rows.end(), [](const Row& r) { return r.reach == 0; }),
             rows.end());
  if (rows.empty()) return;
  std::stable_sort(rows.begin(), rows.end(),
                   [](const Row& a, const Row& b) { return a.mean > b.mean; });
  auto item = [](const Row& r) {
    return "`" + r.design + "` " + formatG(r.mean, 3) + " (reaching " + report::percent(r.reach) +
           " of the cells" +
           (std::isnan(r.valley_z_m)
                ? ""
                : "; valley at z " + formatFixedOr(r.valley_z_m, 2, "-") + " m") +
           ")";
  };
  std::vector<double> means;
  for (const Row& r : rows) means.push_back(r.mean);
  const std::size_t level = report::levelWithFirst(means, defaults::kAuditTolerance * means[0]);
  // Level designs in the study's order: their order by mean is noise.
  std::stable_sort(rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(level),
                   [](const Row& a, const Row& b) { return a.order < b.order; });
  std::string a = "Around the stem (" + std::to_string(options.grid.size()) + " cells, " +
                  metrics::toString(options.measure_space) +
                  " manipulability, optimised in the null space): ";
  if (rows.size() == 1)
    a += "mean ";
  else if (level == 1)
    a += "highest mean ";
  else
    a += level == rows.size() ? "level means, " : "highest means, level with each other, ";
  for (std::size_t k = 0; k < level; ++k) a += (k == 0 ? "" : "; ") + item(rows[k]);
  for (std::size_t k = level; k < rows.size(); ++k)
    a += (k == level ? "; then " : ", ") + item(rows[k]);
  if (level > 1) {
    const double spread = (means[0] - means[level - 1]) / means[0];  // sorted by mean
    a += ". The level ones differ by " + report::percent(spread, 2) +
         ", inside the map's resolution (a cell's value is trusted to " +
         report::percent(defaults::kAuditTolerance, 0) + ", the audit's tolerance)";
  }
  sum.answer.push_back(a + ".");
}

}  // namespace armstudy::dexterity
