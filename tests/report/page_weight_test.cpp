// Page weight of the shipped studies' pages: every HTML page of a study's output folder, with the
// files it loads (src=) and the figures it links (href= to an image of the folder) counted, stays
// under 3 MB, so that a browser paints it without waiting on tens of MB of figures. A link to a
// data file (CSV, JSON, VTK, a design) is a download the reader asks for, not part of the page:
// it is listed, not counted. Sizes are read from the file system, the links from the pages' HTML.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>

#include "io/files.hpp"
#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

constexpr std::uintmax_t kMaxPageBytes = 3'000'000;

struct PageWeight {
  std::uintmax_t bytes = 0;       // the page, the files it loads and the figures it links
  int figures = 0;                // files loaded or figures linked, counted
  std::uintmax_t data_bytes = 0;  // data files linked (not counted)
};

bool isFigure(const fs::path& f) {
  const std::string e = f.extension().string();
  return e == ".svg" || e == ".png" || e == ".jpg" || e == ".jpeg" || e == ".gif" || e == ".webp";
}

// The page plus each distinct file of the output folder it loads by src= or links as a figure by
// href= (links to other pages, anchors and addresses outside the folder are not part of it).
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
      if (attr == " src=\"" || isFigure(f)) {
        w.bytes += fs::file_size(f);
        ++w.figures;
      } else {
        w.data_bytes += fs::file_size(f);
      }
    }
  return w;
}

// Every page of the output folder `out` within kMaxPageBytes; returns the total of the linked data
// files (not counted) and the report's figure count through `figures`.
std::uintmax_t checkPages(const fs::path& out, std::size_t& figures) {
  int pages = 0;
  std::uintmax_t data = 0;
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (!e.is_regular_file() || e.path().extension() != ".html") continue;
    const PageWeight w = pageWeight(e.path(), out);
    INFO(e.path().string() << ": " << w.bytes << " bytes with " << w.figures
                           << " figures counted; data files linked, not counted: " << w.data_bytes
                           << " bytes");
    CHECK(w.bytes <= kMaxPageBytes);
    ++pages;
    data += w.data_bytes;
  }
  REQUIRE(fs::exists(out / "report.html"));
  CHECK(pages >= 1);
  // The report shows its figures (inlined ones count in the page's own bytes).
  const std::string html = readFileOrThrow((out / "report.html").string());
  figures = 0;
  for (std::size_t at = html.find("<img "); at != std::string::npos;
       at = html.find("<img ", at + 1))
    ++figures;
  return data;
}

}  // namespace

TEST_CASE("page weight: arm_calibration's pages stay under 3 MB with their linked figures",
          "[calibration][study][report]") {
  const fs::path out = test::shippedOutput("arm_calibration");
  std::size_t figures = 0;
  CHECK(checkPages(out, figures) > 0);  // its data files are linked and were seen
  CHECK(figures >= 10);
  // The calibrated copies reproduce their fits: their check runs' figures are folded, linked
  // through their folders, and appear in no gallery.
  const std::string html = readFileOrThrow((out / "report.html").string());
  CHECK(html.find("<img src=\"calibration/tcp/calibrated/") == std::string::npos);
  CHECK(html.find("alt=\"calibration/tcp/calibrated/plots/") == std::string::npos);
  CHECK(html.find("href=\"calibration/trajectory/calibrated/\"") != std::string::npos);
  CHECK(html.find("href=\"calibration/trajectory/plots/after_residual_vs_qd1.svg\"") !=
        std::string::npos);
}

TEST_CASE("page weight: the TX40 study's pages stay under 3 MB with their linked figures",
          "[calibration][study][report][dataset]") {
  REQUIRE(fs::exists(test::sourcePath("../shared/datasets/staubli_tx40/data/pos_read_data.csv")));
  const fs::path out = test::shippedOutput("staubli_tx40_identification");
  std::size_t figures = 0;
  CHECK(checkPages(out, figures) > 1'000'000);  // residuals.csv, linked, not counted
  CHECK(figures >= 10);
}

TEST_CASE("page weight: the short shipped studies' pages stay under 3 MB", "[study][report]") {
  for (const std::string name : {"fig5_13_obstacle", "harvest_torque", "stem_ellipsoids",
                                 "stem_obstacles", "thesis_drive_friction"}) {
    INFO(name);
    std::size_t figures = 0;
    checkPages(test::shippedOutput(name), figures);
    CHECK(figures >= 1);
  }
}

TEST_CASE("page weight: the shipped map studies' pages stay under 3 MB", "[study][report]") {
  for (const std::string name :
       {"compare_designs", "spraying_row", "ur5_vs_first_prototype", "stem_heatmap"}) {
    INFO(name);
    std::size_t figures = 0;
    checkPages(test::shippedOutput(name), figures);
    CHECK(figures >= 1);
  }
}
