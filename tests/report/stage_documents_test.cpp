// The report documents the stages hand over (StageResult::reports), on shipped studies: each is the
// Markdown file the stage wrote, and its HTML is what the Markdown converter (markdownToHtml, which
// reads the file's text and not the blocks) gives for that file, headings and links included. The
// stages whose reports are built of blocks (not one block of Markdown kept as written) are named,
// and their documents must hold such blocks.
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

// Blocks of a document other than Markdown kept as written.
std::size_t typedBlocks(const report::Document& doc) {
  std::size_t n = 0;
  for (const report::Block& b : doc.blocks()) n += b.kind != report::Block::Kind::markdown;
  return n;
}

// Runs every stage of the shipped study `name` into `dir` and checks each report document it
// hands over against its file; returns the typed blocks per stage.
std::map<std::string, std::size_t> checkStudy(const std::string& name, const fs::path& dir) {
  const Study study = loadStudy(sourcePath("studies/" + name + ".toml"));
  RunOptions ro;
  ro.threads = 2;
  ro.progress = false;
  const auto image = [](const std::string& rel) { return "IMG:" + rel; };
  std::map<std::string, std::size_t> typed;
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
      typed[stage] += typedBlocks(rf.doc);
    }
  }
  return typed;
}

}  // namespace

TEST_CASE("every stage's report document is its Markdown file and renders to that file's HTML",
          "[report][document][oracle][cli]") {
  const fs::path dir =
      fs::temp_directory_path() / ("armstudy_stage_docs_" + std::to_string(getpid()));
  fs::remove_all(dir);
  // Each study and the stages of it whose reports are built of blocks.
  const std::vector<std::pair<std::string, std::vector<std::string>>> studies = {
      {"fig5_13_obstacle", {"tracking"}},
      {"harvest_torque", {"harvest"}},
  };
  for (const auto& [name, built] : studies) {
    SECTION(name) {
      const std::map<std::string, std::size_t> typed = checkStudy(name, dir / name);
      for (const std::string& stage : built) {
        INFO(name << ": " << stage << " builds its report of blocks");
        CHECK(typed.count(stage));
        if (typed.count(stage)) CHECK(typed.at(stage) > 0);
      }
    }
  }
  fs::remove_all(dir);
}
