// The harvest report's fruit figure (harvest/fruits.svg of the shipped harvest_torque study): every
// fruit of every design appears at its position with the outcome the same run's <design>_fruits.csv
// gives it (picked, the drive check that failed first, or the status that stopped it), one colour
// per outcome named in the legend, the designs' panels on one scale, no text overlapping; the
// report shows the figure ahead of the designs' tables.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/files.hpp"
#include "plot_checks.hpp"
#include "shipped_output.hpp"
#include "stages/harvest/harvest_report.hpp"
#include "test_support.hpp"
#include "trajectory/greenhouse_row.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

constexpr double kPixelTolerance = 0.02;  // [px] the SVG writes positions to 0.01 px

// A fruit as the fruits CSV gives it: position and outcome (the CSV's own columns).
struct CsvFruit {
  double y = 0, z = 0;
  std::string outcome;
};

std::vector<CsvFruit> csvFruits(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> head;
  {
    std::istringstream h(line);
    for (std::string c; std::getline(h, c, ',');) head.push_back(c);
  }
  const auto col = [&](const std::string& name) {
    const auto at = std::find(head.begin(), head.end(), name);
    REQUIRE(at != head.end());
    return static_cast<std::size_t>(at - head.begin());
  };
  const std::size_t y = col("y_m"), z = col("z_m"), status = col("status"),
                    feasible = col("feasible"), joint = col("failing_joint"),
                    quantity = col("failing_quantity");
  std::vector<CsvFruit> out;
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::istringstream r(line);
    for (std::string cell; std::getline(r, cell, ',');) c.push_back(cell);
    c.resize(head.size());
    CsvFruit f{std::stod(c[y]), std::stod(c[z]), ""};
    // The legend names a status or a quantity in words: "rms_current" reads "rms current".
    const auto words = [](std::string w) {
      std::replace(w.begin(), w.end(), '_', ' ');
      return w;
    };
    if (c[status] != "ok" && c[quantity] == "joint_limit")
      f.outcome = "joint limit: " + c[joint];
    else if (c[status] != "ok")
      f.outcome = "not tracked: " + words(c[status]);
    else if (c[feasible] == "1")
      f.outcome = "picked";
    else
      f.outcome = "drive limit: " + c[joint] + " " + words(c[quantity]);
    out.push_back(f);
  }
  return out;
}

double attr(const std::string& s, std::size_t from, const std::string& name) {
  const auto a = s.find(" " + name + "=\"", from) + name.size() + 3;
  return std::stod(s.substr(a, s.find('"', a) - a));
}

struct Dot {
  std::string colour;
  double cx = 0, cy = 0;
  bool legend = false;  // the legend's sample (r = 3; data dots r = 2.6)
};

// The dots of the SVG, with the colour of their group, in drawing order.
std::vector<Dot> dots(const std::string& svg) {
  std::vector<Dot> out;
  for (auto g = svg.find("<g fill=\""); g != std::string::npos; g = svg.find("<g fill=\"", g + 1)) {
    const std::string colour = svg.substr(g + 9, 7);
    const auto end = svg.find("</g>", g);
    for (auto c = svg.find("<circle", g); c < end; c = svg.find("<circle", c + 1))
      out.push_back({colour, attr(svg, c, "cx"), attr(svg, c, "cy"), attr(svg, c, "r") == 3});
  }
  return out;
}

// The legend: the text drawn right after each legend sample, by the sample's colour and panel.
struct LegendEntry {
  std::string colour, label;
  double y = 0;
};
std::vector<LegendEntry> legend(const std::string& svg) {
  std::vector<LegendEntry> out;
  for (auto g = svg.find("<g fill=\""); g != std::string::npos; g = svg.find("<g fill=\"", g + 1)) {
    const auto end = svg.find("</g>", g);
    const auto c = svg.find("<circle", g);
    if (c > end || attr(svg, c, "r") != 3) continue;
    const auto t = svg.find("<text", end);
    const auto b = svg.find('>', t) + 1;
    out.push_back(
        {svg.substr(g + 9, 7), svg.substr(b, svg.find("</text>", b) - b), attr(svg, c, "cy")});
  }
  return out;
}

// The y of each panel title (the design's name) in the SVG.
double textY(const std::string& svg, const std::string& text) {
  const auto at = svg.find(">" + text + "</text>");
  REQUIRE(at != std::string::npos);
  return attr(svg, svg.rfind("<text", at), "y");
}

// Least-squares line v = a + b u.
std::pair<double, double> fitLine(const std::vector<double>& u, const std::vector<double>& v) {
  const double n = static_cast<double>(u.size());
  double su = 0, sv = 0, suu = 0, suv = 0;
  for (std::size_t i = 0; i < u.size(); ++i)
    su += u[i], sv += v[i], suu += u[i] * u[i], suv += u[i] * v[i];
  const double b = (n * suv - su * sv) / (n * suu - su * su);
  return {(sv - b * su) / n, b};
}

}  // namespace

TEST_CASE(
    "harvest fruit figure: every fruit at its position with the outcome its CSV gives, one "
    "colour per outcome, the designs on one scale, no text overlapping",
    "[harvest][report]") {
  const fs::path out = test::shippedOutput("harvest_torque") / "harvest";
  const Study s = loadStudy(test::sourcePath("studies/harvest_torque.toml"));  // its settings
  REQUIRE(fs::exists(out / "fruits.svg"));
  const std::string svg = readFileOrThrow((out / "fruits.svg").string());

  // The figure as laid out (its text boxes) is the file the run wrote.
  const auto& opts = *stageSettings<harvest::HarvestOptions>(s, "harvest");
  std::vector<harvest::DesignResult> results;
  std::vector<const Model*> models;
  for (const StudyDesign& d : s.designs) {
    models.push_back(&d.model);
    results.push_back(
        harvest::evaluateHarvestDesign(d.model, opts, sampleGreenhouseRow(opts.row), 2));
  }
  std::vector<const harvest::DesignResult*> ptrs;
  for (const auto& r : results) ptrs.push_back(&r);
  const report::Drawing drawing = harvest::fruitOutcomeFigure(models, ptrs);
  CHECK(drawing.svg == svg);
  INFO(test::layoutFault(drawing));
  CHECK(test::layoutFault(drawing).empty());

  // Panels top to bottom in design order; each dot belongs to the panel above it.
  std::vector<double> panel_y;
  for (const Model* m : models) panel_y.push_back(textY(svg, m->name));
  REQUIRE(std::is_sorted(panel_y.begin(), panel_y.end()));
  panel_y.push_back(1e9);
  const auto entries = legend(svg);
  const auto all = dots(svg);
  std::set<std::string> failures_seen;
  std::vector<double> z_slopes;
  for (std::size_t k = 0; k < models.size(); ++k) {
    INFO(models[k]->name);
    const auto fruits =
        csvFruits(readFileOrThrow((out / (models[k]->name + "_fruits.csv")).string()));
    // The panel's legend: colour -> outcome, one colour per outcome.
    std::map<std::string, std::string> label;
    for (const auto& e : entries)
      if (e.y > panel_y[k] && e.y < panel_y[k + 1]) {
        CHECK(!label.count(e.colour));
        label[e.colour] = e.label;
      }
    // Per outcome, the fruits of the CSV and the dots of that colour, each sorted along the row.
    std::map<std::string, std::vector<CsvFruit>> want;
    for (const auto& f : fruits) want[f.outcome].push_back(f);
    std::map<std::string, std::vector<Dot>> got;
    for (const auto& d : all)
      if (!d.legend && d.cy > panel_y[k] && d.cy < panel_y[k + 1]) {
        REQUIRE(label.count(d.colour));
        got[label[d.colour]].push_back(d);
      }
    REQUIRE(got.size() == want.size());
    std::vector<double> y, z, cx, cy;
    for (auto& [outcome, fs_] : want) {
      INFO(outcome);
      REQUIRE(got.count(outcome));
      auto& ds = got[outcome];
      REQUIRE(ds.size() == fs_.size());
      std::sort(fs_.begin(), fs_.end(),
                [](const CsvFruit& a, const CsvFruit& b) { return a.y < b.y; });
      std::sort(ds.begin(), ds.end(), [](const Dot& a, const Dot& b) { return a.cx < b.cx; });
      for (std::size_t i = 0; i < ds.size(); ++i) {
        y.push_back(fs_[i].y), z.push_back(fs_[i].z);
        cx.push_back(ds[i].cx), cy.push_back(ds[i].cy);
      }
      if (outcome != "picked") failures_seen.insert(outcome);
    }
    // Every dot where one linear map per axis puts its fruit.
    const auto [ax, bx] = fitLine(y, cx);
    const auto [az, bz] = fitLine(z, cy);
    CHECK(bx > 0);
    CHECK(bz < 0);  // z up
    for (std::size_t i = 0; i < y.size(); ++i) {
      CHECK(std::abs(ax + bx * y[i] - cx[i]) < kPixelTolerance);
      CHECK(std::abs(az + bz * z[i] - cy[i]) < kPixelTolerance);
    }
    z_slopes.push_back(bz);
  }
  // The same height scale in every panel, and the shipped row has fruits that fail.
  for (double b : z_slopes) CHECK(b == Approx(z_slopes.front()).epsilon(1e-4));
  CHECK(!failures_seen.empty());
  // The report shows the figure before the first design's section.
  const std::string md = readFileOrThrow((out / "report.md").string());
  const auto fig = md.find("(fruits.svg)");
  REQUIRE(fig != std::string::npos);
  CHECK(fig < md.find("\n## "));
}
