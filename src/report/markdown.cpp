#include "report/markdown.hpp"

#include <cmath>
#include <cstdio>

namespace armstudy::report {

std::string markdownTable(const std::vector<std::string>& header,
                          const std::vector<std::vector<std::string>>& rows) {
  auto esc = [](const std::string& s) {
    std::string o;
    for (char c : s) {
      if (c == '|')
        o += "\\|";
      else if (c == '\n')
        o += ' ';
      else
        o += c;
    }
    return o;
  };
  std::string out = "|", sep = "|";
  for (const std::string& h : header) {
    const bool right = !h.empty() && h[0] == '>';
    out.append(" ").append(esc(right ? h.substr(1) : h)).append(" |");
    sep.append(right ? " ---: |" : " --- |");
  }
  out.append("\n").append(sep).append("\n");
  for (const auto& r : rows) {
    out += "|";
    for (std::size_t c = 0; c < header.size(); ++c)
      out.append(" ").append(c < r.size() ? esc(r[c]) : std::string()).append(" |");
    out.append("\n");
  }
  return out;
}

std::string fixed(double value, int decimals) {
  if (!std::isfinite(value)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  return buf;
}

std::string percent(double fraction, int decimals) {
  return fixed(100.0 * fraction, decimals).append(" %");
}

std::string scientific(double value, int digits) {
  if (!std::isfinite(value)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, value);
  return buf;
}

}  // namespace armstudy::report
