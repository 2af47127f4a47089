// report.html: the Markdown subset the reports use becomes HTML (tables, figures with captions,
// escaping), figures are inlined as data (base64 checked against known vectors), data files are
// linked, and nothing is fetched from elsewhere.
#include "report/html_report.hpp"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>

#include "io/files.hpp"

using namespace armstudy;
using namespace armstudy::report;
namespace fs = std::filesystem;

TEST_CASE("base64 matches the RFC 4648 test vectors", "[report][html][oracle]") {
  CHECK(base64("") == "");
  CHECK(base64("f") == "Zg==");
  CHECK(base64("fo") == "Zm8=");
  CHECK(base64("foo") == "Zm9v");
  CHECK(base64("foob") == "Zm9vYg==");
  CHECK(base64("fooba") == "Zm9vYmE=");
  CHECK(base64("foobar") == "Zm9vYmFy");
}

TEST_CASE("markdown to HTML: headings, tables, figures with captions, escaping", "[report][html]") {
  const std::string md =
      "# Title `a<b`\n\nText with **bold**, *italic* and a [link](x.vti) & more.\n\n"
      "| name | >v |\n| --- | ---: |\n| a\\|b | 1 |\n\n"
      "![a map](m.svg)\n\n*The caption.*\n\n## Next\n\n- one\n- two\n";
  std::vector<Heading> hs;
  const std::string html = markdownToHtml(
      md, "p-", [](const std::string& u) { return "IMG:" + u; }, &hs);
  REQUIRE(hs.size() == 2);
  CHECK(hs[0].id == "p-0");
  CHECK(hs[1].level == 2);
  CHECK(html.find("<h2 id=\"p-0\">Title <code>a&lt;b</code></h2>") != std::string::npos);
  CHECK(html.find("<strong>bold</strong>") != std::string::npos);
  CHECK(html.find("<em>italic</em>") != std::string::npos);
  CHECK(html.find("<a href=\"x.vti\">link</a> &amp; more") != std::string::npos);
  CHECK(html.find("<td>a|b</td><td class=\"num\">1</td>") != std::string::npos);
  CHECK(html.find("<figure><img src=\"IMG:m.svg\" alt=\"a map\"><figcaption>The "
                  "caption.</figcaption></figure>") != std::string::npos);
  CHECK(html.find("<p><em>The caption.</em></p>") ==
        std::string::npos);  // used once, as the caption
  CHECK(html.find("<li>two</li>") != std::string::npos);
}

TEST_CASE("report.html inlines the figures, links the data files and fetches nothing",
          "[report][html]") {
  const fs::path d = fs::temp_directory_path() / ("armstudy_html_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "reach" / "images");
  const std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"4\" height=\"4\"/>\n";
  writeFileAtomic((d / "reach/images/a.svg").string(), svg);
  writeFileAtomic((d / "reach/images/b.svg").string(), svg);  // shown by no report
  writeFileAtomic((d / "reach/report.md").string(),
                  "# Reach\n\n![map a](images/a.svg)\n\n*Caption a.*\n");
  writeFileAtomic((d / "reach/grid.vti").string(), "x");
  const std::string html = htmlReport(
      d.string(), "s",
      {{"reach",
        {"reach/report.md", "reach/images/a.svg", "reach/images/b.svg", "reach/grid.vti"}}});
  CHECK(html.find("data:image/svg+xml;base64," + base64(svg)) != std::string::npos);
  CHECK(html.find("Caption a.") != std::string::npos);
  CHECK(html.find("<code>reach/images/b.svg</code>") !=
        std::string::npos);  // in the stage's gallery
  CHECK(html.find("<a href=\"reach/grid.vti\">") != std::string::npos);
  CHECK(html.find("src=\"http") == std::string::npos);
  CHECK(html.find("src=\"reach/") == std::string::npos);  // every image inlined
  CHECK(html.find("<link") == std::string::npos);
  fs::remove_all(d);
}

TEST_CASE("report.html links a figure over the inline limit and the figures after the page budget",
          "[report][html]") {
  const fs::path d = fs::temp_directory_path() / ("armstudy_html_big_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "images");
  // An SVG of a given size (padded with a comment).
  auto svgOf = [](std::size_t bytes) {
    const std::string head = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"4\" height=\"4\">",
                      tail = "</svg>\n";
    return head + "<!--" + std::string(bytes - head.size() - tail.size() - 7, 'x') + "-->" + tail;
  };
  std::string md = "# Figures\n\n";
  std::vector<std::string> files = {"report.md"};
  writeFileAtomic((d / "images/big.svg").string(), svgOf(report::kInlineFigureBytes + 1));
  md += "![big](images/big.svg)\n\n";
  files.push_back("images/big.svg");
  // Small figures until twice the page budget: the first ones are carried, the rest linked.
  const std::size_t each = report::kInlineFigureBytes / 2, n = 2 * report::kInlineTotalBytes / each;
  for (std::size_t k = 0; k < n; ++k) {
    const std::string rel = "images/f" + std::to_string(k) + ".svg";
    writeFileAtomic((d / rel).string(), svgOf(each));
    md += "![f" + std::to_string(k) + "](" + rel + ")\n\n";
    files.push_back(rel);
  }
  writeFileAtomic((d / "report.md").string(), md);
  const std::string html = htmlReport(d.string(), "s", {{"reach", files}});
  CHECK(html.find("src=\"images/big.svg\"") != std::string::npos);  // over the limit: linked
  CHECK(html.find("src=\"images/f0.svg\"") == std::string::npos);   // carried
  const std::size_t carried = report::kInlineTotalBytes / each;     // what fits the budget
  CHECK(html.find("src=\"images/f" + std::to_string(carried - 1) + ".svg\"") == std::string::npos);
  CHECK(html.find("src=\"images/f" + std::to_string(carried) + ".svg\"") != std::string::npos);
  CHECK(html.find("src=\"images/f" + std::to_string(n - 1) + ".svg\"") != std::string::npos);
  CHECK(html.size() < report::kInlineTotalBytes * 4 / 3 + 200 * 1024);  // base64 of the budget
  fs::remove_all(d);
}
