// Progressive stem maps (RunOptions::preview_stride): each design's preview is written and
// announced before its map is computed, it covers every k-th gamma and z value, and every other
// file is byte for byte the one a run without the preview writes.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "common/defaults.hpp"
#include "dexterity/stem_grid.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/files.hpp"
#include "preview_support.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

const char* const kDesigns[2] = {"first_prototype_9dof", "final_prototype_7dof"};

std::string studyText() {
  std::string t = "[study]\nname = \"preview\"\n";
  for (const char* d : kDesigns)
    t += "[[design]]\nfile = \"" + test::sourcePath(std::string("designs/") + d + ".toml") + "\"\n";
  return t + R"([dexterity]
stem_x = "0.225 m"
stem_y = "0.7 m"
radius = "0.15 m"
gamma = { min = "-30 deg", max = "30 deg", step = "5 deg" }
z = { min = "0.6 m", max = "0.9 m", step = "0.05 m" }
task = "position_axis"
[dexterity.audit]
cells = 4
starts = 20
)";
}

struct Announced {
  std::string file;
  bool file_there = false, map_there = false;  // when it was announced
};

}  // namespace

TEST_CASE("AxisRange::every keeps the samples 0, k, 2k, ... of a range", "[dexterity]") {
  const dexterity::AxisRange r{-0.5, 0.7, 13};  // step 0.1
  const dexterity::AxisRange a = r.every(3), b = r.every(5);
  CHECK(a.count == 5);
  CHECK(b.count == 3);
  for (int i = 0; i < a.count; ++i) CHECK(a.value(i) == Approx(r.value(3 * i)).margin(1e-15));
  for (int i = 0; i < b.count; ++i) CHECK(b.value(i) == Approx(r.value(5 * i)).margin(1e-15));
  CHECK(r.every(1).count == r.count);
}

TEST_CASE("a stem map preview is written before the maps and leaves their files unchanged",
          "[dexterity]") {
  const fs::path dir = test::emptyTempDir("map_preview_test");
  writeFileAtomic((dir / "preview.toml").string(), studyText());
  const Study study = loadStudy((dir / "preview.toml").string());
  const fs::path out = dir / "progressive" / "preview";
  std::vector<Announced> announced;
  test::runWithAndWithoutPreview(study, dir, 3, [&](const std::string& file) {
    const std::string design = fs::path(file).stem().string();
    announced.push_back(
        {file, fs::exists(file), fs::exists(out / "dexterity" / (design + ".vti"))});
  });

  // Announced once per design, after its preview was written and before any map file.
  REQUIRE(announced.size() == 2);
  std::set<std::string> previews;
  for (const Announced& a : announced) {
    CHECK(a.file_there);
    CHECK_FALSE(a.map_there);
    previews.insert(fs::relative(a.file, out).string());
  }
  CHECK(previews == std::set<std::string>{"dexterity/preview/first_prototype_9dof.png",
                                          "dexterity/preview/final_prototype_7dof.png"});

  // The other files: the same names, the same bytes (the manifest holds timings and options).
  const std::set<std::string> extra = test::previewExtraFiles(dir / "plain" / "preview", out);
  CHECK(extra == std::set<std::string>{"dexterity/preview/first_prototype_9dof.png",
                                       "dexterity/preview/first_prototype_9dof.svg",
                                       "dexterity/preview/final_prototype_7dof.png",
                                       "dexterity/preview/final_prototype_7dof.svg"});

  // The manifest lists the previews; the figure says what it is.
  const auto manifest = nlohmann::json::parse(readFileOrThrow((out / "manifest.json").string()));
  std::set<std::string> listed(manifest["files"].begin(), manifest["files"].end());
  for (const std::string& f : extra) CHECK(listed.count(f) == 1);
  const std::string svg =
      readFileOrThrow((out / "dexterity/preview/first_prototype_9dof.svg").string());
  CHECK(svg.find("preview: 1 in 3 cells along gamma and z, before the map search") !=
        std::string::npos);
}

TEST_CASE("every preview stride the CLI accepts is a valid run option, and only those",
          "[dexterity]") {
  RunOptions o;
  for (int k = 0; k <= defaults::kMaxPreviewStride; ++k) {
    o.preview_stride = k;
    INFO(k);
    CHECK(o.validate().empty());
  }
  for (int k : {-1, defaults::kMaxPreviewStride + 1}) {
    o.preview_stride = k;
    CHECK_FALSE(o.validate().empty());
  }
}
