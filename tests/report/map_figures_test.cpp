// Map figures a reader can read: a stem map of three heights (72 angles wide, 3 rows tall) runs
// through the CLI, and its SVG draws the map at least kMinMapHeight px tall (not a strip of three
// pixel rows) with y ticks that name heights the map holds (two or more, all within the rows'
// centres 0.6..1.2 m, higher values higher up). Read from the SVG text and image elements, as a
// reader's browser gets them.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>

#include "io/files.hpp"
#include "report/plot.hpp"
#include "svg_text.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

const char* kStudy = R"([study]
name = "stem_strip"

[[design]]
file = "DESIGNS/final_prototype_7dof.toml"

[dexterity]
stem_x = "0.225 m"
stem_y = "0.7 m"
radius = "0.15 m"
gamma = { min = "-180 deg", max = "175 deg", step = "5 deg" }
z = { min = "0.6 m", max = "1.2 m", step = "0.3 m" }
task = "position_axis"
measure_space = "translational"
ellipsoids = false
)";

// [m] the heights of the map's first and last row, and a tick value's rounding in the SVG text.
constexpr double kFirstRow = 0.6, kLastRow = 1.2, kTickText = 1e-9;

}  // namespace

TEST_CASE("a stem map of three heights is drawn tall enough, with y ticks on the heights it holds",
          "[report][cli]") {
  const fs::path work =
      fs::temp_directory_path() / ("armstudy_map_figures_" + std::to_string(getpid()));
  fs::create_directories(work);
  std::string study = kStudy;
  study.replace(study.find("DESIGNS"), 7, sourcePath("designs"));
  writeFileAtomic((work / "study.toml").string(), study);
  std::string log;
  REQUIRE(runCommand(binaryPath() + " run " + (work / "study.toml").string() +
                         " --threads 2 --output " + (work / "out").string(),
                     log) == 0);
  const fs::path dir = work / "out" / "stem_strip" / "dexterity";
  int maps = 0;
  for (const char* name : {"final_prototype_7dof_manipulability_optimised.svg",
                           "final_prototype_7dof_manipulability_optimised_normalised.svg",
                           "final_prototype_7dof_status.svg"}) {
    INFO(name);
    REQUIRE(fs::exists(dir / name));
    const std::string svg = readFileOrThrow((dir / name).string());
    SvgImage im;
    REQUIRE(firstSvgImage(svg, im));
    CHECK(im.w > 300);
    CHECK(im.h >= report::kMinMapHeight);
    // The y ticks: numbers left of the map, level with it.
    std::vector<SvgText> ticks;
    for (const SvgText& t : svgTexts(svg))
      if (isSvgNumber(t.s) && t.x < im.x && t.y > im.y && t.y < im.y + im.h + 6) ticks.push_back(t);
    INFO("map " << im.w << " x " << im.h << " px; y ticks: " << ticks.size());
    REQUIRE(ticks.size() >= 2);
    for (std::size_t k = 0; k < ticks.size(); ++k) {
      const double v = std::stod(ticks[k].s);
      INFO("tick '" << ticks[k].s << "'");
      CHECK(v >= kFirstRow - kTickText);
      CHECK(v <= kLastRow + kTickText);
      if (k > 0) CHECK((std::stod(ticks[k - 1].s) < v) == (ticks[k - 1].y > ticks[k].y));
    }
    ++maps;
  }
  CHECK(maps == 3);
  fs::remove_all(work);
}
