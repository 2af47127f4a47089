#pragma once
// Checks on a laid-out figure (report/plot.hpp's Drawing), shared by the tests of the figures.
#include <algorithm>
#include <string>

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

}  // namespace armstudy::test
