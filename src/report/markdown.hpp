#pragma once
// Markdown helpers for human reports: tables, number formatting, and the links and images kept
// in report.html.
#include <string>
#include <vector>

namespace armstudy::report {

// A GitHub-flavoured markdown table. Cells containing '|' are escaped. Columns whose header
// starts with '>' are right-aligned (the '>' is dropped). The separator row is "| --- |", or
// "|---|" when `compact`.
std::string markdownTable(const std::vector<std::string>& header,
                          const std::vector<std::vector<std::string>>& rows, bool compact = false);

// The links and images report.html keeps of Markdown text, which may hold user text (a study's
// description, joint names, a reference's source). A link or image is written in a Markdown file
// of folder `dir` (relative to the output folder, "" for the folder itself); report.html sits in
// the output folder.
//
// reportLinkTarget: the href for a link, "" when it is refused (shown as its text): an http(s) URL
// as written (no whitespace, control characters or backslashes); "#fragment" as written; a
// relative path that stays inside the output folder, rewritten relative to it (its #fragment
// kept). Anything else is refused: other schemes (javascript:, data:, file:, ...), absolute paths,
// paths leaving the folder through "..", and characters other than letters, digits and "-_.~/+=,".
std::string reportLinkTarget(const std::string& url, const std::string& dir);
// reportImagePath: the image's path relative to the output folder, "" when refused: only relative
// paths of those characters that stay inside the output folder (no scheme, http included:
// report.html fetches nothing). Symbolic links are the caller's to check (html_report.cpp).
std::string reportImagePath(const std::string& url, const std::string& dir);

std::string fixed(double value, int decimals);           // "0.125"
std::string percent(double fraction, int decimals = 1);  // 0.5 -> "50.0 %"
std::string scientific(double value, int digits = 3);

}  // namespace armstudy::report
