#include "report/html_blocks.hpp"

#include <algorithm>
#include <filesystem>

#include "common/escape.hpp"
#include "common/join.hpp"
#include "report/markdown.hpp"

namespace armstudy::report::html_detail {
namespace {

namespace fs = std::filesystem;

std::string htmlEscape(const std::string& s) { return xmlEscape(s); }

// Emphasis and links nest at most this deep; deeper text is shown as it is written (user text
// such as 100,000 "**" would otherwise recurse until the stack overflows).
constexpr int kMaxInlineDepth = 8;

std::string linkHtml(const std::string& text, const std::string& url, const Targets& t, int depth);
std::string imageHtml(const std::string& alt, const std::string& url, const Targets& t);

std::string inlineMd(const std::string& s, const Targets& t, int depth) {
  if (depth > kMaxInlineDepth) return htmlEscape(s);
  std::string o;
  std::size_t i = 0;
  auto closing = [&](std::size_t from, const std::string& what) { return s.find(what, from); };
  while (i < s.size()) {
    const char c = s[i];
    if (c == '\\' && i + 1 < s.size() &&
        std::string("\\`*_[]()#|!<>-").find(s[i + 1]) != std::string::npos) {
      o += htmlEscape(std::string(1, s[i + 1]));
      i += 2;
      continue;
    }
    if (c == '`') {
      const std::size_t e = closing(i + 1, "`");
      if (e != std::string::npos) {
        o += "<code>" + htmlEscape(s.substr(i + 1, e - i - 1)) + "</code>";
        i = e + 1;
        continue;
      }
    }
    if ((c == '!' && i + 1 < s.size() && s[i + 1] == '[') || c == '[') {
      const bool img = c == '!';
      const std::size_t lb = i + (img ? 1 : 0);
      const std::size_t rb = closing(lb + 1, "](");
      const std::size_t rp = rb == std::string::npos ? rb : closing(rb + 2, ")");
      if (rb != std::string::npos && rp != std::string::npos) {
        const std::string text = s.substr(lb + 1, rb - lb - 1), url = s.substr(rb + 2, rp - rb - 2);
        o += img ? imageHtml(text, url, t) : linkHtml(text, url, t, depth + 1);
        i = rp + 1;
        continue;
      }
    }
    if (c == '*' && i + 1 < s.size() && s[i + 1] == '*') {
      const std::size_t e = closing(i + 2, "**");
      if (e != std::string::npos && e > i + 2) {
        o += "<strong>" + inlineMd(s.substr(i + 2, e - i - 2), t, depth + 1) + "</strong>";
        i = e + 2;
        continue;
      }
    }
    if (c == '*' && i + 1 < s.size() && s[i + 1] != ' ') {
      std::size_t e = i + 1;
      while ((e = closing(e, "*")) != std::string::npos && e + 1 < s.size() && s[e + 1] == '*')
        e += 2;
      if (e != std::string::npos && e > i + 1 && s[e - 1] != ' ') {
        o += "<em>" + inlineMd(s.substr(i + 1, e - i - 1), t, depth + 1) + "</em>";
        i = e + 1;
        continue;
      }
    }
    o += htmlEscape(std::string(1, c));
    ++i;
  }
  return o;
}

// A link that reportLinkTarget keeps, else its text alone.
std::string linkHtml(const std::string& text, const std::string& url, const Targets& t, int depth) {
  const std::string href = reportLinkTarget(url, t.dir);
  if (href.empty()) return inlineMd(text, t, depth);
  if (t.links && href[0] != '#' && href.find("://") == std::string::npos) {
    std::string path = fs::path(href.substr(0, href.find('#'))).lexically_normal().generic_string();
    while (path.size() > 1 && path.back() == '/') path.pop_back();  // a folder
    t.links->insert(path);
  }
  return "<a href=\"" + htmlEscape(href) + "\">" + inlineMd(text, t, depth) + "</a>";
}

// An image inside the output folder that `t.image` resolves, else its alt text alone.
std::string imageHtml(const std::string& alt, const std::string& url, const Targets& t) {
  const std::string rel = reportImagePath(url, t.dir);
  const std::string src = rel.empty() ? "" : t.image(rel);
  if (src.empty()) return htmlEscape(alt);
  return "<img src=\"" + htmlEscape(src) + "\" alt=\"" + htmlEscape(alt) + "\">";
}

}  // namespace

std::string inlineHtml(const std::string& s, const Targets& t) { return inlineMd(s, t, 0); }

std::vector<std::string> onlyImages(const std::string& s) {
  std::vector<std::string> imgs;
  std::size_t p = 0;
  while (p < s.size()) {
    while (p < s.size() && s[p] == ' ') ++p;
    if (p >= s.size()) break;
    if (s.compare(p, 2, "![") != 0) return {};
    const std::size_t e = s.find(')', s.find("](", p));
    if (e == std::string::npos) return {};
    imgs.push_back(s.substr(p, e - p + 1));
    p = e + 1;
  }
  return imgs;
}

std::string paragraphText(const std::vector<std::string>& p) { return join(p, " "); }

bool wholeItalic(const std::string& p) {
  return p.size() > 2 && p.front() == '*' && p.back() == '*' && p[1] != '*' && p[1] != ' ';
}

void headingHtml(std::ostream& o, int level, const std::string& id, const std::string& text,
                 const Targets& t) {
  o << "<h" << level + 1 << " id=\"" << id << "\">" << inlineHtml(text, t) << "</h" << level + 1
    << ">\n";
}

void paragraphHtml(std::ostream& o, const std::string& text, const Targets& t) {
  o << "<p>" << inlineHtml(text, t) << "</p>\n";
}

void figuresHtml(std::ostream& o, const std::vector<std::string>& imgs, const std::string& caption,
                 const Targets& t) {
  const std::string caption_html = caption.empty() ? "" : inlineHtml(caption, t);
  o << (imgs.size() > 1 ? "<div class=\"gallery\">\n" : "");
  for (const auto& im : imgs) {
    const std::size_t rb = im.find("](");
    const std::string alt = im.substr(2, rb - 2);
    o << "<figure>" << inlineHtml(im, t) << "<figcaption>"
      << (caption.empty() || imgs.size() > 1 ? inlineHtml(alt, t) : caption_html)
      << "</figcaption></figure>\n";
  }
  if (imgs.size() > 1 && !caption.empty()) o << "<p class=\"caption\">" << caption_html << "</p>\n";
  o << (imgs.size() > 1 ? "</div>\n" : "");
}

void codeHtml(std::ostream& o, const std::string& text) {
  o << "<pre><code>" << htmlEscape(text) << "</code></pre>\n";
}

namespace {

// A table of images (maps side by side, a cell in words where a map would be one colour) becomes
// a gallery that wraps to the page's width, each figure captioned by its column's heading: no cell
// holds more than one image, and most cells of every row hold one. False when it is not one.
bool imageTableHtml(std::ostream& o, const std::vector<std::string>& head,
                    const std::vector<std::vector<std::string>>& rows, const Targets& t) {
  std::size_t images = 0;
  for (const auto& row : rows) {
    std::size_t in_row = 0, cells = 0;
    for (const std::string& c : row) {
      const std::size_t n = c.find("![") == std::string::npos ? 0 : onlyImages(c).size();
      if (c.find("![") != std::string::npos && n != 1) return false;
      in_row += n;
      cells += !c.empty();
    }
    if (2 * in_row <= cells) return false;
    images += in_row;
  }
  if (images < 2) return false;
  o << "<div class=\"gallery\">\n";
  for (const auto& cells : rows) {
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (cells[c].empty()) continue;
      // "![design: what](file)": the design, then the column's heading; words: the heading.
      const bool image = cells[c].rfind("![", 0) == 0;
      const std::string alt = image ? cells[c].substr(2, cells[c].find("](") - 2) : "";
      const std::size_t colon = alt.find(": ");
      const std::string caption = (colon == std::string::npos ? "" : alt.substr(0, colon) + ": ") +
                                  (c < head.size() ? head[c] : alt);
      o << "<figure>" << (image ? "" : "<p>") << inlineHtml(cells[c], t) << (image ? "" : "</p>")
        << "<figcaption>" << inlineHtml(caption, t) << "</figcaption></figure>\n";
    }
  }
  o << "</div>\n";
  return true;
}

}  // namespace

void tableHtml(std::ostream& o, const std::vector<std::string>& head,
               const std::vector<bool>& right, const std::vector<std::vector<std::string>>& rows,
               const Targets& t) {
  if (imageTableHtml(o, head, rows, t)) return;
  o << "<div class=\"table-wrap\"><table>\n<thead><tr>";
  for (std::size_t c = 0; c < head.size(); ++c)
    o << "<th" << (right[c] ? " class=\"num\"" : "") << ">" << inlineHtml(head[c], t) << "</th>";
  o << "</tr></thead>\n<tbody>\n";
  for (const auto& cells : rows) {
    o << "<tr>";
    for (std::size_t c = 0; c < std::max(cells.size(), head.size()); ++c)
      o << "<td" << (c < right.size() && right[c] ? " class=\"num\"" : "") << ">"
        << (c < cells.size() ? inlineHtml(cells[c], t) : "") << "</td>";
    o << "</tr>\n";
  }
  o << "</tbody></table></div>\n";
}

void listHtml(std::ostream& o, const std::vector<std::string>& items, const Targets& t,
              const std::vector<std::vector<std::string>>& sub_items) {
  o << "<ul>\n";
  for (std::size_t i = 0; i < items.size(); ++i) {
    o << "<li>" << inlineHtml(items[i], t);
    if (i < sub_items.size() && !sub_items[i].empty()) {
      o << "\n<ul>\n";
      for (const std::string& sub : sub_items[i]) o << "<li>" << inlineHtml(sub, t) << "</li>\n";
      o << "</ul>\n";
    }
    o << "</li>\n";
  }
  o << "</ul>\n";
}

}  // namespace armstudy::report::html_detail
