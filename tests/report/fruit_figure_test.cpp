// harvest's fruits.svg names the fruits: the shipped harvest_torque study runs through the CLI and
// every fruit of each design's <design>_fruits.csv, picked or failed, has its number written beside
// a marker in that design's panel of the figure, and the legend names the outcomes in words. Read
// from the SVG text and circle elements, as a reader's browser gets them.

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <regex>
#include <sstream>

#include "io/files.hpp"
#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

// [px] how far a fruit's number may stand from its marker's centre (the label sits beside it).
constexpr double kLabelReach = 20;

struct Text {
  double x = 0, y = 0;
  std::string s;
};
struct Dot {
  double x = 0, y = 0;
};

// The fruit numbers and statuses of a <design>_fruits.csv (columns fruit, ..., status, ...).
std::vector<std::pair<std::string, std::string>> fruits(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::pair<std::string, std::string>> out;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::istringstream cells(line);
    for (std::string c; std::getline(cells, c, ',');) f.push_back(c);
    if (f.size() > 4) out.push_back({f[0], f[4]});
  }
  return out;
}

}  // namespace

TEST_CASE("harvest's fruit figure writes every fruit's number, failed or picked, beside its marker",
          "[report][cli]") {
  // The fixture "shipped: harvest_torque" runs the study once per suite (tests/CMakeLists.txt).
  const fs::path dir = shippedOutput("harvest_torque") / "harvest";
  const std::string svg = readFileOrThrow((dir / "fruits.svg").string());
  static const std::regex text(R"re(<text x="([-0-9.]+)" y="([-0-9.]+)"[^>]*>([^<]*)</text>)re");
  static const std::regex circle(R"re(<circle cx="([-0-9.]+)" cy="([-0-9.]+)")re");
  std::vector<Text> texts;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), text); it != std::sregex_iterator();
       ++it)
    texts.push_back({std::stod((*it)[1]), std::stod((*it)[2]), (*it)[3]});
  std::vector<Dot> dots;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), circle); it != std::sregex_iterator();
       ++it)
    dots.push_back({std::stod((*it)[1]), std::stod((*it)[2])});
  int failed = 0, designs = 0;
  for (const char* design : {"final_prototype_9dof", "final_prototype_7dof"}) {
    // The design's panel: from its title down to the next panel's title (or the end).
    double top = -1, bottom = 1e9;
    for (const Text& t : texts)
      if (t.s == design) top = t.y;
    for (const Text& t : texts)
      if (t.y > top && t.s.rfind("final_prototype_", 0) == 0) bottom = std::min(bottom, t.y);
    INFO(design << ": panel from y " << top << " to " << bottom);
    REQUIRE(top >= 0);
    ++designs;
    for (const auto& [number, status] :
         fruits(readFileOrThrow((dir / (std::string(design) + "_fruits.csv")).string()))) {
      failed += status != "ok";
      bool labelled = false;
      for (const Text& t : texts)
        if (t.s == number && t.y > top && t.y < bottom)
          for (const Dot& d : dots)
            labelled =
                labelled || std::hypot(t.x + 3.5 * t.s.size() - d.x, t.y - 4 - d.y) < kLabelReach;
      INFO("fruit " << number << " (" << status << ")");
      CHECK(labelled);
    }
  }
  CHECK(designs == 2);
  // The legend in words: no snake_case outside the designs' names ("motor speed", not
  // "motor_speed").
  for (const Text& t : texts)
    if (t.s.rfind("final_prototype_", 0) != 0) {
      INFO("'" << t.s << "'");
      CHECK(t.s.find('_') == std::string::npos);
    }
  CHECK(failed > 0);  // the figure must show failures, not only picked fruits
}
