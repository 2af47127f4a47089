#include "report/html_report.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "io/files.hpp"
#include "report/html_page.hpp"
#include "report/image.hpp"
#include "report/markdown.hpp"

namespace armstudy::report {
namespace {

namespace fs = std::filesystem;

std::string slugless(std::string s) {  // "first_prototype_6dof.svg" -> readable caption
  for (char& c : s)
    if (c == '_') c = ' ';
  return s;
}

bool endsWith(const std::string& s, const std::string& e) {
  return s.size() >= e.size() && s.compare(s.size() - e.size(), e.size(), e) == 0;
}

// ---- inline Markdown ----
// Where a Markdown text's links and images lead: the text was written in folder `dir` of the
// output folder (markdown.hpp reportLinkTarget, reportImagePath); `image` gives an image's src
// from its path relative to the output folder, "" to show its alt text instead; `links`, when
// given, collects the kept links into the output folder (relative to it, without a fragment).
struct Targets {
  const std::function<std::string(const std::string&)>& image;
  std::string dir;
  std::set<std::string>* links = nullptr;
};

// Emphasis and links nest at most this deep; deeper text is shown as it is written (user text
// such as 100,000 "**" would otherwise recurse until the stack overflows).
constexpr int kMaxInlineDepth = 8;

std::string linkHtml(const std::string& text, const std::string& url, const Targets& t, int depth);
std::string imageHtml(const std::string& alt, const std::string& url, const Targets& t);

std::string inlineMd(const std::string& s, const Targets& t, int depth = 0) {
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

std::vector<std::string> tableCells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cur;
  std::size_t i = 0;
  std::string l = line;
  while (!l.empty() && (l.back() == ' ' || l.back() == '\r')) l.pop_back();
  if (!l.empty() && l[0] == '|') i = 1;
  for (; i < l.size(); ++i) {
    if (l[i] == '\\' && i + 1 < l.size() && l[i + 1] == '|') {
      cur += "\\|";
      ++i;
    } else if (l[i] == '|') {
      cells.push_back(cur);
      cur.clear();
    } else {
      cur += l[i];
    }
  }
  if (!cur.empty() && cur.find_first_not_of(' ') != std::string::npos) cells.push_back(cur);
  for (auto& c : cells) {
    const auto a = c.find_first_not_of(' '), b = c.find_last_not_of(' ');
    c = a == std::string::npos ? "" : c.substr(a, b - a + 1);
  }
  return cells;
}

bool isSeparatorRow(const std::string& line) {
  if (line.empty() || line[0] != '|') return false;
  return line.find_first_not_of("|-: ") == std::string::npos && line.find('-') != std::string::npos;
}

bool wholeItalic(const std::string& p) {
  return p.size() > 2 && p.front() == '*' && p.back() == '*' && p[1] != '*' && p[1] != ' ';
}

}  // namespace

// HTML text and attribute values need exactly what XML needs (& < > ").
std::string htmlEscape(const std::string& s) { return xmlEscape(s); }

namespace {
// Appends the base64 (RFC 4648) of `in` to `o`, written in place (report.html inlines tens of MB of
// figures on the one rank that writes the results: docs/performance.md, "The serial rest").
void appendBase64(std::string& o, const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const std::size_t at = o.size();
  o.resize(at + (in.size() + 2) / 3 * 4);
  char* w = o.data() + at;
  const auto* b = reinterpret_cast<const unsigned char*>(in.data());
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (unsigned{b[i]} << 16) | (unsigned{b[i + 1]} << 8) | unsigned{b[i + 2]};
    *w++ = t[v >> 18];
    *w++ = t[(v >> 12) & 63];
    *w++ = t[(v >> 6) & 63];
    *w++ = t[v & 63];
  }
  if (i < in.size()) {
    const unsigned v = (unsigned{b[i]} << 16) | (i + 1 < in.size() ? unsigned{b[i + 1]} << 8 : 0u);
    *w++ = t[v >> 18];
    *w++ = t[(v >> 12) & 63];
    *w++ = i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
    *w++ = '=';
  }
}
}  // namespace

std::string base64(const std::string& in) {
  std::string o;
  appendBase64(o, in);
  return o;
}

namespace {

bool isBlank(const std::string& l) { return l.find_first_not_of(" \t") == std::string::npos; }

std::string paragraphText(const std::vector<std::string>& p) {
  std::string s;
  for (const auto& l : p) s += (s.empty() ? "" : " ") + l;
  return s;
}

// The image links "![alt](file)" a paragraph consists of; empty when it holds anything else.
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

// The Markdown subset the reports write, line by line: headings, paragraphs, figures with their
// captions, fenced code, tables and lists.
class MarkdownToHtml {
 public:
  using Image = std::function<std::string(const std::string&)>;
  MarkdownToHtml(const std::string& md, const std::string& id_prefix, const Image& image,
                 std::vector<Heading>* headings, const std::string& dir,
                 std::set<std::string>* links)
      : id_prefix_(id_prefix), targets_{image, dir, links}, headings_(headings) {
    std::istringstream in(md);
    std::string l;
    while (std::getline(in, l)) {
      if (!l.empty() && l.back() == '\r') l.pop_back();
      lines_.push_back(l);
    }
  }

  std::string run() {
    while (i_ < lines_.size()) {
      const std::string& l = lines_[i_];
      if (isBlank(l)) {
        const std::size_t at = i_;
        flush();  // may consume the caption paragraph after a figure
        if (i_ == at) ++i_;
      } else if (l.rfind("```", 0) == 0) {
        flush();
        code();
      } else if (l[0] == '#' && isHeading(l)) {
        flush();
        heading(l);
      } else if (l[0] == '|' && i_ + 1 < lines_.size() && isSeparatorRow(lines_[i_ + 1])) {
        flush();
        table();
      } else if (l.rfind("- ", 0) == 0 || l.rfind("* ", 0) == 0) {
        flush();
        list();
      } else {
        if (l[0] == '#') flush();
        para_.push_back(l);
        ++i_;
      }
    }
    flush();
    return o_.str();
  }

 private:
  static bool isHeading(const std::string& l) {
    const std::size_t level = l.find_first_not_of('#');
    return level != std::string::npos && level <= 6 && l[level] == ' ';
  }

  std::string nextParagraph(std::size_t from, std::size_t& end) const {
    std::size_t k = from;
    while (k < lines_.size() && isBlank(lines_[k])) ++k;
    std::vector<std::string> p;
    while (k < lines_.size() && !isBlank(lines_[k]) && lines_[k][0] != '#' && lines_[k][0] != '|')
      p.push_back(lines_[k++]);
    end = k;
    return paragraphText(p);
  }

  // A paragraph that is only images becomes figures; an italic paragraph right after it is its
  // caption (the reports write "![alt](file)" then "*caption*").
  void flush() {
    if (para_.empty()) return;
    const std::string s = paragraphText(para_);
    para_.clear();
    const std::vector<std::string> imgs = onlyImages(s);
    if (imgs.empty()) {
      o_ << "<p>" << inlineMd(s, targets_) << "</p>\n";
      return;
    }
    std::size_t end = i_;
    const std::string next = nextParagraph(i_, end);
    std::string caption;
    if (wholeItalic(next)) {
      caption = inlineMd(next.substr(1, next.size() - 2), targets_);
      i_ = end;
    }
    o_ << (imgs.size() > 1 ? "<div class=\"gallery\">\n" : "");
    for (const auto& im : imgs) {
      const std::size_t rb = im.find("](");
      const std::string alt = im.substr(2, rb - 2);
      o_ << "<figure>" << inlineMd(im, targets_) << "<figcaption>"
         << (caption.empty() || imgs.size() > 1 ? inlineMd(alt, targets_) : caption)
         << "</figcaption></figure>\n";
    }
    if (imgs.size() > 1 && !caption.empty()) o_ << "<p class=\"caption\">" << caption << "</p>\n";
    o_ << (imgs.size() > 1 ? "</div>\n" : "");
  }

  void code() {
    std::string text;
    for (++i_; i_ < lines_.size() && lines_[i_].rfind("```", 0) != 0; ++i_)
      text += lines_[i_] + "\n";
    ++i_;
    o_ << "<pre><code>" << htmlEscape(text) << "</code></pre>\n";
  }

  void heading(const std::string& l) {
    const std::size_t level = l.find_first_not_of('#');
    const std::string text = l.substr(level + 1);
    const std::string id = id_prefix_ + std::to_string(n_heading_++);
    o_ << "<h" << level + 1 << " id=\"" << id << "\">" << inlineMd(text, targets_) << "</h"
       << level + 1 << ">\n";
    if (headings_) headings_->push_back({static_cast<int>(level), id, text});
    ++i_;
  }

  // A table of images (maps side by side, a cell in words where a map would be one colour)
  // becomes a gallery that wraps to the page's width, each figure captioned by its column's
  // heading: no cell holds more than one image, and most cells of every row hold one.
  bool imageTable() {
    const auto head = tableCells(lines_[i_]);
    std::size_t end = i_ + 2, images = 0;
    for (; end < lines_.size() && !lines_[end].empty() && lines_[end][0] == '|'; ++end) {
      std::size_t in_row = 0, cells = 0;
      for (const std::string& c : tableCells(lines_[end])) {
        const std::size_t n = c.find("![") == std::string::npos ? 0 : onlyImages(c).size();
        if (c.find("![") != std::string::npos && n != 1) return false;
        in_row += n;
        cells += !c.empty();
      }
      if (2 * in_row <= cells) return false;
      images += in_row;
    }
    if (images < 2) return false;
    o_ << "<div class=\"gallery\">\n";
    for (std::size_t r = i_ + 2; r < end; ++r) {
      const auto cells = tableCells(lines_[r]);
      for (std::size_t c = 0; c < cells.size(); ++c) {
        if (cells[c].empty()) continue;
        // "![design: what](file)": the design, then the column's heading; words: the heading.
        const bool image = cells[c].rfind("![", 0) == 0;
        const std::string alt = image ? cells[c].substr(2, cells[c].find("](") - 2) : "";
        const std::size_t colon = alt.find(": ");
        const std::string caption =
            (colon == std::string::npos ? "" : alt.substr(0, colon) + ": ") +
            (c < head.size() ? head[c] : alt);
        o_ << "<figure>" << (image ? "" : "<p>") << inlineMd(cells[c], targets_)
           << (image ? "" : "</p>") << "<figcaption>" << inlineMd(caption, targets_)
           << "</figcaption></figure>\n";
      }
    }
    o_ << "</div>\n";
    i_ = end;
    return true;
  }

  void table() {
    if (imageTable()) return;
    const auto head = tableCells(lines_[i_]);
    const auto seps = tableCells(lines_[i_ + 1]);
    std::vector<bool> right(head.size(), false);
    for (std::size_t c = 0; c < seps.size() && c < right.size(); ++c)
      right[c] = !seps[c].empty() && seps[c].back() == ':';
    o_ << "<div class=\"table-wrap\"><table>\n<thead><tr>";
    for (std::size_t c = 0; c < head.size(); ++c)
      o_ << "<th" << (right[c] ? " class=\"num\"" : "") << ">" << inlineMd(head[c], targets_)
         << "</th>";
    o_ << "</tr></thead>\n<tbody>\n";
    for (i_ += 2; i_ < lines_.size() && !lines_[i_].empty() && lines_[i_][0] == '|'; ++i_) {
      const auto cells = tableCells(lines_[i_]);
      o_ << "<tr>";
      for (std::size_t c = 0; c < std::max(cells.size(), head.size()); ++c)
        o_ << "<td" << (c < right.size() && right[c] ? " class=\"num\"" : "") << ">"
           << (c < cells.size() ? inlineMd(cells[c], targets_) : "") << "</td>";
      o_ << "</tr>\n";
    }
    o_ << "</tbody></table></div>\n";
  }

  void list() {
    o_ << "<ul>\n";
    for (; i_ < lines_.size() && (lines_[i_].rfind("- ", 0) == 0 || lines_[i_].rfind("* ", 0) == 0);
         ++i_) {
      std::string item = lines_[i_].substr(2);
      while (i_ + 1 < lines_.size() && lines_[i_ + 1].rfind("  ", 0) == 0 &&
             !isBlank(lines_[i_ + 1]))
        item += " " + lines_[++i_].substr(2);
      o_ << "<li>" << inlineMd(item, targets_) << "</li>\n";
    }
    o_ << "</ul>\n";
  }

  std::vector<std::string> lines_;
  const std::string& id_prefix_;
  Targets targets_;
  std::vector<Heading>* headings_;
  std::ostringstream o_;
  std::vector<std::string> para_;
  int n_heading_ = 0;
  std::size_t i_ = 0;
};

}  // namespace

std::string markdownToHtml(const std::string& md, const std::string& id_prefix,
                           const std::function<std::string(const std::string&)>& image,
                           std::vector<Heading>* headings, const std::string& dir,
                           std::set<std::string>* links) {
  return MarkdownToHtml(md, id_prefix, image, headings, dir, links).run();
}

namespace {

// The figures of one report.html: each image's src (a data URI within the page's budget, else a
// link), only for files inside the output folder with symbolic links resolved.
class Figures {
 public:
  explicit Figures(const std::string& output_dir) : root_(output_dir) {
    std::error_code ec;
    base_ = fs::weakly_canonical(fs::absolute(root_), ec);
    if (ec) base_.clear();
  }

  // True when root/rel, symbolic links resolved (a missing tail as written), is inside the folder.
  bool inside(const std::string& rel) const {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(base_ / rel, ec);
    if (ec || base_.empty()) return false;
    const fs::path r = p.lexically_relative(base_);
    return !r.empty() && *r.begin() != "..";
  }

  // The src of the figure `rel` (relative to the output folder): its data URI when it is an .svg
  // or .png file within the limits, else `rel` (a link); "" when it is outside the folder.
  std::string src(const std::string& rel) {
    if (!inside(rel)) return "";
    const fs::path p = root_ / rel;
    std::string mime;
    if (endsWith(rel, ".svg"))
      mime = "image/svg+xml";
    else if (endsWith(rel, ".png"))
      mime = "image/png";
    std::error_code ec;
    if (mime.empty() || !fs::is_regular_file(p, ec)) return rel;  // left as a link
    shown.insert(fs::path(rel).lexically_normal().generic_string());
    const std::size_t size = fs::file_size(p);
    if (size > kInlineFigureBytes || inlined_ + size > kInlineTotalBytes) return rel;  // linked
    inlined_ += size;
    const std::string bytes = readFileOrThrow(p.string());
    std::string uri;
    uri.reserve(5 + mime.size() + 8 + (bytes.size() + 2) / 3 * 4);
    uri.append("data:").append(mime).append(";base64,");
    appendBase64(uri, bytes);
    return uri;
  }

  // `rel` as a link when it is inside the folder, else "".
  std::string link(const std::string& rel) const { return inside(rel) ? rel : ""; }

  std::set<std::string> shown;  // figures a report already shows (relative to the output folder)

 private:
  fs::path root_, base_;
  std::size_t inlined_ = 0;  // bytes of the figures carried so far
};

}  // namespace

std::string htmlReport(const std::string& output_dir, const std::string& study_name,
                       const std::vector<HtmlStage>& stages, const std::string& answer_md,
                       const std::string& lead_md) {
  const fs::path root(output_dir);
  Figures figures(output_dir);
  const std::function<std::string(const std::string&)> dataUri =
                                                           [&](const std::string&rel) {
                                                             return figures.src(rel);
                                                           },
                                                       linked = [&](const std::string&rel) {
                                                         return figures.link(rel);
                                                       };
  std::set<std::string>& shown = figures.shown;
  std::set<std::string> links;  // what the stages' reports link inside the output folder
  // The answer's images are linked, not carried (it opens the page).
  const std::string answer_html =
      answer_md.empty() ? "" : markdownToHtml(answer_md, "answer-", linked);
  const std::string lead_html = lead_md.empty() ? "" : markdownToHtml(lead_md, "lead-", linked);
  std::ostringstream body, nav;
  nav << "<nav class=\"contents\"><strong>Contents</strong>\n<ul>\n";
  int sec = 0;
  for (const HtmlStage& st : stages) {
    const std::string sid = "s" + std::to_string(sec++);
    body << "<section class=\"stage\" id=\"" << sid << "\">\n<h2 class=\"stage-title\">"
         << htmlEscape(st.name) << "</h2>\n";
    nav << "<li><a href=\"#" << sid << "\">" << htmlEscape(st.name) << "</a>\n<ul>\n";
    int md_count = 0;
    for (const std::string& f : st.files) {
      if (!endsWith(f, ".md")) continue;
      const fs::path p = root / f;
      if (!fs::exists(p)) continue;
      const std::string dir = fs::path(f).parent_path().generic_string();
      std::vector<Heading> hs;
      body << markdownToHtml(readFileOrThrow(p.string()),
                             sid + "-" + std::to_string(md_count++) + "-", dataUri, &hs, dir,
                             &links);
      for (const Heading& h : hs)
        if (h.level <= 3)
          nav << "<li class=\"l" << h.level << "\"><a href=\"#" << h.id << "\">"
              << inlineMd(h.text, Targets{linked, dir}) << "</a></li>\n";
    }
    // Figures no report shows or links, itself or its folder (one per figure: an .svg, else its
    // .png).
    const auto linked_to = [&](const std::string& n) {
      for (fs::path p = n; !p.empty() && p != p.parent_path(); p = p.parent_path())
        if (links.count(p.generic_string())) return true;
      return false;
    };
    std::vector<std::string> more;
    std::set<std::string> stems_with_svg;
    for (const std::string& f : st.files)
      if (endsWith(f, ".svg")) stems_with_svg.insert(f.substr(0, f.size() - 4));
    for (const std::string& f : st.files) {
      const std::string n = fs::path(f).lexically_normal().generic_string();
      if (shown.count(n) || linked_to(n)) continue;
      if (endsWith(f, ".svg"))
        more.push_back(f);
      else if (endsWith(f, ".png") && !stems_with_svg.count(f.substr(0, f.size() - 4)) &&
               !shown.count(n.substr(0, n.size() - 4) + ".svg"))
        more.push_back(f);
    }
    if (!more.empty()) {
      body << "<h3 id=\"" << sid << "-more\">Figures</h3>\n<div class=\"gallery\">\n";
      nav << "<li class=\"l3\"><a href=\"#" << sid << "-more\">Figures</a></li>\n";
      for (const std::string& f : more) {
        const std::string src = dataUri(f);
        if (src.empty()) continue;  // outside the output folder
        body << "<figure><img src=\"" << htmlEscape(src) << "\" alt=\"" << htmlEscape(f)
             << "\"><figcaption>" << htmlEscape(slugless(fs::path(f).stem().string())) << " (<code>"
             << htmlEscape(f) << "</code>)</figcaption></figure>\n";
      }
      body << "</div>\n";
    }
    // Data files for ParaView and scripts.
    // (The steps of a .pvd time series are listed by the .pvd, not here.)
    std::vector<std::string> data;
    for (const std::string& f : st.files)
      if (!endsWith(f, ".svg") && !endsWith(f, ".png") && !endsWith(f, ".md") &&
          f.find("/step_") == std::string::npos)
        data.push_back(f);
    if (!data.empty()) {
      body << "<h3 id=\"" << sid
           << "-files\">Data files</h3>\n<p>Open the <code>.vti</code>, <code>.vts</code>, "
              "<code>.vtp</code> and <code>.pvd</code> files in ParaView (all of them in one view: "
              "<code>pvpython scene.py</code>); the tables are CSV and JSON.</p>\n<ul "
              "class=\"files\">\n";
      nav << "<li class=\"l3\"><a href=\"#" << sid << "-files\">Data files</a></li>\n";
      for (const std::string& f : data)
        body << "<li><a href=\"" << htmlEscape(f) << "\"><code>" << htmlEscape(f)
             << "</code></a></li>\n";
      body << "</ul>\n";
    }
    body << "</section>\n";
    nav << "</ul></li>\n";
  }
  nav << "</ul></nav>\n";
  // One copy of the body into the page (it holds the inlined figures).
  return html_detail::page(study_name, lead_html, answer_html, std::move(nav).str(),
                           std::move(body).str());
}

}  // namespace armstudy::report
