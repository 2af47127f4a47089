// The exploration's figures (stages/explore/explore_plots.hpp) on candidates like the shipped
// exploration's: no text overlaps or leaves the canvas, every axis has its name and unit, each
// objective says which way is better (and a minimised one grows downwards in the parallel
// coordinates), ticks spread over the data, a legend names the front, the other designs and the
// base design, and the canvas ends where its content does.
#include "stages/explore/explore_plots.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "io/design_io.hpp"
#include "plot_checks.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;

namespace {

constexpr int kMinTicks = 3;             // per axis, inside the data's spread
constexpr double kTickRangeShare = 0.1;  // ticks within the data range widened by this share
constexpr double kFitMargin_px = 30;     // text reaches this close to the canvas' right and bottom
constexpr double kTickGap_px = 12;       // a tick label's right edge within this left of its axis

struct Axis {
  std::string label;  // as drawn: name and unit
  double lo, hi;      // the candidates' values
};

// 41 candidates over four lengths and the shipped exploration's four objectives (values in their
// ranges); the base design (index 0) has no parameter values, one candidate breaks a constraint.
struct Fixture {
  explore::ExploreOptions o;
  std::vector<explore::Candidate> c;
  std::vector<std::size_t> front;
  std::vector<Axis> axes;
  Fixture() {
    o.base = loadDesign(sourcePath("designs/final_prototype_7dof.toml"));
    const std::vector<std::pair<std::string, std::array<double, 2>>> params = {
        {"joint.j4.x", {0.30, 0.45}},
        {"joint.j7.x", {0.30, 0.425}},
        {"joint.j2.y", {0.40, 0.55}},
        {"joint.j1.z", {0.70, 0.90}}};
    for (const auto& [key, r] : params) {
      explore::Parameter p;
      p.key = key;
      p.lo = r[0], p.hi = r[1];
      o.parameters.push_back(p);
      axes.push_back({key + " [m]", r[0], r[1]});
    }
    auto objective = [&](std::string label, std::string unit, explore::Goal g, double lo, double hi,
                         std::string drawn) {
      explore::Objective ob;
      ob.label = std::move(label);
      ob.unit = std::move(unit);
      ob.goal = g;
      o.objectives.push_back(ob);
      axes.push_back({std::move(drawn), lo, hi});
    };
    objective("stem map coverage", "1", explore::Goal::Maximise, 0.9389, 1,
              "stem map coverage [1]");
    objective("fruits feasible", "1", explore::Goal::Maximise, 0.125, 0.75, "fruits feasible [1]");
    objective("link length [m]", "m", explore::Goal::Minimise, 1.559, 1.758, "link length [m]");
    objective("stem map manipulability", "m^3", explore::Goal::Maximise, 0.2214, 0.3124,
              "stem map manipulability [m^3]");
    const std::size_t n = 41, np = o.parameters.size();
    for (std::size_t i = 0; i < n; ++i) {
      explore::Candidate k;
      k.name = "candidate " + std::to_string(i);
      for (std::size_t a = 0; a < axes.size(); ++a) {
        // Spread over [lo, hi] in a different order per axis; candidate 1 at every low end,
        // candidate 2 at every high end.
        const double t = i == 1 ? 0 : i == 2 ? 1 : std::fmod(0.37 * i * (a + 1) + 0.11 * a, 1.0);
        const double v = axes[a].lo + t * (axes[a].hi - axes[a].lo);
        if (a < np && i > 0) k.params.push_back(v);
        if (a >= np) k.values.push_back(v);
      }
      k.feasible = i != 5;
      c.push_back(k);
      if (i % 4 == 3) front.push_back(i);
    }
  }
};

bool isNumber(const std::string& s, double& v) {
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size();
}

// All texts in drawing order, joined by spaces (wrapped lines read as one).
std::string allText(const report::Drawing& d) {
  std::string t;
  for (const auto& b : d.texts) t += b.text + " ";
  return t;
}

int countText(const report::Drawing& d, const std::string& s) {
  int n = 0;
  for (const auto& b : d.texts) n += b.text == s;
  return n;
}

// The canvas ends where the text does (no large empty margin at the right or the bottom).
bool fitsContent(const report::Drawing& d) {
  double right = 0, bottom = 0;
  for (const auto& b : d.texts) right = std::max(right, b.x1), bottom = std::max(bottom, b.y1);
  return right > d.width - kFitMargin_px && bottom > d.height - kFitMargin_px;
}

bool insideSpread(double v, const Axis& a) {
  const double pad = kTickRangeShare * (a.hi - a.lo);
  return v >= a.lo - pad && v <= a.hi + pad;
}

}  // namespace

TEST_CASE("the Pareto scatter: no text overlaps, units, better directions, ticks over the data",
          "[explore][report]") {
  const Fixture f;
  const report::Drawing d = explore::frontScatterFigure(f.c, f.front, 0, f.o, 0, 1);
  INFO(allText(d));
  INFO(layoutFault(d));
  CHECK(layoutFault(d).empty());
  CHECK(fitsContent(d));
  const std::string all = allText(d);
  CHECK(all.find("stem map coverage [1] (higher is better)") != std::string::npos);
  CHECK(all.find("fruits feasible [1] (higher is better)") != std::string::npos);
  for (const char* entry : {"Pareto front", "other designs", "base design"})
    CHECK(countText(d, entry) == 1);
  CHECK(countText(d, "designs breaking a constraint") == 1);
  // Tick labels: at least kMinTicks on each axis, every one inside the data's spread. The two
  // objectives' ranges are disjoint, so a tick's value tells its axis.
  const Axis &ax = f.axes[4], &ay = f.axes[5];
  int nx = 0, ny = 0;
  for (const auto& b : d.texts) {
    double v;
    if (!isNumber(b.text, v)) continue;
    INFO("tick " << b.text);
    CHECK((insideSpread(v, ax) || insideSpread(v, ay)));
    nx += insideSpread(v, ax);
    ny += insideSpread(v, ay);
  }
  CHECK(nx >= kMinTicks);
  CHECK(ny >= kMinTicks);
}

TEST_CASE(
    "the parallel coordinates: no text overlaps, units, objectives turned so that better is up, "
    "ticks over each axis' data",
    "[explore][report]") {
  const Fixture f;
  const report::Drawing d = explore::parallelFigure(f.c, f.front, 0, f.o);
  INFO(allText(d));
  INFO(layoutFault(d));
  CHECK(layoutFault(d).empty());
  CHECK(fitsContent(d));
  const std::string all = allText(d);
  for (const Axis& a : f.axes) CHECK(all.find(a.label) != std::string::npos);
  CHECK(countText(d, report::kBetterMark) == static_cast<int>(f.o.objectives.size()));
  for (const char* entry : {"Pareto front", "other designs", "base design"})
    CHECK(countText(d, entry) == 1);
  // Each axis' x from the first line of its name (centred on it; the names are drawn in axis
  // order); its tick labels end just left of it. Ticks: at least kMinTicks, inside the data's
  // spread, growing upwards (or downwards for the minimised link length).
  std::size_t next = 0;  // index in d.texts after the previous axis' name
  for (std::size_t a = 0; a < f.axes.size(); ++a) {
    const Axis& axis = f.axes[a];
    INFO(axis.label);
    const report::TextBox* name = nullptr;
    for (; next < d.texts.size() && !name; ++next)
      if (d.texts[next].text.size() >= 4 && axis.label.rfind(d.texts[next].text, 0) == 0)
        name = &d.texts[next];
    REQUIRE(name);
    const double x = (name->x0 + name->x1) / 2;
    INFO("name '" << name->text << "' centred at x = " << x);
    std::map<double, double> y_of;  // tick value -> its label's centre y
    for (const auto& b : d.texts) {
      double v;
      if (isNumber(b.text, v) && b.x1 <= x && b.x1 > x - kTickGap_px) y_of[v] = (b.y0 + b.y1) / 2;
    }
    CHECK(y_of.size() >= static_cast<std::size_t>(kMinTicks));
    const bool down = f.o.parameters.size() <= a &&
                      f.o.objectives[a - f.o.parameters.size()].goal == explore::Goal::Minimise;
    double prev_y = NAN;
    for (const auto& [v, y] : y_of) {
      INFO("tick " << v);
      CHECK(insideSpread(v, axis));
      if (std::isfinite(prev_y)) CHECK((down ? y > prev_y : y < prev_y));
      prev_y = y;
    }
  }
}
