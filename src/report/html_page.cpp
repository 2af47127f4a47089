#include "report/html_page.hpp"

#include <sstream>

#include "report/html_report.hpp"

namespace armstudy::report::html_detail {
namespace {

const char* kCss = R"(
:root { --fg: #1d1d1f; --muted: #555; --line: #d0d4da; --band: #f4f6f8; --accent: #1f5fa8; }
* { box-sizing: border-box; }
body { margin: 0; font: 15px/1.5 "DejaVu Sans", "Segoe UI", Helvetica, Arial, sans-serif; color: var(--fg); }
header { background: var(--band); border-bottom: 1px solid var(--line); padding: 18px 28px; }
header h1 { margin: 0; font-size: 24px; }
header p { margin: 4px 0 0; color: var(--muted); }
main { max-width: 1180px; margin: 0 auto; padding: 8px 28px 40px; }
section.answer { border: 2px solid var(--accent); padding: 4px 18px 10px; margin: 18px 0; }
section.answer h2 { font-size: 20px; color: var(--accent); margin: 10px 0 4px; }
p.method { color: var(--muted); }
nav.contents { border: 1px solid var(--line); background: var(--band); padding: 10px 18px; margin: 18px 0; }
nav.contents ul { margin: 4px 0; padding-left: 20px; }
nav.contents li.l3 { margin-left: 18px; font-size: 14px; }
section.stage { border-top: 3px solid var(--accent); margin-top: 28px; padding-top: 6px; }
h1, h2, h3, h4 { line-height: 1.25; overflow-wrap: anywhere; }
h2.stage-title { font-size: 22px; color: var(--accent); text-transform: capitalize; }
a { color: var(--accent); }
code { font-family: "DejaVu Sans Mono", monospace; font-size: 90%; background: var(--band); padding: 0 3px;
       overflow-wrap: anywhere; }
pre { background: var(--band); padding: 8px; overflow-x: auto; }
p, li { overflow-wrap: anywhere; }
.table-wrap { overflow-x: auto; margin: 10px 0; max-width: 100%; }
table { border-collapse: collapse; font-size: 13.5px; }
th, td { border: 1px solid var(--line); padding: 3px 8px; vertical-align: top; }
th { background: var(--band); }
td.num, th.num { text-align: right; font-variant-numeric: tabular-nums; }
td img { max-width: 300px; }
figure { margin: 14px 0; max-width: 100%; overflow: hidden; break-inside: avoid; page-break-inside: avoid; }
figure img { display: block; max-width: 100%; height: auto; border: 1px solid var(--line); }
figcaption { color: var(--muted); font-size: 13.5px; margin-top: 4px; }
.gallery { display: flex; flex-wrap: wrap; gap: 14px; }
.gallery figure { flex: 1 1 460px; max-width: 100%; }
ul.files { columns: 2 340px; font-size: 13.5px; }
figure img { cursor: zoom-in; }
figure.zoom { position: fixed; inset: 0; z-index: 10; margin: 0; padding: 12px; overflow: auto;
              background: rgba(255, 255, 255, 0.97); cursor: zoom-out; }
figure.zoom img { width: 100%; max-width: none; cursor: zoom-out; }
@media (max-width: 700px) {
  header, main { padding-left: 10px; padding-right: 10px; }
  section.answer { padding: 2px 10px 6px; }
  .gallery figure { flex-basis: 100%; }
  table { font-size: 12.5px; }
  ul.files { columns: 1; }
}
@media print {
  body { font-size: 11pt; }
  header { background: none; }
  nav.contents { break-after: page; }
  section.stage { break-before: page; }
  a { color: inherit; text-decoration: none; }
  .table-wrap { overflow: visible; }
}
)";

}  // namespace

std::string page(const std::string& study_name, const std::string& lead_html,
                 const std::string& answer_html, const std::string& nav_html,
                 const std::string& body_html) {
  std::ostringstream head;
  head << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<meta name=\"viewport\" content=\"width=device-width, "
          "initial-scale=1\">\n<title>armstudy: "
       << htmlEscape(study_name) << "</title>\n<style>" << kCss
       << "</style>\n</head>\n<body>\n<header><h1>Study " << htmlEscape(study_name) << "</h1>\n"
       << lead_html << "</header>\n<main>\n";
  if (!answer_html.empty())
    head << "<section class=\"answer\" id=\"answer\">\n" << answer_html << "</section>\n";
  head << "<p class=\"method\">Details by stage below (the Markdown reports beside this file hold "
          "the same text).</p>\n";
  const std::string tail =
      "</main>\n<script>\ndocument.addEventListener('click', e => {\n"
      "  const f = e.target.closest('figure');\n  if (f) f.classList.toggle('zoom');\n});\n"
      "document.addEventListener('keydown', e => {\n"
      "  if (e.key === 'Escape') document.querySelectorAll('figure.zoom').forEach(f => "
      "f.classList.remove('zoom'));\n});\n</script>\n</body>\n</html>\n";
  std::string out = std::move(head).str();
  out.reserve(out.size() + nav_html.size() + body_html.size() + tail.size());
  out.append(nav_html).append(body_html).append(tail);
  return out;
}

}  // namespace armstudy::report::html_detail
