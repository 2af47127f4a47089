#pragma once
// One self-contained HTML page per study (output/<study>/report.html), built from what the stages
// wrote: each stage's Markdown reports converted to HTML (the subset they use: headings,
// paragraphs, tables, lists, images, links, code, emphasis), every figure inlined as a data URI
// with its caption, the figures no report shows, and links to the data files (.vti, .vtp, .csv,
// ...). Inline CSS, nothing fetched; readable on a laptop and printable.
#include <functional>
#include <set>
#include <string>
#include <vector>

namespace armstudy::report {

struct HtmlStage {
  std::string name;                // "reach"
  std::vector<std::string> files;  // what the stage wrote, relative to the output folder
};

// Figures carried inside report.html (data URIs): each at most kInlineFigureBytes, together at
// most kInlineTotalBytes in page order; larger ones, and those after the budget is spent, are
// linked (relative to report.html, which sits in the output folder), so the page stays light
// whatever the study's size.
inline constexpr std::size_t kInlineFigureBytes = 100 * 1024;
inline constexpr std::size_t kInlineTotalBytes = 3 * 1024 * 1024;

// The page for a study whose results are in `output_dir`. Reads the listed Markdown and figure
// files from there. `lead_md` (the study's description and question, Markdown) heads the page
// under its title; `answer_md` (the study's answer and warnings, Markdown) follows, above the
// contents.
std::string htmlReport(const std::string& output_dir, const std::string& study_name,
                       const std::vector<HtmlStage>& stages, const std::string& answer_md = "",
                       const std::string& lead_md = "");

// Markdown (the subset above) to HTML, written in folder `dir` of the output folder. Links and
// images are kept as report/markdown.hpp reportLinkTarget and reportImagePath allow (else their
// text is shown); an image's path relative to the output folder is resolved with `image` (returns
// the src to use, e.g. a data URI, or "" to show the alt text); headings get ids
// "<id_prefix><n>" and are listed in `headings` as (level, id, text) when it is given; `links`,
// when given, collects the kept links into the output folder (relative to it, without a fragment).
struct Heading {
  int level = 1;
  std::string id, text;
};
std::string markdownToHtml(const std::string& md, const std::string& id_prefix,
                           const std::function<std::string(const std::string&)>& image,
                           std::vector<Heading>* headings = nullptr, const std::string& dir = "",
                           std::set<std::string>* links = nullptr);

std::string base64(const std::string& bytes);
std::string htmlEscape(const std::string& s);

}  // namespace armstudy::report
