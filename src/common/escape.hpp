#pragma once
// The one XML / HTML escape (SVG figures, report.html, URDF export): & < > " as entities. Text with
// none of them (e.g. a figure's base64 data) is returned as it is, without a character-by-character
// copy (report.html inlines tens of MB of figures: docs/performance.md, "The serial rest").
#include <cstring>
#include <string>

namespace armstudy {

// `s` with every character c for which `sub(c)` gives a text replaced by that text.
template <class Sub>
std::string substituteChars(const std::string& s, Sub sub) {
  std::string o;
  o.reserve(s.size() + s.size() / 8);
  for (const char c : s) {
    if (const char* r = sub(c))
      o += r;
    else
      o += c;
  }
  return o;
}

inline std::string xmlEscape(const std::string& s) {
  const auto has = [&](char c) { return std::memchr(s.data(), c, s.size()) != nullptr; };
  if (!has('&') && !has('<') && !has('>') && !has('"')) return s;
  return substituteChars(s, [](char c) -> const char* {
    switch (c) {
      case '&':
        return "&amp;";
      case '<':
        return "&lt;";
      case '>':
        return "&gt;";
      case '"':
        return "&quot;";
      default:
        return nullptr;
    }
  });
}

}  // namespace armstudy
