#pragma once
// The one plotting module of the engine: map figures (a cell raster with axes, colour bar and
// legend), x-y plots (one panel per unit, categories, reference lines, a diagonal) and binned
// heatmaps. Laid out into a display list (plot_layout.hpp), written as SVG (text as <text>) and,
// when asked, drawn with cairo as PNG; every piece of text is placed from its measured extents in
// the figures' font (DejaVu Sans from its file), so labels never overprint each other and never
// leave the canvas. Each Drawing lists the boxes of the text it drew, for checks.
#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "report/image.hpp"

namespace armstudy::report {

// A piece of text on the canvas and the box it covers [px, y down].
struct TextBox {
  std::string text;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
struct Drawing {
  std::string svg;  // always
  std::string png;  // when asked for (Format::svg_and_png)
  double width = 0, height = 0;
  std::vector<TextBox> texts;
};
enum class Format { svg, svg_and_png };

// ---- Map figures: a cell map with axes, ticks, labels, a colour bar and a legend ----
// The axes' extents are the data coordinates of the raster's inner edges (renderCellMap's border
// excluded): for a grid with cell centres from..to and spacing step, lo = from - step/2 (cellAxis).
// Ticks are placed over the cells' centres from..to where these are given (cellAxis), else over
// lo..hi.
struct MapAxis {
  std::string label;  // with its unit, e.g. "x [m]"
  double lo = 0, hi = 1;
  double from = std::numeric_limits<double>::quiet_NaN(), to = from;  // first and last centre
};
struct LegendEntry {
  Rgb colour;
  std::string label;
};
struct ColourScale {
  std::function<Rgb(double t)> map;  // t in [0, 1]
  double lo = 0, hi = 1;             // values at t = 0 and t = 1
  std::string label;                 // quantity and unit, e.g. "manipulability [m^3]"
};
struct MapFigure {
  std::string title;
  MapAxis x, y;
  std::vector<LegendEntry> legend;   // categorical colours (e.g. reach status); empty = none
  std::optional<ColourScale> scale;  // continuous colour bar right of the map
  int border_px = 2;                 // renderCellMap's frame around the cells
};
// The map keeps its width and is drawn at least kMinMapHeight px tall: a map of a few rows (a stem
// map of three heights) has its rows of cells stretched so that they and their y ticks can be read.
constexpr double kMinMapHeight = 150;
Drawing mapFigure(const RasterImage& map, const MapFigure& figure, Format format = Format::svg);
// Axis extent of a grid axis with cell centres from..to (inclusive) and spacing step.
MapAxis cellAxis(std::string label, double from, double to, double step);

// ---- X-y plots ----
enum class Marker { dot, ring, square };  // filled circle, hollow circle, hollow square
struct PlotSeries {
  std::string label;  // legend text; empty = not in the legend
  std::vector<double> x, y;
  std::optional<Rgb> colour;  // default: seriesColour(index of the series in its panel)
  bool lines = true;          // connect the points
  bool markers = false;       // a dot per point
  bool dashed = false;
  Marker marker = Marker::dot;  // the markers' shape
  double marker_size = 2.6;     // radius, or half the side of a square [px]
  // Text beside each marker (a fruit's number), index for index with x and y; "" or missing: none.
  // Set beside the marker where it overlaps no other such text and stays in the plot area.
  std::vector<std::string> point_labels;
};
struct RefLine {  // a horizontal (y = value) or vertical (x = value) reference line
  double value = 0;
  std::string label;  // legend text, e.g. "continuous current limit"
  bool horizontal = true;
  Rgb colour{90, 90, 90};
};
struct PlotPanel {
  std::string title;    // optional, above the panel
  std::string y_label;  // with its unit
  std::vector<PlotSeries> series;
  std::vector<RefLine> lines;
  bool diagonal = false;  // y = x (measured vs predicted); x and y share one range
  // A fixed y range {lo, hi} (e.g. one range for the panels or figures that compare before and
  // after); default: the data's range, padded.
  std::optional<std::array<double, 2>> y_range;
};
struct PlotSpec {
  std::string title, x_label;  // the panels share the x axis
  std::vector<PlotPanel> panels;
  std::vector<std::string> x_categories;  // if set: x values are indices 0..n-1 with these labels
  double x_margin = 0;  // share of the x data range added on both sides (markers off the frame)
  double width = 720;   // canvas width [px]; grows to fit text if needed
  double panel_height = 260;  // plot area height of each panel [px]
};
Drawing plot(const PlotSpec& spec, Format format = Format::svg);
// Thinning for drawing: a line of more points than this keeps, of each run of consecutive points
// in one pixel column, the first, lowest, highest and last (peaks stay visible); a figure of more
// markers than this draws the plot areas that hold markers as images. The figure then carries
// kThinNote under its x label; data files keep every point.
constexpr std::size_t kThinAbove = 2000;
extern const char* const kThinNote;
// Distinct colours for series, in order (wraps after 10; never light grey).
Rgb seriesColour(int k);

// ---- Binned heatmaps with the value written in each cell ----
struct HeatCell {
  double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;
  double value = 0;
  bool flagged = false;  // drawn with a thick frame and a '*' after the value
};
struct HeatmapSpec {
  std::string title, x_label, y_label, value_label;  // value_label: quantity and unit
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  std::vector<HeatCell> cells;
  // Sequential (viridis from 0 or the minimum to the maximum) for absolute values; diverging
  // (blue - white - red, symmetric about 0, saturating at +-scale; 0 = max |value|) for signed
  // ones.
  bool diverging = false;
  double scale = 0;
  std::string flagged_note = "* / thick frame: flagged";
  int value_digits = 2;  // significant digits of the cell text
};
Drawing heatmap(const HeatmapSpec& spec, Format format = Format::svg);

// ---- Parallel coordinates: one vertical axis per quantity, one polyline per item ----
// An objective's axis is turned so that better values are at the top (a minimised quantity grows
// downwards) and marked "better" above; an axis without a goal grows upwards.
enum class Better { none, higher, lower };
struct ParallelAxis {
  std::string label;  // name and unit, e.g. "link length [m]"
  Better better = Better::none;
};
struct ParallelGroup {  // items drawn alike, one legend entry
  std::string label;
  Rgb colour;
  double line_width = 1;
  std::vector<std::vector<double>> items;  // per item a value per axis; NaN: not known (skipped)
};
struct ParallelSpec {
  std::string title;
  std::vector<ParallelAxis> axes;
  std::vector<ParallelGroup> groups;  // drawn in order, the last on top
  double axis_height = 280;           // [px]
};
Drawing parallelCoordinates(const ParallelSpec& spec, Format format = Format::svg);
// The mark above a better-is-higher axis, and the wording of an x-y axis label with a goal.
extern const char* const kBetterMark;
std::string withBetter(const std::string& label, Better better);

// Blue - white - red diverging colour map, t in [0, 1] (0.5 = white).
Rgb diverging(double t);

}  // namespace armstudy::report
