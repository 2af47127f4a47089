#include "report/document.hpp"

#include <sstream>

#include "common/escape.hpp"
#include "report/html_blocks.hpp"
#include "report/markdown.hpp"

namespace armstudy::report {

namespace {

Block block(Block::Kind kind) {
  Block b;
  b.kind = kind;
  return b;
}

std::string withNewline(std::string s) {
  if (s.empty() || s.back() != '\n') s += '\n';
  return s;
}

std::string imageMarkdown(const FigureImage& im) { return "![" + im.alt + "](" + im.path + ")"; }

// A table cell as the Markdown table holds it between the pipes: '|' escaped, a line break a
// blank, trimmed.
std::string cellText(const std::string& s) {
  const std::string e = substituteChars(s, [](char c) -> const char* {
    return c == '|' ? "\\|" : c == '\n' ? " " : nullptr;
  });
  const auto a = e.find_first_not_of(' '), b = e.find_last_not_of(' ');
  return a == std::string::npos ? "" : e.substr(a, b - a + 1);
}

const std::vector<std::string>& subItems(const Block& b, std::size_t i) {
  static const std::vector<std::string> none;
  return i < b.sub_items.size() ? b.sub_items[i] : none;
}

std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n') c = ' ';
  return s;
}

}  // namespace

Document& Document::heading(int level, std::string text) {
  Block b = block(Block::Kind::heading);
  b.level = level;
  b.text = std::move(text);
  blocks_.push_back(std::move(b));
  return *this;
}

Document& Document::paragraph(std::string text) {
  Block b = block(Block::Kind::paragraph);
  b.text = std::move(text);
  blocks_.push_back(std::move(b));
  return *this;
}

Document& Document::figures(std::vector<FigureImage> images, std::string caption) {
  Block b = block(Block::Kind::figures);
  b.images = std::move(images);
  b.text = std::move(caption);
  blocks_.push_back(std::move(b));
  return *this;
}

Document& Document::table(std::vector<std::string> header,
                          std::vector<std::vector<std::string>> rows, TableRule rule) {
  Block b = block(Block::Kind::table);
  b.header = std::move(header);
  b.rows = std::move(rows);
  b.rule = rule;
  blocks_.push_back(std::move(b));
  return *this;
}

Document& Document::list(std::vector<std::string> items) {
  Block b = block(Block::Kind::list);
  b.items = std::move(items);
  blocks_.push_back(std::move(b));
  return *this;
}

Document& Document::nestedList(std::vector<ListItem> items) {
  Block b = block(Block::Kind::list);
  for (ListItem& item : items) {
    b.items.push_back(std::move(item.text));
    b.sub_items.push_back(std::move(item.sub_items));
  }
  blocks_.push_back(std::move(b));
  return *this;
}

Document& Document::code(std::string text) {
  Block b = block(Block::Kind::code);
  b.text = withNewline(std::move(text));
  blocks_.push_back(std::move(b));
  return *this;
}

Document& Document::markdown(std::string md) {
  Block b = block(Block::Kind::markdown);
  b.text = std::move(md);
  blocks_.push_back(std::move(b));
  return *this;
}

Document& Document::append(const Document& other) {
  blocks_.insert(blocks_.end(), other.blocks_.begin(), other.blocks_.end());
  return *this;
}

std::string toMarkdown(const Document& doc) {
  std::string md;
  for (const Block& b : doc.blocks()) {
    switch (b.kind) {
      case Block::Kind::heading:
        md += std::string(b.level, '#') + " " + b.text + "\n\n";
        break;
      case Block::Kind::paragraph:
        md += b.text + "\n\n";
        break;
      case Block::Kind::figures:
        for (std::size_t i = 0; i < b.images.size(); ++i)
          md += (i ? " " : "") + imageMarkdown(b.images[i]);
        md += "\n\n";
        if (!b.text.empty()) md += "*" + b.text + "*\n\n";
        break;
      case Block::Kind::table:
        md += markdownTable(b.header, b.rows, b.rule == TableRule::compact) + "\n";
        break;
      case Block::Kind::list:
        for (std::size_t i = 0; i < b.items.size(); ++i) {
          md += "- " + b.items[i] + "\n";
          for (const std::string& sub : subItems(b, i)) md += "  - " + sub + "\n";
        }
        md += "\n";
        break;
      case Block::Kind::code:
        md += "```\n" + b.text + "```\n\n";
        break;
      case Block::Kind::markdown:
        md += b.text;
        break;
    }
  }
  return md;
}

namespace {

// A table block's HTML: its cells as the Markdown table holds them.
void tableBlockHtml(std::ostream& o, const Block& b, const html_detail::Targets& t) {
  std::vector<std::string> head;
  std::vector<bool> right;
  for (const std::string& h : b.header) {
    right.push_back(!h.empty() && h[0] == '>');
    head.push_back(cellText(right.back() ? h.substr(1) : h));
  }
  std::vector<std::vector<std::string>> rows;
  for (const auto& r : b.rows) {
    rows.emplace_back();
    for (std::size_t c = 0; c < b.header.size(); ++c)
      rows.back().push_back(c < r.size() ? cellText(r[c]) : "");
  }
  html_detail::tableHtml(o, head, right, rows, t);
}

}  // namespace

std::string toHtml(const Document& doc, const std::string& id_prefix,
                   const std::function<std::string(const std::string&)>& image,
                   std::vector<Heading>* headings, const std::string& dir,
                   std::set<std::string>* links) {
  const html_detail::Targets t{image, dir, links};
  std::ostringstream o;
  int n = 0;  // the next heading's number
  for (const Block& b : doc.blocks()) {
    switch (b.kind) {
      case Block::Kind::heading: {
        const std::string id = id_prefix + std::to_string(n++);
        html_detail::headingHtml(o, b.level, id, b.text, t);
        if (headings) headings->push_back({b.level, id, b.text});
        break;
      }
      case Block::Kind::paragraph:
        html_detail::paragraphHtml(o, oneLine(b.text), t);
        break;
      case Block::Kind::figures: {
        std::vector<std::string> images;
        for (const FigureImage& im : b.images) images.push_back(imageMarkdown(im));
        html_detail::figuresHtml(o, images, b.text, t);
        break;
      }
      case Block::Kind::table:
        tableBlockHtml(o, b, t);
        break;
      case Block::Kind::list:
        html_detail::listHtml(o, b.items, t, b.sub_items);
        break;
      case Block::Kind::code:
        html_detail::codeHtml(o, b.text);
        break;
      case Block::Kind::markdown:
        o << html_detail::markdownHtml(b.text, id_prefix, &n, t, headings);
        break;
    }
  }
  return o.str();
}

}  // namespace armstudy::report
