#pragma once
// Private to the report renderers (html_blocks.cpp, markdown_html.cpp, document.cpp,
// html_report.cpp): the HTML of each kind of block and of inline text, shared by the Markdown
// converter (markdownToHtml) and the document renderer (toHtml), so that a document and its
// Markdown give the same page.
#include <functional>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "report/document.hpp"

namespace armstudy::report::html_detail {

// Where a text's links and images lead: the text was written in folder `dir` of the output folder
// (markdown.hpp reportLinkTarget, reportImagePath); `image` gives an image's src from its path
// relative to the output folder, "" to show its alt text instead; `links`, when given, collects
// the kept links into the output folder (relative to it, without a fragment).
struct Targets {
  const std::function<std::string(const std::string&)>& image;
  std::string dir;
  std::set<std::string>* links = nullptr;
};

// Inline Markdown (code, strong, emphasis, links, images, backslash escapes) as HTML.
std::string inlineHtml(const std::string& s, const Targets& t);

// The image links "![alt](file)" a paragraph consists of; empty when it holds anything else.
std::vector<std::string> onlyImages(const std::string& s);

// A paragraph's lines joined with blanks, as one paragraph's text.
std::string paragraphText(const std::vector<std::string>& lines);

// "*caption*": a paragraph in emphasis as a whole, which captions the figures above it.
bool wholeItalic(const std::string& p);

void headingHtml(std::ostream& o, int level, const std::string& id, const std::string& text,
                 const Targets& t);
void paragraphHtml(std::ostream& o, const std::string& text, const Targets& t);
// Figures ("![alt](file)" each) with their caption ("" = each its alt text).
void figuresHtml(std::ostream& o, const std::vector<std::string>& images,
                 const std::string& caption, const Targets& t);
void codeHtml(std::ostream& o, const std::string& text);
// A table from its cells as written between the pipes (trimmed, "\|" for a '|'): a gallery when
// it is a table of images, else a table whose `right` columns are right-aligned.
void tableHtml(std::ostream& o, const std::vector<std::string>& head,
               const std::vector<bool>& right, const std::vector<std::vector<std::string>>& rows,
               const Targets& t);
// A list; `sub_items`, when given, holds per item the items indented under it (a list inside it).
void listHtml(std::ostream& o, const std::vector<std::string>& items, const Targets& t,
              const std::vector<std::vector<std::string>>& sub_items = {});

// Markdown (the subset of html_report.hpp) as HTML, its headings numbered from `*heading_number`
// (advanced past them) with ids "<id_prefix><n>".
std::string markdownHtml(const std::string& md, const std::string& id_prefix, int* heading_number,
                         const Targets& t, std::vector<Heading>* headings);

}  // namespace armstudy::report::html_detail
