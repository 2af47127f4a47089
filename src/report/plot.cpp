#include "report/plot.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <memory>

#include "common/errors.hpp"
#include "common/format.hpp"

namespace armstudy::report {
namespace {

// Layout constants [px, font sizes in px].
constexpr double kPad = 10;          // canvas edge to anything
constexpr double kTitleSize = 15;
constexpr double kLabelSize = 13;    // axis and colour-bar labels, legend
constexpr double kTickSize = 11;     // tick labels
constexpr double kTickLen = 5;
constexpr double kGap = 6;           // between neighbouring pieces of text
constexpr double kBarWidth = 16;     // colour bar
constexpr double kSwatch = 22;       // legend sample
constexpr const char* kFont = "DejaVu Sans";
constexpr double kPi = 3.14159265358979323846;

std::string tickText(double v) { return formatG(v, 6); }

std::string valueText(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

// Measures text with cairo's toy font API (the same font the drawing uses).
class Meter {
 public:
  Meter() : surface_(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 4, 4)), cr_(cairo_create(surface_)) {
    cairo_select_font_face(cr_, kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  }
  ~Meter() {
    cairo_destroy(cr_);
    cairo_surface_destroy(surface_);
  }
  Meter(const Meter&) = delete;
  Meter& operator=(const Meter&) = delete;
  double width(const std::string& s, double size) const {
    cairo_set_font_size(cr_, size);
    cairo_text_extents_t e;
    cairo_text_extents(cr_, s.c_str(), &e);
    return std::max(e.x_advance, e.x_bearing + e.width);
  }
  double ascent(double size) const {
    cairo_set_font_size(cr_, size);
    cairo_font_extents_t f;
    cairo_font_extents(cr_, &f);
    return f.ascent;
  }
  double height(double size) const {
    cairo_set_font_size(cr_, size);
    cairo_font_extents_t f;
    cairo_font_extents(cr_, &f);
    return f.ascent + f.descent;
  }
  // Greedy word wrap to lines no wider than max_w (a single longer word stays one line).
  std::vector<std::string> wrap(const std::string& s, double size, double max_w) const {
    std::vector<std::string> lines;
    std::string line, word;
    auto flush_word = [&] {
      if (word.empty()) return;
      const std::string cand = line.empty() ? word : line + " " + word;
      if (!line.empty() && width(cand, size) > max_w) {
        lines.push_back(line);
        line = word;
      } else {
        line = cand;
      }
      word.clear();
    };
    for (char c : s) {
      if (c == ' ') flush_word();
      else word += c;
    }
    flush_word();
    if (!line.empty() || lines.empty()) lines.push_back(line);
    return lines;
  }

 private:
  cairo_surface_t* surface_;
  cairo_t* cr_;
};

enum class HAlign { left, centre, right };
enum class VAlign { top, middle, bottom };

// A display list: the layout computes every position first, then the list is replayed on an SVG
// and, when asked, an image surface.
class Scene {
 public:
  explicit Scene(const Meter& m) : m_(m) {}
  double W = 0, H = 0;
  std::vector<TextBox> texts;

  void op(std::function<void(cairo_t*)> f) { ops_.push_back(std::move(f)); }

  // Horizontal text anchored at (x, y) by its measured box.
  TextBox text(const std::string& s, double x, double y, double size, HAlign h, VAlign v, Rgb c = {0, 0, 0}) {
    const double w = m_.width(s, size), hh = m_.height(size), asc = m_.ascent(size);
    const double x0 = x - w * (h == HAlign::left ? 0 : h == HAlign::centre ? 0.5 : 1);
    const double y0 = y - hh * (v == VAlign::top ? 0 : v == VAlign::middle ? 0.5 : 1);
    op([=](cairo_t* cr) {
      cairo_set_source_rgb(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0);
      cairo_set_font_size(cr, size);
      cairo_move_to(cr, x0, y0 + asc);
      cairo_show_text(cr, s.c_str());
    });
    TextBox b{s, x0, y0, x0 + w, y0 + hh};
    if (!s.empty()) texts.push_back(b);
    return b;
  }
  // Text reading bottom to top, its box centred at (x, y).
  void vtext(const std::string& s, double x, double y, double size) {
    const double w = m_.width(s, size);
    upward(s, x, size, y, -w / 2, y - w / 2, y + w / 2);
  }
  // Text reading bottom to top, centred on x, its end (top) at y.
  void hanging(const std::string& s, double x, double y, double size) {
    const double w = m_.width(s, size);
    upward(s, x, size, y + w, 0, y, y + w);
  }
  // Text reading bottom to top, centred on x: drawn rotated about (x, pivot_y), starting `start`
  // from there along the text; its box spans top .. bottom in y.
  void upward(const std::string& s, double x, double size, double pivot_y, double start, double top,
              double bottom) {
    const double hh = m_.height(size), asc = m_.ascent(size);
    op([=](cairo_t* cr) {
      cairo_save(cr);
      cairo_set_source_rgb(cr, 0, 0, 0);
      cairo_set_font_size(cr, size);
      cairo_translate(cr, x, pivot_y);
      cairo_rotate(cr, -kPi / 2);
      cairo_move_to(cr, start, -hh / 2 + asc);
      cairo_show_text(cr, s.c_str());
      cairo_restore(cr);
    });
    if (!s.empty()) texts.push_back({s, x - hh / 2, top, x + hh / 2, bottom});
  }
  void rect(double x, double y, double w, double h, std::optional<Rgb> fill, std::optional<Rgb> stroke,
            double lw = 1) {
    op([=](cairo_t* cr) {
      cairo_rectangle(cr, x, y, w, h);
      if (fill) {
        cairo_set_source_rgb(cr, fill->r / 255.0, fill->g / 255.0, fill->b / 255.0);
        if (stroke) cairo_fill_preserve(cr);
        else cairo_fill(cr);
      }
      if (stroke) {
        cairo_set_source_rgb(cr, stroke->r / 255.0, stroke->g / 255.0, stroke->b / 255.0);
        cairo_set_line_width(cr, lw);
        cairo_stroke(cr);
      }
    });
  }
  void line(double x0, double y0, double x1, double y1, Rgb c, double lw = 1, bool dashed = false) {
    polyline({{x0, y0}, {x1, y1}}, c, lw, dashed);
  }
  void polyline(std::vector<std::pair<double, double>> pts, Rgb c, double lw, bool dashed,
                std::optional<std::array<double, 4>> clip = std::nullopt) {
    if (pts.size() < 2) return;
    op([=](cairo_t* cr) {
      cairo_save(cr);
      if (clip) {
        cairo_rectangle(cr, (*clip)[0], (*clip)[1], (*clip)[2], (*clip)[3]);
        cairo_clip(cr);
      }
      cairo_set_source_rgb(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0);
      cairo_set_line_width(cr, lw);
      cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
      if (dashed) {
        const double d[2] = {6, 4};
        cairo_set_dash(cr, d, 2, 0);
      }
      cairo_move_to(cr, pts[0].first, pts[0].second);
      for (std::size_t i = 1; i < pts.size(); ++i) cairo_line_to(cr, pts[i].first, pts[i].second);
      cairo_stroke(cr);
      cairo_restore(cr);
    });
  }
  void dots(std::vector<std::pair<double, double>> pts, Rgb c, double r) {
    if (pts.empty()) return;
    op([=](cairo_t* cr) {
      cairo_set_source_rgba(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0, 0.75);
      for (const auto& [x, y] : pts) {
        cairo_new_sub_path(cr);
        cairo_arc(cr, x, y, r, 0, 2 * kPi);
      }
      cairo_fill(cr);
    });
  }
  void image(const RasterImage& img, double x, double y) {
    auto data = std::make_shared<std::vector<unsigned char>>();
    const int stride = cairo_format_stride_for_width(CAIRO_FORMAT_RGB24, img.width());
    data->assign(static_cast<std::size_t>(stride) * img.height(), 0);
    for (int r = 0; r < img.height(); ++r)
      for (int c = 0; c < img.width(); ++c) {
        const Rgb p = img.at(c, r);
        auto* px = reinterpret_cast<std::uint32_t*>(data->data() + static_cast<std::size_t>(r) * stride) + c;
        *px = (std::uint32_t{p.r} << 16) | (std::uint32_t{p.g} << 8) | p.b;
      }
    const int w = img.width(), h = img.height();
    op([=](cairo_t* cr) {
      cairo_surface_t* s = cairo_image_surface_create_for_data(data->data(), CAIRO_FORMAT_RGB24, w, h, stride);
      cairo_save(cr);
      cairo_set_source_surface(cr, s, x, y);
      cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
      cairo_rectangle(cr, x, y, w, h);
      cairo_fill(cr);
      cairo_restore(cr);
      cairo_surface_destroy(s);
    });
  }
  void fit(double x, double y) {
    W = std::max(W, x);
    H = std::max(H, y);
  }

  Drawing render(Format format) const {
    Drawing d;
    d.width = std::ceil(W);
    d.height = std::ceil(H);
    d.texts = texts;
    auto append = [](void* closure, const unsigned char* data, unsigned int length) {
      static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
      return CAIRO_STATUS_SUCCESS;
    };
    {
      cairo_surface_t* s = cairo_svg_surface_create_for_stream(append, &d.svg, d.width, d.height);
      cairo_svg_surface_restrict_to_version(s, CAIRO_SVG_VERSION_1_1);
      play(s);
      cairo_surface_finish(s);
      ARMSTUDY_CHECK(cairo_surface_status(s) == CAIRO_STATUS_SUCCESS, "cairo could not write the SVG figure");
      cairo_surface_destroy(s);
    }
    d.svg = numberIds(d.svg);
    if (format == Format::svg_and_png) {
      cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, static_cast<int>(d.width),
                                                      static_cast<int>(d.height));
      play(s);
      cairo_surface_flush(s);
      ARMSTUDY_CHECK(cairo_surface_write_to_png_stream(s, append, &d.png) == CAIRO_STATUS_SUCCESS,
                     "cairo could not write the PNG figure");
      cairo_surface_destroy(s);
    }
    return d;
  }

 private:
  void play(cairo_surface_t* s) const {
    cairo_t* cr = cairo_create(s);
    cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    for (const auto& f : ops_) f(cr);
    cairo_destroy(cr);
  }
  // cairo names SVG elements from process-wide counters ("surface12", "image7"): the same figure
  // would differ with what was drawn before it. Numbers them in order of first appearance.
  static std::string numberIds(const std::string& svg) {
    std::map<std::string, std::string> renamed;
    std::map<std::string, int> next;
    std::string out;
    out.reserve(svg.size());
    std::size_t i = 0;
    while (i < svg.size()) {
      const std::size_t p = svg.find("id=\"", i);
      const std::size_t q = svg.find("#", i);
      const std::size_t at = std::min(p, q);
      if (at == std::string::npos) break;
      const std::size_t start = at + (at == p ? 4 : 1);
      out.append(svg, i, start - i);
      std::size_t e = start;
      while (e < svg.size() && (std::isalpha(static_cast<unsigned char>(svg[e])) || svg[e] == '-')) ++e;
      std::size_t d = e;
      while (d < svg.size() && std::isdigit(static_cast<unsigned char>(svg[d]))) ++d;
      const std::string prefix = svg.substr(start, e - start);
      if ((prefix == "surface" || prefix == "image" || prefix == "source-") && d > e) {
        const std::string old = svg.substr(start, d - start);
        auto it = renamed.find(old);
        if (it == renamed.end()) it = renamed.emplace(old, prefix + std::to_string(next[prefix]++)).first;
        out += it->second;
        i = d;
      } else {
        i = start;
      }
    }
    out.append(svg, i, std::string::npos);
    return out;
  }

  const Meter& m_;
  std::vector<std::function<void(cairo_t*)>> ops_;
};

const Rgb kBlack{0, 0, 0}, kGrid{225, 225, 225}, kFrame{60, 60, 60};

// Ticks whose labels do not overlap along an axis of `length_px` (labels' extent along the axis
// from `extent`): fewer ticks until the labels have room.
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

// Title lines centred over [x0, x1] from y; returns the y below them.
double titleBlock(Scene& s, const Meter& m, const std::string& title, double x0, double x1, double y,
                  double size = kTitleSize) {
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

// A vertical colour bar: bar at (x, y0..y1), ticks and labels to its right, then the scale's label
// reading upwards (wrapped to the bar's height). Returns the right edge of what it drew.
double colourBar(Scene& s, const Meter& m, const ColourScale& sc, double x, double y0, double y1,
                 bool draw = true, double label_len = 0) {
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

}  // namespace

MapAxis cellAxis(std::string label, double from, double to, double step) {
  const double h = 0.5 * (to > from ? step : 1.0);
  return MapAxis{std::move(label), from - h, to + h};
}

Rgb seriesColour(int k) {
  static const Rgb c[10] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44},  {214, 39, 40},  {148, 103, 189},
                            {140, 86, 75},  {227, 119, 194}, {80, 80, 80}, {188, 189, 34}, {23, 190, 207}};
  return c[((k % 10) + 10) % 10];
}

Rgb diverging(double t) {
  if (!std::isfinite(t)) t = 0.5;
  t = std::clamp(2 * t - 1, -1.0, 1.0);
  const auto ch = [](double v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 255.0))); };
  // White at 0, towards (33, 102, 172) below and (178, 24, 43) above.
  if (t < 0) return {ch(255 + t * (255 - 33)), ch(255 + t * (255 - 102)), ch(255 + t * (255 - 172))};
  return {ch(255 - t * (255 - 178)), ch(255 - t * (255 - 24)), ch(255 - t * (255 - 43))};
}

Drawing mapFigure(const RasterImage& map, const MapFigure& f, Format format) {
  const Meter m;
  Scene s(m);
  const double w = map.width(), h = map.height(), bp = f.border_px;
  const double th = m.height(kTickSize), lh = m.height(kLabelSize);
  // Ticks first (their labels set the margins).
  const double inner_w = w - 2 * bp, inner_h = h - 2 * bp;
  const auto xt = f.x.hi > f.x.lo ? fittingTicks(f.x.lo, f.x.hi, inner_w, 80, [&](const std::string& t) {
    return m.width(t, kTickSize);
  })
                                  : std::vector<double>{};
  const auto yt = f.y.hi > f.y.lo ? fittingTicks(f.y.lo, f.y.hi, inner_h, 60, [&](const std::string&) { return th; })
                                  : std::vector<double>{};
  double ytw = 0;
  for (double t : yt) ytw = std::max(ytw, m.width(tickText(t), kTickSize));
  // Labels reading upwards wrap to the map's height, or to 300 px beside a shorter map; what is
  // longer than the map gets room above and below it.
  const double vlen = std::max(h, 300.0);
  const auto ylines = m.wrap(f.y.label, kLabelSize, vlen);
  double vext = 0;
  for (const auto& l : ylines) vext = std::max(vext, m.width(l, kLabelSize));
  if (f.scale)
    for (const auto& l : m.wrap(f.scale->label, kLabelSize, vlen)) vext = std::max(vext, m.width(l, kLabelSize));
  const double vextra = std::max(0.0, (vext - h) / 2);
  const double ml = kPad + lh * ylines.size() + kGap + ytw + 2 + kTickLen;
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
  for (const auto& word : m.wrap(f.title, kTitleSize, 0)) W = std::max(W, m.width(word, kTitleSize) + 2 * kPad);
  const double mt = titleBlock(s, m, f.title, kPad, W - kPad, kPad) + vextra;
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
  for (std::size_t k = 0; k < ylines.size(); ++k) s.vtext(ylines[k], kPad + lh * (k + 0.5), mt + h / 2, kLabelSize);
  if (f.scale) colourBar(s, m, *f.scale, ml + w + 2 * kGap + 6, mt, mt + h, true, vlen);
  double ly = mt;
  const double row = std::max(lh, 14.0) + 6;
  for (const auto& e : f.legend) {
    s.rect(legend_x, ly + (row - 14) / 2, 14, 14, e.colour, Rgb{85, 85, 85});
    s.text(e.label, legend_x + kSwatch + kGap, ly + row / 2, kLabelSize, HAlign::left, VAlign::middle);
    ly += row;
  }
  s.fit(W, std::max({y, ly, mt + h + vextra}) + kPad);
  return s.render(format);
}

namespace {

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
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

XAxisPlan planXAxis(const Meter& m, const Range& xr, double w, const std::vector<std::string>& cats) {
  XAxisPlan p;
  const double th = m.height(kTickSize);
  if (cats.empty()) {
    p.ticks = fittingTicks(xr.lo, xr.hi, w, 80, [&](const std::string& t) { return m.width(t, kTickSize); });
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

void drawFrame(Scene& s, const Frame& f, const XAxisPlan& xp, const std::vector<double>& yt,
               const std::vector<std::string>& cats) {
  for (double t : yt) s.line(f.x0, f.py(t), f.x0 + f.w, f.py(t), kGrid);
  if (cats.empty())
    for (double t : xp.ticks) s.line(f.px(t), f.y0, f.px(t), f.y0 + f.h, kGrid);
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
      if (xp.vertical) s.hanging(cats[i], px, yb + kTickLen + 2, kTickSize);
      else s.text(cats[i], px, yb + kTickLen + 2, kTickSize, HAlign::centre, VAlign::top);
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

}  // namespace

Drawing plot(const PlotSpec& spec, Format format) {
  ARMSTUDY_CHECK(!spec.panels.empty(), "a plot needs at least one panel");
  const Meter m;
  Scene s(m);
  const double lh = m.height(kLabelSize), ph = spec.panel_height;
  // Shared x range.
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
    if (!(xr.hi > xr.lo)) xr.pad(0.05);
  }
  // Per panel: y range, ticks, legend.
  struct P {
    Range yr;
    std::vector<double> yt;
    std::vector<std::string> ylines, legend;
  };
  std::vector<P> ps(spec.panels.size());
  double ytw = 0, yl_cols = 0, legend_w = 0;
  for (std::size_t k = 0; k < spec.panels.size(); ++k) {
    const PlotPanel& pan = spec.panels[k];
    P& p = ps[k];
    for (const auto& se : pan.series)
      for (std::size_t i = 0; i < se.x.size() && i < se.y.size(); ++i)
        if (std::isfinite(se.x[i])) p.yr.add(se.y[i]);
    for (const auto& l : pan.lines)
      if (l.horizontal) p.yr.add(l.value);
    if (pan.diagonal) {
      p.yr.add(xr.lo), p.yr.add(xr.hi);
    }
    p.yr.pad(0.06);
    p.yt = yTicks(m, p.yr, ph);
    ytw = std::max(ytw, widestTick(m, p.yt));
    p.ylines = m.wrap(pan.y_label, kLabelSize, ph);
    yl_cols = std::max(yl_cols, static_cast<double>(p.ylines.size()));
    for (const auto& se : pan.series)
      if (!se.label.empty()) p.legend.push_back(se.label);
    for (const auto& l : pan.lines)
      if (!l.label.empty()) p.legend.push_back(l.label);
    legend_w = std::max(legend_w, legendWidth(m, p.legend));
  }
  if (spec.panels.size() == 1 && spec.panels[0].diagonal) {
    Range both = xr;
    both.add(ps[0].yr.lo), both.add(ps[0].yr.hi);
    xr = ps[0].yr = both;
    ps[0].yt = yTicks(m, ps[0].yr, ph);
  }
  const double ml = kPad + lh * yl_cols + kGap + ytw + 2 + kTickLen;
  const double mr = kPad + (legend_w > 0 ? legend_w + 2 * kGap : 0);
  double W = std::max(spec.width, ml + 240 + mr);
  const XAxisPlan xp = planXAxis(m, xr, W - ml - mr, spec.x_categories);
  for (const auto& word : m.wrap(spec.title, kTitleSize, 0)) W = std::max(W, m.width(word, kTitleSize) + 2 * kPad);
  const double pw = W - ml - mr;
  double y = titleBlock(s, m, spec.title, kPad, W - kPad, kPad);
  for (std::size_t k = 0; k < spec.panels.size(); ++k) {
    const PlotPanel& pan = spec.panels[k];
    P& p = ps[k];
    if (!pan.title.empty()) y = titleBlock(s, m, pan.title, ml, ml + pw, y, kLabelSize);
    else y += m.height(kTickSize) / 2;  // room for the top y tick label
    const Frame f{ml, y, pw, ph, xr, p.yr};
    drawFrame(s, f, xp, p.yt, spec.x_categories);
    for (std::size_t c = 0; c < p.ylines.size(); ++c)
      s.vtext(p.ylines[c], kPad + lh * (c + 0.5), y + ph / 2, kLabelSize);
    const std::array<double, 4> clip{ml, y, pw, ph};
    if (pan.diagonal) s.polyline({{f.px(xr.lo), f.py(xr.lo)}, {f.px(xr.hi), f.py(xr.hi)}}, {136, 136, 136}, 1, true, clip);
    for (const auto& l : pan.lines) {
      if (l.horizontal) s.polyline({{ml, f.py(l.value)}, {ml + pw, f.py(l.value)}}, l.colour, 1.5, true, clip);
      else s.polyline({{f.px(l.value), y}, {f.px(l.value), y + ph}}, l.colour, 1.5, true, clip);
    }
    for (std::size_t i = 0; i < pan.series.size(); ++i) {
      const PlotSeries& se = pan.series[i];
      const Rgb c = se.colour.value_or(seriesColour(static_cast<int>(i)));
      std::vector<std::pair<double, double>> pts, run;
      auto flush = [&] {
        if (se.lines) s.polyline(run, c, 1.6, se.dashed, clip);
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
      if (se.markers) s.dots(pts, c, 2.6);
    }
    // Legend right of the panel.
    const double lx = ml + pw + 2 * kGap;
    double ly = y;
    const double row = lh + 6;
    auto entry = [&](const std::string& label, Rgb c, bool dashed, bool marker, bool line) {
      if (line) s.line(lx, ly + row / 2, lx + kSwatch, ly + row / 2, c, 2, dashed);
      if (marker) s.dots({{lx + kSwatch / 2, ly + row / 2}}, c, 3);
      s.text(label, lx + kSwatch + kGap, ly + row / 2, kLabelSize, HAlign::left, VAlign::middle);
      ly += row;
    };
    for (std::size_t i = 0; i < pan.series.size(); ++i)
      if (!pan.series[i].label.empty())
        entry(pan.series[i].label, pan.series[i].colour.value_or(seriesColour(static_cast<int>(i))),
              pan.series[i].dashed, pan.series[i].markers, pan.series[i].lines);
    for (const auto& l : pan.lines)
      if (!l.label.empty()) entry(l.label, l.colour, true, false, true);
    y = std::max(y + ph + xp.below, ly) + kGap;
  }
  for (const auto& l : m.wrap(spec.x_label, kLabelSize, pw)) {
    s.text(l, ml + pw / 2, y, kLabelSize, HAlign::centre, VAlign::top);
    y += lh;
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
    double lo = std::isfinite(vr.lo) ? std::min(0.0, vr.lo) : 0, hi = std::isfinite(vr.hi) ? vr.hi : 1;
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
  for (const auto& word : m.wrap(h.title, kTitleSize, 0)) W = std::max(W, m.width(word, kTitleSize) + 2 * kPad);
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
    if (c.flagged) s.rect(f.px(c.x_lo), f.py(c.y_hi), f.px(c.x_hi) - f.px(c.x_lo), f.py(c.y_lo) - f.py(c.y_hi), std::nullopt, kBlack, 3);
  drawFrame(s, f, xp, yt, {});
  for (std::size_t c = 0; c < ylines.size(); ++c) s.vtext(ylines[c], kPad + lh * (c + 0.5), y + ph / 2, kLabelSize);
  colourBar(s, m, sc, ml + pw + 2 * kGap, y, y + ph);
  double yb = y + ph + xp.below + kGap;
  if (!h.flagged_note.empty()) s.text(h.flagged_note, ml + pw + 2 * kGap, yb, kTickSize, HAlign::left, VAlign::top);
  for (const auto& l : m.wrap(h.x_label, kLabelSize, pw)) {
    s.text(l, ml + pw / 2, yb, kLabelSize, HAlign::centre, VAlign::top);
    yb += lh;
  }
  s.fit(W, yb + kPad + (h.flagged_note.empty() ? 0 : th));
  return s.render(format);
}

}  // namespace armstudy::report
