#pragma once
// Private to the plotting module (report/plot.cpp, report/plot_layout.cpp): text measured with
// cairo in the figures' font (Meter), the display list every figure is laid out into (Scene), the
// layout constants and the pieces several figure kinds share (ticks that fit, titles, colour bars,
// legends).
#include <cairo.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "common/format.hpp"
#include "report/plot.hpp"

namespace armstudy::report::plot_detail {

// Layout constants [px, font sizes in px].
constexpr double kPad = 10;  // canvas edge to anything
constexpr double kTitleSize = 15;
constexpr double kLabelSize = 13;  // axis and colour-bar labels, legend
constexpr double kTickSize = 11;   // tick labels
constexpr double kTickLen = 5;
constexpr double kGap = 6;             // between neighbouring pieces of text
constexpr double kLeading = 2;         // between the lines of a wrapped title
constexpr double kBarWidth = 16;       // colour bar
constexpr double kSwatch = 22;         // legend sample
constexpr double kMarkerStroke = 1.5;  // hollow markers' line width
constexpr const char* kFont = "DejaVu Sans";

inline std::string tickText(double v) { return formatG(v, 6); }

inline std::string valueText(double v, int digits) { return formatG(v, digits); }

// The figures' font: DejaVu Sans read from its file (ARMSTUDY_FONT_FILE, fonts-dejavu-core) with
// FreeType and drawn without hinting, so text is measured and drawn the same in every process,
// whatever fontconfig, the environment or earlier drawing would choose. Without that file: cairo's
// "DejaVu Sans" through fontconfig, with a warning on stderr once.
cairo_font_face_t* figureFont();
void useFigureFont(cairo_t* cr);  // selects figureFont() and its fixed font options

// Measures text in the figures' font.
class Meter {
 public:
  Meter()
      : surface_(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 4, 4)),
        cr_(cairo_create(surface_)) {
    useFigureFont(cr_);
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
      if (c == ' ')
        flush_word();
      else
        word += c;
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

// What a figure draws, in drawing order (the display list's items): each writes itself as SVG
// (`id` numbers what it defines, in order) and draws itself with cairo (plot_layout.cpp).
struct DrawOp {
  virtual ~DrawOp() = default;
  virtual void svg(std::string& out, int id) const = 0;
  virtual void draw(cairo_t* cr) const = 0;
};
struct TextOp final : DrawOp {  // at (x, y) baseline-left; upright, or rotated -90 deg about (x, y)
  TextOp(std::string s_, double x_, double y_, double size_, Rgb c_, bool upward_)
      : s(std::move(s_)), x(x_), y(y_), size(size_), c(c_), upward(upward_) {}
  std::string s;
  double x, y, size;
  Rgb c;
  bool upward;
  void svg(std::string& out, int id) const override;
  void draw(cairo_t* cr) const override;
};
struct RectOp final : DrawOp {
  RectOp(double x_, double y_, double w_, double h_, double lw_, std::optional<Rgb> fill_,
         std::optional<Rgb> stroke_)
      : x(x_), y(y_), w(w_), h(h_), lw(lw_), fill(fill_), stroke(stroke_) {}
  double x, y, w, h, lw;
  std::optional<Rgb> fill, stroke;
  void svg(std::string& out, int id) const override;
  void draw(cairo_t* cr) const override;
};
struct PolylineOp final : DrawOp {
  PolylineOp(std::vector<std::pair<double, double>> pts_, Rgb c_, double lw_, bool dashed_,
             std::optional<std::array<double, 4>> clip_)
      : pts(std::move(pts_)), c(c_), lw(lw_), dashed(dashed_), clip(clip_) {}
  std::vector<std::pair<double, double>> pts;
  Rgb c;
  double lw;
  bool dashed;
  std::optional<std::array<double, 4>> clip;  // x, y, w, h
  void svg(std::string& out, int id) const override;
  void draw(cairo_t* cr) const override;
};
struct DotsOp final : DrawOp {  // filled circles at 75 % opacity, or hollow circles or squares
  DotsOp(std::vector<std::pair<double, double>> pts_, Rgb c_, double r_, Marker shape_)
      : pts(std::move(pts_)), c(c_), r(r_), shape(shape_) {}
  std::vector<std::pair<double, double>> pts;
  Rgb c;
  double r;  // radius, or half the side of a square
  Marker shape;
  void svg(std::string& out, int id) const override;
  void draw(cairo_t* cr) const override;
};
struct ImageOp final : DrawOp {
  ImageOp(RasterImage img_, double x_, double y_) : img(std::move(img_)), x(x_), y(y_) {}
  RasterImage img;
  double x, y;
  void svg(std::string& out, int id) const override;
  void draw(cairo_t* cr) const override;
};

// A display list: the layout computes every position first, then the list is written as SVG (text
// as <text> elements in the figures' font family, so it can be searched and copied; no glyph
// outlines) and, when asked, replayed on a cairo image surface for the PNG.
class Scene {
 public:
  explicit Scene(const Meter& m) : m_(m) {}
  double W = 0, H = 0;
  std::vector<TextBox> texts;

  // Horizontal text anchored at (x, y) by its measured box.
  TextBox text(const std::string& s, double x, double y, double size, HAlign h, VAlign v,
               Rgb c = {0, 0, 0}) {
    const double w = m_.width(s, size), hh = m_.height(size), asc = m_.ascent(size);
    const double x0 = x - w * (h == HAlign::left ? 0 : h == HAlign::centre ? 0.5 : 1);
    const double y0 = y - hh * (v == VAlign::top ? 0 : v == VAlign::middle ? 0.5 : 1);
    ops_.push_back(std::make_unique<TextOp>(s, x0, y0 + asc, size, c, false));
    TextBox b{s, x0, y0, x0 + w, y0 + hh};
    if (!s.empty()) texts.push_back(b);
    return b;
  }
  // Text reading bottom to top, its box centred at (x, y).
  void vtext(const std::string& s, double x, double y, double size) {
    const double w = m_.width(s, size);
    upward(s, x, size, y + w / 2, y - w / 2, y + w / 2);
  }
  // Text reading bottom to top, centred on x, its end (top) at y.
  void hanging(const std::string& s, double x, double y, double size) {
    const double w = m_.width(s, size);
    upward(s, x, size, y + w, y, y + w);
  }
  // Text reading bottom to top, centred on x, starting at y = start_y; its box spans top .. bottom.
  void upward(const std::string& s, double x, double size, double start_y, double top,
              double bottom) {
    const double hh = m_.height(size), asc = m_.ascent(size);
    ops_.push_back(std::make_unique<TextOp>(s, x - hh / 2 + asc, start_y, size, kBlackText, true));
    if (!s.empty()) texts.push_back({s, x - hh / 2, top, x + hh / 2, bottom});
  }
  void rect(double x, double y, double w, double h, std::optional<Rgb> fill,
            std::optional<Rgb> stroke, double lw = 1) {
    ops_.push_back(std::make_unique<RectOp>(x, y, w, h, lw, fill, stroke));
  }
  void line(double x0, double y0, double x1, double y1, Rgb c, double lw = 1, bool dashed = false) {
    polyline({{x0, y0}, {x1, y1}}, c, lw, dashed);
  }
  void polyline(std::vector<std::pair<double, double>> pts, Rgb c, double lw, bool dashed,
                std::optional<std::array<double, 4>> clip = std::nullopt) {
    if (pts.size() >= 2)
      ops_.push_back(std::make_unique<PolylineOp>(std::move(pts), c, lw, dashed, clip));
  }
  void dots(std::vector<std::pair<double, double>> pts, Rgb c, double r,
            Marker shape = Marker::dot) {
    if (!pts.empty()) ops_.push_back(std::make_unique<DotsOp>(std::move(pts), c, r, shape));
  }
  void image(const RasterImage& img, double x, double y) {
    ops_.push_back(std::make_unique<ImageOp>(img, x, y));
  }
  void fit(double x, double y) {
    W = std::max(W, x);
    H = std::max(H, y);
  }

  Drawing render(Format format) const;  // plot_layout.cpp

  // The number of drawing operations so far (a mark for rasterise).
  std::size_t size() const { return ops_.size(); }
  // Replaces the operations added since `from` by one image of them, clipped to the rectangle at
  // (x, y), w x h px, on a white ground (plot_layout.cpp): a dense cloud of markers then weighs a
  // compressed image instead of one SVG element per point.
  void rasterise(std::size_t from, double x, double y, int w, int h);

 private:
  static constexpr Rgb kBlackText{0, 0, 0};
  const Meter& m_;
  std::vector<std::unique_ptr<const DrawOp>> ops_;
};

inline const Rgb kBlack{0, 0, 0}, kGrid{225, 225, 225}, kFrame{60, 60, 60};

// Ticks whose labels do not overlap along an axis of `length_px` (labels' extent along the axis
// from `extent`): fewer ticks until the labels have room.
std::vector<double> fittingTicks(double lo, double hi, double length_px, double per_tick_px,
                                 const std::function<double(const std::string&)>& extent);
// Title lines centred over [x0, x1] from y; returns the y below them.
double titleBlock(Scene& s, const Meter& m, const std::string& title, double x0, double x1,
                  double y, double size = kTitleSize);
double widestLine(const Meter& m, const std::string& s, double size, double max_w);
// A vertical colour bar: bar at (x, y0..y1), ticks and labels to its right, then the scale's label
// reading upwards (wrapped to the bar's height). Returns the right edge of what it drew.
double colourBar(Scene& s, const Meter& m, const ColourScale& sc, double x, double y0, double y1,
                 bool draw = true, double label_len = 0);
double legendWidth(const Meter& m, const std::vector<std::string>& labels);

}  // namespace armstudy::report::plot_detail
