#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "common/angles.hpp"
#include "common/format.hpp"
#include "metrics/measure_declarations.hpp"
#include "stages/dexterity/dexterity_status.hpp"
#include "stages/dexterity/dexterity_summary.hpp"

// The dexterity stage's report sections of one design and the designs side by side, as blocks.
namespace armstudy::dexterity {

namespace {

// "a/b" as a percentage with one decimal, "-" when b is 0.
// A row of the field statistics table: the extremes and where they are.
std::vector<std::string> statsRow(const std::string& what, const FieldStats& s) {
  if (!s.any) return {what, "-", "-", "-", "-"};
  return {what, formatFixedOr(s.min, 3, "-"),
          "gamma " + formatFixedOr(s.gamma_at_min * kRadToDeg, 0, "-") + " deg, z " +
              formatFixedOr(s.z_at_min, 2, "-") + " m",
          formatFixedOr(s.max, 3, "-"),
          "gamma " + formatFixedOr(s.gamma_at_max * kRadToDeg, 0, "-") + " deg, z " +
              formatFixedOr(s.z_at_max, 2, "-") + " m"};
}

// The design's numbers: reachable cells, best manipulability, valley, and the fields' extremes.
report::Document designNumbers(const DexterityOptions& options, const DexterityMap& map,
                               const MapFields& f, const MapSummary& s) {
  const std::string unit = manipulabilityUnit(options.measure_space);
  return report::Document()
      .paragraph(
          "Reachable: " + std::to_string(s.R) + " of " + std::to_string(map.cells.size()) +
          " cells (gamma < 0: " + formatShare(s.reach_neg, s.n_neg, 1) + ", gamma >= 0: " +
          formatShare(s.reach_pos, s.n_pos, 1) + "). Best manipulability (normalisation value): " +
          (s.R ? formatG(f.manipulability().best, 4) + " " + unit : "-") +
          ". Valley of the optimised map (the row of lowest mean): " + valleyText(map, s, unit) +
          ". Mean null-space iterations: " +
          (s.R ? formatFixedOr(double(s.iters) / s.R, 1, "-") : "-") + " (timings: manifest.json).")
      .table({"field", "min", "where", "max", "where"},
             {statsRow("manipulability, optimised [" + unit + "]",
                       fieldStats(map, f.manipulability().opt)),
              statsRow("manipulability, plain [" + unit + "]",
                       fieldStats(map, f.manipulability().plain)),
              statsRow("manipulability, optimised (normalised)", s.mo),
              statsRow("manipulability, plain (normalised)", s.mp),
              statsRow("transmission beta along u, optimised", s.beta_s),
              statsRow("transmission beta along u, plain", s.bp)},
             report::TableRule::compact);
}

// The design's maps side by side (a row of images; words where a map would be one colour).
report::Document designMaps(const Model& m, const MapSummary& s,
                            std::map<std::string, std::string>& png) {
  if (s.R == 0)
    return report::Document().paragraph(
        "No cell is reachable, so no manipulability or transmission map is drawn. Status: " +
        png["status"]);
  const auto image = [&](const std::string& what, const std::string& key) {
    return "![" + m.name + ": " + what + "](" + png[key] + ")";
  };
  return report::Document().table(
      {"optimised manipulability", "plain manipulability",
       "optimised manipulability, one scale for all designs",
       "transmission (optimised), one scale for all designs", "status"},
      {{image("optimised manipulability, normalised", "manipulability_optimised_normalised"),
        image("plain manipulability, normalised", "manipulability_plain_normalised"),
        image("optimised manipulability, shared scale", "manipulability_optimised"),
        image("optimised transmission, shared scale", "transmission_optimised"), png["status"]}},
      report::TableRule::compact);
}

}  // namespace

std::string manipulabilityUnit(metrics::MeasureSpace space) {
  return metrics::figureUnitIn(metrics::declaredMeasure("manipulability"), space);
}

// The design's row of the side-by-side table.
std::vector<std::string> comparisonRow(const Model& m, const DexterityMap& map, const MapFields& f,
                                       const MapSummary& s, const std::string& unit) {
  double mean_abs = 0;
  for (double v : f.manipulability().opt) mean_abs += std::isnan(v) ? 0.0 : v;
  return {m.name,
          std::to_string(m.dof()),
          formatShare(s.R, static_cast<int>(map.cells.size()), 1),
          formatShare(s.reach_neg, s.n_neg, 1),
          formatShare(s.reach_pos, s.n_pos, 1),
          s.R ? formatFixedOr(f.manipulability().best, 4, "-") : "-",
          s.R ? formatFixedOr(s.mean_p, 3, "-") : "-",
          s.R ? formatFixedOr(s.mean_o, 3, "-") : "-",
          s.R ? formatFixedOr(mean_abs / s.R, 3, "-") : "-",
          valleyText(map, s, unit)};
}

// The design's report section: reachability, field statistics, the images and the map search.
report::Document designSection(const Model& m, const DexterityOptions& options,
                               const DexterityMap& map, const MapFields& f, const MapSummary& s,
                               std::map<std::string, std::string>& png) {
  report::Document doc;
  doc.heading(2, m.name);
  if (s.R == 0) {  // a stem out of reach: say so, rather than means of nothing
    const std::string text = m.name + " reaches none of the " + std::to_string(map.cells.size()) +
                             " stem cells: check its base placement and units against the stem";
    doc.paragraph("**Warning:** " + text + ".");
    std::fprintf(stderr, "armstudy: warning: %s\n", text.c_str());
  }
  doc.append(designNumbers(options, map, f, s)).append(designMaps(m, s, png));
  const MapSearchSummary& se = map.search;
  return doc.paragraph(
      "Map search (docs/dexterity.md): after the chained rows, " +
      std::to_string(se.seeding_cells) + " cells got " + std::to_string(options.seed_starts) +
      " seeded starts each (" + std::to_string(se.multistart_improved) + " improved), then " +
      std::to_string(se.rounds) +
      (se.rounds == 1 ? " neighbour-propagation round improved "
                      : " neighbour-propagation rounds improved ") +
      std::to_string(se.neighbour_improved) +
      (se.neighbour_improved == 1 ? " cell value" : " cell values") +
      (se.converged ? " until no cell changed" : " (stopped by the round cap: not converged)") +
      ". Field `found_by` in the .vti: 0 chained row, 1 multi-start, 2 neighbour.");
}

// The designs side by side (a summary for one design): one row each.
report::Document comparisonSection(const Study& study, const DexterityOptions& options,
                                   std::vector<std::vector<std::string>> rows) {
  return report::Document()
      .heading(2, study.designs.size() > 1 ? "Side by side" : "Summary")
      .table({"design", "DoF", "reachable", "reachable gamma<0", "reachable gamma>=0",
              "best manipulability", "mean normalised (plain)", "mean normalised (optimised)",
              "mean manipulability, optimised [" + manipulabilityUnit(options.measure_space) + "]",
              "valley: lowest row mean, optimised"},
             rows, report::TableRule::compact);
}

}  // namespace armstudy::dexterity
