#pragma once
// Minimal PNG writer (8-bit RGB, stored/uncompressed deflate blocks, CRC-32 and Adler-32 computed
// here) so reports carry map images without an image library. Also a perceptual colour map.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace armstudy::dexterity {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // row-major, top row first, 3 bytes per pixel
  RgbImage(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0) {}
  void set(int x, int y, std::array<std::uint8_t, 3> c);
};

// PNG file bytes of an image.
std::string encodePng(const RgbImage& image);

// Viridis-like colour map for t in [0, 1] (clamped).
std::array<std::uint8_t, 3> colourMap(double t);

// Heat map of a (cols x rows) field, row 0 at the bottom of the image, `scale` pixels per cell.
// NaN cells are drawn grey. Values map linearly from [lo, hi] to the colour map.
RgbImage heatmapImage(const std::vector<double>& values, int cols, int rows, double lo, double hi,
                      int scale);

}  // namespace armstudy::dexterity
