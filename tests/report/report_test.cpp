// Report helpers: PNG bytes read back with VTK's own PNG reader, colour maps, markdown tables.
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>

#include "report/image.hpp"
#include "report/markdown.hpp"

using namespace armstudy::report;

TEST_CASE("cell maps written as PNG read back pixel for pixel with vtkPNGReader",
          "[report][oracle]") {
  const RasterImage img = renderCellMap(
      5, 3,
      [](int i, int j) {
        return Rgb{static_cast<std::uint8_t>(40 * i), static_cast<std::uint8_t>(80 * j), 7};
      },
      10, 1);
  CHECK(img.width() == 2 * 5 + 2);
  CHECK(img.height() == 2 * 3 + 2);
  // Cell (0, 0) is bottom-left; the border is grey.
  CHECK(img.at(1, img.height() - 2) == Rgb{0, 0, 7});
  CHECK(img.at(0, 0) == Rgb{128, 128, 128});
  const std::string path =
      (std::filesystem::temp_directory_path() / "armstudy_report_test.png").string();
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
