// Figures that compare designs share one colour scale: a small study of the 7- and 9-DoF final
// prototypes runs through the CLI, and the colour bars of the two designs' manipulability maps
// (reach) and transmission and absolute manipulability maps (dexterity) carry the same tick labels
// and a unit. The tick labels are read from the SVG text, so the check is on what a reader sees.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <regex>

#include "io/files.hpp"
#include "svg_text.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

const char* kSharedScaleStudy = R"([study]
name = "shared_scales"

[[design]]
file = "DESIGNS/final_prototype_7dof.toml"
[[design]]
file = "DESIGNS/final_prototype_9dof.toml"

[reach]
task_space = "position"

[[reach.grid]]
name = "wall"
x = { from = "-0.4 m", to = "0.8 m", step = "0.1 m" }
y = "0.7 m"
z = { from = "0.2 m", to = "1.6 m", step = "0.1 m" }

[dexterity]
stem_x = "0.225 m"
stem_y = "0.7 m"
radius = "0.15 m"
gamma = { min = "-pi/2", max = "pi/2", step = "20 deg" }
z = { min = "0.3 m", max = "1.5 m", step = "20 cm" }
task = "position_axis"
measure_space = "translational"
ellipsoids = false
)";

}  // namespace

TEST_CASE("the designs' maps of one quantity share one colour scale with its unit",
          "[report][cli]") {
  const fs::path work =
      fs::temp_directory_path() / ("armstudy_shared_scale_" + std::to_string(getpid()));
  fs::create_directories(work);
  const std::string study =
      std::regex_replace(kSharedScaleStudy, std::regex("DESIGNS"), sourcePath("designs"));
  writeFileAtomic((work / "study.toml").string(), study);
  std::string log;
  REQUIRE(runCommand(binaryPath() + " run " + (work / "study.toml").string() +
                         " --threads 2 --output " + (work / "out").string(),
                     log) == 0);
  const fs::path out = work / "out" / "shared_scales";
  struct Pair {
    std::string a, b, label_start, unit;
  };
  const std::vector<Pair> pairs = {
      {"reach/images/wall__final_prototype_7dof_manipulability.svg",
       "reach/images/wall__final_prototype_9dof_manipulability.svg", "manipulability", "[m^3]"},
      {"dexterity/final_prototype_7dof_transmission_optimised.svg",
       "dexterity/final_prototype_9dof_transmission_optimised.svg", "transmission", "[m/rad]"},
      {"dexterity/final_prototype_7dof_manipulability_optimised.svg",
       "dexterity/final_prototype_9dof_manipulability_optimised.svg", "manipulability", "[m^3]"}};
  for (const Pair& p : pairs) {
    INFO(p.a << " vs " << p.b);
    REQUIRE(fs::exists(out / p.a));
    REQUIRE(fs::exists(out / p.b));
    const ColourBar a = colourBar(readFileOrThrow((out / p.a).string()), p.label_start);
    const ColourBar b = colourBar(readFileOrThrow((out / p.b).string()), p.label_start);
    INFO("ticks " << Catch::Detail::stringify(a.ticks) << " vs "
                  << Catch::Detail::stringify(b.ticks));
    REQUIRE(a.ticks.size() >= 2);
    CHECK(a.ticks == b.ticks);
    CHECK(a.label == b.label);
    CHECK(a.label.find(p.unit) != std::string::npos);
  }
  fs::remove_all(work);
}

TEST_CASE("a fit's before and after residual maps share one colour scale with its unit",
          "[report][cli][calibration]") {
  const fs::path work =
      fs::temp_directory_path() / ("armstudy_shared_scale_fit_" + std::to_string(getpid()));
  fs::create_directories(work);
  const std::string design = sourcePath("designs/final_prototype_7dof.toml");
  const std::string data = (work / "tcp.csv").string(), out = (work / "tcp").string();
  std::string log;
  // The arm_calibration study's TCP case: a joint offset and a link length error hidden.
  REQUIRE(runCommand(binaryPath() + " synth " + design +
                         " --kind tcp --rows 60 --noise 2e-4 --seed 1"
                         " --hide joint_offset.j3:offset=0.01 --hide link_length.j4.x:dx=0.005"
                         " --out " +
                         data,
                     log) == 0);
  REQUIRE(runCommand(binaryPath() + " fit " + design + " --kind tcp --data " + data +
                         " --auto --out " + out,
                     log) == 0);
  INFO(log);
  const fs::path before = work / "tcp/plots/before_workspace_map.svg",
                 after = work / "tcp/plots/after_workspace_map.svg";
  REQUIRE(fs::exists(before));
  REQUIRE(fs::exists(after));
  const ColourBar a = colourBar(readFileOrThrow(before.string()), "|mean residual|");
  const ColourBar b = colourBar(readFileOrThrow(after.string()), "|mean residual|");
  INFO("ticks " << Catch::Detail::stringify(a.ticks) << " vs "
                << Catch::Detail::stringify(b.ticks));
  REQUIRE(a.ticks.size() >= 2);
  CHECK(a.ticks == b.ticks);
  CHECK(a.label == b.label);
  CHECK(a.label.find("[mm]") != std::string::npos);  // TCP residuals in mm
  fs::remove_all(work);
}
