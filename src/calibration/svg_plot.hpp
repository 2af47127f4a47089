#pragma once
// Minimal SVG charts for the calibration report: scatter/line plots and a binned heatmap.
// Written here because the shared report helpers (src/report, branch `reach`) were not on main
// when this was built; they can replace these once merged. Output is deterministic text.
#include <string>
#include <vector>

namespace armstudy::calibration {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
  std::string color = "#1f77b4";
  bool lines = false;    // connect the points
  bool markers = true;
};

struct PlotSpec {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  bool diagonal = false;                     // draw y = x (measured vs predicted)
  std::vector<double> h_lines;               // horizontal reference lines (dashed)
  std::vector<std::string> x_categories;     // if set: x are indices 0..n-1 with these labels
};
std::string svgPlot(const PlotSpec& spec);

struct HeatCell {
  double x_lo, x_hi, y_lo, y_hi;
  double value;
  int n;
  bool flagged;
};
struct HeatmapSpec {
  std::string title, x_label, y_label, value_label;
  double x_min, x_max, y_min, y_max;
  double scale = 0;  // colour saturates at +-scale (symmetric, diverging); 0 = max |value|
  std::vector<HeatCell> cells;
};
std::string svgHeatmap(const HeatmapSpec& spec);

}  // namespace armstudy::calibration
