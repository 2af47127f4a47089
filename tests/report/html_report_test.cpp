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
