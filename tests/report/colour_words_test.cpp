// The words for colours against the colours drawn (shipped stem_obstacles study, reach with
// self-collision and obstacles): every "<name> (#rrggbb)" of the reach report's map colours names
// that colour as Okabe & Ito (2008) do, and each of those colours is drawn in the report's maps.
#include <catch2/catch.hpp>
#include <filesystem>
#include <map>
#include <regex>

#include "io/files.hpp"
#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

// Okabe & Ito 2008, "Color Universal Design", the published palette; and the light grey the maps
// use for "out of reach".
const std::map<std::string, std::string> kPublished = {
    {"#e69f00", "orange"},         {"#56b4e9", "sky blue"}, {"#009e73", "bluish green"},
    {"#f0e442", "yellow"},         {"#0072b2", "blue"},     {"#d55e00", "vermillion"},
    {"#cc79a7", "reddish purple"}, {"#000000", "black"},    {"#e6e6e6", "light grey"}};

}  // namespace

TEST_CASE("reach map colours: each colour word is the colour drawn", "[reach][report]") {
  const fs::path out = test::shippedOutput("stem_obstacles") / "reach";
  const std::string md = readFileOrThrow((out / "report.md").string());
  const auto at = md.find("Map colours: ");
  REQUIRE(at != std::string::npos);
  const std::string sentence = md.substr(at, md.find('\n', at) - at);
  INFO(sentence);
  const std::regex named(R"(([a-z][a-z ]*[a-z]) \((#[0-9a-f]{6})\) )");
  std::string svgs;
  for (const auto& e : fs::directory_iterator(out / "images"))
    if (e.path().extension() == ".svg") svgs += readFileOrThrow(e.path().string());
  int n = 0;
  for (auto it = std::sregex_iterator(sentence.begin(), sentence.end(), named);
       it != std::sregex_iterator(); ++it) {
    const std::string name = (*it)[1], hex = (*it)[2];
    INFO(name << " " << hex);
    REQUIRE(kPublished.count(hex));
    const std::string& want = kPublished.at(hex);
    // the word right before the hex ends with the published name ("Map colours: bluish green")
    CHECK(name.size() >= want.size());
    CHECK(name.compare(name.size() - want.size(), want.size(), want) == 0);
    CHECK(svgs.find(hex) != std::string::npos);  // drawn (the maps' legends)
    ++n;
  }
  CHECK(n == 5);  // reachable, out of reach, joint limits, self-collision, obstacle contact
  CHECK(sentence.find("blue (#0072b2) reachable only in self-collision") != std::string::npos);
  CHECK(sentence.find("black (#000000) reachable only in contact with an obstacle") !=
        std::string::npos);
}

TEST_CASE("status map legends use words, not identifiers (shipped stem_row)",
          "[dexterity][report]") {
  const fs::path out = test::shippedOutput("stem_row") / "dexterity";
  const std::string svg = readFileOrThrow((out / "first_prototype_9dof_status.svg").string());
  const std::regex text(R"(<text[^>]*>([^<]*)</text>)");
  int labels = 0;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), text); it != std::sregex_iterator();
       ++it) {
    const std::string t = (*it)[1];
    if (t.find("first_prototype_9dof") != std::string::npos)
      continue;  // the title names the design
    INFO(t);
    CHECK(t.find('_') == std::string::npos);
    labels += t.rfind("only in ", 0) == 0;  // the statuses this map shows
  }
  CHECK(labels == 2);  // self-collision and obstacle contact
}

TEST_CASE("the spraying row's manipulability maps name the task's 5 rows beside m^3",
          "[reach][report]") {
  // Thesis eq. (3.1): the spraying task constrains x, y, z, alpha and gamma, 5 rows of which 2 are
  // angular; a scale labelled m^3 alone would read as the 3 position rows.
  const fs::path out = test::shippedOutput("spraying_row") / "reach";
  int maps = 0;
  for (const auto& e : fs::directory_iterator(out / "images")) {
    const std::string name = e.path().filename().string();
    if (e.path().extension() != ".svg" || name.find("_manipulability") == std::string::npos)
      continue;
    INFO(name);
    const std::string svg = readFileOrThrow(e.path().string());
    std::string words;  // the figure's text, wrapped lines joined
    const std::regex text(R"(<text[^>]*>([^<]*)</text>)");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), text); it != std::sregex_iterator();
         ++it)
      words += std::string((*it)[1]) + " ";
    INFO(words);
    CHECK(words.find("[m^3; 5 rows, the 2 angular ones weighed by 1 m]") != std::string::npos);
    CHECK(words.find("[m^3]") == std::string::npos);
    ++maps;
  }
  CHECK(maps >= 1);
}
