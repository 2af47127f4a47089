#include "calibration/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace armstudy::calibration {
namespace {

constexpr double W = 720, H = 460, L = 80, R = 170, T = 40, B = 60;  // canvas and margins [px]

std::string num(double v, int prec = 4) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", prec, v);
  return b;
}

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else o += c;
  }
  return o;
}

std::vector<double> niceTicks(double lo, double hi, int target = 6) {
  std::vector<double> t;
  if (!(hi > lo)) return {lo};
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  const double first = std::ceil(lo / step) * step;
  // Below one ulp `v += step` never advances (a constant column plus rounding): ticks by index.
  if (!(first + step > first)) return {lo};
  const double n = std::floor((hi + 1e-9 * step - first) / step);
  for (int i = 0; i <= static_cast<int>(std::min(n, 1000.0)); ++i) {
    const double v = first + i * step;
    t.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
  }
  return t;
}

struct Frame {
  double x0, x1, y0, y1;
  double px(double x) const { return L + (x - x0) / (x1 - x0) * (W - L - R); }
  double py(double y) const { return H - B - (y - y0) / (y1 - y0) * (H - T - B); }
};

std::string header(const std::string& title) {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(W) + "\" height=\"" + num(H) +
         "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
         "<text x=\"" + num(W / 2) + "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" + esc(title) + "</text>\n";
}

std::string axes(const Frame& f, const std::string& xl, const std::string& yl,
                 const std::vector<std::string>& cats) {
  std::string s;
  s += "<rect x=\"" + num(L) + "\" y=\"" + num(T) + "\" width=\"" + num(W - L - R) + "\" height=\"" +
       num(H - T - B) + "\" fill=\"none\" stroke=\"black\"/>\n";
  if (cats.empty()) {
    for (double t : niceTicks(f.x0, f.x1))
      s += "<line x1=\"" + num(f.px(t), 6) + "\" y1=\"" + num(H - B) + "\" x2=\"" + num(f.px(t), 6) + "\" y2=\"" +
           num(T) + "\" stroke=\"#e0e0e0\"/><text x=\"" + num(f.px(t), 6) + "\" y=\"" + num(H - B + 16) +
           "\" text-anchor=\"middle\">" + num(t) + "</text>\n";
  } else {
    for (std::size_t i = 0; i < cats.size(); ++i)
      s += "<text transform=\"translate(" + num(f.px(double(i)), 6) + "," + num(H - B + 12) +
           ") rotate(20)\" font-size=\"10\">" + esc(cats[i]) + "</text>\n";
  }
  for (double t : niceTicks(f.y0, f.y1))
    s += "<line x1=\"" + num(L) + "\" y1=\"" + num(f.py(t), 6) + "\" x2=\"" + num(W - R) + "\" y2=\"" +
         num(f.py(t), 6) + "\" stroke=\"#e0e0e0\"/><text x=\"" + num(L - 6) + "\" y=\"" + num(f.py(t) + 4, 6) +
         "\" text-anchor=\"end\">" + num(t) + "</text>\n";
  s += "<text x=\"" + num((L + W - R) / 2) + "\" y=\"" + num(H - 12) + "\" text-anchor=\"middle\">" + esc(xl) + "</text>\n";
  s += "<text transform=\"translate(18," + num((T + H - B) / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
       esc(yl) + "</text>\n";
  return s;
}

}  // namespace

std::string svgPlot(const PlotSpec& p) {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : p.series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x0 = std::min(x0, s.x[i]);
      x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]);
      y1 = std::max(y1, s.y[i]);
    }
  for (double h : p.h_lines) {
    y0 = std::min(y0, h);
    y1 = std::max(y1, h);
  }
  if (!std::isfinite(x0)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (p.diagonal) x0 = y0 = std::min(x0, y0), x1 = y1 = std::max(x1, y1);
  const double dx = x1 > x0 ? 0.05 * (x1 - x0) : 1, dy = y1 > y0 ? 0.08 * (y1 - y0) : 1;
  Frame f{x0 - dx, x1 + dx, y0 - dy, y1 + dy};
  if (!p.x_categories.empty()) f.x0 = -0.5, f.x1 = p.x_categories.size() - 0.5;
  std::string s = header(p.title) + axes(f, p.x_label, p.y_label, p.x_categories);
  if (p.diagonal)
    s += "<line x1=\"" + num(f.px(f.x0), 6) + "\" y1=\"" + num(f.py(f.x0), 6) + "\" x2=\"" + num(f.px(f.x1), 6) +
         "\" y2=\"" + num(f.py(f.x1), 6) + "\" stroke=\"#888\" stroke-dasharray=\"4 3\"/>\n";
  for (double h : p.h_lines)
    s += "<line x1=\"" + num(L) + "\" y1=\"" + num(f.py(h), 6) + "\" x2=\"" + num(W - R) + "\" y2=\"" +
         num(f.py(h), 6) + "\" stroke=\"#888\" stroke-dasharray=\"4 3\"/>\n";
  int legend = 0;
  for (const auto& se : p.series) {
    if (se.lines) {
      std::string pts;
      for (std::size_t i = 0; i < se.x.size(); ++i)
        if (std::isfinite(se.y[i])) pts += num(f.px(se.x[i]), 6) + "," + num(f.py(se.y[i]), 6) + " ";
      s += "<polyline points=\"" + pts + "\" fill=\"none\" stroke=\"" + se.color + "\" stroke-width=\"1.5\"/>\n";
    }
    if (se.markers)
      for (std::size_t i = 0; i < se.x.size(); ++i)
        if (std::isfinite(se.x[i]) && std::isfinite(se.y[i]))
          s += "<circle cx=\"" + num(f.px(se.x[i]), 6) + "\" cy=\"" + num(f.py(se.y[i]), 6) +
               "\" r=\"2.5\" fill=\"" + se.color + "\" fill-opacity=\"0.7\"/>\n";
    if (!se.label.empty()) {
      const double ly = T + 10 + 18 * legend++;
      s += "<rect x=\"" + num(W - R + 10) + "\" y=\"" + num(ly - 8) + "\" width=\"10\" height=\"10\" fill=\"" +
           se.color + "\"/><text x=\"" + num(W - R + 25) + "\" y=\"" + num(ly + 1) + "\">" + esc(se.label) + "</text>\n";
    }
  }
  return s + "</svg>\n";
}

std::string svgHeatmap(const HeatmapSpec& h) {
  Frame f{h.x_min, h.x_max, h.y_min, h.y_max};
  if (!(f.x1 > f.x0)) f.x1 = f.x0 + 1;
  if (!(f.y1 > f.y0)) f.y1 = f.y0 + 1;
  double scale = h.scale;
  if (!(scale > 0))
    for (const auto& c : h.cells) scale = std::max(scale, std::abs(c.value));
  if (!(scale > 0)) scale = 1;
  auto colour = [&](double v) {  // blue - white - red
    const double t = std::clamp(v / scale, -1.0, 1.0);
    const int r = t > 0 ? 255 : static_cast<int>(255 * (1 + t));
    const int b = t < 0 ? 255 : static_cast<int>(255 * (1 - t));
    const int g = static_cast<int>(255 * (1 - std::abs(t)));
    char buf[16];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", r, g, b);
    return std::string(buf);
  };
  std::string s = header(h.title);
  for (const auto& c : h.cells) {
    const double x = f.px(c.x_lo), y = f.py(c.y_hi), w = f.px(c.x_hi) - x, hh = f.py(c.y_lo) - y;
    s += "<rect x=\"" + num(x, 6) + "\" y=\"" + num(y, 6) + "\" width=\"" + num(w, 6) + "\" height=\"" + num(hh, 6) +
         "\" fill=\"" + colour(c.value) + "\" stroke=\"" + (c.flagged ? "black" : "#bbb") + "\" stroke-width=\"" +
         (c.flagged ? "3" : "0.5") + "\"/>\n";
    s += "<text x=\"" + num(x + w / 2, 6) + "\" y=\"" + num(y + hh / 2 + 4, 6) +
         "\" text-anchor=\"middle\" font-size=\"9\">" + num(c.value, 2) + (c.flagged ? "*" : "") + "</text>\n";
  }
  s += axes(f, h.x_label, h.y_label, {});
  // Colour bar.
  for (int i = 0; i < 20; ++i) {
    const double v = scale * (1 - 2.0 * i / 19);
    s += "<rect x=\"" + num(W - R + 20) + "\" y=\"" + num(T + 12 * i, 6) + "\" width=\"16\" height=\"12\" fill=\"" +
         colour(v) + "\"/>\n";
  }
  s += "<text x=\"" + num(W - R + 40) + "\" y=\"" + num(T + 10) + "\">+" + num(scale, 3) + "</text>\n";
  s += "<text x=\"" + num(W - R + 40) + "\" y=\"" + num(T + 240) + "\">-" + num(scale, 3) + "</text>\n";
  s += "<text x=\"" + num(W - R + 10) + "\" y=\"" + num(T + 262) + "\">" + esc(h.value_label) + "</text>\n";
  s += "<text x=\"" + num(W - R + 10) + "\" y=\"" + num(T + 280) + "\">* / bold: flagged</text>\n";
  return s + "</svg>\n";
}

}  // namespace armstudy::calibration
