#include "report/plot_layout.hpp"

#include <cairo-ft.h>
#include <ft2build.h>

#include <numbers>
#include FT_FREETYPE_H

#include <cstdint>
#include <filesystem>
#include <iostream>

#include "common/format.hpp"
#include "report/html_report.hpp"  // base64

namespace armstudy::report::plot_detail {

cairo_font_face_t* figureFont() {
  static cairo_font_face_t* face = [] {
    const char* file = ARMSTUDY_FONT_FILE;
    FT_Library lib = nullptr;
    FT_Face ft = nullptr;
    if (std::filesystem::exists(file) && FT_Init_FreeType(&lib) == 0 &&
        FT_New_Face(lib, file, 0, &ft) == 0)
      return cairo_ft_font_face_create_for_ft_face(
          ft, FT_LOAD_NO_HINTING);  // lives as long as the process
    std::cerr << "armstudy: warning: the figures' font " << file
              << " is missing (Debian: fonts-dejavu-core); figures use fontconfig's \"DejaVu "
                 "Sans\" and may "
                 "differ between machines and environments\n";
    return cairo_toy_font_face_create(kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  }();
  return face;
}

void useFigureFont(cairo_t* cr) {
  cairo_set_font_face(cr, figureFont());
  cairo_font_options_t* o = cairo_font_options_create();
  cairo_font_options_set_hint_style(o, CAIRO_HINT_STYLE_NONE);
  cairo_font_options_set_hint_metrics(o, CAIRO_HINT_METRICS_OFF);
  cairo_font_options_set_antialias(o, CAIRO_ANTIALIAS_GRAY);
  cairo_set_font_options(cr, o);
  cairo_font_options_destroy(o);
}

void TextOp::svg(std::string& o, int) const {
  const TextOp& t = *this;
  o += "<text x=\"" + formatTrimmed(t.upward ? 0 : t.x) + "\" y=\"" +
       formatTrimmed(t.upward ? 0 : t.y) + "\" font-size=\"" + formatTrimmed(t.size) + "\"";
  if (t.upward)
    o += " transform=\"translate(" + formatTrimmed(t.x) + "," + formatTrimmed(t.y) +
         ") rotate(-90)\"";
  if (!(t.c == Rgb{0, 0, 0})) o += " fill=\"" + hex(t.c) + "\"";
  o += ">" + xmlEscape(t.s) + "</text>\n";
}
void RectOp::svg(std::string& o, int) const {
  const RectOp& r = *this;
  o += "<rect x=\"" + formatTrimmed(r.x) + "\" y=\"" + formatTrimmed(r.y) + "\" width=\"" +
       formatTrimmed(r.w) + "\" height=\"" + formatTrimmed(r.h) + "\" fill=\"" +
       (r.fill ? hex(*r.fill) : "none") + "\"";
  if (r.stroke)
    o += " stroke=\"" + hex(*r.stroke) + "\" stroke-width=\"" + formatTrimmed(r.lw) + "\"";
  o += "/>\n";
}
void PolylineOp::svg(std::string& o, int id) const {
  const PolylineOp& p = *this;
  if (p.clip)
    o += "<clipPath id=\"clip" + std::to_string(id) + "\"><rect x=\"" +
         formatTrimmed((*p.clip)[0]) + "\" y=\"" + formatTrimmed((*p.clip)[1]) + "\" width=\"" +
         formatTrimmed((*p.clip)[2]) + "\" height=\"" + formatTrimmed((*p.clip)[3]) +
         "\"/></clipPath>\n";
  o += "<polyline fill=\"none\" stroke=\"" + hex(p.c) + "\" stroke-width=\"" + formatTrimmed(p.lw) +
       "\" stroke-linejoin=\"round\"";
  if (p.dashed) o += " stroke-dasharray=\"6,4\"";
  if (p.clip) o += " clip-path=\"url(#clip" + std::to_string(id) + ")\"";
  o += " points=\"";
  for (std::size_t i = 0; i < p.pts.size(); ++i)
    o += (i ? " " : "") + formatTrimmed(p.pts[i].first) + "," + formatTrimmed(p.pts[i].second);
  o += "\"/>\n";
}
void DotsOp::svg(std::string& o, int) const {
  const DotsOp& d = *this;
  if (d.shape == Marker::dot)
    o += "<g fill=\"" + hex(d.c) + "\" fill-opacity=\"0.75\">";
  else
    o += "<g fill=\"none\" stroke=\"" + hex(d.c) + "\" stroke-width=\"" +
         formatTrimmed(kMarkerStroke) + "\">";
  for (const auto& [x, y] : d.pts)
    if (d.shape == Marker::square)
      o += "<rect x=\"" + formatTrimmed(x - d.r) + "\" y=\"" + formatTrimmed(y - d.r) +
           "\" width=\"" + formatTrimmed(2 * d.r) + "\" height=\"" + formatTrimmed(2 * d.r) +
           "\"/>";
    else
      o += "<circle cx=\"" + formatTrimmed(x) + "\" cy=\"" + formatTrimmed(y) + "\" r=\"" +
           formatTrimmed(d.r) + "\"/>";
  o += "</g>\n";
}
void ImageOp::svg(std::string& o, int) const {
  const ImageOp& im = *this;
  o += "<image x=\"" + formatTrimmed(im.x) + "\" y=\"" + formatTrimmed(im.y) + "\" width=\"" +
       std::to_string(im.img.width()) + "\" height=\"" + std::to_string(im.img.height()) +
       "\" image-rendering=\"optimizeSpeed\" style=\"image-rendering:pixelated\" "
       "xlink:href=\"data:image/png;base64," +
       base64(encodePng(im.img)) + "\"/>\n";
}

namespace {
void setColour(cairo_t* cr, Rgb c, double alpha = 1) {
  cairo_set_source_rgba(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0, alpha);
}
}  // namespace

void TextOp::draw(cairo_t* cr) const {
  const TextOp& t = *this;
  cairo_save(cr);
  setColour(cr, t.c);
  cairo_set_font_size(cr, t.size);
  cairo_translate(cr, t.x, t.y);
  if (t.upward) cairo_rotate(cr, -std::numbers::pi / 2);
  cairo_move_to(cr, 0, 0);
  cairo_show_text(cr, t.s.c_str());
  cairo_restore(cr);
}
void RectOp::draw(cairo_t* cr) const {
  const RectOp& r = *this;
  cairo_rectangle(cr, r.x, r.y, r.w, r.h);
  if (r.fill) {
    setColour(cr, *r.fill);
    if (r.stroke)
      cairo_fill_preserve(cr);
    else
      cairo_fill(cr);
  }
  if (r.stroke) {
    setColour(cr, *r.stroke);
    cairo_set_line_width(cr, r.lw);
    cairo_stroke(cr);
  }
}
void PolylineOp::draw(cairo_t* cr) const {
  const PolylineOp& p = *this;
  cairo_save(cr);
  if (p.clip) {
    cairo_rectangle(cr, (*p.clip)[0], (*p.clip)[1], (*p.clip)[2], (*p.clip)[3]);
    cairo_clip(cr);
  }
  setColour(cr, p.c);
  cairo_set_line_width(cr, p.lw);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  if (p.dashed) {
    const double d[2] = {6, 4};
    cairo_set_dash(cr, d, 2, 0);
  }
  cairo_move_to(cr, p.pts[0].first, p.pts[0].second);
  for (std::size_t i = 1; i < p.pts.size(); ++i) cairo_line_to(cr, p.pts[i].first, p.pts[i].second);
  cairo_stroke(cr);
  cairo_restore(cr);
}
void DotsOp::draw(cairo_t* cr) const {
  const DotsOp& d = *this;
  setColour(cr, d.c, d.shape == Marker::dot ? 0.75 : 1);
  for (const auto& [x, y] : d.pts) {
    cairo_new_sub_path(cr);
    if (d.shape == Marker::square)
      cairo_rectangle(cr, x - d.r, y - d.r, 2 * d.r, 2 * d.r);
    else
      cairo_arc(cr, x, y, d.r, 0, 2 * std::numbers::pi);
  }
  if (d.shape == Marker::dot) {
    cairo_fill(cr);
  } else {
    cairo_set_line_width(cr, kMarkerStroke);
    cairo_stroke(cr);
  }
}
void ImageOp::draw(cairo_t* cr) const {
  const ImageOp& im = *this;
  const RasterImage& img = im.img;
  const int w = img.width(), h = img.height();
  const int stride = cairo_format_stride_for_width(CAIRO_FORMAT_RGB24, w);
  std::vector<unsigned char> data(static_cast<std::size_t>(stride) * h, 0);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const Rgb p = img.at(c, r);
      auto* px =
          reinterpret_cast<std::uint32_t*>(data.data() + static_cast<std::size_t>(r) * stride) + c;
      *px = (std::uint32_t{p.r} << 16) | (std::uint32_t{p.g} << 8) | p.b;
    }
  cairo_surface_t* s =
      cairo_image_surface_create_for_data(data.data(), CAIRO_FORMAT_RGB24, w, h, stride);
  cairo_save(cr);
  cairo_set_source_surface(cr, s, im.x, im.y);
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_rectangle(cr, im.x, im.y, w, h);
  cairo_fill(cr);
  cairo_restore(cr);
  cairo_surface_destroy(s);
}

void Scene::rasterise(std::size_t from, double x, double y, int w, int h) {
  ARMSTUDY_CHECK(from <= ops_.size() && w > 0 && h > 0, "rasterise: bad mark or size");
  cairo_surface_t* surf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  cairo_t* cr = cairo_create(surf);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_translate(cr, -x, -y);
  cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);  // few colours: a small PNG
  for (std::size_t i = from; i < ops_.size(); ++i) ops_[i]->draw(cr);
  cairo_destroy(cr);
  cairo_surface_flush(surf);
  RasterImage img(w, h);
  const unsigned char* data = cairo_image_surface_get_data(surf);
  const int stride = cairo_image_surface_get_stride(surf);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const std::uint32_t v =
          reinterpret_cast<const std::uint32_t*>(data + static_cast<std::size_t>(r) * stride)[c];
      img.set(c, r,
              Rgb{static_cast<std::uint8_t>(v >> 16), static_cast<std::uint8_t>(v >> 8),
                  static_cast<std::uint8_t>(v)});
    }
  cairo_surface_destroy(surf);
  ops_.resize(from);
  ops_.push_back(std::make_unique<ImageOp>(std::move(img), x, y));
}

Drawing Scene::render(Format format) const {
  Drawing d;
  d.width = std::ceil(W);
  d.height = std::ceil(H);
  d.texts = texts;
  const std::string w = std::to_string(static_cast<long>(d.width)),
                    h = std::to_string(static_cast<long>(d.height));
  d.svg =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" "
      "xmlns:xlink=\"http://www.w3.org/1999/xlink\" version=\"1.1\" width=\"" +
      w + "\" height=\"" + h + "\" viewBox=\"0 0 " + w + " " + h + "\" font-family=\"'" +
      std::string(kFont) + "', Verdana, sans-serif\" style=\"white-space:pre\">\n<rect width=\"" +
      w + "\" height=\"" + h + "\" fill=\"#ffffff\"/>\n";
  int id = 0;
  for (const auto& op : ops_) op->svg(d.svg, id++);
  d.svg += "</svg>\n";
  if (format == Format::svg_and_png) {
    cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, static_cast<int>(d.width),
                                                    static_cast<int>(d.height));
    cairo_t* cr = cairo_create(s);
    useFigureFont(cr);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    for (const auto& op : ops_) op->draw(cr);
    cairo_destroy(cr);
    cairo_surface_flush(s);
    auto append = [](void* closure, const unsigned char* data, unsigned int length) {
      static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
      return CAIRO_STATUS_SUCCESS;
    };
    ARMSTUDY_CHECK(cairo_surface_write_to_png_stream(s, append, &d.png) == CAIRO_STATUS_SUCCESS,
                   "cairo could not write the PNG figure");
    cairo_surface_destroy(s);
  }
  return d;
}

std::vector<double> fittingTicks(double lo, double hi, double length_px, double per_tick_px,
                                 const std::function<double(const std::string&)>& extent) {
  std::vector<double> fallback;
  const int base = std::max(3, static_cast<int>(length_px / per_tick_px));
  std::vector<int>
      targets;  // fewer ticks first down to 1, then more (a range just over a 1-2-5 step)
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

double titleBlock(Scene& s, const Meter& m, const std::string& title, double x0, double x1,
                  double y, double size) {
  if (title.empty()) return y;
  const std::vector<std::string> lines = m.wrap(title, size, x1 - x0);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    s.text(lines[k], (x0 + x1) / 2, y, size, HAlign::centre, VAlign::top);
    y += m.height(size) + (k + 1 < lines.size() ? kLeading : 0);
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
      s.rect(x, y1 - h * (k + 1.0) / steps, kBarWidth, h / steps + 0.6, sc.map((k + 0.5) / steps),
             std::nullopt);
  if (draw) s.rect(x, y0, kBarWidth, h, std::nullopt, kFrame);
  double widest = 0;
  const auto ticks = sc.hi > sc.lo
                         ? fittingTicks(sc.lo, sc.hi, h, 40,
                                        [&](const std::string&) { return m.height(kTickSize); })
                         : std::vector<double>{sc.lo};
  for (double t : ticks) {
    const double py = sc.hi > sc.lo ? y1 - (t - sc.lo) / (sc.hi - sc.lo) * h : (y0 + y1) / 2;
    widest = std::max(widest, m.width(tickText(t), kTickSize));
    if (draw) {
      s.line(x + kBarWidth, py, x + kBarWidth + kTickLen - 1, py, kBlack);
      s.text(tickText(t), x + kBarWidth + kTickLen + 2, py, kTickSize, HAlign::left,
             VAlign::middle);
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
