// report.html's gallery ("Figures" of a stage) holds the figures no report shows or links: a
// figure a report links, or whose folder it links, is placed there by the report and is neither
// inlined nor repeated in the gallery; a figure nothing names still is.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>

#include "io/files.hpp"
#include "report/html_report.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

TEST_CASE(
    "report.html leaves out of the gallery the figures a report links or whose folder it links",
    "[report][html]") {
  const fs::path d = fs::temp_directory_path() / ("armstudy_fold_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "cal/e/plots");
  fs::create_directories(d / "cal/e/check/plots");
  const std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"4\" height=\"4\"/>\n";
  for (const char* f : {"cal/e/plots/before_a.svg", "cal/e/plots/after_a.svg",
                        "cal/e/check/plots/before_a.svg", "cal/e/plots/other.svg"})
    writeFileAtomic((d / f).string(), svg);
  const std::string md =
      "# Cal\n\n![e/plots/before_a.svg](e/plots/before_a.svg)\n\nAfter: "
      "[a](e/plots/after_a.svg); the check run in [`e/check/`](e/check/).\n";
  writeFileAtomic((d / "cal/report.md").string(), md);
  const std::string html =
      report::htmlReport(d.string(), "s",
                         {{"cal",
                           {"cal/report.md", "cal/e/plots/before_a.svg", "cal/e/plots/after_a.svg",
                            "cal/e/check/plots/before_a.svg", "cal/e/plots/other.svg"},
                           {{"cal/report.md", report::Document().markdown(md)}}}});
  CHECK(html.find("<a href=\"cal/e/plots/after_a.svg\">a</a>") != std::string::npos);
  CHECK(html.find("<a href=\"cal/e/check/\">") != std::string::npos);
  CHECK(html.find("<code>cal/e/plots/after_a.svg</code>") == std::string::npos);
  CHECK(html.find("<code>cal/e/check/plots/before_a.svg</code>") == std::string::npos);
  CHECK(html.find("<code>cal/e/plots/other.svg</code>") != std::string::npos);  // in the gallery
  std::size_t images = 0;
  for (std::size_t at = html.find("<img "); at != std::string::npos;
       at = html.find("<img ", at + 1))
    ++images;
  CHECK(images == 2);  // before_a shown, other.svg in the gallery
  fs::remove_all(d);
}
