// report.html: the Markdown subset the reports use becomes HTML (tables, figures with captions,
// escaping), figures are inlined as data (base64 checked against known vectors), data files are
// linked, and nothing is fetched from elsewhere.
#include "report/html_report.hpp"

#include <unistd.h>

#include <algorithm>
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
  const Document doc = Document().markdown("# Reach\n\n![map a](images/a.svg)\n\n*Caption a.*\n");
  writeFileAtomic((d / "reach/report.md").string(), toMarkdown(doc));
  writeFileAtomic((d / "reach/grid.vti").string(), "x");
  const std::string html = htmlReport(
      d.string(), "s",
      {{"reach",
        {"reach/report.md", "reach/images/a.svg", "reach/images/b.svg", "reach/grid.vti"},
        {{"reach/report.md", doc}}}});
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
  const std::string html =
      htmlReport(d.string(), "s", {{"reach", files, {{"report.md", Document().markdown(md)}}}});
  CHECK(html.find("src=\"images/big.svg\"") != std::string::npos);  // over the limit: linked
  CHECK(html.find("src=\"images/f0.svg\"") == std::string::npos);   // carried
  const std::size_t carried = report::kInlineTotalBytes / each;     // what fits the budget
  CHECK(html.find("src=\"images/f" + std::to_string(carried - 1) + ".svg\"") == std::string::npos);
  CHECK(html.find("src=\"images/f" + std::to_string(carried) + ".svg\"") != std::string::npos);
  CHECK(html.find("src=\"images/f" + std::to_string(n - 1) + ".svg\"") != std::string::npos);
  CHECK(html.size() < report::kInlineTotalBytes * 4 / 3 + 200 * 1024);  // base64 of the budget
  fs::remove_all(d);
}

namespace {

// The href values of <a> elements in `html`, as a browser reads them (the entities of htmlEscape
// decoded).
std::vector<std::string> hrefs(const std::string& html) {
  std::vector<std::string> out;
  for (std::size_t at = html.find("<a href=\""); at != std::string::npos;
       at = html.find("<a href=\"", at + 1)) {
    const std::size_t from = at + 9, to = html.find('"', from);
    std::string v = html.substr(from, to - from);
    for (const auto& [entity, c] : {std::pair<std::string, std::string>{"&quot;", "\""},
                                    {"&lt;", "<"},
                                    {"&gt;", ">"},
                                    {"&amp;", "&"}})
      for (std::size_t k = v.find(entity); k != std::string::npos; k = v.find(entity, k + 1))
        v.replace(k, entity.size(), c);
    out.push_back(v);
  }
  return out;
}

// The scheme a browser finds in an href: tabs and newlines removed, leading spaces and control
// characters skipped, lower case, up to the first ':' (empty when there is none before / ? #).
std::string browserScheme(std::string href) {
  std::erase_if(href, [](char c) { return c == '\t' || c == '\n' || c == '\r'; });
  std::size_t a = 0;
  while (a < href.size() && static_cast<unsigned char>(href[a]) <= 0x20) ++a;
  const std::size_t colon = href.find(':', a), stop = href.find_first_of("/?#", a);
  if (colon == std::string::npos || (stop != std::string::npos && stop < colon)) return "";
  std::string s = href.substr(a, colon - a);
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

TEST_CASE("report Markdown links: only http(s) and relative paths inside the output folder",
          "[report][html][hardening]") {
  const fs::path d =
      fs::temp_directory_path() / ("armstudy_html_links_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "reach");
  struct Case {
    std::string url;
    bool kept;
    std::string href;  // where a kept link in reach/report.md points (from the output folder)
  };
  const Case cases[] = {
      {"javascript:alert.name", false, ""},
      {"JaVaScRiPt:alert.name", false, ""},
      {" javascript:alert.name", false, ""},
      {"java\tscript:alert.name", false, ""},
      {"java&#x09;script:alert.name", false, ""},
      {"&#106;avascript:alert.name", false, ""},
      {"&#x6A;avascript&#58;alert.name", false, ""},
      {"data:text/html;base64,PHNjcmlwdD5hbGVydCgxKTwvc2NyaXB0Pg==", false, ""},
      {"file:///etc/passwd", false, ""},
      {"vbscript:msgbox.name", false, ""},
      {"//evil.example/x", false, ""},
      {"/etc/passwd", false, ""},
      {"\\\\evil.example\\x", false, ""},
      {"../../etc/passwd", false, ""},
      {"../../report.md", false, ""},
      {"%2e%2e/%2e%2e/etc/passwd", false, ""},
      {"https://example.org/a?b=c", true, "https://example.org/a?b=c"},
      {"HTTP://example.org/", true, "HTTP://example.org/"},
      {"grid.vti", true, "reach/grid.vti"},
      {"../view.html", true, "view.html"},
      {"#frag", true, "#frag"},
  };
  for (const Case& c : cases) {
    INFO(c.url);
    // In a stage's report (a paragraph and a table cell, where joint names and references'
    // sources appear) and, refused ones, in the study's answer.
    const std::string md =
        "Text [the link](" + c.url + ") end.\n\n| a |\n| --- |\n| [cell](" + c.url + ") |\n";
    writeFileAtomic((d / "reach/report.md").string(), md);
    const std::string html =
        htmlReport(d.string(), "s",
                   {{"reach", {"reach/report.md"}, {{"reach/report.md", Document().markdown(md)}}}},
                   Document().markdown(c.kept ? "" : "Answer [the link](" + c.url + ") end.\n"));
    std::vector<std::string> links;  // the stage's and the answer's (not the contents' #s0...)
    for (const std::string& h : hrefs(html))
      if (h.rfind("#s0", 0) != 0) links.push_back(h);
    for (const std::string& h : links) {
      INFO(h);
      const std::string scheme = browserScheme(h);
      CHECK((scheme.empty() || scheme == "http" || scheme == "https"));
      CHECK(h.rfind("/", 0) != 0);
      CHECK(h.find("..") == std::string::npos);
    }
    if (c.kept) {
      CHECK(links == std::vector<std::string>{c.href, c.href});
    } else {
      CHECK(links.empty());
      CHECK(html.find("Text the link end.") != std::string::npos);  // shown as its text
      CHECK(html.find("<td>cell</td>") != std::string::npos);
      CHECK(html.find("Answer the link end.") != std::string::npos);
    }
  }
  fs::remove_all(d);
}

TEST_CASE("report.html inlines only images inside the output folder, symbolic links resolved",
          "[report][html][hardening]") {
  const fs::path top =
      fs::temp_directory_path() / ("armstudy_html_images_" + std::to_string(getpid()));
  fs::remove_all(top);
  const fs::path d = top / "out", secret_dir = top / "elsewhere";
  fs::create_directories(d / "reach" / "images");
  fs::create_directories(secret_dir);
  const std::string own = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"4\" height=\"4\"/>\n";
  const std::string secret =
      "<svg xmlns=\"http://www.w3.org/2000/svg\"><text>SECRET-OUTSIDE</text></svg>\n";
  writeFileAtomic((d / "reach/images/own.svg").string(), own);
  writeFileAtomic((secret_dir / "secret.svg").string(), secret);
  writeFileAtomic((secret_dir / "secret.png").string(), secret);
  // Symbolic links inside the output folder that lead out of it: a file and a folder.
  fs::create_symlink(secret_dir / "secret.svg", d / "reach/images/link.svg");
  fs::create_directory_symlink(secret_dir, d / "reach/linked_folder");
  REQUIRE(fs::is_symlink(d / "reach/images/link.svg"));
  REQUIRE(fs::is_symlink(d / "reach/linked_folder"));
  const std::string abs_svg = (secret_dir / "secret.svg").string();
  const std::string md =
      "# Reach\n\n![own](images/own.svg)\n\n"
      "Absolute: ![a](" +
      abs_svg +
      ") and up: ![b](../../elsewhere/secret.svg) ![c](../../elsewhere/"
      "secret.png)\n\nLinks: ![d](images/link.svg) "
      "![e](linked_folder/secret.svg)\n\n"
      "| joint | source |\n| --- | --- |\n| ![f](" +
      abs_svg +
      ") | ![g](images/link.svg) |\n\n"
      "Remote: ![h](https://example.org/pixel.png) "
      "![i](data:image/svg+xml;base64,AAAA)\n";
  writeFileAtomic((d / "reach/report.md").string(), md);
  const std::string answer = "Answer ![j](" + abs_svg + ") ![k](reach/images/link.svg)\n";
  const std::string html =
      htmlReport(d.string(), "s",
                 {{"reach",
                   {"reach/report.md", "reach/images/own.svg", "reach/images/link.svg"},
                   {{"reach/report.md", Document().markdown(md)}}}},
                 Document().markdown(answer));
  CHECK(html.find("data:image/svg+xml;base64," + base64(own)) != std::string::npos);
  CHECK(html.find(base64(secret)) == std::string::npos);  // neither the .svg nor the .png
  CHECK(html.find("SECRET-OUTSIDE") == std::string::npos);
  CHECK(html.find("elsewhere") == std::string::npos);  // not even linked
  CHECK(html.find(abs_svg) == std::string::npos);
  CHECK(html.find("src=\"reach/images/link.svg\"") == std::string::npos);
  CHECK(html.find("linked_folder") == std::string::npos);
  CHECK(html.find("example.org") == std::string::npos);  // nothing fetched
  CHECK(html.find("src=\"data:image/svg+xml;base64,AAAA") == std::string::npos);
  // Each refused image is shown as its alt text (in a table of images, as its figure).
  for (const char* alt :
       {"Absolute: a and up: b c", "Links: d e", "<figure>f<figcaption>joint</figcaption>",
        "<figure>g<figcaption>source</figcaption>", "Remote: h i", "Answer j k"}) {
    INFO(alt);
    CHECK(html.find(alt) != std::string::npos);
  }
  fs::remove_all(top);
}

TEST_CASE("deeply nested emphasis and links in user text render as text, without a crash",
          "[report][html][hardening]") {
  const auto img = [](const std::string& u) { return "IMG:" + u; };
  constexpr int kMaxNesting = 10;  // the renderer's depth limit and a margin
  std::string stars, brackets;
  for (int k = 0; k < 100000; ++k) stars += "**";
  for (int k = 0; k < 20000; ++k) brackets += "[*";
  for (const std::string& text : {stars + "x", "*" + stars + "x*", brackets + "x](a)"}) {
    const std::string html = markdownToHtml("# Study\n\n" + text + "\n", "p-", img);
    CHECK(html.find("x") != std::string::npos);
    int depth = 0, deepest = 0;  // of <strong>, <em> and <a> elements
    for (std::size_t at = html.find('<'); at != std::string::npos; at = html.find('<', at + 1)) {
      if (html.compare(at, 3, "<a ") == 0 || html.compare(at, 4, "<em>") == 0 ||
          html.compare(at, 8, "<strong>") == 0)
        deepest = std::max(deepest, ++depth);
      else if (html.compare(at, 4, "</a>") == 0 || html.compare(at, 5, "</em>") == 0 ||
               html.compare(at, 9, "</strong>") == 0)
        --depth;
    }
    CHECK(depth == 0);
    CHECK(deepest <= kMaxNesting);
  }
}

TEST_CASE("the study's description and question head report.html, above the answer",
          "[report][html]") {
  const fs::path d = fs::temp_directory_path() / ("armstudy_lead_" + std::to_string(getpid()));
  fs::create_directories(d / "reach");
  writeFileAtomic((d / "reach/report.md").string(), "# Reach\n\nbody\n");
  const std::string html = htmlReport(
      d.string(), "s",
      {{"reach", {"reach/report.md"}, {{"reach/report.md", Document().heading(1, "Reach")}}}},
      Document().heading(2, "Answer").list({"yes"}),
      Document().paragraph("What it is.").paragraph("**Question:** Which half?"));
  const std::size_t q = html.find("<strong>Question:</strong> Which half?");
  REQUIRE(q != std::string::npos);
  CHECK(html.find("What it is.") < q);
  CHECK(q < html.find("</header>"));
  CHECK(html.find("</header>") < html.find("id=\"answer\""));
  fs::remove_all(d);
}

TEST_CASE(
    "report.html renders the documents the stages hand over and reads no Markdown file back: a "
    "report file without a document is linked",
    "[report][html]") {
  const fs::path d = fs::temp_directory_path() / ("armstudy_docs_" + std::to_string(getpid()));
  fs::create_directories(d / "reach");
  fs::create_directories(d / "calibration/e");
  // On disk, text the page must not show: the stage's document is what it renders.
  writeFileAtomic((d / "reach/report.md").string(), "# From the disk\n\nstale text\n");
  writeFileAtomic((d / "calibration/e/report.md").string(), "# Entry\n\nwritten by the fit\n");
  const Document doc = Document().heading(1, "Reach").table({"design", ">share"}, {{"a", "50 %"}});
  const std::string html = htmlReport(d.string(), "s",
                                      {{"reach", {"reach/report.md"}, {{"reach/report.md", doc}}},
                                       {"calibration", {"calibration/e/report.md"}, {}}});
  CHECK(html.find("From the disk") == std::string::npos);
  CHECK(html.find("stale text") == std::string::npos);
  CHECK(html.find("<h2 id=\"s0-0-0\">Reach</h2>") != std::string::npos);
  CHECK(html.find("<td class=\"num\">50 %</td>") != std::string::npos);
  CHECK(html.find("written by the fit") == std::string::npos);
  CHECK(html.find("<a href=\"calibration/e/report.md\"><code>calibration/e/report.md</code></a>") !=
        std::string::npos);
  // The document's page is the page of its Markdown.
  CHECK(html == htmlReport(d.string(), "s",
                           {{"reach",
                             {"reach/report.md"},
                             {{"reach/report.md", Document().markdown(toMarkdown(doc))}}},
                            {"calibration", {"calibration/e/report.md"}, {}}}));
  fs::remove_all(d);
}
