// Each design of a study drawn at its zero pose in the reports: the reach stage's report draws the
// designs it evaluates (reach/images/arm_<design>.svg), the study's report.md shows every design
// and draws the ones no stage drew in designs/; the files are the bytes `armstudy draw` writes
// for the design file, the same for 1 and 2 threads, and report.html carries them.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/files.hpp"
#include "report/html_report.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

fs::path tempDir(const std::string& name) {
  return test::emptyTempDir("design_drawing_test_" + name);
}

const char* const kDesigns[2] = {"first_prototype_6dof", "final_prototype_7dof"};

std::string studyText(const std::string& name, const std::string& stages) {
  std::string t = "[study]\nname = \"" + name + "\"\n";
  for (const char* d : kDesigns)
    t += "[[design]]\nfile = \"" + sourcePath(std::string("designs/") + d + ".toml") + "\"\n";
  return t + stages;
}

fs::path run(const fs::path& dir, const std::string& name, int threads) {
  const Study study = loadStudy((dir / (name + ".toml")).string());
  RunOptions ro;
  ro.output_root = (dir / ("out" + std::to_string(threads))).string();
  ro.threads = threads;
  ro.progress = false;
  runStudy(study, ro);
  return dir / ("out" + std::to_string(threads)) / name;
}

// What `armstudy draw` writes for the design file at q = 0.
std::string drawnByCli(const fs::path& dir, const std::string& design) {
  const std::string svg = (dir / (design + "_cli.svg")).string();
  std::string out;
  REQUIRE(runCommand(
              binaryPath() + " draw " + sourcePath("designs/" + design + ".toml") + " --out " + svg,
              out) == 0);
  return readFileOrThrow(svg);
}

bool lists(const fs::path& out, const std::string& rel) {
  const auto man = nlohmann::json::parse(readFileOrThrow((out / "manifest.json").string()));
  for (const auto& f : man["files"])
    if (f == rel) return true;
  return false;
}

}  // namespace

TEST_CASE("Reports draw each design at its zero pose: the reach report, for 1 and 2 threads",
          "[reach][arm_drawing]") {
  const fs::path dir = tempDir("reach");
  std::ofstream(dir / "s.toml") << studyText("s", R"(
[reach]
task_space = "position"
[[reach.grid]]
name = "line"
x = { from = "0 m", to = "0.4 m", step = "0.2 m" }
y = "0.6 m"
z = "1.0 m"
)");
  const fs::path one = run(dir, "s", 1), two = run(dir, "s", 2);
  const std::string reach_md = readFileOrThrow((one / "reach/report.md").string());
  const std::string study_md = readFileOrThrow((one / "report.md").string());
  const std::string html = readFileOrThrow((one / "report.html").string());
  for (const std::string d : kDesigns) {
    INFO(d);
    const std::string rel = "reach/images/arm_" + d + ".svg";
    REQUIRE(fs::exists(one / rel));
    const std::string svg = readFileOrThrow((one / rel).string());
    CHECK(svg == readFileOrThrow((two / rel).string()));
    CHECK(svg == drawnByCli(dir, d));
    CHECK(lists(one, rel));
    CHECK(reach_md.find("](images/arm_" + d + ".svg)") != std::string::npos);
    CHECK(study_md.find("](" + rel + ")") != std::string::npos);
    CHECK(html.find(report::base64(svg)) != std::string::npos);  // carried inline, once
    CHECK(html.find(report::base64(svg)) == html.rfind(report::base64(svg)));
  }
  CHECK_FALSE(fs::exists(one / "designs"));  // every design is drawn once, by the reach stage
}

TEST_CASE("Reports draw each design at its zero pose: designs/ when no stage draws them",
          "[reach][arm_drawing]") {
  const fs::path dir = tempDir("bare");
  std::ofstream(dir / "bare.toml") << studyText("bare", "");
  const fs::path out = run(dir, "bare", 2);
  const std::string study_md = readFileOrThrow((out / "report.md").string());
  const std::string page_md = readFileOrThrow((out / "designs/report.md").string());
  const std::string html = readFileOrThrow((out / "report.html").string());
  CHECK(lists(out, "designs/report.md"));
  for (const std::string d : kDesigns) {
    INFO(d);
    const std::string rel = "designs/arm_" + d + ".svg";
    REQUIRE(fs::exists(out / rel));
    const std::string svg = readFileOrThrow((out / rel).string());
    CHECK(svg == drawnByCli(dir, d));
    CHECK(lists(out, rel));
    CHECK(study_md.find("](" + rel + ")") != std::string::npos);
    CHECK(page_md.find("](arm_" + d + ".svg)") != std::string::npos);
    CHECK(html.find(report::base64(svg)) != std::string::npos);
  }
}

TEST_CASE("Reports draw each design at its zero pose: the designs a reach section leaves out",
          "[reach][arm_drawing]") {
  const fs::path dir = tempDir("subset");
  std::ofstream(dir / "sub.toml") << studyText("sub", R"(
[reach]
task_space = "position"
designs = ["first_prototype_6dof"]
[[reach.grid]]
name = "line"
x = { from = "0 m", to = "0.4 m", step = "0.2 m" }
y = "0.6 m"
z = "1.0 m"
)");
  const fs::path out = run(dir, "sub", 2);
  const std::string study_md = readFileOrThrow((out / "report.md").string());
  // The evaluated design is drawn by the reach stage only, the other one by the study.
  CHECK(fs::exists(out / "reach/images/arm_first_prototype_6dof.svg"));
  CHECK_FALSE(fs::exists(out / "designs/arm_first_prototype_6dof.svg"));
  CHECK_FALSE(fs::exists(out / "reach/images/arm_final_prototype_7dof.svg"));
  REQUIRE(fs::exists(out / "designs/arm_final_prototype_7dof.svg"));
  CHECK(readFileOrThrow((out / "designs/arm_final_prototype_7dof.svg").string()) ==
        drawnByCli(dir, "final_prototype_7dof"));
  CHECK(study_md.find("](reach/images/arm_first_prototype_6dof.svg)") != std::string::npos);
  CHECK(study_md.find("](designs/arm_final_prototype_7dof.svg)") != std::string::npos);
}
