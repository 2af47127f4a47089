#pragma once
// What the dexterity stage's report and summary.json say about one design's map (private to
// src/stages/dexterity): field statistics, reachable cells by the sign of gamma, means over the
// reachable cells and the valley of the optimised map; the report's sections built of them
// (dexterity_report.cpp).
#include <map>
#include <string>
#include <vector>

#include "report/document.hpp"
#include "stages/dexterity/dexterity_output.hpp"

namespace armstudy::dexterity {

// What the report and summary.json say about one design's map: field statistics, reachable cells
// by the sign of gamma, and means over the reachable cells.
struct MapSummary {
  FieldStats mo, mp, beta_s,
      bp;  // manipulability optimised/plain (normalised), transmission opt./plain
  int reach_neg = 0, n_neg = 0, reach_pos = 0, n_pos = 0, iters = 0;
  int R = 0;                      // reachable cells
  double mean_p = 0, mean_o = 0;  // mean normalised manipulability, plain and optimised
  // The valley: the z row with the lowest mean optimised manipulability over its reachable
  // cells (normalised and absolute); -1 when no row has a reachable cell.
  int valley_row = -1;
  double valley_norm = 0, valley_abs = 0;
};

// Computes the statistics, counts and means of one design's map.
MapSummary summarise(const DexterityMap& map, const MapFields& f, const StemGrid& g);
// The valley's height [m], NaN when the map has none inside its grid (too few rows, no reachable
// row, or the lowest row mean on the grid's edge).
double valleyHeight(const StemGrid& grid, const MapSummary& s);
// "z 0.65 m (row mean 0.660, 0.519 m^3)", or "-"; "at the edge" when it is the first or last row.
std::string valleyText(const DexterityMap& map, const MapSummary& s, const std::string& unit);

// The unit of the absolute manipulability (metrics/measure_declarations.hpp).
std::string manipulabilityUnit(metrics::MeasureSpace space);

// The design's row of the side-by-side table.
std::vector<std::string> comparisonRow(const Model& m, const DexterityMap& map, const MapFields& f,
                                       const MapSummary& s, const std::string& unit);

// The design's report section: reachability, field statistics, the images (`png`: the figures'
// names per image key, "status": the status map's table cell) and the map search. A design that
// reaches no cell is a warning there and on stderr.
report::Document designSection(const Model& m, const DexterityOptions& options,
                               const DexterityMap& map, const MapFields& f, const MapSummary& s,
                               std::map<std::string, std::string>& png);

// The designs side by side (titled "Summary" for one design): `rows` from comparisonRow.
report::Document comparisonSection(const Study& study, const DexterityOptions& options,
                                   std::vector<std::vector<std::string>> rows);

}  // namespace armstudy::dexterity
