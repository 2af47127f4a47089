#pragma once
// One self-contained HTML page per study (output/<study>/report.html), rendered from the stages'
// report documents (report/document.hpp: headings, paragraphs, tables, lists, figures, code,
// Markdown kept as written), every figure inlined as a data URI with its caption, the figures no
// report shows, and links to the data files (.vti, .vtp, .csv, ...). Inline CSS, nothing fetched;
// readable on a laptop and printable.
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "report/document.hpp"

namespace armstudy::report {

struct HtmlStage {
  std::string name;                 // "reach"
  std::vector<std::string> files;   // what the stage wrote, relative to the output folder
  std::vector<ReportFile> reports;  // the documents of its report files (.md in `files`)
};

// Figures carried inside report.html (data URIs): each at most kInlineFigureBytes, together at
// most kInlineTotalBytes in page order; larger ones, and those after the budget is spent, are
// linked (relative to report.html, which sits in the output folder), so the page stays light
// whatever the study's size.
inline constexpr std::size_t kInlineFigureBytes = 100 * 1024;
inline constexpr std::size_t kInlineTotalBytes = 3 * 1024 * 1024;

// The page for a study whose results are in `output_dir`. Each stage's report files are rendered
// from the documents it handed over, never read back from the folder (a listed .md file without a
// document is linked among the data files); the figures are read from the folder.
// `lead` (the study's description and question) heads the page under its title; `answer` (the
// study's answer and warnings) follows, above the contents.
std::string htmlReport(const std::string& output_dir, const std::string& study_name,
                       const std::vector<HtmlStage>& stages, const Document& answer = {},
                       const Document& lead = {});

// Markdown (the subset above) to HTML, written in folder `dir` of the output folder. Links and
// images are kept as report/markdown.hpp reportLinkTarget and reportImagePath allow (else their
// text is shown); an image's path relative to the output folder is resolved with `image` (returns
// the src to use, e.g. a data URI, or "" to show the alt text); headings get ids
// "<id_prefix><n>" and are listed in `headings` as (level, id, text) when it is given; `links`,
// when given, collects the kept links into the output folder (relative to it, without a fragment).
std::string markdownToHtml(const std::string& md, const std::string& id_prefix,
                           const std::function<std::string(const std::string&)>& image,
                           std::vector<Heading>* headings = nullptr, const std::string& dir = "",
                           std::set<std::string>* links = nullptr);

std::string base64(const std::string& bytes);
std::string htmlEscape(const std::string& s);

}  // namespace armstudy::report
