#include "report/plot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "report/plot_layout.hpp"

namespace armstudy::report {
using namespace plot_detail;

const char* const kThinNote =
    "Drawn thinned: a line of more than 2000 points keeps per pixel column its first, lowest, "
    "highest and last point; a figure of more than 2000 markers draws its plot areas as images. "
    "The data files hold every point.";

MapAxis cellAxis(std::string label, double from, double to, double step) {
  const double h = 0.5 * (to > from ? step : 1.0);
  return MapAxis{std::move(label), from - h, to + h, from, to};
}

Rgb seriesColour(int k) {
  static const Rgb c[10] = {{31, 119, 180},  {255, 127, 14}, {44, 160, 44},   {214, 39, 40},
                            {148, 103, 189}, {140, 86, 75},  {227, 119, 194}, {80, 80, 80},
                            {188, 189, 34},  {23, 190, 207}};
  return c[((k % 10) + 10) % 10];
}

Rgb diverging(double t) {
  if (!std::isfinite(t)) t = 0.5;
  t = std::clamp(2 * t - 1, -1.0, 1.0);
  const auto ch = [](double v) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 255.0)));
  };
  // White at 0, towards (33, 102, 172) below and (178, 24, 43) above.
  if (t < 0)
    return {ch(255 + t * (255 - 33)), ch(255 + t * (255 - 102)), ch(255 + t * (255 - 172))};
  return {ch(255 - t * (255 - 178)), ch(255 - t * (255 - 24)), ch(255 - t * (255 - 43))};
}

namespace {

// The ticks of a map axis drawn over `length_px` (the cells' inner extent): over the cells' centres
// where the axis gives them (a tick off the data would name a value no cell holds), else over the
// whole extent; a single row or column gets its centre.
std::vector<double> mapTicks(const MapAxis& a, double length_px, double per_tick_px,
                             const std::function<double(const std::string&)>& extent) {
  if (!(a.hi > a.lo)) return {};
  if (!(std::isfinite(a.from) && std::isfinite(a.to))) {
    return fittingTicks(a.lo, a.hi, length_px, per_tick_px, extent);
  }
  if (!(a.to > a.from)) return {a.from};
  const double span_px = length_px * (a.to - a.from) / (a.hi - a.lo);
  std::vector<double> t = fittingTicks(a.from, a.to, span_px, per_tick_px, extent);
  if (t.size() < 2) t = {a.from, a.to};  // no round value between: the first and last centre
  return t;
}

// The raster with the rows inside its frame (`border` px) repeated to `height` px in all, each row
// of cells keeping its share; a raster at least that tall as it is.
RasterImage stretchRows(const RasterImage& map, int border, int height) {
  const int h = map.height(), w = map.width();
  if (height <= h || h <= 2 * border) return map;
  RasterImage out(w, height);
  const int inner_src = h - 2 * border, inner_dst = height - 2 * border;
  for (int r = 0; r < height; ++r) {
    const int src = r < border             ? r
                    : r >= height - border ? h - (height - r)
                                           : border + (r - border) * inner_src / inner_dst;
    for (int c = 0; c < w; ++c) out.set(c, r, map.at(c, src));
  }
  return out;
}

}  // namespace

Drawing mapFigure(const RasterImage& raster, const MapFigure& f, Format format) {
  const Meter m;
  Scene s(m);
  const RasterImage map =
      stretchRows(raster, f.border_px, static_cast<int>(std::ceil(kMinMapHeight)));
  const double w = map.width(), h = map.height(), bp = f.border_px;
  const double th = m.height(kTickSize), lh = m.height(kLabelSize);
  // Ticks first (their labels set the margins).
  const double inner_w = w - 2 * bp, inner_h = h - 2 * bp;
  const auto xt =
      mapTicks(f.x, inner_w, 80, [&](const std::string& t) { return m.width(t, kTickSize); });
  const auto yt = mapTicks(f.y, inner_h, 60, [&](const std::string&) { return th; });
  double ytw = 0;
  for (double t : yt) ytw = std::max(ytw, m.width(tickText(t), kTickSize));
  // Labels reading upwards wrap to the map's height, or to 300 px beside a shorter map; what is
  // longer than the map gets room above and below it.
  const double vlen = std::max(h, 300.0);
  const auto ylines = m.wrap(f.y.label, kLabelSize, vlen);
  double vext = 0;
  for (const auto& l : ylines) vext = std::max(vext, m.width(l, kLabelSize));
  if (f.scale)
    for (const auto& l : m.wrap(f.scale->label, kLabelSize, vlen))
      vext = std::max(vext, m.width(l, kLabelSize));
  const double vextra = std::max(0.0, (vext - h) / 2);
  // The map's corner on whole pixels, so that its cells stay sharp squares in the PNG.
  const double ml = std::ceil(kPad + lh * ylines.size() + kGap + ytw + 2 + kTickLen);
  // Right side: colour bar, then legend.
  double right = ml + w;
  if (f.scale) right = colourBar(s, m, *f.scale, right + 2 * kGap + 6, 0, h, false, vlen);
  std::vector<std::string> labels;
  for (const auto& e : f.legend) labels.push_back(e.label);
  const double legend_x = right + 2 * kGap;
  if (!labels.empty()) right = legend_x + legendWidth(m, labels);
  // Half of the outermost x tick labels may stick out past the map.
  double x_over = 0;
  for (double t : xt) {
    const double px = ml + bp + (t - f.x.lo) / (f.x.hi - f.x.lo) * inner_w;
    x_over = std::max(x_over, px + m.width(tickText(t), kTickSize) / 2 - right);
  }
  double W = std::max({right + std::max(0.0, x_over) + kPad, 320.0,
                       ml + widestLine(m, f.x.label, kLabelSize, w) + kPad});
  // A title wider than everything else wraps; a single word longer than the canvas widens it.
  for (const auto& word : m.wrap(f.title, kTitleSize, 0))
    W = std::max(W, m.width(word, kTitleSize) + 2 * kPad);
  // Below the title: room for the upper half of the top tick labels (or the vertical labels).
  const double mt =
      std::ceil(titleBlock(s, m, f.title, kPad, W - kPad, kPad) + std::max(vextra, th / 2));
  const double iy0 = mt + bp, iy1 = mt + h - bp, ix0 = ml + bp, ix1 = ml + w - bp;
  s.image(map, ml, mt);
  for (double t : xt) {
    const double px = ix0 + (t - f.x.lo) / (f.x.hi - f.x.lo) * (ix1 - ix0);
    s.line(px, mt + h, px, mt + h + kTickLen, kBlack);
    s.text(tickText(t), px, mt + h + kTickLen + 2, kTickSize, HAlign::centre, VAlign::top);
  }
  for (double t : yt) {
    const double py = iy1 - (t - f.y.lo) / (f.y.hi - f.y.lo) * (iy1 - iy0);
    s.line(ml - kTickLen, py, ml, py, kBlack);
    s.text(tickText(t), ml - kTickLen - 2, py, kTickSize, HAlign::right, VAlign::middle);
  }
  double y = mt + h + kTickLen + 2 + th + kGap;
  for (const auto& l : m.wrap(f.x.label, kLabelSize, std::max(w, W - ml - kPad))) {
    s.text(l, ml + w / 2, y, kLabelSize, HAlign::centre, VAlign::top);
    y += lh;
  }
  for (std::size_t k = 0; k < ylines.size(); ++k)
    s.vtext(ylines[k], kPad + lh * (k + 0.5), mt + h / 2, kLabelSize);
  if (f.scale) colourBar(s, m, *f.scale, ml + w + 2 * kGap + 6, mt, mt + h, true, vlen);
  double ly = mt;
  const double row = std::max(lh, 14.0) + 6;
  for (const auto& e : f.legend) {
    s.rect(legend_x, ly + (row - 14) / 2, 14, 14, e.colour, Rgb{85, 85, 85});
    s.text(e.label, legend_x + kSwatch + kGap, ly + row / 2, kLabelSize, HAlign::left,
           VAlign::middle);
    ly += row;
  }
  s.fit(W, std::max({y, ly, mt + h + vextra}) + kPad);
  return s.render(format);
}

namespace {

struct Range {
  double lo = std::numeric_limits<double>::infinity(),
         hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  void pad(double frac) {
    if (!(hi >= lo)) lo = 0, hi = 1;
    if (!(hi > lo)) {
      const double d = lo == 0 ? 0.5 : 0.05 * std::abs(lo);
      lo -= d, hi += d;
      return;
    }
    const double d = frac * (hi - lo);
    lo -= d, hi += d;
  }
};

// A plot area's frame: axes, grid and tick labels. Returns the bottom of the x tick labels.
struct Frame {
  double x0, y0, w, h;  // plot area [px]
  Range xr, yr;
  double px(double x) const { return x0 + (x - xr.lo) / (xr.hi - xr.lo) * w; }
  double py(double y) const { return y0 + h - (y - yr.lo) / (yr.hi - yr.lo) * h; }
};

struct XAxisPlan {
  std::vector<double> ticks;
  bool vertical = false;  // category labels reading upwards (they do not fit side by side)
  double below = 0;       // height of the tick labels below the plot area
};

XAxisPlan planXAxis(const Meter& m, const Range& xr, double w,
                    const std::vector<std::string>& cats) {
  XAxisPlan p;
  const double th = m.height(kTickSize);
  if (cats.empty()) {
    p.ticks = fittingTicks(xr.lo, xr.hi, w, 80,
                           [&](const std::string& t) { return m.width(t, kTickSize); });
    p.below = kTickLen + 2 + th;
    return p;
  }
  double widest = 0;
  for (const auto& c : cats) widest = std::max(widest, m.width(c, kTickSize));
  const double spacing = w / std::max<std::size_t>(1, cats.size());
  p.vertical = widest + kGap > spacing;
  p.below = kTickLen + 2 + (p.vertical ? widest : th);
  return p;
}

// The grid lines of the plot area at the ticks.
void drawGrid(Scene& s, const Frame& f, const XAxisPlan& xp, const std::vector<double>& yt,
              const std::vector<std::string>& cats) {
  for (double t : yt) s.line(f.x0, f.py(t), f.x0 + f.w, f.py(t), kGrid);
  if (cats.empty())
    for (double t : xp.ticks) s.line(f.px(t), f.y0, f.px(t), f.y0 + f.h, kGrid);
}

void drawFrame(Scene& s, const Frame& f, const XAxisPlan& xp, const std::vector<double>& yt,
               const std::vector<std::string>& cats) {
  drawGrid(s, f, xp, yt, cats);
  s.rect(f.x0, f.y0, f.w, f.h, std::nullopt, kFrame);
  const double yb = f.y0 + f.h;
  if (cats.empty()) {
    for (double t : xp.ticks) {
      s.line(f.px(t), yb, f.px(t), yb + kTickLen, kBlack);
      s.text(tickText(t), f.px(t), yb + kTickLen + 2, kTickSize, HAlign::centre, VAlign::top);
    }
  } else {
    for (std::size_t i = 0; i < cats.size(); ++i) {
      const double px = f.px(static_cast<double>(i));
      s.line(px, yb, px, yb + kTickLen, kBlack);
      if (xp.vertical)
        s.hanging(cats[i], px, yb + kTickLen + 2, kTickSize);
      else
        s.text(cats[i], px, yb + kTickLen + 2, kTickSize, HAlign::centre, VAlign::top);
    }
  }
  for (double t : yt) {
    s.line(f.x0 - kTickLen, f.py(t), f.x0, f.py(t), kBlack);
    s.text(tickText(t), f.x0 - kTickLen - 2, f.py(t), kTickSize, HAlign::right, VAlign::middle);
  }
}

std::vector<double> yTicks(const Meter& m, const Range& yr, double h) {
  return fittingTicks(yr.lo, yr.hi, h, 45, [&](const std::string&) { return m.height(kTickSize); });
}

double widestTick(const Meter& m, const std::vector<double>& t) {
  double w = 0;
  for (double v : t) w = std::max(w, m.width(tickText(v), kTickSize));
  return w;
}

// The x range shared by all panels: the categories, or the finite data and vertical lines.
Range sharedXRange(const PlotSpec& spec) {
  Range xr;
  if (!spec.x_categories.empty()) {
    xr.lo = -0.5, xr.hi = spec.x_categories.size() - 0.5;
  } else {
    for (const auto& p : spec.panels) {
      for (const auto& se : p.series)
        for (std::size_t i = 0; i < se.x.size() && i < se.y.size(); ++i)
          if (std::isfinite(se.y[i])) xr.add(se.x[i]);
      for (const auto& l : p.lines)
        if (!l.horizontal) xr.add(l.value);
    }
    if (!(xr.hi > xr.lo))
      xr.pad(0.05);
    else if (spec.x_margin > 0)
      xr.pad(spec.x_margin);
  }
  return xr;
}

// One panel's y range, ticks, wrapped y label and legend entries.
struct PanelPlan {
  Range yr;
  std::vector<double> yt;
  std::vector<std::string> ylines, legend;
};

// Every panel's plan, and the widest y ticks, y label lines and legend among them.
struct PanelPlans {
  std::vector<PanelPlan> ps;
  double ytw = 0, yl_cols = 0, legend_w = 0;
};

// Plans the panels; a single diagonal panel gets one range for both axes (xr included).
PanelPlans planPanels(const PlotSpec& spec, const Meter& m, Range& xr) {
  const double ph = spec.panel_height;
  PanelPlans pl;
  pl.ps.resize(spec.panels.size());
  for (std::size_t k = 0; k < spec.panels.size(); ++k) {
    const PlotPanel& pan = spec.panels[k];
    PanelPlan& p = pl.ps[k];
    for (const auto& se : pan.series)
      for (std::size_t i = 0; i < se.x.size() && i < se.y.size(); ++i)
        if (std::isfinite(se.x[i])) p.yr.add(se.y[i]);
    for (const auto& l : pan.lines)
      if (l.horizontal) p.yr.add(l.value);
    if (pan.diagonal) {
      p.yr.add(xr.lo), p.yr.add(xr.hi);
    }
    p.yr.pad(0.06);
    if (pan.y_range) p.yr = Range{(*pan.y_range)[0], (*pan.y_range)[1]};
    p.yt = yTicks(m, p.yr, ph);
    pl.ytw = std::max(pl.ytw, widestTick(m, p.yt));
    p.ylines = m.wrap(pan.y_label, kLabelSize, ph);
    pl.yl_cols = std::max(pl.yl_cols, static_cast<double>(p.ylines.size()));
    for (const auto& se : pan.series)
      if (!se.label.empty()) p.legend.push_back(se.label);
    for (const auto& l : pan.lines)
      if (!l.label.empty()) p.legend.push_back(l.label);
    pl.legend_w = std::max(pl.legend_w, legendWidth(m, p.legend));
  }
  if (spec.panels.size() == 1 && spec.panels[0].diagonal) {
    Range both = xr;
    both.add(pl.ps[0].yr.lo), both.add(pl.ps[0].yr.hi);
    xr = pl.ps[0].yr = both;
    pl.ps[0].yt = yTicks(m, pl.ps[0].yr, ph);
  }
  return pl;
}

using Points = std::vector<std::pair<double, double>>;

bool dense(const PlotSeries& se) { return std::min(se.x.size(), se.y.size()) > kThinAbove; }

// Whether the figure draws more than kThinAbove markers in all: its marker panels are then drawn
// as images.
bool rasterMarkers(const PlotSpec& spec) {
  std::size_t n = 0;
  for (const auto& pan : spec.panels)
    for (const auto& se : pan.series)
      if (se.markers) n += std::min(se.x.size(), se.y.size());
  return n > kThinAbove;
}

// A line's points as drawn: of each run of consecutive points in one pixel column, the first, the
// lowest, the highest and the last, in their order (min/max decimation: peaks stay visible).
Points thinLine(const Points& run) {
  Points out;
  std::size_t a = 0;
  while (a < run.size()) {
    const double col = std::floor(run[a].first);
    std::size_t b = a, lo = a, hi = a;
    while (b < run.size() && std::floor(run[b].first) == col) {
      if (run[b].second < run[lo].second) lo = b;
      if (run[b].second > run[hi].second) hi = b;
      ++b;
    }
    std::vector<std::size_t> keep{a, lo, hi, b - 1};
    std::sort(keep.begin(), keep.end());
    keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
    for (std::size_t k : keep) out.push_back(run[k]);
    a = b;
  }
  return out;
}

// A panel's series in frame f: lines broken at non-finite points, and markers. The line of a
// series of more than kThinAbove points is thinned for drawing (thinLine).
void drawSeries(Scene& s, const Frame& f, const PlotPanel& pan, const std::array<double, 4>& clip) {
  for (std::size_t i = 0; i < pan.series.size(); ++i) {
    const PlotSeries& se = pan.series[i];
    const Rgb c = se.colour.value_or(seriesColour(static_cast<int>(i)));
    const bool thin = dense(se);
    Points pts, run;
    auto flush = [&] {
      if (se.lines) s.polyline(thin ? thinLine(run) : run, c, 1.6, se.dashed, clip);
      run.clear();
    };
    for (std::size_t j = 0; j < se.x.size() && j < se.y.size(); ++j) {
      if (!std::isfinite(se.x[j]) || !std::isfinite(se.y[j])) {
        flush();
        continue;
      }
      run.emplace_back(f.px(se.x[j]), f.py(se.y[j]));
      pts.push_back(run.back());
    }
    flush();
    if (se.markers) s.dots(pts, c, se.marker_size, se.marker);
  }
}

// The series' point labels (PlotSeries::point_labels) in frame f, each beside its marker: right,
// left, above or below, the first place that overlaps no label already set and stays inside the
// plot area (else right of it).
void drawPointLabels(Scene& s, const Meter& m, const Frame& f, const PlotPanel& pan) {
  std::vector<TextBox> placed;
  const double th = m.height(kTickSize);
  const auto free = [&](const TextBox& b) {
    if (b.x0 < f.x0 || b.x1 > f.x0 + f.w || b.y0 < f.y0 || b.y1 > f.y0 + f.h) return false;
    return std::none_of(placed.begin(), placed.end(), [&](const TextBox& o) {
      return b.x0 < o.x1 && o.x0 < b.x1 && b.y0 < o.y1 && o.y0 < b.y1;
    });
  };
  for (const PlotSeries& se : pan.series)
    for (std::size_t j = 0; j < se.point_labels.size() && j < se.x.size() && j < se.y.size(); ++j) {
      const std::string& t = se.point_labels[j];
      if (t.empty() || !std::isfinite(se.x[j]) || !std::isfinite(se.y[j])) continue;
      const double x = f.px(se.x[j]), y = f.py(se.y[j]), w = m.width(t, kTickSize);
      const double d = se.marker_size + 2;
      const TextBox options[] = {{t, x + d, y - th / 2, x + d + w, y + th / 2},
                                 {t, x - d - w, y - th / 2, x - d, y + th / 2},
                                 {t, x - w / 2, y - d - th, x + w / 2, y - d},
                                 {t, x - w / 2, y + d, x + w / 2, y + d + th}};
      TextBox b = options[0];
      for (const TextBox& o : options)
        if (free(o)) {
          b = o;
          break;
        }
      placed.push_back(s.text(t, b.x0, b.y0, kTickSize, HAlign::left, VAlign::top));
    }
}

// The legend of a panel at x = lx from y down; returns the bottom of its entries.
double drawPanelLegend(Scene& s, const Meter& m, const PlotPanel& pan, double lx, double y) {
  const double lh = m.height(kLabelSize);
  double ly = y;
  const double row = lh + 6;
  auto entry = [&](const std::string& label, Rgb c, bool dashed, const PlotSeries* marker,
                   bool line) {
    if (line) s.line(lx, ly + row / 2, lx + kSwatch, ly + row / 2, c, 2, dashed);
    if (marker)
      s.dots({{lx + kSwatch / 2, ly + row / 2}}, c, std::max(3.0, marker->marker_size),
             marker->marker);
    s.text(label, lx + kSwatch + kGap, ly + row / 2, kLabelSize, HAlign::left, VAlign::middle);
    ly += row;
  };
  for (std::size_t i = 0; i < pan.series.size(); ++i)
    if (!pan.series[i].label.empty())
      entry(pan.series[i].label, pan.series[i].colour.value_or(seriesColour(static_cast<int>(i))),
            pan.series[i].dashed, pan.series[i].markers ? &pan.series[i] : nullptr,
            pan.series[i].lines);
  for (const auto& l : pan.lines)
    if (!l.label.empty()) entry(l.label, l.colour, true, nullptr, true);
  return ly;
}

// One panel from y down, its plot area at x = ml, pw wide: title, frame, y label, diagonal,
// reference lines, series and legend. Returns the y below it; sets thinned if a series was.
double drawPanel(Scene& s, const Meter& m, const PlotSpec& spec, const PlotPanel& pan,
                 const PanelPlan& p, const Range& xr, const XAxisPlan& xp, double ml, double pw,
                 double y, bool& thinned) {
  const double lh = m.height(kLabelSize), ph = spec.panel_height;
  if (!pan.title.empty())
    y = titleBlock(s, m, pan.title, ml, ml + pw, y, kLabelSize);
  else
    y += m.height(kTickSize) / 2;  // room for the top y tick label
  const Frame f{ml, y, pw, ph, xr, p.yr};
  drawFrame(s, f, xp, p.yt, spec.x_categories);
  for (std::size_t c = 0; c < p.ylines.size(); ++c)
    s.vtext(p.ylines[c], kPad + lh * (c + 0.5), y + ph / 2, kLabelSize);
  const std::array<double, 4> clip{ml, y, pw, ph};
  // A panel with a dense cloud of markers draws its plot area (grid, reference lines, series) as
  // one image, then its frame again on top.
  const bool raster =
      rasterMarkers(spec) && std::any_of(pan.series.begin(), pan.series.end(),
                                         [](const PlotSeries& se) { return se.markers; });
  const std::size_t mark = s.size();
  if (raster) drawGrid(s, f, xp, p.yt, spec.x_categories);
  if (pan.diagonal)
    s.polyline({{f.px(xr.lo), f.py(xr.lo)}, {f.px(xr.hi), f.py(xr.hi)}}, {136, 136, 136}, 1, true,
               clip);
  for (const auto& l : pan.lines) {
    if (l.horizontal)
      s.polyline({{ml, f.py(l.value)}, {ml + pw, f.py(l.value)}}, l.colour, 1.5, true, clip);
    else
      s.polyline({{f.px(l.value), y}, {f.px(l.value), y + ph}}, l.colour, 1.5, true, clip);
  }
  drawSeries(s, f, pan, clip);
  if (raster) {
    s.rasterise(mark, ml, y, static_cast<int>(std::lround(pw)), static_cast<int>(std::lround(ph)));
    s.rect(ml, y, pw, ph, std::nullopt, kFrame);
  }
  drawPointLabels(s, m, f, pan);
  if (raster || std::any_of(pan.series.begin(), pan.series.end(), dense)) thinned = true;
  // Legend right of the panel.
  const double ly = drawPanelLegend(s, m, pan, ml + pw + 2 * kGap, y);
  return std::max(y + ph + xp.below, ly) + kGap;
}

}  // namespace

// Panels stacked under a title, sharing the x axis and its label; legends right of the panels.
Drawing plot(const PlotSpec& spec, Format format) {
  ARMSTUDY_CHECK(!spec.panels.empty(), "a plot needs at least one panel");
  const Meter m;
  Scene s(m);
  const double lh = m.height(kLabelSize);
  Range xr = sharedXRange(spec);
  const PanelPlans pl = planPanels(spec, m, xr);
  const double ml = kPad + lh * pl.yl_cols + kGap + pl.ytw + 2 + kTickLen;
  const double mr = kPad + (pl.legend_w > 0 ? pl.legend_w + 2 * kGap : 0);
  double W = std::max(spec.width, ml + 240 + mr);
  const XAxisPlan xp = planXAxis(m, xr, W - ml - mr, spec.x_categories);
  for (const auto& word : m.wrap(spec.title, kTitleSize, 0))
    W = std::max(W, m.width(word, kTitleSize) + 2 * kPad);
  const double pw = W - ml - mr;
  double y = titleBlock(s, m, spec.title, kPad, W - kPad, kPad);
  bool thinned = false;
  for (std::size_t k = 0; k < spec.panels.size(); ++k)
    y = drawPanel(s, m, spec, spec.panels[k], pl.ps[k], xr, xp, ml, pw, y, thinned);
  for (const auto& l : m.wrap(spec.x_label, kLabelSize, pw)) {
    s.text(l, ml + pw / 2, y, kLabelSize, HAlign::centre, VAlign::top);
    y += lh;
  }
  if (thinned) {
    y += kGap;
    for (const auto& l : m.wrap(kThinNote, kTickSize, W - 2 * kPad)) {
      s.text(l, kPad, y, kTickSize, HAlign::left, VAlign::top);
      y += m.height(kTickSize);
    }
  }
  s.fit(W, y + kPad);
  return s.render(format);
}

Drawing heatmap(const HeatmapSpec& h, Format format) {
  const Meter m;
  Scene s(m);
  const double lh = m.height(kLabelSize), th = m.height(kTickSize);
  Range xr{h.x_min, h.x_max}, yr{h.y_min, h.y_max};
  if (!(xr.hi > xr.lo)) xr.hi = xr.lo + 1;
  if (!(yr.hi > yr.lo)) yr.hi = yr.lo + 1;
  Range vr;
  for (const auto& c : h.cells) vr.add(c.value);
  ColourScale sc;
  if (h.diverging) {
    double a = h.scale;
    if (!(a > 0)) a = std::max(std::abs(vr.lo), std::abs(vr.hi));
    if (!(a > 0) || !std::isfinite(a)) a = 1;
    sc = ColourScale{diverging, -a, a, h.value_label};
  } else {
    double lo = std::isfinite(vr.lo) ? std::min(0.0, vr.lo) : 0,
           hi = std::isfinite(vr.hi) ? vr.hi : 1;
    if (h.scale > 0) hi = h.scale;
    if (!(hi > lo)) hi = lo + 1;
    sc = ColourScale{viridis, lo, hi, h.value_label};
  }
  const double ph = 360;
  const auto yt = yTicks(m, yr, ph);
  const auto ylines = m.wrap(h.y_label, kLabelSize, ph);
  const double ml = kPad + lh * ylines.size() + kGap + widestTick(m, yt) + 2 + kTickLen;
  const double bar_w = colourBar(s, m, sc, 0, 0, ph, false);
  const double note_w = h.flagged_note.empty() ? 0 : m.width(h.flagged_note, kTickSize);
  const double mr = kPad + 2 * kGap + std::max(bar_w, note_w);
  double W = std::max(720.0, ml + 300 + mr);
  for (const auto& word : m.wrap(h.title, kTitleSize, 0))
    W = std::max(W, m.width(word, kTitleSize) + 2 * kPad);
  const double pw = W - ml - mr;
  double y = titleBlock(s, m, h.title, kPad, W - kPad, kPad) + th / 2;
  const Frame f{ml, y, pw, ph, xr, yr};
  const XAxisPlan xp = planXAxis(m, xr, pw, {});
  for (const auto& c : h.cells) {
    const double x0 = f.px(c.x_lo), x1 = f.px(c.x_hi), y0 = f.py(c.y_hi), y1 = f.py(c.y_lo);
    const double t = (c.value - sc.lo) / (sc.hi - sc.lo);
    const Rgb fill = std::isfinite(c.value) ? sc.map(t) : Rgb{200, 200, 200};
    s.rect(x0, y0, x1 - x0, y1 - y0, fill, Rgb{187, 187, 187}, 0.5);
    // The value in the cell, in the largest size that fits, black or white by the fill's lightness.
    const std::string text = (std::isfinite(c.value) ? valueText(c.value, h.value_digits) : "n/a") +
                             (c.flagged ? "*" : "");
    for (double size = 11; size >= 7; size -= 1)
      if (m.width(text, size) + 4 <= x1 - x0 && m.height(size) + 2 <= y1 - y0) {
        const double lum = 0.299 * fill.r + 0.587 * fill.g + 0.114 * fill.b;
        s.text(text, (x0 + x1) / 2, (y0 + y1) / 2, size, HAlign::centre, VAlign::middle,
               lum < 140 ? Rgb{255, 255, 255} : kBlack);
        break;
      }
  }
  for (const auto& c : h.cells)
    if (c.flagged)
      s.rect(f.px(c.x_lo), f.py(c.y_hi), f.px(c.x_hi) - f.px(c.x_lo), f.py(c.y_lo) - f.py(c.y_hi),
             std::nullopt, kBlack, 3);
  drawFrame(s, f, xp, yt, {});
  for (std::size_t c = 0; c < ylines.size(); ++c)
    s.vtext(ylines[c], kPad + lh * (c + 0.5), y + ph / 2, kLabelSize);
  colourBar(s, m, sc, ml + pw + 2 * kGap, y, y + ph);
  double yb = y + ph + xp.below + kGap;
  if (!h.flagged_note.empty())
    s.text(h.flagged_note, ml + pw + 2 * kGap, yb, kTickSize, HAlign::left, VAlign::top);
  for (const auto& l : m.wrap(h.x_label, kLabelSize, pw)) {
    s.text(l, ml + pw / 2, yb, kLabelSize, HAlign::centre, VAlign::top);
    yb += lh;
  }
  s.fit(W, yb + kPad + (h.flagged_note.empty() ? 0 : th));
  return s.render(format);
}

}  // namespace armstudy::report
