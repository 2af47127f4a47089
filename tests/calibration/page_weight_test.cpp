// Page weight of the calibration studies' reports: every HTML page of a shipped calibration study's
// output, with the files it links (img src, a href to files of the output folder) counted, stays
// under 3 MB, so that a browser paints it without waiting on tens of MB of figures. Sizes are read
// from the file system, the links from the pages' own HTML.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>

#include "io/files.hpp"
#include "study_support.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

constexpr std::uintmax_t kMaxPageBytes = 3'000'000;

struct PageWeight {
  std::uintmax_t bytes = 0;  // the page and every file it links
  int linked = 0;            // files linked and counted
};

// The page plus each distinct file of the output folder it links by src= or href= (links to
// other pages, anchors and addresses outside the folder are not part of this page's weight).
PageWeight pageWeight(const fs::path& page, const fs::path& root) {
  PageWeight w;
  w.bytes = fs::file_size(page);
  const std::string html = readFileOrThrow(page.string());
  std::set<fs::path> seen;
  const std::string root_s = fs::weakly_canonical(root).string();
  // Attribute values of src="..." and href="..." (scanned by hand: the pages carry data URIs of
  // megabytes, too long for std::regex's recursion).
  for (const std::string attr : {" src=\"", " href=\""})
    for (std::size_t at = html.find(attr); at != std::string::npos; at = html.find(attr, at + 1)) {
      const std::size_t from = at + attr.size(), to = html.find('"', from);
      if (to == std::string::npos) break;
      std::string target = html.substr(from, std::min(to - from, std::size_t{4096}));
      target = target.substr(0, target.find_first_of("#?"));
      if (target.empty()) continue;
      if (target.find("://") != std::string::npos || target.rfind("data:", 0) == 0) continue;
      const fs::path f = fs::weakly_canonical(page.parent_path() / target);
      if (f.extension() == ".html" || !fs::is_regular_file(f)) continue;
      if (f.string().rfind(root_s, 0) != 0 || !seen.insert(f).second) continue;
      w.bytes += fs::file_size(f);
      ++w.linked;
    }
  return w;
}

void checkPages(const std::string& study_file, const std::string& name) {
  const fs::path out = test::runShippedStudy(study_file, test::emptyTempDir(name));
  int pages = 0, linked = 0;
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (!e.is_regular_file() || e.path().extension() != ".html") continue;
    const PageWeight w = pageWeight(e.path(), out);
    INFO(e.path().string() << ": " << w.bytes << " bytes with " << w.linked << " linked files");
    CHECK(w.bytes <= kMaxPageBytes);
    ++pages;
    linked += w.linked;
  }
  CHECK(fs::exists(out / "report.html"));
  CHECK(pages >= 1);
  CHECK(linked >= 1);  // linked files were found and counted
  // The report shows its figures (inlined ones count in the page's own bytes).
  const std::string html = readFileOrThrow((out / "report.html").string());
  std::size_t figures = 0;
  for (std::size_t at = html.find("<img "); at != std::string::npos;
       at = html.find("<img ", at + 1))
    ++figures;
  CHECK(figures >= 10);
}

}  // namespace

TEST_CASE("page weight: arm_calibration's pages stay under 3 MB with their linked figures",
          "[calibration][study][report]") {
  checkPages("studies/arm_calibration.toml", "page_weight_arm");
}

TEST_CASE("page weight: the TX40 study's pages stay under 3 MB with their linked figures",
          "[calibration][study][report][dataset]") {
  REQUIRE(fs::exists(test::sourcePath("../shared/datasets/staubli_tx40/data/pos_read_data.csv")));
  checkPages("studies/staubli_tx40_identification.toml", "page_weight_tx40");
}
