#include "report/plot_layout.hpp"

namespace armstudy::report::plot_detail {

std::vector<double> fittingTicks(double lo, double hi, double length_px, double per_tick_px,
                                 const std::function<double(const std::string&)>& extent) {
  std::vector<double> fallback;
  const int base = std::max(3, static_cast<int>(length_px / per_tick_px));
  std::vector<int> targets;  // fewer ticks first down to 1, then more (a range just over a 1-2-5 step)
  for (int t = base; t >= 1; --t) targets.push_back(t);
  for (int t = base + 1; t <= base + 6; ++t) targets.push_back(t);
  for (const int target : targets) {
    const auto t = niceTicks(lo, hi, target);
    if (t.size() < 2) {
      if (fallback.empty()) fallback = t;
      continue;
    }
    const double spacing = length_px * (t[1] - t[0]) / (hi - lo);
    double widest = 0;
    for (double v : t) widest = std::max(widest, extent(tickText(v)));
    if (widest + kGap <= spacing) return t;
    fallback = {t.front()};
  }
  return fallback;
}

double titleBlock(Scene& s, const Meter& m, const std::string& title, double x0, double x1, double y,
                  double size) {
  if (title.empty()) return y;
  for (const std::string& line : m.wrap(title, size, x1 - x0)) {
    s.text(line, (x0 + x1) / 2, y, size, HAlign::centre, VAlign::top);
    y += m.height(size);
  }
  return y + kGap;
}

double widestLine(const Meter& m, const std::string& s, double size, double max_w) {
  double w = 0;
  for (const auto& l : m.wrap(s, size, max_w)) w = std::max(w, m.width(l, size));
  return w;
}

double colourBar(Scene& s, const Meter& m, const ColourScale& sc, double x, double y0, double y1,
                 bool draw, double label_len) {
  const double h = y1 - y0;
  const int steps = 128;
  if (draw)
    for (int k = 0; k < steps; ++k)
      s.rect(x, y1 - h * (k + 1.0) / steps, kBarWidth, h / steps + 0.6, sc.map((k + 0.5) / steps), std::nullopt);
  if (draw) s.rect(x, y0, kBarWidth, h, std::nullopt, kFrame);
  double widest = 0;
  const auto ticks = sc.hi > sc.lo ? fittingTicks(sc.lo, sc.hi, h, 40, [&](const std::string&) {
    return m.height(kTickSize);
  })
                                   : std::vector<double>{sc.lo};
  for (double t : ticks) {
    const double py = sc.hi > sc.lo ? y1 - (t - sc.lo) / (sc.hi - sc.lo) * h : (y0 + y1) / 2;
    widest = std::max(widest, m.width(tickText(t), kTickSize));
    if (draw) {
      s.line(x + kBarWidth, py, x + kBarWidth + kTickLen - 1, py, kBlack);
      s.text(tickText(t), x + kBarWidth + kTickLen + 2, py, kTickSize, HAlign::left, VAlign::middle);
    }
  }
  double cx = x + kBarWidth + kTickLen + 2 + widest + kGap;
  const auto lines = m.wrap(sc.label, kLabelSize, std::max(h, label_len));
  const double lh = m.height(kLabelSize);
  for (const auto& l : lines) {
    if (draw) s.vtext(l, cx + lh / 2, (y0 + y1) / 2, kLabelSize);
    cx += lh;
  }
  return cx;
}

double legendWidth(const Meter& m, const std::vector<std::string>& labels) {
  double w = 0;
  for (const auto& l : labels) w = std::max(w, m.width(l, kLabelSize));
  return labels.empty() ? 0 : kSwatch + kGap + w;
}

}  // namespace armstudy::report::plot_detail
