#pragma once
// A written SVG figure read back as a reader's browser gets it: its <text> elements with their
// anchor positions, its first <image>, and a map figure's colour bar. Independent of the writer
// (report/plot.cpp): regular expressions over the file's text.
#include <map>
#include <regex>
#include <string>
#include <vector>

namespace armstudy::test {

struct SvgText {
  double x = 0, y = 0;  // [px] the element's x and y attributes
  std::string s;        // its text
};

struct SvgImage {
  double x = 0, y = 0, w = 0, h = 0;  // [px]
};

// Every <text> element, in file order.
inline std::vector<SvgText> svgTexts(const std::string& svg) {
  static const std::regex text(R"re(<text x="([-0-9.]+)" y="([-0-9.]+)"[^>]*>([^<]*)</text>)re");
  std::vector<SvgText> out;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), text); it != std::sregex_iterator();
       ++it)
    out.push_back({std::stod((*it)[1]), std::stod((*it)[2]), (*it)[3]});
  return out;
}

// A text that is one number ("0.6", "-12", "1.5e-05").
inline bool isSvgNumber(const std::string& s) {
  static const std::regex number(R"([-+]?[0-9.]+(e[-+]?[0-9]+)?)");
  return std::regex_match(s, number);
}

// The first <image> element; false when there is none.
inline bool firstSvgImage(const std::string& svg, SvgImage& im) {
  static const std::regex image(
      R"re(<image x="([-0-9.]+)" y="([-0-9.]+)" width="([-0-9.]+)" height="([-0-9.]+)")re");
  std::smatch m;
  if (!std::regex_search(svg, m, image)) return false;
  im = {std::stod(m[1]), std::stod(m[2]), std::stod(m[3]), std::stod(m[4])};
  return true;
}

// The colour bar of a map figure: its tick labels (the numeric labels that share the largest left
// x of the figure; the bar's labels stand left-aligned right of it) and its label (the text that
// starts with label_start; empty when label_start is empty or no text starts with it).
struct ColourBar {
  std::vector<std::string> ticks;
  std::string label;
};

inline ColourBar colourBar(const std::string& svg, const std::string& label_start = "") {
  std::map<double, std::vector<std::string>> numeric_at_x;
  ColourBar bar;
  for (const SvgText& t : svgTexts(svg)) {
    if (isSvgNumber(t.s)) numeric_at_x[t.x].push_back(t.s);
    if (!label_start.empty() && t.s.rfind(label_start, 0) == 0) bar.label = t.s;
  }
  for (auto it = numeric_at_x.rbegin(); it != numeric_at_x.rend(); ++it)
    if (it->second.size() >= 2) {
      bar.ticks = it->second;
      break;
    }
  return bar;
}

}  // namespace armstudy::test
