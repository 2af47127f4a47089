#pragma once
// Raster cell maps for reports: map rendering of 2-D cell data, colour maps, PNG encoding (VTK's
// PNG writer, in memory), tick values. Figures with axes are drawn by report/plot.hpp.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/escape.hpp"  // xmlEscape, for SVG text

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
  void set(int x, int y, Rgb c);  // (0, 0) = top-left pixel
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

// Perceptually ordered colour map (viridis), t in [0, 1] (clamped).
Rgb viridis(double t);
// Colours for categories 0..7 (wraps), indexed by status (ReachStatus: 0 reachable, 1 out of reach,
// 2 joint limits, 3 representation singularity, 4 self-collision, 5 torque / drive limit, 6
// obstacle collision): the Okabe-Ito colours (okabeIto) but light grey for "out of reach", in an
// order that keeps every pair apart for red-green colour-blind readers (bluish green, light grey,
// orange, vermillion, blue, sky blue, black, reddish purple): self-collision (blue) stands apart
// from both reachable (bluish green) and joint limits (orange), the statuses it borders.
Rgb categorical(int k);
// The Okabe-Ito colours (Okabe & Ito 2008, "Color Universal Design"), told apart with every common
// colour-vision deficiency, k = 0..7 (wraps): vermillion, bluish green, blue, orange, reddish
// purple, sky blue, black, yellow.
Rgb okabeIto(int k);
std::string hex(Rgb c);  // "#rrggbb"
// The name of a colour of categorical / okabeIto ("bluish green", "light grey", ...), "" for any
// other colour: text that names a drawn colour takes it from here.
std::string colourName(Rgb c);

// PNG bytes of an image (via vtkPNGWriter), and an atomic write to a file.
std::string encodePng(const RasterImage& image);
void writePng(const std::string& path, const RasterImage& image);

// "Nice" tick values (1, 2, 5 x 10^k steps) covering [lo, hi], about `target` of them.
std::vector<double> niceTicks(double lo, double hi, int target = 5);
}  // namespace armstudy::report
