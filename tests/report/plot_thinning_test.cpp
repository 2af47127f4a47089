// Dense figures are drawn thinned: a line of many points keeps its extremes (checked against
// reference lines drawn at the data's own minimum and maximum), a figure of many markers draws
// them as an image, and both say so under the figure.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "report/plot.hpp"

using namespace armstudy::report;

namespace {

// The points of every <polyline> of the SVG, per polyline.
std::vector<std::vector<std::pair<double, double>>> polylines(const std::string& svg) {
  std::vector<std::vector<std::pair<double, double>>> out;
  for (std::size_t at = svg.find("<polyline"); at != std::string::npos;
       at = svg.find("<polyline", at + 1)) {
    const std::size_t a = svg.find("points=\"", at) + 8, b = svg.find('"', a);
    std::istringstream in(svg.substr(a, b - a));
    std::vector<std::pair<double, double>> pts;
    double x, y;
    char comma;
    while (in >> x >> comma >> y) pts.emplace_back(x, y);
    out.push_back(pts);
  }
  return out;
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("plot thinning: a line of 20000 points keeps its peaks and says it was thinned",
          "[report][plot]") {
  PlotSpec spec;
  spec.title = "dense line";
  spec.x_label = "t [s]";
  PlotPanel pan;
  pan.y_label = "y [1]";
  PlotSeries se;
  se.colour = Rgb{200, 0, 0};
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double t = i / double(n);
    se.x.push_back(t);
    se.y.push_back(std::sin(40 * t) + (i == 12345 ? 5.0 : 0.0) - (i == 777 ? 3.0 : 0.0));
  }
  const double hi = *std::max_element(se.y.begin(), se.y.end());
  const double lo = *std::min_element(se.y.begin(), se.y.end());
  pan.series.push_back(se);
  pan.lines.push_back(RefLine{hi, "", true, Rgb{1, 2, 3}});
  pan.lines.push_back(RefLine{lo, "", true, Rgb{1, 2, 3}});
  spec.panels.push_back(pan);
  const Drawing d = plot(spec);
  const auto lines = polylines(d.svg);
  // The series is the longest polyline; the two reference lines are horizontal at y(lo), y(hi).
  const auto series = *std::max_element(
      lines.begin(), lines.end(), [](const auto& a, const auto& b) { return a.size() < b.size(); });
  std::vector<double> ref_y;
  for (const auto& l : lines)
    if (l.size() == 2 && l[0].second == l[1].second && &l != &series) ref_y.push_back(l[0].second);
  REQUIRE(ref_y.size() >= 2);
  double top = 1e9, bottom = -1e9;
  for (const auto& p : series) top = std::min(top, p.second), bottom = std::max(bottom, p.second);
  INFO("drawn points " << series.size());
  CHECK(series.size() <= 4 * static_cast<std::size_t>(d.width));
  CHECK(series.size() < static_cast<std::size_t>(n) / 4);
  // Peaks stay: the drawn line reaches the reference lines at the data's maximum and minimum.
  CHECK(
      std::any_of(ref_y.begin(), ref_y.end(), [&](double y) { return std::abs(y - top) < 0.01; }));
  CHECK(std::any_of(ref_y.begin(), ref_y.end(),
                    [&](double y) { return std::abs(y - bottom) < 0.01; }));
  CHECK(d.svg.find("Drawn thinned") != std::string::npos);
}

TEST_CASE("plot thinning: a figure of 3000 markers draws them as an image and 300 stay vector",
          "[report][plot]") {
  for (const int n : {300, 3000}) {
    PlotSpec spec;
    spec.title = "cloud";
    spec.x_label = "x [m]";
    PlotPanel pan;
    pan.y_label = "y [m]";
    PlotSeries se;
    se.lines = false;
    se.markers = true;
    for (int i = 0; i < n; ++i) {
      se.x.push_back(std::fmod(i * 0.618034, 1.0));
      se.y.push_back(std::fmod(i * 0.414214, 1.0));
    }
    pan.series.push_back(se);
    spec.panels.push_back(pan);
    const Drawing d = plot(spec);
    INFO(n << " markers");
    if (n > static_cast<int>(kThinAbove)) {
      CHECK(count(d.svg, "<circle") == 0);
      CHECK(count(d.svg, "<image") == 1);
      CHECK(d.svg.find("Drawn thinned") != std::string::npos);
    } else {
      CHECK(count(d.svg, "<circle") == static_cast<std::size_t>(n));
      CHECK(d.svg.find("Drawn thinned") == std::string::npos);
    }
  }
}
