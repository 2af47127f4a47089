#pragma once
// The one XML / HTML escape (SVG figures, report.html, URDF export): & < > " as entities. Text with
// none of them (e.g. a figure's base64 data) is returned as it is, without a character-by-character
// copy (report.html inlines tens of MB of figures: docs/performance.md, "The serial rest").
#include <cstring>
#include <string>

namespace armstudy {

inline std::string xmlEscape(const std::string& s) {
  const auto has = [&](char c) { return std::memchr(s.data(), c, s.size()) != nullptr; };
  if (!has('&') && !has('<') && !has('>') && !has('"')) return s;
  std::string o;
  o.reserve(s.size() + s.size() / 8);
  for (const char c : s) {
    if (c == '&')
      o += "&amp;";
    else if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '"')
      o += "&quot;";
    else
      o += c;
  }
  return o;
}

}  // namespace armstudy
