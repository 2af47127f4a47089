// Markdown to HTML (html_report.hpp markdownToHtml): the subset the reports write, read line by
// line into blocks, each written by the block writers the document renderer shares
// (html_blocks.hpp).
#include <sstream>

#include "report/html_blocks.hpp"
#include "report/html_report.hpp"

namespace armstudy::report {
namespace html_detail {
namespace {

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

bool isBlank(const std::string& l) { return l.find_first_not_of(" \t") == std::string::npos; }

// The Markdown subset the reports write, line by line: headings, paragraphs, figures with their
// captions, fenced code, tables and lists.
class MarkdownToHtml {
 public:
  MarkdownToHtml(const std::string& md, const std::string& id_prefix, int* heading_number,
                 const Targets& targets, std::vector<Heading>* headings)
      : id_prefix_(id_prefix), n_heading_(*heading_number), targets_(targets), headings_(headings) {
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
    if (imgs.empty()) return paragraphHtml(o_, s, targets_);
    std::size_t end = i_;
    const std::string next = nextParagraph(i_, end);
    std::string caption;
    if (wholeItalic(next)) {
      caption = next.substr(1, next.size() - 2);
      i_ = end;
    }
    figuresHtml(o_, imgs, caption, targets_);
  }

  void code() {
    std::string text;
    for (++i_; i_ < lines_.size() && lines_[i_].rfind("```", 0) != 0; ++i_)
      text += lines_[i_] + "\n";
    ++i_;
    codeHtml(o_, text);
  }

  void heading(const std::string& l) {
    const std::size_t level = l.find_first_not_of('#');
    const std::string text = l.substr(level + 1);
    const std::string id = id_prefix_ + std::to_string(n_heading_++);
    headingHtml(o_, static_cast<int>(level), id, text, targets_);
    if (headings_) headings_->push_back({static_cast<int>(level), id, text});
    ++i_;
  }

  void table() {
    const auto head = tableCells(lines_[i_]);
    const auto seps = tableCells(lines_[i_ + 1]);
    std::vector<bool> right(head.size(), false);
    for (std::size_t c = 0; c < seps.size() && c < right.size(); ++c)
      right[c] = !seps[c].empty() && seps[c].back() == ':';
    std::vector<std::vector<std::string>> rows;
    for (i_ += 2; i_ < lines_.size() && !lines_[i_].empty() && lines_[i_][0] == '|'; ++i_)
      rows.push_back(tableCells(lines_[i_]));
    tableHtml(o_, head, right, rows, targets_);
  }

  static bool isItem(const std::string& l) {
    return l.rfind("- ", 0) == 0 || l.rfind("* ", 0) == 0;
  }

  // A list; an indented line is an item under the last item ("  - ") or continues the last item.
  void list() {
    std::vector<std::string> items;
    std::vector<std::vector<std::string>> subs;
    for (; i_ < lines_.size() && isItem(lines_[i_]); ++i_) {
      items.push_back(lines_[i_].substr(2));
      subs.emplace_back();
      while (i_ + 1 < lines_.size() && lines_[i_ + 1].rfind("  ", 0) == 0 &&
             !isBlank(lines_[i_ + 1])) {
        const std::string l = lines_[++i_].substr(2);
        if (isItem(l))
          subs.back().push_back(l.substr(2));
        else if (subs.back().empty())
          items.back() += " " + l;
        else
          subs.back().back() += " " + l.substr(l.find_first_not_of(' '));
      }
    }
    listHtml(o_, items, targets_, subs);
  }

  std::vector<std::string> lines_;
  const std::string& id_prefix_;
  int& n_heading_;  // the next heading's number
  const Targets& targets_;
  std::vector<Heading>* headings_;
  std::ostringstream o_;
  std::vector<std::string> para_;
  std::size_t i_ = 0;
};

}  // namespace

std::string markdownHtml(const std::string& md, const std::string& id_prefix, int* heading_number,
                         const Targets& t, std::vector<Heading>* headings) {
  return MarkdownToHtml(md, id_prefix, heading_number, t, headings).run();
}

}  // namespace html_detail

std::string markdownToHtml(const std::string& md, const std::string& id_prefix,
                           const std::function<std::string(const std::string&)>& image,
                           std::vector<Heading>* headings, const std::string& dir,
                           std::set<std::string>* links) {
  int n = 0;
  return html_detail::markdownHtml(md, id_prefix, &n, html_detail::Targets{image, dir, links},
                                   headings);
}

}  // namespace armstudy::report
