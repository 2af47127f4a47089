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

void dexterityAnswer(const Study& study, const DexterityOptions& options,
                     const std::vector<double>& valley_z_m, StageResult& sum) {
  struct Row {
    std::string design;
    double mean, reach, valley_z_m;
    std::size_t order;  // the study's design order
  };
  std::vector<Row> rows;
  for (std::size_t di = 0; di < study.designs.size(); ++di) {
    const std::string& name = study.designs[di].model.name;
    const std::string p = "dexterity/" + name;
    rows.push_back({name, sum.metrics.scalars.at(p + "/manipulability_mean_optimised"),
                    sum.metrics.scalars.at(p + "/reachable_fraction"), valley_z_m[di], di});
    if (rows.back().reach == 0)
      sum.warnings.push_back("`" + name + "` reaches none of the " +
                             std::to_string(options.grid.size()) + " cells around the stem.");
  }
  rows.erase(std::remove_if(rows.begin(), rows.end(), [](const Row& r) { return r.reach == 0; }),
             rows.end());
  if (rows.empty()) return;
  std::stable_sort(rows.begin(), rows.end(),
                   [](const Row& a, const Row& b) { return a.mean > b.mean; });
  auto item = [](const Row& r) {
    return "`" + r.design + "` " + formatG(r.mean, 3) + " (reaching " + report::percent(r.reach) +
           " of the cells" +
           (std::isnan(r.valley_z_m) ? "" : "; valley at z " + fmt(r.valley_z_m, 2) + " m") + ")";
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
