#pragma once
// Small raster images for reports: map/heatmap rendering of 2-D cell data, colour maps, PNG
// encoding (VTK's PNG writer, in memory), a minimal SVG line plot and SVG map figures with axes. Used by the reachability
// report; dexterity, dynamics and calibration reports can draw their heatmaps and plots with it.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace armstudy::report {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
};

class RasterImage {
 public:
  RasterImage(int width, int height, Rgb fill = {255, 255, 255});
  int width() const { return w_; }
  int height() const { return h_; }
  void set(int x, int y, Rgb c);          // (0, 0) = top-left pixel
  Rgb at(int x, int y) const;
  const std::vector<std::uint8_t>& rgb() const { return rgb_; }

 private:
  int w_, h_;
  std::vector<std::uint8_t> rgb_;
};

// Renders an nx x ny cell map: cell (i, j) is drawn as a square block with i to the right and j
// upwards (so a map of an x-y grid looks like the x-y plane seen from +z). Blocks are scaled so
// the image is at least `min_size_px` on its longer side; `border_px` of grey frame around it.
RasterImage renderCellMap(int nx, int ny, const std::function<Rgb(int i, int j)>& color,
                          int min_size_px = 480, int border_px = 2);

// Horizontal colour bar (for heatmap legends): `width` x `height`, left = 0, right = 1.
RasterImage renderColorBar(int width, int height, const std::function<Rgb(double t)>& colormap);

// Heatmap legend: `map` with a horizontal colour bar (left = 0, right = 1 of the colour map) of
// `bar_height_px` below it, separated by `gap_px` of white; the bar spans the map's width.
RasterImage withColorBar(const RasterImage& map, const std::function<Rgb(double t)>& colormap,
                         int bar_height_px = 16, int gap_px = 6);

// Perceptually ordered colour map (viridis), t in [0, 1] (clamped).
Rgb viridis(double t);
// Distinct colours for categories 0..7 (wraps).
Rgb categorical(int k);
std::string hex(Rgb c);  // "#rrggbb"

// PNG bytes of an image (via vtkPNGWriter), and an atomic write to a file.
std::string encodePng(const RasterImage& image);
void writePng(const std::string& path, const RasterImage& image);

// A minimal SVG line plot: one or more series over a shared x axis, axis labels and ticks.
struct Series {
  std::string label;
  std::vector<double> x, y;
};
std::string svgLinePlot(const std::vector<Series>& series, const std::string& x_label,
                        const std::string& y_label, const std::string& title, int width = 640,
                        int height = 400);

// ---- Map figures: a cell map with axes, ticks, labels and a legend (SVG) ----
// The map raster is embedded as a PNG (data URI, drawn pixelated) and framed by axes whose
// extents are the data coordinates of the raster's inner edges (renderCellMap's border excluded):
// for a grid with cell centres from..to and spacing step, lo = from - step/2, hi = to + step/2.
struct MapAxis {
  std::string label;  // e.g. "x [m]"
  double lo = 0, hi = 1;
};
struct LegendEntry {
  Rgb colour;
  std::string label;
};
struct ColourScale {
  std::function<Rgb(double t)> map;  // t in [0, 1]
  double lo = 0, hi = 1;             // values at t = 0 and t = 1
  std::string label;
};
struct MapFigure {
  std::string title;
  MapAxis x, y;
  std::vector<LegendEntry> legend;   // categorical colours (e.g. reach status); empty = none
  std::optional<ColourScale> scale;  // continuous colour bar below the map
  int border_px = 2;                 // renderCellMap's frame around the cells
};
std::string svgMapFigure(const RasterImage& map, const MapFigure& figure);
// Axis extent of a grid axis with cell centres from..to (inclusive) and spacing step.
MapAxis cellAxis(std::string label, double from, double to, double step);

// "Nice" tick values (1, 2, 5 x 10^k steps) covering [lo, hi], about `target` of them.
std::vector<double> niceTicks(double lo, double hi, int target = 5);
// Text for SVG/XML: & < > " escaped.
std::string xmlEscape(const std::string& s);

}  // namespace armstudy::report
