// The figures of the shipped arm calibration study say what a reviewer checks, read from the files
// the study writes: the TCP residuals at their own scale (millimetres), before and after the fit in
// one figure on one range and in that order; the residual-versus-joint figures in millimetres, the
// before and after figure of a joint on the same ticks; the calibrated copy's check run titled for
// the design it shows; each "before" figure ahead of its "after" figure on the report pages. The
// residual sizes come from the same run's result.json and residuals.csv.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/files.hpp"
#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

// The ticks of a residual axis lie inside the range the figure draws (the largest residual, 6 %
// padded); nice 1-2-5 ticks reach at least this fraction of it.
constexpr double kTickReach = 0.3;
constexpr double kRangePad = 1.06;
constexpr double kTitleSize = 15, kPanelTitleSize = 13, kTickSize = 11;  // report/plot_layout.hpp

struct SvgText {
  std::string text;
  double x = 0, y = 0, size = 0;
  bool upward = false;
};

std::vector<SvgText> svgTexts(const std::string& svg) {
  static const std::regex re(
      R"re(<text x="([-0-9.]+)" y="([-0-9.]+)" font-size="([0-9.]+)"( transform="translate\(([-0-9.]+),([-0-9.]+)\) rotate\(-90\)")?[^>]*>([^<]*)</text>)re");
  std::vector<SvgText> out;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator();
       ++it) {
    const auto& m = *it;
    SvgText t;
    t.upward = m[4].matched;
    t.x = std::stod(m[t.upward ? 5 : 1].str());
    t.y = std::stod(m[t.upward ? 6 : 2].str());
    t.size = std::stod(m[3].str());
    t.text = m[7].str();
    out.push_back(t);
  }
  return out;
}

std::string title(const std::vector<SvgText>& texts) {
  std::string t;
  for (const SvgText& s : texts)
    if (s.size == kTitleSize) t += (t.empty() ? "" : " ") + s.text;
  return t;
}

// The panel titles (upright label-size text starting with the model's name), top to bottom.
std::vector<SvgText> panelTitles(const std::vector<SvgText>& texts) {
  std::vector<SvgText> p;
  for (const SvgText& s : texts)
    if (s.size == kPanelTitleSize && !s.upward &&
        (s.text.rfind("before:", 0) == 0 || s.text.rfind("after:", 0) == 0 ||
         s.text.rfind("calibrated design", 0) == 0))
      p.push_back(s);
  std::sort(p.begin(), p.end(), [](const SvgText& a, const SvgText& b) { return a.y < b.y; });
  return p;
}

// The y tick labels between y0 and y1: tick-size numbers alone on their baseline (the x tick
// labels of a panel share one baseline).
std::vector<double> yTicks(const std::vector<SvgText>& texts, double y0, double y1) {
  std::map<double, int> per_row;
  for (const SvgText& s : texts)
    if (s.size == kTickSize) ++per_row[s.y];
  std::vector<double> v;
  for (const SvgText& s : texts)
    if (s.size == kTickSize && per_row[s.y] == 1 && s.y > y0 && s.y < y1)
      v.push_back(std::stod(s.text));
  std::sort(v.begin(), v.end());
  return v;
}

bool hasText(const std::vector<SvgText>& texts, const std::string& t) {
  return std::any_of(texts.begin(), texts.end(), [&](const SvgText& s) { return s.text == t; });
}

// The largest |residual| of a channel after the fit [mm], from residuals.csv.
double afterMaxMm(const fs::path& entry, const std::string& channel) {
  std::istringstream in(readFileOrThrow((entry / "residuals.csv").string()));
  std::string line, cell;
  std::getline(in, line);
  std::istringstream header(line);
  int col = -1;
  for (int k = 0; std::getline(header, cell, ','); ++k)
    if (cell == "residual_" + channel) col = k;
  REQUIRE(col >= 0);
  double a = 0;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    for (int k = 0; std::getline(row, cell, ','); ++k)
      if (k == col) a = std::max(a, std::abs(std::stod(cell)));
  }
  return 1e3 * a;
}

// The images of a page in page order: the text between `open` and `close` after each `start`
// (a plain search: the HTML page's data URIs are too long for std::regex).
std::vector<std::string> images(const std::string& text, const std::string& start,
                                const std::string& open, const std::string& close) {
  std::vector<std::string> out;
  for (auto at = text.find(start); at != std::string::npos; at = text.find(start, at + 1)) {
    const auto b = text.find(open, at);
    const auto e = b == std::string::npos ? b : text.find(close, b + open.size());
    if (e == std::string::npos) break;
    out.push_back(text.substr(b + open.size(), e - b - open.size()));
  }
  return out;
}

// Every "before_<x>" figure of a folder comes ahead of its "after_<x>" figure, and the figures of a
// calibrated copy's check run come after the entry's own; returns the pairs shown.
int checkOrder(const std::vector<std::string>& figures, const std::string& entry) {
  std::map<std::string, std::size_t> at;
  std::size_t last_own = 0, first_check = figures.size();
  bool any = false;
  for (std::size_t i = 0; i < figures.size(); ++i) {
    const std::string& f = figures[i];
    if (f.find(entry + "/") == std::string::npos) continue;
    any = true;
    at[f] = i;
    if (f.find("/calibrated/") != std::string::npos)
      first_check = std::min(first_check, i);
    else
      last_own = std::max(last_own, i);
  }
  REQUIRE(any);
  CHECK(last_own < first_check);
  int pairs = 0;
  for (const auto& [f, i] : at) {
    const auto p = f.find("/after_");
    if (p == std::string::npos) continue;
    const std::string before = f.substr(0, p) + "/before_" + f.substr(p + 7);
    INFO(f);
    REQUIRE(at.count(before));
    CHECK(at.at(before) < i);
    ++pairs;
  }
  return pairs;
}

}  // namespace

TEST_CASE(
    "arm calibration figures: TCP residuals in mm, before and after on one range in order, the "
    "check run titled for the calibrated design, before ahead of after on the pages",
    "[calibration][study][report]") {
  const fs::path out = test::shippedOutput("arm_calibration"), tcp = out / "calibration/tcp";
  const nlohmann::json result =
      nlohmann::json::parse(readFileOrThrow((tcp / "result.json").string()));

  for (const std::string c : {"x", "y", "z"}) {
    INFO("channel " << c);
    const fs::path f = tcp / "plots" / ("residual_vs_predicted_" + c + ".svg");
    REQUIRE(fs::exists(f));
    const auto texts = svgTexts(readFileOrThrow(f.string()));
    const auto panels = panelTitles(texts);
    REQUIRE(panels.size() == 2);
    CHECK(panels[0].text == "before: as designed");
    CHECK(panels[1].text.rfind("after: calibrated", 0) == 0);
    CHECK(hasText(texts, "measured - predicted [mm]"));
    const auto before = yTicks(texts, panels[0].y, panels[1].y);
    const auto after = yTicks(texts, panels[1].y, 1e9);
    CHECK(before == after);  // one range
    REQUIRE(!before.empty());
    const double a = std::max(1e3 * result["as_designed"]["channels"][c]["max"].get<double>(),
                              afterMaxMm(tcp, c));
    const double reach = std::max(std::abs(before.front()), std::abs(before.back()));
    CHECK(reach >= kTickReach * a);
    CHECK(reach <= kRangePad * a);
  }
  // Residual against each joint: millimetres, the before and after figures on the same ticks.
  for (int j = 1; j <= 7; ++j) {
    const std::string q = "q" + std::to_string(j);
    INFO(q);
    const auto b =
        svgTexts(readFileOrThrow((tcp / "plots" / ("before_residual_vs_" + q + ".svg")).string()));
    const auto a =
        svgTexts(readFileOrThrow((tcp / "plots" / ("after_residual_vs_" + q + ".svg")).string()));
    CHECK(hasText(b, "residual [mm]"));
    CHECK(hasText(a, "residual [mm]"));
    CHECK(yTicks(b, 0, 1e9) == yTicks(a, 0, 1e9));
    CHECK(title(b).rfind("before: as designed", 0) == 0);
    CHECK(title(a).rfind("after: calibrated", 0) == 0);
  }
  // The check run shows the calibrated copy: no figure of it is titled "as designed".
  int checked = 0;
  for (const std::string entry : {"tcp", "tcp_variant", "trajectory"})
    for (const auto& e : fs::directory_iterator(out / "calibration" / entry / "calibrated/plots")) {
      const auto texts = svgTexts(readFileOrThrow(e.path().string()));
      const std::string t = title(texts);
      INFO(e.path().string() << ": " << t);
      const auto panels = panelTitles(texts);
      const std::string named = panels.empty() ? t : panels.front().text;
      CHECK(named.rfind("calibrated design (check run)", 0) == 0);
      CHECK(t.find("as designed") == std::string::npos);
      ++checked;
    }
  CHECK(checked > 0);
  // On the stage report and on the study's page, before figures precede after figures; an after
  // figure not shown (the fit leaves no bin flagged) is linked instead.
  const std::string md = readFileOrThrow((out / "calibration/report.md").string());
  const std::string html = readFileOrThrow((out / "report.html").string());
  for (const std::string entry : {"tcp", "tcp_variant", "trajectory"}) {
    INFO(entry);
    const int shown = checkOrder(images(md, "![", "](", ")"), entry);
    CHECK(checkOrder(images(html, "<img ", "alt=\"", "\""), entry) == shown);
    int after = 0, linked = 0;
    for (const auto& e : fs::directory_iterator(out / "calibration" / entry / "plots")) {
      const std::string name = e.path().filename().string();
      if (name.rfind("after_", 0) != 0) continue;
      ++after;
      const std::string rel = entry + "/plots/" + name;
      if (md.find("![" + rel + "](" + rel + ")") == std::string::npos &&
          md.find("](" + rel + ")") != std::string::npos &&
          html.find("<a href=\"calibration/" + rel + "\">") != std::string::npos)
        ++linked;
    }
    CHECK(after > 0);
    CHECK(shown + linked == after);
  }
}

TEST_CASE(
    "armstudy compare of a calibrated copy (studies/arm_calibration.sh) titles its figures for the "
    "calibrated design, a compare of the design as given for that one",
    "[calibration][cli][report]") {
  const fs::path d = test::emptyTempDir("calibration_figures_cli");
  const std::string design = test::sourcePath("designs/final_prototype_7dof.toml"),
                    data = (d / "tcp.csv").string(), out = (d / "tcp").string();
  std::string log;
  REQUIRE(test::runCommand(test::binaryPath() + " synth " + design +
                               " --kind tcp --rows 30 --noise 2e-4 --seed 1"
                               " --hide joint_offset.j3:offset=0.01 --out " +
                               data,
                           log) == 0);
  const auto firstPanel = [&](const std::string& file) {
    const auto p = panelTitles(svgTexts(readFileOrThrow((d / "tcp/plots" / file).string())));
    return p.empty() ? std::string() : p.front().text;
  };
  const auto titleOf = [&](const std::string& file) {
    return title(svgTexts(readFileOrThrow((d / "tcp/plots" / file).string())));
  };
  REQUIRE(test::runCommand(test::binaryPath() + " compare " + design + " --kind tcp --data " +
                               data + " --out " + out,
                           log) == 0);
  CHECK(firstPanel("residual_vs_predicted_x.svg") == "before: as designed");
  CHECK(titleOf("before_residual_vs_q1.svg").rfind("before: as designed", 0) == 0);
  REQUIRE(test::runCommand(test::binaryPath() + " fit " + design + " --kind tcp --data " + data +
                               " --auto --out " + out,
                           log) == 0);
  REQUIRE(test::runCommand(test::binaryPath() + " compare " + out +
                               "/final_prototype_7dof_calibrated.toml --kind tcp --data " + data +
                               " --out " + out,
                           log) == 0);
  INFO(log);
  CHECK(firstPanel("residual_vs_predicted_x.svg") == "calibrated design (check run)");
  CHECK(titleOf("before_residual_vs_q1.svg").rfind("calibrated design (check run)", 0) == 0);
  fs::remove_all(d);
}
