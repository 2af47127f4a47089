// Report helpers: PNG bytes read back with VTK's own PNG reader, colour maps, markdown tables.
#include <vtkBase64Utilities.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>

#include <algorithm>
#include <sstream>

#include <catch2/catch.hpp>
#include <filesystem>

#include "report/image.hpp"
#include "report/markdown.hpp"

using namespace armstudy::report;

TEST_CASE("cell maps written as PNG read back pixel for pixel with vtkPNGReader", "[report][oracle]") {
  const RasterImage img = renderCellMap(5, 3, [](int i, int j) { return Rgb{static_cast<std::uint8_t>(40 * i), static_cast<std::uint8_t>(80 * j), 7}; }, 10, 1);
  CHECK(img.width() == 2 * 5 + 2);
  CHECK(img.height() == 2 * 3 + 2);
  // Cell (0, 0) is bottom-left; the border is grey.
  CHECK(img.at(1, img.height() - 2) == Rgb{0, 0, 7});
  CHECK(img.at(0, 0) == Rgb{128, 128, 128});
  const std::string path = (std::filesystem::temp_directory_path() / "armstudy_report_test.png").string();
  writePng(path, img);
  vtkNew<vtkPNGReader> r;
  r->SetFileName(path.c_str());
  r->Update();
  vtkImageData* d = r->GetOutput();
  int dims[3];
  d->GetDimensions(dims);
  REQUIRE(dims[0] == img.width());
  REQUIRE(dims[1] == img.height());
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const auto* p = static_cast<unsigned char*>(d->GetScalarPointer(x, img.height() - 1 - y, 0));
      const Rgb c = img.at(x, y);
      CHECK((p[0] == c.r && p[1] == c.g && p[2] == c.b));
    }
  std::filesystem::remove(path);
}

TEST_CASE("viridis ends and categorical colours are distinct", "[report]") {
  CHECK(viridis(0) == Rgb{68, 1, 84});
  CHECK(viridis(1) == Rgb{253, 231, 37});
  CHECK(viridis(-3) == viridis(0));
  for (int a = 0; a < 8; ++a)
    for (int b = a + 1; b < 8; ++b) CHECK_FALSE(categorical(a) == categorical(b));
  CHECK(hex(Rgb{255, 0, 16}) == "#ff0010");
}

TEST_CASE("markdown tables escape pipes and align numeric columns", "[report]") {
  const std::string t = markdownTable({"name", ">value"}, {{"a|b", "1"}, {"c"}});
  CHECK(t == "| name | value |\n| --- | ---: |\n| a\\|b | 1 |\n| c |  |\n");
  CHECK(percent(0.1234) == "12.3 %");
  CHECK(fixed(NAN, 2) == "n/a");
}

TEST_CASE("SVG line plots contain one polyline per series", "[report]") {
  const std::string svg = svgLinePlot({{"a", {0, 1, 2}, {0, 1, 4}}, {"b", {0, 2}, {1, 1}}}, "x", "y", "t");
  std::size_t n = 0;
  for (std::size_t p = svg.find("<polyline"); p != std::string::npos; p = svg.find("<polyline", p + 1)) ++n;
  CHECK(n == 2);
  CHECK(svg.rfind("<svg", 0) == 0);
}

TEST_CASE("nice ticks are 1-2-5 steps covering the range", "[report]") {
  CHECK(niceTicks(0, 1, 5) == std::vector<double>{0, 0.2, 0.4, 0.6000000000000001, 0.8, 1});
  const auto t = niceTicks(0.95, 1.35, 4);
  REQUIRE(t.size() == 4);
  CHECK(t.front() == Approx(1.0));
  CHECK(t.back() == Approx(1.3));
  const auto s = niceTicks(-0.5, 0.5, 5);
  CHECK(std::count(s.begin(), s.end(), 0.0) == 1);  // zero is exactly zero
  CHECK(niceTicks(1, 1).empty());
}

TEST_CASE("map figures: the embedded PNG is the map, tick labels sit on the data coordinates of the cells",
          "[report][oracle]") {
  // 10 x 4 cells: x centres -0.45..0.45 step 0.1, z centres 1.0..1.3 step 0.1.
  const int border = 2;
  const RasterImage map = renderCellMap(10, 4, [](int i, int j) { return Rgb{static_cast<std::uint8_t>(20 * i), static_cast<std::uint8_t>(50 * j), 9}; }, 200, border);
  MapFigure f;
  f.title = "a < b & \"c\"";
  f.x = cellAxis("x [m]", -0.45, 0.45, 0.1);
  f.y = cellAxis("z [m]", 1.0, 1.3, 0.1);
  f.legend = {{categorical(0), "reachable"}, {categorical(4), "only in self-collision"}};
  f.scale = ColourScale{viridis, 0, 2.5, "manipulability"};
  const std::string svg = svgMapFigure(map, f);

  vtkNew<vtkXMLDataParser> p;
  std::istringstream stream(svg);
  p->SetStream(&stream);
  REQUIRE(p->Parse() == 1);  // well-formed XML (escaping included)
  vtkXMLDataElement* root = p->GetRootElement();
  REQUIRE(std::string(root->GetName()) == "svg");
  vtkXMLDataElement* image = root->FindNestedElementWithName("image");
  REQUIRE(image);
  // The PNG inside decodes to exactly encodePng(map).
  std::string href = image->GetAttribute("href");
  const std::string prefix = "data:image/png;base64,";
  REQUIRE(href.rfind(prefix, 0) == 0);
  href = href.substr(prefix.size());
  std::string png(href.size(), '\0');
  const std::size_t n = vtkBase64Utilities::DecodeSafely(reinterpret_cast<const unsigned char*>(href.data()), href.size(),
                                                         reinterpret_cast<unsigned char*>(png.data()), png.size());
  png.resize(n);
  CHECK(png == encodePng(map));

  double ix = 0, iy = 0;
  image->GetScalarAttribute("x", ix);
  image->GetScalarAttribute("y", iy);
  const double block = (map.width() - 2.0 * border) / 10;  // pixels per cell
  const double h = map.height();
  // Every x tick label under the map: its position equals where the cell containing that x
  // value is drawn (block centres at (i + 0.5) * block from the inner left edge).
  int x_ticks = 0, y_ticks = 0, found_title = 0, found_legend = 0;
  for (int k = 0; k < root->GetNumberOfNestedElements(); ++k) {
    vtkXMLDataElement* e = root->GetNestedElement(k);
    if (std::string(e->GetName()) != "text" || !e->GetCharacterData()) continue;
    const std::string text = e->GetCharacterData();
    double x = 0, y = 0;
    e->GetScalarAttribute("x", x);
    e->GetScalarAttribute("y", y);
    if (text == "a < b & \"c\"") ++found_title;
    if (text == "only in self-collision") ++found_legend;
    if (std::abs(y - (iy + h + 18)) < 1e-9) {  // x tick
      const double v = std::stod(text);
      const double cell = (v - (-0.45)) / 0.1;  // fractional cell index of value v
      CHECK(x == Approx(ix + border + (cell + 0.5) * block).margin(1e-6));
      ++x_ticks;
    }
    if (std::string(e->GetAttribute("text-anchor") ? e->GetAttribute("text-anchor") : "") == "end") {  // y tick
      const double v = std::stod(text);
      const double cell = (v - 1.0) / 0.1;
      const double block_y = (h - 2.0 * border) / 4;
      CHECK(y - 4 == Approx(iy + h - border - (cell + 0.5) * block_y).margin(1e-6));
      ++y_ticks;
    }
  }
  CHECK(x_ticks >= 3);
  CHECK(y_ticks >= 2);
  CHECK(found_title == 1);
  CHECK(found_legend == 1);
}
