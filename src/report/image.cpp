#include "report/image.hpp"

#include <vtkBase64Utilities.h>
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

RasterImage renderColorBar(int width, int height, const std::function<Rgb(double)>& cmap) {
  RasterImage img(width, height);
  for (int x = 0; x < width; ++x) {
    const Rgb c = cmap(width > 1 ? static_cast<double>(x) / (width - 1) : 0.0);
    for (int y = 0; y < height; ++y) img.set(x, y, c);
  }
  return img;
}

RasterImage withColorBar(const RasterImage& map, const std::function<Rgb(double)>& cmap,
                         int bar_height_px, int gap_px) {
  ARMSTUDY_CHECK(bar_height_px > 0 && gap_px >= 0, "colour bar needs a positive height");
  RasterImage img(map.width(), map.height() + gap_px + bar_height_px);
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) img.set(x, y, map.at(x, y));
  const RasterImage bar = renderColorBar(map.width(), bar_height_px, cmap);
  for (int y = 0; y < bar_height_px; ++y)
    for (int x = 0; x < map.width(); ++x) img.set(x, map.height() + gap_px + y, bar.at(x, y));
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
  auto mix = [&](int c) { return static_cast<std::uint8_t>(std::lround(k[i][c] + f * (k[i + 1][c] - k[i][c]))); };
  return {mix(0), mix(1), mix(2)};
}

Rgb categorical(int k) {
  static const Rgb c[8] = {{44, 160, 44},   {230, 230, 230}, {255, 127, 14}, {148, 103, 189},
                           {214, 39, 40},   {31, 119, 180},  {140, 86, 75},  {188, 189, 34}};
  return c[((k % 8) + 8) % 8];
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
  w->WriteToMemoryOn();
  w->Write();
  vtkUnsignedCharArray* out = w->GetResult();
  ARMSTUDY_CHECK(out && out->GetNumberOfTuples() > 0, "PNG encoding failed");
  return std::string(reinterpret_cast<const char*>(out->GetPointer(0)),
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

std::string xmlEscape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '&') o += "&amp;";
    else if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '"') o += "&quot;";
    else o += c;
  }
  return o;
}

namespace {
// Tick label: shortest of %g with up to 6 significant digits.
std::string tickText(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
}  // namespace

MapAxis cellAxis(std::string label, double from, double to, double step) {
  const double h = 0.5 * (to > from ? step : 1.0);
  return MapAxis{std::move(label), from - h, to + h};
}

std::string svgMapFigure(const RasterImage& map, const MapFigure& f) {
  const std::string png = encodePng(map);
  std::string b64(png.size() * 4 / 3 + 8, '\0');
  const unsigned long n = vtkBase64Utilities::Encode(reinterpret_cast<const unsigned char*>(png.data()),
                                                     png.size(), reinterpret_cast<unsigned char*>(b64.data()), 0);
  b64.resize(n);
  const int w = map.width(), h = map.height(), bp = f.border_px;
  const double ml = 64, mt = f.title.empty() ? 12 : 32, mb = 46 + (f.scale ? 58 : 0);
  const double legend_w = f.legend.empty() ? 0 : 230;
  const double mr = 16 + legend_w;
  const double W = ml + w + mr, H = mt + h + mb;
  // Data -> pixel on the raster's inner area.
  const double ix0 = ml + bp, ix1 = ml + w - bp, iy0 = mt + bp, iy1 = mt + h - bp;
  auto X = [&](double v) { return ix0 + (v - f.x.lo) / (f.x.hi - f.x.lo) * (ix1 - ix0); };
  auto Y = [&](double v) { return iy1 - (v - f.y.lo) / (f.y.hi - f.y.lo) * (iy1 - iy0); };
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!f.title.empty())
    o << "<text x=\"" << ml + w / 2.0 << "\" y=\"20\" text-anchor=\"middle\" font-size=\"14\">" << xmlEscape(f.title)
      << "</text>\n";
  o << "<image x=\"" << ml << "\" y=\"" << mt << "\" width=\"" << w << "\" height=\"" << h
    << "\" style=\"image-rendering:pixelated\" preserveAspectRatio=\"none\" href=\"data:image/png;base64," << b64
    << "\"/>\n";
  if (f.x.hi > f.x.lo)
    for (double t : niceTicks(f.x.lo, f.x.hi, std::max(2, w / 90))) {
      const double px = X(t);
      o << "<line x1=\"" << px << "\" y1=\"" << mt + h << "\" x2=\"" << px << "\" y2=\"" << mt + h + 5
        << "\" stroke=\"black\"/><text x=\"" << px << "\" y=\"" << mt + h + 18 << "\" text-anchor=\"middle\">"
        << tickText(t) << "</text>\n";
    }
  if (f.y.hi > f.y.lo)
    for (double t : niceTicks(f.y.lo, f.y.hi, std::max(2, h / 70))) {
      const double py = Y(t);
      o << "<line x1=\"" << ml - 5 << "\" y1=\"" << py << "\" x2=\"" << ml << "\" y2=\"" << py
        << "\" stroke=\"black\"/><text x=\"" << ml - 8 << "\" y=\"" << py + 4 << "\" text-anchor=\"end\">"
        << tickText(t) << "</text>\n";
    }
  o << "<text x=\"" << ml + w / 2.0 << "\" y=\"" << mt + h + 38 << "\" text-anchor=\"middle\">" << xmlEscape(f.x.label)
    << "</text>\n<text x=\"16\" y=\"" << mt + h / 2.0 << "\" text-anchor=\"middle\" transform=\"rotate(-90 16 "
    << mt + h / 2.0 << ")\">" << xmlEscape(f.y.label) << "</text>\n";
  if (f.scale) {
    const ColourScale& s = *f.scale;
    const double by = mt + h + 50, bh = 14;
    const int steps = 64;
    for (int k = 0; k < steps; ++k)
      o << "<rect x=\"" << ml + w * double(k) / steps << "\" y=\"" << by << "\" width=\"" << w / double(steps) + 0.5
        << "\" height=\"" << bh << "\" fill=\"" << hex(s.map((k + 0.5) / steps)) << "\"/>\n";
    o << "<rect x=\"" << ml << "\" y=\"" << by << "\" width=\"" << w << "\" height=\"" << bh
      << "\" fill=\"none\" stroke=\"black\"/>\n";
    if (s.hi > s.lo)
      for (double t : niceTicks(s.lo, s.hi, 5)) {
        const double px = ml + (t - s.lo) / (s.hi - s.lo) * w;
        o << "<line x1=\"" << px << "\" y1=\"" << by + bh << "\" x2=\"" << px << "\" y2=\"" << by + bh + 4
          << "\" stroke=\"black\"/><text x=\"" << px << "\" y=\"" << by + bh + 16 << "\" text-anchor=\"middle\">"
          << tickText(t) << "</text>\n";
      }
    o << "<text x=\"" << ml + w / 2.0 << "\" y=\"" << by - 4 << "\" text-anchor=\"middle\">" << xmlEscape(s.label)
      << "</text>\n";
  }
  for (std::size_t k = 0; k < f.legend.size(); ++k) {
    const double lx = ml + w + 16, ly = mt + 4 + 20.0 * k;
    o << "<rect x=\"" << lx << "\" y=\"" << ly << "\" width=\"14\" height=\"14\" fill=\"" << hex(f.legend[k].colour)
      << "\" stroke=\"#555\"/><text x=\"" << lx + 20 << "\" y=\"" << ly + 11 << "\">" << xmlEscape(f.legend[k].label)
      << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

std::string svgLinePlot(const std::vector<Series>& series, const std::string& x_label,
                        const std::string& y_label, const std::string& title, int width,
                        int height) {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const Series& s : series)
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x0 = std::min(x0, s.x[i]);
      x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]);
      y1 = std::max(y1, s.y[i]);
    }
  if (!(x1 > x0)) { x0 -= 0.5; x1 += 0.5; }
  if (!(y1 > y0)) { y0 -= 0.5; y1 += 0.5; }
  const double ml = 70, mr = 20, mt = 30, mb = 50;
  const double pw = width - ml - mr, ph = height - mt - mb;
  auto X = [&](double v) { return ml + (v - x0) / (x1 - x0) * pw; };
  auto Y = [&](double v) { return mt + ph - (v - y0) / (y1 - y0) * ph; };
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << width / 2 << "\" y=\"18\" text-anchor=\"middle\">" << xmlEscape(title) << "</text>\n"
    << "<rect x=\"" << ml << "\" y=\"" << mt << "\" width=\"" << pw << "\" height=\"" << ph
    << "\" fill=\"none\" stroke=\"black\"/>\n";
  for (double xv : niceTicks(x0, x1, 5))
    o << "<text x=\"" << X(xv) << "\" y=\"" << mt + ph + 16 << "\" text-anchor=\"middle\">" << tickText(xv)
      << "</text>\n";
  for (double yv : niceTicks(y0, y1, 5))
    o << "<text x=\"" << ml - 6 << "\" y=\"" << Y(yv) + 4 << "\" text-anchor=\"end\">" << tickText(yv)
      << "</text>\n";
  o << "<text x=\"" << ml + pw / 2 << "\" y=\"" << height - 10 << "\" text-anchor=\"middle\">"
    << xmlEscape(x_label) << "</text>\n<text x=\"14\" y=\"" << mt + ph / 2
    << "\" text-anchor=\"middle\" transform=\"rotate(-90 14 " << mt + ph / 2 << ")\">" << xmlEscape(y_label)
    << "</text>\n";
  auto colour = [](std::size_t k) { return hex(categorical(static_cast<int>(k) + 5 * (k > 0))); };
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    o << "<polyline fill=\"none\" stroke=\"" << colour(k) << "\" stroke-width=\"1.5\" points=\"";
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) o << X(s.x[i]) << "," << Y(s.y[i]) << " ";
    o << "\"/>\n";
  }
  // Legend over the curves, in a half-transparent box: curves stay visible, the text legible.
  std::size_t longest = 0;
  for (const Series& s : series) longest = std::max(longest, s.label.size());
  o << "<rect x=\"" << ml + 4 << "\" y=\"" << mt + 4 << "\" width=\"" << 12 + 7.0 * longest << "\" height=\""
    << 6 + 14.0 * series.size() << "\" fill=\"white\" fill-opacity=\"0.8\" stroke=\"#ccc\"/>\n";
  for (std::size_t k = 0; k < series.size(); ++k)
    o << "<text x=\"" << ml + 8 << "\" y=\"" << mt + 16 + 14 * k << "\" fill=\"" << colour(k) << "\">"
      << xmlEscape(series[k].label) << "</text>\n";
  o << "</svg>\n";
  return o.str();
}

}  // namespace armstudy::report
