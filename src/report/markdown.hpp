#pragma once
// Markdown helpers for human reports: tables and number formatting.
#include <string>
#include <vector>

namespace armstudy::report {

// A GitHub-flavoured markdown table. Cells containing '|' are escaped. Columns whose header
// starts with '>' are right-aligned (the '>' is dropped).
std::string markdownTable(const std::vector<std::string>& header,
                          const std::vector<std::vector<std::string>>& rows);

std::string fixed(double value, int decimals);           // "0.125"
std::string percent(double fraction, int decimals = 1);  // 0.5 -> "50.0 %"
std::string scientific(double value, int digits = 3);

}  // namespace armstudy::report
