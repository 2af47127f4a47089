#pragma once
// Private to the plotting module (report/plot.cpp, report/plot_layout.cpp): text measured with
// cairo (Meter), the display list every figure is laid out into (Scene), the layout constants and
// the pieces several figure kinds share (ticks that fit, titles, colour bars, legends).
#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "common/format.hpp"
#include "report/plot.hpp"

namespace armstudy::report::plot_detail {

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

inline std::string tickText(double v) { return formatG(v, 6); }

inline std::string valueText(double v, int digits) {
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

inline const Rgb kBlack{0, 0, 0}, kGrid{225, 225, 225}, kFrame{60, 60, 60};

// Ticks whose labels do not overlap along an axis of `length_px` (labels' extent along the axis
// from `extent`): fewer ticks until the labels have room.
std::vector<double> fittingTicks(double lo, double hi, double length_px, double per_tick_px,
                                 const std::function<double(const std::string&)>& extent);
// Title lines centred over [x0, x1] from y; returns the y below them.
double titleBlock(Scene& s, const Meter& m, const std::string& title, double x0, double x1, double y,
                  double size = kTitleSize);
double widestLine(const Meter& m, const std::string& s, double size, double max_w);
// A vertical colour bar: bar at (x, y0..y1), ticks and labels to its right, then the scale's label
// reading upwards (wrapped to the bar's height). Returns the right edge of what it drew.
double colourBar(Scene& s, const Meter& m, const ColourScale& sc, double x, double y0, double y1,
                 bool draw = true, double label_len = 0);
double legendWidth(const Meter& m, const std::vector<std::string>& labels);

}  // namespace armstudy::report::plot_detail
