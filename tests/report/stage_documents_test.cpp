// The report documents the stages hand over (StageResult::reports), on shipped studies: each is the
// Markdown file the stage wrote, and its HTML is what the Markdown converter (markdownToHtml, which
// reads the file's text and not the blocks) gives for that file, headings and links included. The
// stages whose reports are built of blocks (not one block of Markdown kept as written) are named,
// and their documents must hold such blocks; those built of blocks alone must hold no Markdown
// kept as written.
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <map>
#include <set>

#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/files.hpp"
#include "report/document.hpp"
#include "report/html_report.hpp"
#include "test_support.hpp"

using namespace armstudy;
using armstudy::test::sourcePath;
namespace fs = std::filesystem;

namespace {

// Blocks of a document of Markdown kept as written (`raw`) or not.
std::size_t blocksOf(const report::Document& doc, bool raw) {
  std::size_t n = 0;
  for (const report::Block& b : doc.blocks()) n += (b.kind == report::Block::Kind::markdown) == raw;
  return n;
}

// The blocks of a stage's report documents: typed ones and Markdown kept as written.
struct StageBlocks {
  std::size_t typed = 0, raw = 0;
};

// Runs every stage of the shipped study `name` into `dir` and checks each report document it
// hands over against its file; returns the blocks per stage.
std::map<std::string, StageBlocks> checkStudy(const std::string& name, const fs::path& dir) {
  const Study study = loadStudy(sourcePath("studies/" + name + ".toml"));
  RunOptions ro;
  ro.threads = 2;
  ro.progress = false;
  const auto image = [](const std::string& rel) { return "IMG:" + rel; };
  std::map<std::string, StageBlocks> blocks;
  for (const StudySection& section : study.sections) {
    const std::string stage = section.stage->name();
    const StageResult r = runStage(study, stage, dir.string(), ro);
    std::size_t md_files = 0;
    for (const std::string& f : r.files)
      md_files += f.size() > 3 && f.substr(f.size() - 3) == ".md";
    INFO(name << ": stage " << stage);
    CHECK(r.reports.size() <= md_files);
    CHECK_FALSE(r.reports.empty());
    for (const report::ReportFile& rf : r.reports) {
      INFO(rf.path);
      CHECK(std::find(r.files.begin(), r.files.end(), rf.path) != r.files.end());
      const std::string md = readFileOrThrow((dir / rf.path).string());
      CHECK(report::toMarkdown(rf.doc) == md);
      const std::string folder = fs::path(rf.path).parent_path().generic_string();
      std::vector<report::Heading> hd, hm;
      std::set<std::string> ld, lm;
      CHECK(report::toHtml(rf.doc, "p-", image, &hd, folder, &ld) ==
            report::markdownToHtml(md, "p-", image, &hm, folder, &lm));
      CHECK(hd.size() == hm.size());
      CHECK(ld == lm);
      blocks[stage].typed += blocksOf(rf.doc, false);
      blocks[stage].raw += blocksOf(rf.doc, true);
    }
  }
  return blocks;
}

}  // namespace

TEST_CASE("every stage's report document is its Markdown file and renders to that file's HTML",
          "[report][document][oracle][cli]") {
  const fs::path dir =
      fs::temp_directory_path() / ("armstudy_stage_docs_" + std::to_string(getpid()));
  fs::remove_all(dir);
  // Each study, the stages of it whose reports are built of blocks, and those of them built of
  // blocks alone.
  struct Built {
    std::string study;
    std::vector<std::string> stages, alone;
  };
  const std::vector<Built> studies = {
      {"fig5_13_obstacle", {"tracking"}, {}},
      {"harvest_torque", {"harvest"}, {}},
      {"ur5_vs_first_prototype", {"reach"}, {"reach"}},
      {"stem_row", {"dexterity"}, {"dexterity"}},
  };
  for (const Built& b : studies) {
    SECTION(b.study) {
      const std::map<std::string, StageBlocks> blocks = checkStudy(b.study, dir / b.study);
      for (const std::string& stage : b.stages) {
        INFO(b.study << ": " << stage << " builds its report of blocks");
        REQUIRE(blocks.count(stage));
        CHECK(blocks.at(stage).typed > 0);
      }
      for (const std::string& stage : b.alone) {
        INFO(b.study << ": " << stage << " builds its report of blocks alone");
        REQUIRE(blocks.count(stage));
        CHECK(blocks.at(stage).raw == 0);
      }
    }
  }
  fs::remove_all(dir);
}
