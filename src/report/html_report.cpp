#include "report/html_report.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "io/files.hpp"
#include "report/html_blocks.hpp"
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

// The document the stage handed over for its report file `f`; null when it handed over none.
const Document* reportDocument(const HtmlStage& st, const std::string& f) {
  for (const ReportFile& r : st.reports)
    if (r.path == f) return &r.doc;
  return nullptr;
}

}  // namespace

std::string htmlReport(const std::string& output_dir, const std::string& study_name,
                       const std::vector<HtmlStage>& stages, const Document& answer,
                       const Document& lead) {
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
  const std::string answer_html = answer.empty() ? "" : toHtml(answer, "answer-", linked);
  const std::string lead_html = lead.empty() ? "" : toHtml(lead, "lead-", linked);
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
      const Document* doc = reportDocument(st, f);
      if (!doc) continue;  // listed among the data files
      const std::string dir = fs::path(f).parent_path().generic_string();
      std::vector<Heading> hs;
      body << toHtml(*doc, sid + "-" + std::to_string(md_count++) + "-", dataUri, &hs, dir, &links);
      for (const Heading& h : hs)
        if (h.level <= 3)
          nav << "<li class=\"l" << h.level << "\"><a href=\"#" << h.id << "\">"
              << html_detail::inlineHtml(h.text, html_detail::Targets{linked, dir})
              << "</a></li>\n";
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
    // Data files for ParaView and scripts, and Markdown files without a document (linked, never
    // read). (The steps of a .pvd time series are listed by the .pvd, not here.)
    std::vector<std::string> data;
    for (const std::string& f : st.files)
      if (!endsWith(f, ".svg") && !endsWith(f, ".png") &&
          !(endsWith(f, ".md") && reportDocument(st, f)) && f.find("/step_") == std::string::npos)
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
