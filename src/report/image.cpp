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

RasterImage renderColorBar(int width, int height, const std::function<Rgb(double)>& cmap) {
  RasterImage img(width, height);
  for (int x = 0; x < width; ++x) {
    const Rgb c = cmap(width > 1 ? static_cast<double>(x) / (width - 1) : 0.0);
    for (int y = 0; y < height; ++y) img.set(x, y, c);
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
    << "<text x=\"" << width / 2 << "\" y=\"18\" text-anchor=\"middle\">" << title << "</text>\n"
    << "<rect x=\"" << ml << "\" y=\"" << mt << "\" width=\"" << pw << "\" height=\"" << ph
    << "\" fill=\"none\" stroke=\"black\"/>\n";
  for (int t = 0; t <= 4; ++t) {
    const double xv = x0 + (x1 - x0) * t / 4, yv = y0 + (y1 - y0) * t / 4;
    o << "<text x=\"" << X(xv) << "\" y=\"" << mt + ph + 16 << "\" text-anchor=\"middle\">" << xv
      << "</text>\n<text x=\"" << ml - 6 << "\" y=\"" << Y(yv) + 4 << "\" text-anchor=\"end\">"
      << yv << "</text>\n";
  }
  o << "<text x=\"" << ml + pw / 2 << "\" y=\"" << height - 10 << "\" text-anchor=\"middle\">"
    << x_label << "</text>\n<text x=\"14\" y=\"" << mt + ph / 2
    << "\" text-anchor=\"middle\" transform=\"rotate(-90 14 " << mt + ph / 2 << ")\">" << y_label
    << "</text>\n";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    o << "<polyline fill=\"none\" stroke=\"" << hex(categorical(static_cast<int>(k) + 5 * (k > 0)))
      << "\" stroke-width=\"1.5\" points=\"";
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) o << X(s.x[i]) << "," << Y(s.y[i]) << " ";
    o << "\"/>\n<text x=\"" << ml + 8 << "\" y=\"" << mt + 16 + 14 * k << "\" fill=\""
      << hex(categorical(static_cast<int>(k) + 5 * (k > 0))) << "\">" << s.label << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

}  // namespace armstudy::report
