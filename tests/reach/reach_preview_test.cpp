// Progressive reach maps (RunOptions::preview_stride): each grid's preview of each design and
// orientation is written and announced before the grid's maps are computed, it covers every k-th
// value of each axis, and every other file is byte for byte the one a run without it writes.
#include "stages/reach/reach_preview.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/files.hpp"
#include "preview_support.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

const char* const kPreviewDesigns[2] = {"first_prototype_6dof", "final_prototype_7dof"};

// A 2-D grid of two orientations and a 3-D grid (its figures project the shortest axis out).
std::string previewStudyText() {
  std::string t = "[study]\nname = \"reach_preview\"\n";
  for (const char* d : kPreviewDesigns)
    t += "[[design]]\nfile = \"" + test::sourcePath(std::string("designs/") + d + ".toml") + "\"\n";
  return t + R"([reach]
task_space = "spraying"
[reach.audit]
poses = 4
starts = 10
[[reach.grid]]
name = "row"
x = { from = "-0.6 m", to = "0.6 m", step = "0.05 m" }
y = { from = "0.3 m", to = "1.0 m", step = "0.05 m" }
z = "1.2 m"
alpha = "0 deg"
gamma = ["-40 deg", "40 deg"]
[[reach.grid]]
name = "box"
x = { from = "-0.4 m", to = "0.4 m", step = "0.1 m" }
y = { from = "0.3 m", to = "0.9 m", step = "0.1 m" }
z = { from = "0.8 m", to = "1.4 m", step = "0.2 m" }
alpha = "0 deg"
gamma = "0 deg"
)";
}

struct ReachAnnounced {
  std::string file;
  bool file_there = false, map_there = false;  // when it was announced
};

}  // namespace

TEST_CASE("a reach preview grid keeps the samples 0, k, 2k, ... of each axis", "[reach]") {
  TaskGrid g;
  g.axes[0] = {-0.6, 0.6, 0.05};  // 25 values
  g.axes[1] = {0.3, 1.0, 0.1};    // 8 values
  g.axes[2] = {1.2, 1.2, 1.0};    // one value
  g.orientations = {{0, 0, -0.5}, {0, 0, 0.5}};
  for (int k : {1, 3, 4, 7}) {
    INFO(k);
    const TaskGrid c = previewGrid(g, k);
    for (int a = 0; a < 3; ++a) {
      const int n = g.axes[a].count();
      REQUIRE(c.axes[a].count() == (n - 1) / k + 1);
      for (int i = 0; i < c.axes[a].count(); ++i)
        CHECK(c.axes[a].value(i) == Approx(g.axes[a].value(n > 1 ? k * i : 0)).margin(1e-12));
    }
    CHECK(c.orientations.size() == 2);
    CHECK(c.validate().empty());
  }
}

TEST_CASE("a reach preview is written before the grid's maps and leaves their files unchanged",
          "[reach]") {
  const fs::path dir = test::emptyTempDir("reach_preview_test");
  writeFileAtomic((dir / "preview.toml").string(), previewStudyText());
  const Study study = loadStudy((dir / "preview.toml").string());
  const fs::path out = dir / "progressive" / "reach_preview";
  std::vector<ReachAnnounced> announced;
  test::runWithAndWithoutPreview(study, dir, 3, [&](const std::string& file) {
    const std::string stem = fs::path(file).stem().string();  // <grid>__<design>[_o<k>]
    const std::string grid = stem.substr(0, stem.find("__"));
    std::string design = stem.substr(grid.size() + 2);
    if (design.size() > 3 && design.compare(design.size() - 3, 2, "_o") == 0)
      design.resize(design.size() - 3);
    announced.push_back(
        {file, fs::exists(file), fs::exists(out / "reach" / grid / (design + ".vti"))});
  });

  // Announced once per design and orientation, after its preview was written and before the
  // grid's map of that design.
  std::set<std::string> previews;
  for (const ReachAnnounced& a : announced) {
    INFO(a.file);
    CHECK(a.file_there);
    CHECK_FALSE(a.map_there);
    previews.insert(fs::relative(a.file, out).string());
  }
  std::set<std::string> expected;
  for (const char* d : kPreviewDesigns) {
    for (const char* o : {"_o0", "_o1"})
      expected.insert(std::string("reach/preview/row__") + d + o);
    expected.insert(std::string("reach/preview/box__") + d);
  }
  std::set<std::string> expected_png, expected_all;
  for (const std::string& e : expected) {
    expected_png.insert(e + ".png");
    expected_all.insert(e + ".png");
    expected_all.insert(e + ".svg");
  }
  CHECK(announced.size() == expected.size());
  CHECK(previews == expected_png);

  // The other files: the same names, the same bytes (the manifest holds timings and options).
  const std::set<std::string> extra = test::previewExtraFiles(dir / "plain" / "reach_preview", out);
  CHECK(extra == expected_all);

  // The manifest lists the previews; the figures say what they are.
  const auto manifest = nlohmann::json::parse(readFileOrThrow((out / "manifest.json").string()));
  std::set<std::string> listed(manifest["files"].begin(), manifest["files"].end());
  for (const std::string& f : extra) CHECK(listed.count(f) == 1);
  const std::string svg =
      readFileOrThrow((out / "reach/preview/row__first_prototype_6dof_o1.svg").string());
  CHECK(svg.find("(preview: 1 in 3 values") != std::string::npos);
  const std::string box =
      readFileOrThrow((out / "reach/preview/box__first_prototype_6dof.svg").string());
  CHECK(box.find("that are reachable") != std::string::npos);  // 3-D: the projected fraction
}

TEST_CASE("a reach preview is drawn also when the study's outputs leave out the images",
          "[reach]") {
  const fs::path dir = test::emptyTempDir("reach_preview_vtk_only");
  writeFileAtomic((dir / "vtk_only.toml").string(),
                  "[study]\nname = \"vtk_only\"\n[[design]]\nfile = \"" +
                      test::sourcePath("designs/first_prototype_6dof.toml") + "\"\n" + R"([reach]
task_space = "spraying"
outputs = ["vtk"]
[[reach.grid]]
name = "row"
x = { from = "-0.6 m", to = "0.6 m", step = "0.1 m" }
y = { from = "0.3 m", to = "1.0 m", step = "0.1 m" }
z = "1.2 m"
alpha = "0 deg"
gamma = "40 deg"
)");
  RunOptions o;
  o.output_root = (dir / "out").string();
  o.threads = 2;
  o.progress = false;
  o.preview_stride = 2;
  std::vector<std::string> announced;
  o.on_preview = [&](const std::string& file) { announced.push_back(file); };
  runStudy(loadStudy((dir / "vtk_only.toml").string()), o);
  const fs::path out = dir / "out" / "vtk_only";
  REQUIRE(announced.size() == 1);
  CHECK(fs::relative(announced[0], out).string() == "reach/preview/row__first_prototype_6dof.png");
  CHECK(fs::exists(out / "reach/preview/row__first_prototype_6dof.svg"));
  CHECK_FALSE(fs::exists(out / "reach/images/row__first_prototype_6dof.png"));  // as asked
  CHECK(fs::exists(out / "reach/row/first_prototype_6dof.vti"));
}
