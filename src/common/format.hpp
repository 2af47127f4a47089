#pragma once
// The project's number formats. Every number that becomes text goes through one of these, so a
// value reads the same in every report, label, message and data file.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <system_error>

namespace armstudy {

// printf's "%.<digits>g": the short form in reports, labels, messages and names.
inline std::string formatG(double v, int digits) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

// printf's "%.<decimals>f": a fixed number of decimals (tables, coordinates, SVG, views).
inline std::string formatFixed(double v, int decimals) {
  char b[352];  // the 309 integer digits of the largest double, the sign and the decimals
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

// printf's "%.<digits>e": the limits in plausibility messages ("1e+03").
inline std::string formatScientific(double v, int digits) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*e", digits, v);
  return b;
}

// "%.17g": 17 significant digits, enough for every double to read back as itself (CSV columns,
// design files, URDF files).
inline std::string formatRoundTrip(double v) { return formatG(v, 17); }

// The shortest text that reads back as the same double (std::to_chars).
inline std::string formatShortest(double v) {
  char b[32];
  const auto [end, ec] = std::to_chars(b, b + sizeof b, v);
  return ec == std::errc() ? std::string(b, end) : formatRoundTrip(v);
}

// formatG of a finite v; `otherwise` for NaN and infinities (a table's "-", an empty CSV cell).
inline std::string formatGOr(double v, int digits, const char* otherwise) {
  return std::isfinite(v) ? formatG(v, digits) : otherwise;
}

// formatFixed of a finite v; `otherwise` for NaN and infinities (a table's "-").
inline std::string formatFixedOr(double v, int decimals, const char* otherwise) {
  return std::isfinite(v) ? formatFixed(v, decimals) : otherwise;
}

// part of whole in percent, 100 * part / whole with `decimals` decimals ("12.5 %"); "-" when whole
// is 0.
inline std::string formatShare(long part, long whole, int decimals) {
  return whole ? formatFixed(100.0 * part / whole, decimals) + " %" : "-";
}

// Two decimals without trailing zeros and without "-0" ("12.5", "3", "-0.25"): SVG coordinates.
inline std::string formatTrimmed(double v) {
  std::string t = formatFixed(std::abs(v) < 0.005 ? 0.0 : v, 2);
  while (t.back() == '0') t.pop_back();
  if (t.back() == '.') t.pop_back();
  return t;
}

// A TOML float: formatRoundTrip, with ".0" where that reads as an integer.
inline std::string formatTomlFloat(double v) {
  std::string s = formatRoundTrip(v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

// s with spaces in front up to `width` characters (printf's "%<width>s").
inline std::string padLeft(std::string s, std::size_t width) {
  if (s.size() < width) s.insert(0, width - s.size(), ' ');
  return s;
}

}  // namespace armstudy
