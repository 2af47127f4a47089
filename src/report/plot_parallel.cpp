// Parallel coordinates (report/plot.hpp): one vertical axis per quantity with ticks that fit, its
// name and unit wrapped below it, "better" marks over objectives, one polyline per item and a
// legend of the groups at the right.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "report/plot.hpp"
#include "report/plot_layout.hpp"

namespace armstudy::report {
using namespace plot_detail;

const char* const kBetterMark = "better \u2191";

std::string withBetter(const std::string& label, Better better) {
  if (better == Better::higher) return label + " (higher is better)";
  if (better == Better::lower) return label + " (lower is better)";
  return label;
}

namespace {

constexpr double kMinAxisSpacing = 110;  // [px] between neighbouring axes
constexpr double kRangePad = 0.05;       // of an axis' data spread, above and below

// One axis: its value range (the data's, padded), ticks, and which way it grows.
struct AxisPlan {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  std::vector<double> ticks;
  double tick_w = 0;  // widest tick label
  std::vector<std::string> name;
  bool down = false;  // values grow downwards (a minimised quantity: better is up)
  double at(double v, double top, double h) const {
    const double t = (v - lo) / (hi - lo);
    return down ? top + t * h : top + h - t * h;
  }
};

AxisPlan planAxis(const Meter& m, const ParallelSpec& spec, std::size_t a) {
  AxisPlan p;
  for (const auto& g : spec.groups)
    for (const auto& item : g.items)
      if (a < item.size() && std::isfinite(item[a]))
        p.lo = std::min(p.lo, item[a]), p.hi = std::max(p.hi, item[a]);
  if (!(p.hi >= p.lo)) p.lo = 0, p.hi = 1;
  const double d =
      p.hi > p.lo ? kRangePad * (p.hi - p.lo) : (p.lo == 0 ? 0.5 : 0.05 * std::abs(p.lo));
  p.lo -= d, p.hi += d;
  p.ticks = fittingTicks(p.lo, p.hi, spec.axis_height, 45,
                         [&](const std::string&) { return m.height(kTickSize); });
  for (double t : p.ticks) p.tick_w = std::max(p.tick_w, m.width(tickText(t), kTickSize));
  p.down = spec.axes[a].better == Better::lower;
  return p;
}

// The polylines of every item, broken where a value is not known.
void drawItems(Scene& s, const ParallelSpec& spec, const std::vector<AxisPlan>& ax,
               const std::vector<double>& x, double top) {
  for (const auto& g : spec.groups)
    for (const auto& item : g.items) {
      std::vector<std::pair<double, double>> run;
      for (std::size_t a = 0; a < ax.size(); ++a) {
        if (a < item.size() && std::isfinite(item[a])) {
          run.emplace_back(x[a], ax[a].at(item[a], top, spec.axis_height));
          continue;
        }
        s.polyline(run, g.colour, g.line_width, false);
        run.clear();
      }
      s.polyline(run, g.colour, g.line_width, false);
    }
}

}  // namespace

Drawing parallelCoordinates(const ParallelSpec& spec, Format format) {
  ARMSTUDY_CHECK(!spec.axes.empty(), "parallel coordinates need at least one axis");
  const Meter m;
  Scene s(m);
  const double th = m.height(kTickSize), lh = m.height(kLabelSize), H = spec.axis_height;
  const double mark_w = m.width(kBetterMark, kTickSize);
  std::vector<AxisPlan> ax;
  for (std::size_t a = 0; a < spec.axes.size(); ++a) ax.push_back(planAxis(m, spec, a));
  // Spacing: room for the next axis' tick labels, the longest word of a name, the mark.
  double spacing = kMinAxisSpacing;
  for (std::size_t a = 0; a < ax.size(); ++a) {
    if (a > 0) spacing = std::max(spacing, ax[a].tick_w + kTickLen + 2 + 3 * kGap);
    for (const auto& word : m.wrap(spec.axes[a].label, kLabelSize, 0))
      spacing = std::max(spacing, m.width(word, kLabelSize) + kGap);
    spacing = std::max(spacing, mark_w + kGap);
  }
  const double name_w = spacing - kGap;
  double half0 = 0, half_last = 0;  // how far the first and last axis' text reaches sideways
  for (std::size_t a = 0; a < ax.size(); ++a) {
    ax[a].name = m.wrap(spec.axes[a].label, kLabelSize, name_w);
    double half = spec.axes[a].better != Better::none ? mark_w / 2 : 0;
    for (const auto& l : ax[a].name) half = std::max(half, m.width(l, kLabelSize) / 2);
    if (a == 0) half0 = std::max(half, ax[a].tick_w + kTickLen + 2);
    if (a + 1 == ax.size()) half_last = half;
  }
  std::vector<double> x(ax.size());
  for (std::size_t a = 0; a < ax.size(); ++a) x[a] = kPad + half0 + a * spacing;
  std::vector<std::string> legend;
  for (const auto& g : spec.groups)
    if (!g.label.empty()) legend.push_back(g.label);
  const double legend_x = x.back() + half_last + 3 * kGap;
  double W = legend_x + legendWidth(m, legend) + kPad;
  for (const auto& word : m.wrap(spec.title, kTitleSize, 0))
    W = std::max(W, m.width(word, kTitleSize) + 2 * kPad);
  // Title, the "better" marks, the axes with their ticks, the names below.
  double y = titleBlock(s, m, spec.title, kPad, W - kPad, kPad);
  const double top = y + th + kGap + th / 2;
  drawItems(s, spec, ax, x, top);
  double bottom = top + H;
  for (std::size_t a = 0; a < ax.size(); ++a) {
    if (spec.axes[a].better != Better::none)
      s.text(kBetterMark, x[a], y, kTickSize, HAlign::centre, VAlign::top);
    s.line(x[a], top, x[a], top + H, kFrame, 1.2);
    for (double t : ax[a].ticks) {
      const double py = ax[a].at(t, top, H), w = m.width(tickText(t), kTickSize);
      s.line(x[a] - kTickLen, py, x[a], py, kBlack);
      s.rect(x[a] - kTickLen - 3 - w, py - th / 2, w + 2, th, Rgb{255, 255, 255}, std::nullopt);
      s.text(tickText(t), x[a] - kTickLen - 2, py, kTickSize, HAlign::right, VAlign::middle);
    }
    double ny = top + H + th / 2 + kGap;
    for (const auto& l : ax[a].name) {
      s.text(l, x[a], ny, kLabelSize, HAlign::centre, VAlign::top);
      ny += lh;
    }
    bottom = std::max(bottom, ny);
  }
  // Legend: a line of each group's colour and width, from the axes' top down.
  double ly = top;
  const double row = lh + 6;
  for (const auto& g : spec.groups) {
    if (g.label.empty()) continue;
    s.line(legend_x, ly + row / 2, legend_x + kSwatch, ly + row / 2, g.colour,
           std::max(2.0, g.line_width));
    s.text(g.label, legend_x + kSwatch + kGap, ly + row / 2, kLabelSize, HAlign::left,
           VAlign::middle);
    ly += row;
  }
  s.fit(W, std::max(bottom, ly) + kPad);
  return s.render(format);
}

}  // namespace armstudy::report
