#pragma once
// The project's number formats. Every number that becomes text goes through one of these, so a
// value reads the same in every report, label, message and data file.
#include <charconv>
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

// s with spaces in front up to `width` characters (printf's "%<width>s").
inline std::string padLeft(std::string s, std::size_t width) {
  if (s.size() < width) s.insert(0, width - s.size(), ' ');
  return s;
}

}  // namespace armstudy
