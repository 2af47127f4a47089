#include "report/image.hpp"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/errors.hpp"
#include "io/files.hpp"

namespace armstudy::report {

RasterImage::RasterImage(int width, int height, Rgb fill) : w_(width), h_(height) {
  ARMSTUDY_CHECK(width > 0 && height > 0, "image size must be positive");
  rgb_.resize(static_cast<std::size_t>(w_) * h_ * 3);
  for (std::size_t p = 0; p < rgb_.size(); p += 3) {
    rgb_[p] = fill.r;
    rgb_[p + 1] = fill.g;
    rgb_[p + 2] = fill.b;
  }
}

void RasterImage::set(int x, int y, Rgb c) {
  ARMSTUDY_CHECK(x >= 0 && x < w_ && y >= 0 && y < h_, "pixel outside the image");
  const std::size_t p = (static_cast<std::size_t>(y) * w_ + x) * 3;
  rgb_[p] = c.r;
  rgb_[p + 1] = c.g;
  rgb_[p + 2] = c.b;
}

Rgb RasterImage::at(int x, int y) const {
  ARMSTUDY_CHECK(x >= 0 && x < w_ && y >= 0 && y < h_, "pixel outside the image");
  const std::size_t p = (static_cast<std::size_t>(y) * w_ + x) * 3;
  return {rgb_[p], rgb_[p + 1], rgb_[p + 2]};
}

RasterImage renderCellMap(int nx, int ny, const std::function<Rgb(int, int)>& color,
                          int min_size_px, int border_px) {
  ARMSTUDY_CHECK(nx > 0 && ny > 0, "cell map needs cells");
  const int longer = std::max(nx, ny);
  const int block = std::max(1, (min_size_px + longer - 1) / longer);
  const int w = nx * block + 2 * border_px, h = ny * block + 2 * border_px;
  RasterImage img(w, h, Rgb{128, 128, 128});
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Rgb c = color(i, j);
      const int y0 = border_px + (ny - 1 - j) * block;  // j grows upwards
      const int x0 = border_px + i * block;
      for (int dy = 0; dy < block; ++dy)
        for (int dx = 0; dx < block; ++dx) img.set(x0 + dx, y0 + dy, c);
    }
  return img;
}

Rgb viridis(double t) {
  // Viridis sampled at 9 points, linearly interpolated.
  static const double k[9][3] = {{68, 1, 84},    {71, 44, 122},  {59, 81, 139},
                                 {44, 113, 142}, {33, 144, 141}, {39, 173, 129},
                                 {92, 200, 99},  {170, 220, 50}, {253, 231, 37}};
  if (!std::isfinite(t)) t = 0;
  t = std::clamp(t, 0.0, 1.0) * 8.0;
  const int i = std::min(7, static_cast<int>(t));
  const double f = t - i;
  auto mix = [&](int c) {
    return static_cast<std::uint8_t>(std::lround(k[i][c] + f * (k[i + 1][c] - k[i][c])));
  };
  return {mix(0), mix(1), mix(2)};
}

Rgb categorical(int k) {
  static const Rgb c[8] = {{0, 158, 115}, {230, 230, 230}, {230, 159, 0}, {213, 94, 0},
                           {0, 114, 178}, {86, 180, 233},  {0, 0, 0},     {204, 121, 167}};
  return c[((k % 8) + 8) % 8];
}

Rgb okabeIto(int k) {
  static const Rgb c[8] = {{213, 94, 0},    {0, 158, 115},  {0, 114, 178}, {230, 159, 0},
                           {204, 121, 167}, {86, 180, 233}, {0, 0, 0},     {240, 228, 66}};
  return c[((k % 8) + 8) % 8];
}

std::string colourName(Rgb c) {
  static const std::pair<Rgb, const char*> names[] = {{{213, 94, 0}, "vermillion"},
                                                      {{0, 158, 115}, "bluish green"},
                                                      {{0, 114, 178}, "blue"},
                                                      {{230, 159, 0}, "orange"},
                                                      {{204, 121, 167}, "reddish purple"},
                                                      {{86, 180, 233}, "sky blue"},
                                                      {{0, 0, 0}, "black"},
                                                      {{240, 228, 66}, "yellow"},
                                                      {{230, 230, 230}, "light grey"}};
  for (const auto& [rgb, name] : names)
    if (rgb.r == c.r && rgb.g == c.g && rgb.b == c.b) return name;
  return "";
}

std::string hex(Rgb c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
  return buf;
}

std::string encodePng(const RasterImage& image) {
  vtkNew<vtkImageData> data;
  data->SetDimensions(image.width(), image.height(), 1);
  vtkNew<vtkUnsignedCharArray> arr;
  arr->SetNumberOfComponents(3);
  arr->SetNumberOfTuples(static_cast<vtkIdType>(image.width()) * image.height());
  // VTK images start at the bottom row; RasterImage rows start at the top.
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const Rgb c = image.at(x, image.height() - 1 - y);
      const vtkIdType t = static_cast<vtkIdType>(y) * image.width() + x;
      arr->SetTypedComponent(t, 0, c.r);
      arr->SetTypedComponent(t, 1, c.g);
      arr->SetTypedComponent(t, 2, c.b);
    }
  data->GetPointData()->SetScalars(arr);
  vtkNew<vtkPNGWriter> w;
  w->SetInputData(data);
  w->SetCompressionLevel(9);
  w->WriteToMemoryOn();
  w->Write();
  vtkUnsignedCharArray* out = w->GetResult();
  ARMSTUDY_CHECK(out && out->GetNumberOfTuples() > 0, "PNG encoding failed");
  return std::string(
      reinterpret_cast<const char*>(out->GetPointer(0)),
      static_cast<std::size_t>(out->GetNumberOfTuples() * out->GetNumberOfComponents()));
}

void writePng(const std::string& path, const RasterImage& image) {
  writeFileAtomic(path, encodePng(image));
}

std::vector<double> niceTicks(double lo, double hi, int target) {
  std::vector<double> t;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return t;
  const double raw = (hi - lo) / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw * (1 - 1e-9)) {
      step = m * mag;
      break;
    }
  const double eps = 1e-9 * step;
  const double first = std::ceil((lo - eps) / step) * step;
  // A range narrower than the values' resolution (a constant column plus rounding): the step is
  // below one ulp and `v += step` would never advance. Ticks by index, at most a few hundred.
  if (!(first + step > first)) return {lo};
  const double n = std::floor((hi + eps - first) / step);
  for (int i = 0; i <= static_cast<int>(std::min(n, 1000.0)); ++i) {
    const double v = first + i * step;
    t.push_back(std::abs(v) < eps ? 0.0 : v);
  }
  return t;
}

}  // namespace armstudy::report
