// A report document (report/document.hpp) renders to the Markdown its blocks stand for, and its
// HTML is the HTML that the Markdown converter (markdownToHtml, a parser that does not see the
// blocks) gives for that Markdown: headings and their ids, paragraphs, figures with and without a
// caption, tables (right-aligned columns, '|' in a cell, a table of images), lists, code and
// Markdown kept as written, whose headings continue the numbering.
#include "report/document.hpp"

#include <catch2/catch.hpp>

#include "report/html_report.hpp"

using namespace armstudy::report;

namespace {

const std::function<std::string(const std::string&)> kImage = [](const std::string& rel) {
  return rel.find("refused") != std::string::npos ? "" : "IMG:" + rel;
};

// The document's HTML against its Markdown's, headings and links included.
void requireSameAsMarkdown(const Document& doc, const std::string& dir = "") {
  const std::string md = toMarkdown(doc);
  INFO("Markdown:\n" << md);
  std::vector<Heading> hd, hm;
  std::set<std::string> ld, lm;
  const std::string from_doc = toHtml(doc, "p-", kImage, &hd, dir, &ld);
  const std::string from_md = markdownToHtml(md, "p-", kImage, &hm, dir, &lm);
  CHECK(from_doc == from_md);
  REQUIRE(hd.size() == hm.size());
  for (std::size_t k = 0; k < hd.size(); ++k) {
    CHECK(hd[k].level == hm[k].level);
    CHECK(hd[k].id == hm[k].id);
    CHECK(hd[k].text == hm[k].text);
  }
  CHECK(ld == lm);
}

}  // namespace

TEST_CASE("a document's Markdown is its blocks written out", "[report][document]") {
  Document d;
  d.heading(1, "Reach `s`")
      .paragraph("Text with **bold**.")
      .table({"design", ">share"}, {{"a|b", "50.0 %"}})
      .figures({{"map", "m.svg"}, {"other", "o.svg"}}, "Both maps.")
      .list({"one", "two"})
      .code("x = 1")
      .markdown("## Kept\n\nas written\n");
  CHECK(toMarkdown(d) ==
        "# Reach `s`\n\nText with **bold**.\n\n| design | share |\n| --- | ---: |\n"
        "| a\\|b | 50.0 % |\n\n![map](m.svg) ![other](o.svg)\n\n*Both maps.*\n\n- one\n- two\n\n"
        "```\nx = 1\n```\n\n## Kept\n\nas written\n");
}

TEST_CASE("a document's HTML is its Markdown's HTML, block by block",
          "[report][document][oracle]") {
  SECTION("headings, paragraphs, emphasis, links and code") {
    requireSameAsMarkdown(Document()
                              .heading(1, "Title `a<b`")
                              .paragraph("Text with **bold**, *italic*, a [link](x.vti) & more.")
                              .paragraph("A line\nand its continuation.")
                              .heading(2, "Next [up](../refused.vti)")
                              .heading(3, "Third")
                              .code("a < b\n  c & d\n"),
                          "reach");
  }
  SECTION("figures: one with its caption, several with one, refused and uncaptioned ones") {
    requireSameAsMarkdown(Document()
                              .figures({{"a map", "images/m.svg"}}, "The *caption*.")
                              .figures({{"a", "a.svg"}, {"b", "b.png"}}, "Two maps.")
                              .figures({{"c", "refused.svg"}})
                              .figures({{"d: e", "d.svg"}, {"f", "f.svg"}}),
                          "dexterity");
  }
  SECTION("lists with items indented under an item") {
    const Document d = Document().nestedList({ListItem{"`a`:", {"one [x](x.csv)", "two"}},
                                              ListItem{"b", {}}, ListItem{"`c`:", {"three"}}});
    CHECK(toMarkdown(d) == "- `a`:\n  - one [x](x.csv)\n  - two\n- b\n- `c`:\n  - three\n\n");
    requireSameAsMarkdown(d, "explore");
    // The items indented under an item are a list inside it.
    CHECK(toHtml(d, "p-", kImage) ==
          "<ul>\n<li><code>a</code>:\n<ul>\n<li>one <a href=\"x.csv\">x</a></li>\n<li>two</li>\n"
          "</ul>\n</li>\n<li>b</li>\n<li><code>c</code>:\n<ul>\n<li>three</li>\n</ul>\n</li>\n"
          "</ul>\n");
  }
  SECTION("tables: right-aligned columns, '|' and line breaks in cells, short rows, images") {
    requireSameAsMarkdown(
        Document()
            .table({"name", ">v [m]", "note"},
                   {{"a|b", "1", " padded "}, {"two\nlines", "2"}, {"`c|d`", "", "[x](x.csv)"}})
            .table({"design", ">plain", ">optimised"},
                   {{"7dof", "![7dof: plain](p7.svg)", "![7dof: optimised](o7.svg)"},
                    {"9dof", "![9dof: plain](p9.svg)", "one colour: 0.5"}})
            .table({"a", "b"}, {{"![x](x.svg)", "text"}}));
  }
  SECTION("lists and Markdown kept as written, its headings numbered after the blocks'") {
    requireSameAsMarkdown(Document()
                              .heading(1, "Study")
                              .list({"**reach:** 50.0 %", "a [link](f.md)"})
                              .markdown("## Kept\n\n| a | >b |\n| --- | ---: |\n| 1 | 2 |\n\n"
                                        "![m](m.svg)\n\n*Its caption.*\n\n- x\n  y\n")
                              .heading(2, "After"));
  }
}
