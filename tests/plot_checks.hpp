#pragma once
// Checks on a laid-out figure (report/plot.hpp's Drawing) and on its pixels, shared by the tests of
// the figures.
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <algorithm>
#include <string>
#include <vector>

#include "report/plot.hpp"

namespace armstudy::test {

inline constexpr double kTouch = 0.5;  // [px^2] boxes that share no more than this area only touch

// Every text box on the canvas and no two overlapping; the first fault found, or "".
inline std::string layoutFault(const report::Drawing& d) {
  for (const report::TextBox& b : d.texts)
    if (b.x0 < 0 || b.y0 < 0 || b.x1 > d.width || b.y1 > d.height)
      return "'" + b.text + "' leaves the canvas";
  for (std::size_t i = 0; i < d.texts.size(); ++i)
    for (std::size_t j = i + 1; j < d.texts.size(); ++j) {
      const report::TextBox &a = d.texts[i], &b = d.texts[j];
      const double w = std::min(a.x1, b.x1) - std::max(a.x0, b.x0),
                   h = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
      if (w > 0 && h > 0 && w * h > kTouch) return "'" + a.text + "' overlaps '" + b.text + "'";
    }
  return "";
}

inline const report::TextBox* findText(const report::Drawing& d, const std::string& t) {
  for (const report::TextBox& b : d.texts)
    if (b.text == t) return &b;
  return nullptr;
}

// Decoded PNG as RGB rows (top row first).
struct Pixels {
  int w = 0, h = 0;
  std::vector<report::Rgb> p;
  report::Rgb at(int x, int y) const { return p[static_cast<std::size_t>(y) * w + x]; }
};
inline Pixels decode(const std::string& png) {
  vtkNew<vtkPNGReader> r;
  r->SetMemoryBuffer(png.data());
  r->SetMemoryBufferLength(static_cast<vtkIdType>(png.size()));
  r->Update();
  vtkImageData* d = r->GetOutput();
  int dims[3];
  d->GetDimensions(dims);
  Pixels px;
  px.w = dims[0];
  px.h = dims[1];
  const int nc = d->GetNumberOfScalarComponents();
  for (int y = 0; y < px.h; ++y)
    for (int x = 0; x < px.w; ++x) {
      const auto* c = static_cast<unsigned char*>(d->GetScalarPointer(x, px.h - 1 - y, 0));
      px.p.push_back(nc >= 3 ? report::Rgb{c[0], c[1], c[2]} : report::Rgb{c[0], c[0], c[0]});
    }
  return px;
}

}  // namespace armstudy::test
