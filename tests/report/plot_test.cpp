// The plotting module (report/plot.hpp): text boxes measured by cairo never overlap and stay on the
// canvas, tick labels sit on the data coordinates of the map (checked on the rendered pixels), cell
// text contrasts with its cell, the SVG is well-formed XML and the same figure gives the same
// bytes.
#include "report/plot.hpp"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "plot_checks.hpp"

using namespace armstudy::report;
using armstudy::test::decode;
using armstudy::test::findText;
using armstudy::test::layoutFault;
using armstudy::test::Pixels;

namespace {

bool wellFormedSvg(const std::string& svg) {
  vtkNew<vtkXMLDataParser> p;
  std::istringstream stream(svg);
  p->SetStream(&stream);
  return p->Parse() == 1 && std::string(p->GetRootElement()->GetName()) == "svg";
}

MapFigure mapOf10x4(std::string title, std::string scale_label) {
  MapFigure f;
  f.title = std::move(title);
  f.x = cellAxis("x [m]", -0.45, 0.45, 0.1);
  f.y = cellAxis("z [m]", 1.0, 1.3, 0.1);
  f.legend = {{categorical(0), "reachable"}, {categorical(4), "only in self-collision"}};
  f.scale = ColourScale{viridis, 0, 2.5, std::move(scale_label)};
  return f;
}

Rgb cellColour(int i, int j) {
  return Rgb{static_cast<std::uint8_t>(20 * i), static_cast<std::uint8_t>(50 * j), 9};
}

}  // namespace

TEST_CASE(
    "map figures: tick labels sit over the cells they name, text never overlaps or leaves the "
    "canvas",
    "[report][plot][oracle]") {
  const int border = 2;
  const RasterImage map = renderCellMap(10, 4, cellColour, 400, border);  // 40 px per cell
  const Drawing d =
      mapFigure(map, mapOf10x4("a < b & \"c\"", "manipulability [m^3]"), Format::svg_and_png);
  CHECK(wellFormedSvg(d.svg));  // escaping included
  CHECK(layoutFault(d).empty());
  CHECK(findText(d, "a < b & \"c\""));
  CHECK(findText(d, "only in self-collision"));
  CHECK(findText(d, "manipulability [m^3]"));
  const Pixels px = decode(d.png);
  REQUIRE(px.w == static_cast<int>(d.width));
  REQUIRE(px.h == static_cast<int>(d.height));
  // x = 0 is the edge between cells 4 and 5: the label "0" is centred on it. Just above the
  // label's tick, the rendered map shows cell 4 on the left and cell 5 on the right of its centre.
  const TextBox* zero = findText(d, "0");
  REQUIRE(zero);
  const int cx = static_cast<int>(std::lround((zero->x0 + zero->x1) / 2));
  const int y = static_cast<int>(zero->y0) - 12;  // inside the bottom cell row
  CHECK(px.at(cx - 4, y) == cellColour(4, 0));
  CHECK(px.at(cx + 4, y) == cellColour(5, 0));
  // 0.2 is the edge between cells 6 and 7.
  const TextBox* two = findText(d, "0.2");
  REQUIRE(two);
  const int cx2 = static_cast<int>(std::lround((two->x0 + two->x1) / 2));
  CHECK(px.at(cx2 - 4, y) == cellColour(6, 0));
  CHECK(px.at(cx2 + 4, y) == cellColour(7, 0));
}

TEST_CASE(
    "map figures: a long title wraps and a long colour-bar label stays clear of the axis labels",
    "[report][plot]") {
  const RasterImage map = renderCellMap(10, 4, cellColour, 120, 2);
  const std::string title =
      "stem_heatmap: first_prototype_6dof, orientation alpha 0 deg, gamma 0 deg, coverage of "
      "the whole grid with self-collision checked";
  const Drawing d = mapFigure(
      map, mapOf10x4(title, "normalised manipulability sqrt(det(J J^T)) / max, optimised [1]"));
  INFO(layoutFault(d));
  CHECK(layoutFault(d).empty());
  CHECK_FALSE(findText(d, title));  // wrapped into lines, none wider than the canvas
  CHECK(wellFormedSvg(d.svg));
}

TEST_CASE(
    "plots: one panel per unit, long category labels read upwards, legends and limit lines, no "
    "text overlaps",
    "[report][plot]") {
  PlotSpec p;
  p.title = "error ladder of a calibration with many long category names";
  p.x_label = "model";
  for (int k = 0; k < 9; ++k)
    p.x_categories.push_back("nominal + offsets + elasticity step " + std::to_string(k));
  PlotPanel a{"position", "TCP error [mm]", {}, {}, false, std::nullopt};
  PlotSeries s;
  s.label = "RMS";
  s.markers = true;
  for (int k = 0; k < 9; ++k) s.x.push_back(k), s.y.push_back(10.0 / (k + 1));
  a.series.push_back(s);
  a.lines.push_back({1.0, "requirement", true, Rgb{214, 39, 40}});
  PlotPanel b{"orientation", "TCP error [deg]", {s}, {}, false, std::nullopt};
  p.panels = {a, b};
  const Drawing d = plot(p, Format::svg_and_png);
  INFO(layoutFault(d));
  CHECK(layoutFault(d).empty());
  CHECK(wellFormedSvg(d.svg));
  CHECK(findText(d, "requirement"));
  CHECK(findText(d, "TCP error [mm]"));
  CHECK(findText(d, "TCP error [deg]"));
  const TextBox* last = findText(d, "nominal + offsets + elasticity step 8");
  REQUIRE(last);
  CHECK(last->y1 - last->y0 > 100);  // reading upwards: as tall as the label is long
  CHECK(decode(d.png).w == static_cast<int>(d.width));
}

TEST_CASE("series colours are distinct and none is too light to see on white", "[report][plot]") {
  for (int a = 0; a < 10; ++a) {
    const Rgb c = seriesColour(a);
    CHECK(0.299 * c.r + 0.587 * c.g + 0.114 * c.b < 190);
    for (int b = a + 1; b < 10; ++b) CHECK_FALSE(seriesColour(a) == seriesColour(b));
  }
}

TEST_CASE("heatmaps: cell text is white on dark cells and black on light ones",
          "[report][plot][oracle]") {
  HeatmapSpec h;
  h.title = "residual map";
  h.x_label = "speed [rad/s]";
  h.y_label = "load [N m]";
  h.value_label = "RMS residual [A]";
  h.x_min = 0, h.x_max = 2, h.y_min = 0, h.y_max = 1;
  h.cells = {{0, 1, 0, 1, 0.0, false}, {1, 2, 0, 1, 8.0, true}};  // darkest and lightest viridis
  const Drawing d = heatmap(h, Format::svg_and_png);
  CHECK(layoutFault(d).empty());
  const Pixels px = decode(d.png);
  auto count = [&](const TextBox& b, bool white) {
    int n = 0;
    for (int y = static_cast<int>(b.y0) + 1; y < static_cast<int>(b.y1); ++y)
      for (int x = static_cast<int>(b.x0) + 1; x < static_cast<int>(b.x1); ++x) {
        const Rgb c = px.at(x, y);
        n += white ? (c.r > 220 && c.g > 220 && c.b > 220) : (c.r < 40 && c.g < 40 && c.b < 40);
      }
    return n;
  };
  const TextBox* dark = findText(d, "0");
  const TextBox* light = findText(d, "8*");
  REQUIRE(dark);
  REQUIRE(light);
  CHECK(count(*dark, true) > 5);
  CHECK(count(*light, false) > 5);
}

TEST_CASE("the same figure gives the same SVG bytes whatever was drawn before", "[report][plot]") {
  const RasterImage map = renderCellMap(10, 4, cellColour, 100, 2);
  const std::string first = mapFigure(map, mapOf10x4("t", "v [1]")).svg;
  (void)mapFigure(map, mapOf10x4("other", "w [1]"), Format::svg_and_png);
  CHECK(mapFigure(map, mapOf10x4("t", "v [1]")).svg == first);
}

TEST_CASE(
    "SVG text is text a reader can search and copy, in the figures' font, with no glyph outlines",
    "[report][plot]") {
  const RasterImage map = renderCellMap(10, 4, cellColour, 100, 2);
  const Drawing d = mapFigure(map, mapOf10x4("a < b & \"c\"", "manipulability [m^3]"));
  CHECK(d.svg.find(">a &lt; b &amp; &quot;c&quot;</text>") != std::string::npos);
  CHECK(d.svg.find(">manipulability [m^3]</text>") != std::string::npos);
  CHECK(d.svg.find("font-family=\"'DejaVu Sans'") != std::string::npos);
  CHECK(d.svg.find("<symbol") == std::string::npos);
  CHECK(d.svg.find("glyph") == std::string::npos);
  // Every text the layout placed is in the SVG once per placement.
  std::size_t texts = 0;
  for (std::size_t at = d.svg.find("<text "); at != std::string::npos;
       at = d.svg.find("<text ", at + 1))
    ++texts;
  CHECK(texts == d.texts.size());
}
