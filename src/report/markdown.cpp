#include "report/markdown.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <string_view>

#include "common/escape.hpp"
#include "common/format.hpp"

namespace armstudy::report {

std::string markdownTable(const std::vector<std::string>& header,
                          const std::vector<std::vector<std::string>>& rows, bool compact) {
  const auto esc = [](const std::string& s) {
    return substituteChars(s, [](char c) -> const char* {
      return c == '|' ? "\\|" : c == '\n' ? " " : nullptr;
    });
  };
  std::string out = "|", sep = "|";
  for (const std::string& h : header) {
    const bool right = !h.empty() && h[0] == '>';
    out.append(" ").append(esc(right ? h.substr(1) : h)).append(" |");
    sep.append(compact ? (right ? "---:|" : "---|") : (right ? " ---: |" : " --- |"));
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

namespace {

bool startsWithNoCase(const std::string& s, const std::string& prefix) {
  if (s.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[i])) != prefix[i]) return false;
  return true;
}

bool plainPathCharacters(const std::string& s) {
  for (const char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) &&
        std::string_view("-_.~/+=,").find(c) == std::string_view::npos)
      return false;
  return true;
}

// `path` (written in folder `dir`) relative to the output folder; "" when it is not a plain
// relative path or leaves the folder.
std::string insideOutput(const std::string& path, const std::string& dir) {
  if (path.empty() || path[0] == '/' || !plainPathCharacters(path)) return "";
  const std::filesystem::path p = (std::filesystem::path(dir) / path).lexically_normal();
  const std::string s = p.generic_string();
  if (s.empty() || p.is_absolute() || s == ".." || s.rfind("../", 0) == 0) return "";
  return s;
}

}  // namespace

std::string reportLinkTarget(const std::string& url, const std::string& dir) {
  if (startsWithNoCase(url, "http://") || startsWithNoCase(url, "https://")) {
    for (const char c : url)
      if (static_cast<unsigned char>(c) <= 0x20 || c == 0x7f || c == '\\') return "";
    return url;
  }
  const std::size_t hash = url.find('#');
  const std::string path = url.substr(0, hash),
                    fragment = hash == std::string::npos ? "" : url.substr(hash);
  if (!plainPathCharacters(fragment.empty() ? fragment : fragment.substr(1))) return "";
  if (path.empty()) return fragment;  // "#id": in the same page ("" when both are empty)
  const std::string inside = insideOutput(path, dir);
  return inside.empty() ? "" : inside + fragment;
}

std::string reportImagePath(const std::string& url, const std::string& dir) {
  return insideOutput(url, dir);
}

std::string fixed(double value, int decimals) { return formatFixedOr(value, decimals, "n/a"); }

std::string percent(double fraction, int decimals) {
  return fixed(100.0 * fraction, decimals).append(" %");
}

std::string scientific(double value, int digits) { return formatGOr(value, digits, "n/a"); }

}  // namespace armstudy::report
