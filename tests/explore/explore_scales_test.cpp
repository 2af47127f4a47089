// An exploration's front designs, each run alone, share their maps' colour scales, and its
// recommendations call a best design level with the others inside the objective's resolution: a
// small grid exploration of the final 7-DoF prototype on a coarse stem map runs through the CLI;
// the colour bars of every written front design's absolute manipulability and transmission maps
// carry the same tick labels (read from the SVG text, as a reader sees them), and with a link
// length resolution of 1 m the answer calls the shortest design level with the other front
// designs.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <map>

#include "io/files.hpp"
#include "svg_text.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

const char* kStudy = R"([study]
name = "front_scales"

[[design]]
file = "DESIGNS/final_prototype_7dof.toml"

[dexterity]
stem_x = "0.225 m"
stem_y = "0.7 m"
radius = "0.15 m"
gamma = { min = "-90 deg", max = "90 deg", step = "30 deg" }
z = { min = "0.3 m", max = "1.3 m", step = "25 cm" }
task = "position_axis"
measure_space = "translational"
ellipsoids = false

[explore]
design = "final_prototype_7dof"
method = "grid"
front_designs = 4

[[explore.parameter]]
key = "joint.j4.x"
values = ["0.30 m", "0.40 m", "0.50 m"]

[[explore.parameter]]
key = "joint.j7.x"
values = ["0.30 m", "0.45 m"]

[[explore.objective]]
label = "stem map coverage"
metric = "dexterity/{design}/reachable_fraction"
goal = "max"

[[explore.objective]]
label = "stem map manipulability"
metric = "dexterity/{design}/manipulability_mean_optimised"
goal = "max"

[[explore.objective]]
label = "link length [m]"
metric = "cost/link_length"
goal = "min"
resolution = 1
)";

}  // namespace

TEST_CASE(
    "an exploration's front designs share their maps' colour scales, and a best design inside the "
    "resolution is level",
    "[explore][report][cli]") {
  const fs::path work =
      fs::temp_directory_path() / ("armstudy_explore_scales_" + std::to_string(getpid()));
  fs::create_directories(work);
  std::string study = kStudy;
  study.replace(study.find("DESIGNS"), 7, sourcePath("designs"));
  writeFileAtomic((work / "study.toml").string(), study);
  std::string log;
  REQUIRE(runCommand(binaryPath() + " run " + (work / "study.toml").string() +
                         " --threads 2 --output " + (work / "out").string(),
                     log) == 0);
  const fs::path out = work / "out" / "front_scales";
  for (const std::string kind : {"_manipulability_optimised.svg", "_transmission_optimised.svg"}) {
    std::map<std::string, std::vector<std::string>> ticks;  // per front design's map
    for (const auto& e : fs::recursive_directory_iterator(out / "explore" / "front")) {
      const std::string name = e.path().filename().string();
      if (name.size() > kind.size() &&
          name.compare(name.size() - kind.size(), kind.size(), kind) == 0)
        ticks[name] = colourBar(readFileOrThrow(e.path().string())).ticks;
    }
    INFO(kind << ": " << ticks.size() << " front design maps");
    REQUIRE(ticks.size() >= 2);
    for (const auto& [name, t] : ticks) {
      INFO(name << ": " << Catch::Detail::stringify(t) << " vs "
                << Catch::Detail::stringify(ticks.begin()->second));
      CHECK(t.size() >= 2);
      CHECK(t == ticks.begin()->second);
    }
  }
  // Every front design within 1 m of link length: the best in it is level with the others.
  const std::string md = readFileOrThrow((out / "report.md").string());
  INFO(md.substr(0, 3000));
  const std::size_t best = md.find("best link length: `");
  REQUIRE(best != std::string::npos);
  const std::size_t end = md.find("; ", best);
  CHECK(md.substr(best, end - best).find("level with ") != std::string::npos);
  CHECK(md.substr(best, end - best).find("within the resolution 1:") != std::string::npos);
  fs::remove_all(work);
}
