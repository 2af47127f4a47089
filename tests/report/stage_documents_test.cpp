// The report documents the stages hand over (StageResult::reports), on shipped studies: every
// Markdown file a stage writes has one, each is the file the stage wrote, and its HTML is what the
// Markdown converter (markdownToHtml, which reads the file's text and not the blocks) gives for
// that file, headings and links included; the stage's part of report.html is built from them, not
// from the files (changed on disk before it is built). The reports built of blocks are named, and
// their documents must hold no Markdown kept as written.
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

// Blocks of a document that are Markdown kept as written.
std::size_t rawBlocks(const report::Document& doc) {
  std::size_t n = 0;
  for (const report::Block& b : doc.blocks()) n += b.kind == report::Block::Kind::markdown;
  return n;
}

bool isMarkdownFile(const std::string& f) {
  return f.size() > 3 && f.substr(f.size() - 3) == ".md";
}

// The stage's part of report.html, built after every Markdown file the stage wrote was replaced on
// disk: none of the replaced text may show, every document's text must.
void checkPageFromDocuments(const std::string& stage, const StageResult& r, const fs::path& dir) {
  const std::string stale = "STALE TEXT ON DISK";
  for (const std::string& f : r.files)
    if (isMarkdownFile(f))
      writeFileAtomic((dir / f).string(), "# " + stale + "\n\n" + stale + "\n");
  const std::string html = report::htmlReport(dir.string(), "s", {{stage, r.files, r.reports}});
  CHECK(html.find(stale) == std::string::npos);
  for (const report::ReportFile& rf : r.reports) {
    // The document's first line as plain text (up to its first inline mark).
    std::string first = report::toMarkdown(rf.doc);
    first = first.substr(0, first.find('\n'));
    first = first.substr(first.find_first_not_of("# "));
    first = first.substr(0, first.find_first_of("`*[!_\\<>&|"));
    INFO(rf.path << ": " << first);
    CHECK(first.size() >= 8);
    CHECK(html.find(first) != std::string::npos);
  }
}

// Runs every stage of the study file `path` into `dir` and checks each report document it hands
// over against its file; returns the documents by path.
std::map<std::string, report::Document> checkStudy(const std::string& path, const fs::path& dir) {
  const Study study = loadStudy(path);
  RunOptions ro;
  ro.threads = 2;
  ro.progress = false;
  const auto image = [](const std::string& rel) { return "IMG:" + rel; };
  std::map<std::string, report::Document> docs;
  for (const StudySection& section : study.sections) {
    const std::string stage = section.stage->name();
    const StageResult r = runStage(study, stage, dir.string(), ro);
    std::set<std::string> md_files;
    for (const std::string& f : r.files)
      if (isMarkdownFile(f)) md_files.insert(f);
    INFO(path << ": stage " << stage);
    std::set<std::string> with_document;
    for (const report::ReportFile& rf : r.reports) with_document.insert(rf.path);
    CHECK(with_document == md_files);
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
      docs[rf.path] = rf.doc;
    }
    checkPageFromDocuments(stage, r, dir);
  }
  return docs;
}

// studies/explore_final_prototype.toml made fast (as tests/explore/explore_test.cpp does): a
// coarse stem map, one stem's fruits, short approaches, a budget of 6 calls, one front design
// written with its stages' reports; written into `dir`.
std::string fastExploreStudy(const fs::path& dir) {
  std::string text = readFileOrThrow(sourcePath("studies/explore_final_prototype.toml"));
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
  };
  replace("../designs/", sourcePath("designs/"));
  replace(R"(step = "10 deg")", R"(step = "30 deg")");
  replace(R"(z = { min = "0 m", max = "1.5 m", step = "5 cm" })",
          R"(z = { min = "0.3 m", max = "1.3 m", step = "25 cm" })");
  replace("stems = 4", "stems = 1");
  replace("duration = 2.0", "duration = 0.5");
  replace("rate = 500", "rate = 200");
  replace("budget = 80", "budget = 6");
  replace("front_designs = 3", "front_designs = 1");
  fs::create_directories(dir);
  writeFileAtomic((dir / "explore_final_prototype.toml").string(), text);
  return (dir / "explore_final_prototype.toml").string();
}

}  // namespace

TEST_CASE("every stage's report document is its Markdown file and renders to that file's HTML",
          "[report][document][oracle][cli]") {
  const fs::path dir =
      fs::temp_directory_path() / ("armstudy_stage_docs_" + std::to_string(getpid()));
  fs::remove_all(dir);
  // Each study and the reports of it built of blocks: a path, or a folder and a file name ("*/"
  // between them: any folder below).
  const std::vector<std::pair<std::string, std::vector<std::string>>> studies = {
      {"fig5_13_obstacle", {"tracking/report.md"}},
      {"harvest_torque", {"harvest/report.md"}},
      {"thesis_drive_friction", {"calibration/report.md"}},
      {"explore_final_prototype", {"explore/explore.md", "explore/front/*/harvest/report.md"}},
      {"ur5_vs_first_prototype", {"reach/report.md"}},
      {"stem_row", {"dexterity/report.md"}},
  };
  for (const auto& [name, built] : studies) {
    SECTION(name) {
      const std::string path = name == "explore_final_prototype"
                                   ? fastExploreStudy(dir / "study")
                                   : sourcePath("studies/" + name + ".toml");
      const std::map<std::string, report::Document> docs = checkStudy(path, dir / name);
      for (const std::string& pattern : built) {
        const std::size_t star = pattern.find("*/");
        std::size_t matched = 0;
        for (const auto& [p, doc] : docs) {
          const bool match = star == std::string::npos
                                 ? p == pattern
                                 : p.rfind(pattern.substr(0, star), 0) == 0 &&
                                       p.size() > pattern.size() &&
                                       p.substr(p.size() - (pattern.size() - star - 1)) ==
                                           pattern.substr(star + 1);
          if (!match) continue;
          ++matched;
          INFO(name << ": " << p << " is built of blocks");
          CHECK(rawBlocks(doc) == 0);
          CHECK_FALSE(doc.empty());
        }
        INFO(name << ": " << pattern);
        CHECK(matched > 0);
      }
    }
  }
  fs::remove_all(dir);
}
