#pragma once
// Private to report.html (report/html_report.cpp): the page around a report's parts, with its
// style sheet and the script that enlarges a figure on a click.
#include <string>

namespace armstudy::report::html_detail {

// The page around the contents (`nav_html`) and the stages (`body_html`): head, style, the study's
// description and question (`lead_html`), the answer block, and the script that enlarges a figure
// on a click (another click or Escape puts it back).
std::string page(const std::string& study_name, const std::string& lead_html,
                 const std::string& answer_html, const std::string& nav_html,
                 const std::string& body_html);

}  // namespace armstudy::report::html_detail
