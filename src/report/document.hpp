#pragma once
// A report as data: a list of typed blocks (heading, paragraph, figures, table, list, code) that
// the stages build and one renderer writes as Markdown (report.md files) and as HTML (report.html).
// Inline text (a paragraph, a cell, a caption) is Markdown's inline subset: `code`, **strong**,
// *emphasis*, [links](target) and ![images](file). The HTML of a document is the HTML that
// markdownToHtml (html_report.hpp) gives for its Markdown.
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace armstudy::report {

struct FigureImage {
  std::string alt, path;  // path relative to the report's folder
};

// A list item with the items indented under it (inline, one line each).
struct ListItem {
  std::string text;
  std::vector<std::string> sub_items;
};

// How a table's separator row is written in Markdown: "| --- |" (padded) or "|---|" (compact); the
// HTML is the same.
enum class TableRule { padded, compact };

struct Block {
  enum class Kind { heading, paragraph, figures, table, list, code, markdown };
  Kind kind = Kind::paragraph;
  int level = 0;     // heading: 1 = "#"
  std::string text;  // heading and paragraph (inline), the figures' caption, code, Markdown
  std::vector<FigureImage> images;                  // figures
  std::vector<std::string> header;                  // table; '>' first: right-aligned
  std::vector<std::vector<std::string>> rows;       // table
  TableRule rule = TableRule::padded;               // table
  std::vector<std::string> items;                   // list (inline, one line each)
  std::vector<std::vector<std::string>> sub_items;  // list: per item, those indented under it
};

class Document {
 public:
  Document() = default;
  explicit Document(std::vector<Block> blocks) : blocks_(std::move(blocks)) {}
  Document& heading(int level, std::string text);
  Document& paragraph(std::string text);
  // Images side by side with one caption under them ("" = each captioned by its alt text).
  Document& figures(std::vector<FigureImage> images, std::string caption = "");
  Document& table(std::vector<std::string> header, std::vector<std::vector<std::string>> rows,
                  TableRule rule = TableRule::padded);
  Document& list(std::vector<std::string> items);
  Document& nestedList(std::vector<ListItem> items);  // items with items indented under them
  Document& code(std::string text);
  // Markdown kept as written: a part of a report not built of blocks (the Markdown subset above).
  Document& markdown(std::string md);
  Document& append(const Document& other);
  const std::vector<Block>& blocks() const { return blocks_; }
  bool empty() const { return blocks_.empty(); }

 private:
  std::vector<Block> blocks_;
};

// A report file of a stage: its path relative to the output folder and its document.
struct ReportFile {
  std::string path;
  Document doc;
};

// A heading of a page: its level ("#" = 1), id and text (inline).
struct Heading {
  int level = 1;
  std::string id, text;
};

std::string toMarkdown(const Document& doc);

// The document's HTML, written in folder `dir` of the output folder; `image`, `headings`, `links`
// and the heading ids as markdownToHtml (html_report.hpp) gives them.
std::string toHtml(const Document& doc, const std::string& id_prefix,
                   const std::function<std::string(const std::string&)>& image,
                   std::vector<Heading>* headings = nullptr, const std::string& dir = "",
                   std::set<std::string>* links = nullptr);

}  // namespace armstudy::report
