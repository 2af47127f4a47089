// The friction effect tables of the docs against the declarations of src/drive
// (friction_effects.cpp): every effect has exactly one row in docs/drives.md ("Terms and laws",
// with its term and each of its [drive.friction] keys and motor-side units) and in
// docs/calibration.md ("Effect catalogue", with the residual pattern the reports name), and no row
// names an effect that is not declared.
#include <catch2/catch.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "drive/friction.hpp"
#include "io/files.hpp"
#include "test_support.hpp"

using namespace armstudy;

namespace {

struct Row {
  std::string name;  // first cell, backticks removed
  std::string rest;  // the other cells
};

// The rows of the first Markdown table after the line that starts with `heading`.
std::vector<Row> tableAfter(const std::string& file, const std::string& heading) {
  std::istringstream is(readFileOrThrow(test::sourcePath(file)));
  std::vector<Row> rows;
  bool in_section = false, in_table = false;
  for (std::string l; std::getline(is, l);) {
    if (!in_section) {
      in_section = l.rfind(heading, 0) == 0;
      continue;
    }
    const bool row = l.rfind("|", 0) == 0;
    if (in_table && !row) break;
    if (!row) continue;
    if (!in_table) {  // the header and the separator
      in_table = true;
      std::getline(is, l);
      continue;
    }
    const auto end = l.find('|', 1);
    std::string name = l.substr(1, end - 1);
    std::string clean;
    for (char c : name)
      if (c != '`' && c != ' ') clean += c;
    rows.push_back({clean, l.substr(end)});
  }
  return rows;
}

// Which words of a declaration its docs row must hold.
enum class Words { drives, calibration };

void checkTable(const std::vector<Row>& rows, Words words) {
  std::set<std::string> declared;
  for (const drive::EffectDeclaration& d : drive::effectDeclarations()) declared.insert(d.name);
  std::multiset<std::string> documented;
  for (const Row& r : rows) {
    INFO("docs row '" << r.name << "'");
    CHECK(declared.count(r.name) == 1);
    documented.insert(r.name);
  }
  for (const drive::EffectDeclaration& d : drive::effectDeclarations()) {
    INFO("declared effect '" << d.name << "'");
    CHECK(documented.count(d.name) == 1);
    for (const Row& r : rows) {
      if (r.name != d.name) continue;
      if (words == Words::calibration) {  // the pattern the reports name
        CHECK(r.rest.find(d.pattern) != std::string::npos);
        continue;
      }
      CHECK(r.rest.find("`" + std::string(d.law)) != std::string::npos);  // the term
      for (const drive::EffectParameter& p : d.params) {
        INFO("key " << p.key);
        CHECK(r.rest.find("`" + std::string(p.key) + "`") != std::string::npos);
        CHECK(r.rest.find(std::string("[") + p.unit_motor + "]") != std::string::npos);
      }
    }
  }
}

}  // namespace

TEST_CASE("docs/drives.md: one row per declared friction effect, with its keys",
          "[calibration][docs]") {
  const std::vector<Row> rows = tableAfter("docs/drives.md", "## Terms (\"effects\") and laws");
  REQUIRE_FALSE(rows.empty());
  checkTable(rows, Words::drives);
}

TEST_CASE("docs/calibration.md: one catalogue row per declared drive effect",
          "[calibration][docs]") {
  const std::vector<Row> rows = tableAfter("docs/calibration.md", "## Effect catalogue");
  REQUIRE_FALSE(rows.empty());
  checkTable(rows, Words::calibration);
}
