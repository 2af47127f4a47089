// Status colours that red-green colour-blind readers can tell apart: every pair of status colours
// (report::categorical) and every pair of legend colours drawn together in a status map of the
// shipped stem_heatmap_panda and harvest_torque studies stays at least kMinDeltaE apart in CIELAB
// after simulating deuteranopia and protanopia with the matrices of Machado, Oliveira & Fernandes
// (2009), "A physiologically-based model for simulation of color vision deficiency", IEEE TVCG
// 15(6), severity 1.0, applied to linear sRGB. One status has one colour in every map.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <map>

#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/files.hpp"
#include "report/image.hpp"
#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

// CIE76 colour difference below which two colours of a map are taken as confusable (about 2.3 is
// just noticeable side by side; small map cells and legend swatches need far more).
constexpr double kMinDeltaE = 15;

using Matrix = std::array<std::array<double, 3>, 3>;
// Machado et al. (2009), Table 1, severity 1.0.
constexpr Matrix kDeuteranopia{{{0.367322, 0.860646, -0.227968},
                                {0.280085, 0.672501, 0.047413},
                                {-0.011820, 0.042940, 0.968881}}};
constexpr Matrix kProtanopia{{{0.152286, 1.052583, -0.204868},
                              {0.114503, 0.786281, 0.099216},
                              {-0.003882, -0.048116, 1.051998}}};

double linear(std::uint8_t c) {
  const double v = c / 255.0;
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

// CIELAB (D65) of a colour as seen with the deficiency `m`.
std::array<double, 3> seenLab(report::Rgb c, const Matrix& m) {
  const std::array<double, 3> l{linear(c.r), linear(c.g), linear(c.b)};
  std::array<double, 3> s{};
  for (int i = 0; i < 3; ++i)
    s[i] = std::clamp(m[i][0] * l[0] + m[i][1] * l[1] + m[i][2] * l[2], 0.0, 1.0);
  const double X = 0.4124 * s[0] + 0.3576 * s[1] + 0.1805 * s[2],
               Y = 0.2126 * s[0] + 0.7152 * s[1] + 0.0722 * s[2],
               Z = 0.0193 * s[0] + 0.1192 * s[1] + 0.9505 * s[2];
  const auto f = [](double t) { return t > 0.008856 ? std::cbrt(t) : 7.787 * t + 16.0 / 116; };
  const double fx = f(X / 0.95047), fy = f(Y), fz = f(Z / 1.08883);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

double seenDifference(report::Rgb a, report::Rgb b, const Matrix& m) {
  const auto p = seenLab(a, m), q = seenLab(b, m);
  return std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
}

report::Rgb fromHex(const std::string& h) {
  const auto v = std::stoul(h.substr(1), nullptr, 16);
  return {static_cast<std::uint8_t>(v >> 16), static_cast<std::uint8_t>(v >> 8),
          static_cast<std::uint8_t>(v)};
}

// The legend of a map figure: each swatch (a rect framed in #555555) and the text after it.
std::vector<std::pair<std::string, std::string>> legend(const std::string& svg) {
  std::vector<std::pair<std::string, std::string>> out;
  const std::string frame = "stroke=\"#555555\"";
  for (auto at = svg.find(frame); at != std::string::npos; at = svg.find(frame, at + 1)) {
    const auto rect = svg.rfind("<rect", at);
    const auto fill = svg.find("fill=\"", rect) + 6;
    const auto t = svg.find("<text", at);
    const auto b = svg.find('>', t) + 1;
    out.emplace_back(svg.substr(fill, 7), svg.substr(b, svg.find("</text>", b) - b));
  }
  return out;
}

}  // namespace

TEST_CASE("status colours stay apart for deuteranopes and protanopes (Machado et al. 2009)",
          "[report][oracle]") {
  // The deficiency model itself: pure red and green, far apart for normal vision, come close.
  const report::Rgb red{214, 39, 40}, green{44, 160, 44};
  CHECK(seenDifference(red, green, kDeuteranopia) < kMinDeltaE);
  for (const Matrix* m : {&kDeuteranopia, &kProtanopia})
    for (int a = 0; a < 8; ++a)
      for (int b = a + 1; b < 8; ++b) {
        INFO("categories " << a << " and " << b);
        CHECK(seenDifference(report::categorical(a), report::categorical(b), *m) >= kMinDeltaE);
      }
}

TEST_CASE(
    "the status maps of shipped studies: legend colours drawn together stay apart for "
    "deuteranopes, one colour per status in every map",
    "[report][oracle][study]") {
  // The fixtures "shipped: <study>" run the studies once per suite (tests/CMakeLists.txt).
  std::vector<fs::path> svgs;
  for (const char* study : {"stem_heatmap_panda", "harvest_torque"})
    for (const auto& e : fs::recursive_directory_iterator(test::shippedOutput(study)))
      if (e.path().extension() == ".svg") svgs.push_back(e.path());
  std::map<std::string, std::string> colour_of;  // legend label -> colour, over every map
  int maps = 0;
  bool reach_and_collision = false;
  for (const fs::path& svg : svgs) {
    const auto entries = legend(readFileOrThrow(svg.string()));
    if (entries.size() < 2) continue;
    ++maps;
    INFO(svg.string());
    bool reachable = false, collision = false;
    for (std::size_t i = 0; i < entries.size(); ++i) {
      const auto& [colour, label] = entries[i];
      reachable = reachable || label == "reachable";
      collision = collision || label.find("collision") != std::string::npos;
      if (colour_of.count(label)) CHECK(colour_of[label] == colour);
      colour_of[label] = colour;
      for (std::size_t j = i + 1; j < entries.size(); ++j) {
        INFO(label << " " << colour << " vs " << entries[j].second << " " << entries[j].first);
        CHECK(seenDifference(fromHex(colour), fromHex(entries[j].first), kDeuteranopia) >=
              kMinDeltaE);
      }
    }
    reach_and_collision = reach_and_collision || (reachable && collision);
  }
  CHECK(maps >= 3);
  CHECK(reach_and_collision);
}
