// The measures table of docs/dexterity.md against the declarations it documents
// (metrics/measure_declarations.hpp): one row per declared measure, in the declared order, with the
// arrays, units, glyphs and figure the declaration gives the maps.
#include "metrics/measure_declarations.hpp"

#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;

namespace {

// The cells of a Markdown table row "| a | b |" (trimmed).
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line.substr(1));
  while (std::getline(in, cell, '|')) {
    const auto b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
    out.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  return out;
}

// The body rows of the table whose header starts with `header` in the Markdown file.
std::vector<std::vector<std::string>> tableRows(const std::string& path,
                                                const std::string& header) {
  std::ifstream in(path);
  REQUIRE(in.good());
  std::vector<std::vector<std::string>> rows;
  std::string line;
  bool inside = false;
  int skip = 0;
  while (std::getline(in, line)) {
    if (!inside && line.rfind(header, 0) == 0) {
      inside = true;
      skip = 1;  // the |---| line
      continue;
    }
    if (!inside) continue;
    if (line.empty() || line[0] != '|') break;
    if (skip-- > 0) continue;
    rows.push_back(cells(line));
  }
  return rows;
}

// The row the declaration implies (the first six columns; the seventh is the meaning in words).
std::vector<std::string> expectedRow(const metrics::MeasureDeclaration& d) {
  const std::string name = d.name;
  return {"`" + name + "`",
          d.on_maps
              ? "`" + name + "_{plain,optimised}" + (d.normalised ? "[_normalised]" : "") + "`"
              : "-",
          d.unit_translational,
          d.unit_full,
          d.on_glyphs ? "yes" : "no",
          d.figure_label ? d.figure_label : "-"};
}

}  // namespace

TEST_CASE("docs/dexterity.md's measures table lists every declared measure as declared",
          "[metrics][docs]") {
  const auto rows = tableRows(sourcePath("docs/dexterity.md"), "| measure | map arrays |");
  const auto decl = metrics::measureDeclarations();
  REQUIRE(rows.size() == decl.size());
  for (std::size_t k = 0; k < decl.size(); ++k) {
    INFO("row " << k + 1 << " of the measures table, declaration " << decl[k].name);
    REQUIRE(rows[k].size() == 7);
    const std::vector<std::string> want = expectedRow(decl[k]);
    for (std::size_t c = 0; c < want.size(); ++c) CHECK(rows[k][c] == want[c]);
    CHECK(!rows[k][6].empty());  // the meaning
  }
}

TEST_CASE("each declared measure names its own DexterityMeasures member and units",
          "[metrics][declarations]") {
  // Distinct names and members: a copied row would write one value under two names.
  const auto decl = metrics::measureDeclarations();
  metrics::DexterityMeasures m;
  double v = 1.0;
  for (const auto& d : decl) m.*d.value = v++;
  v = 1.0;
  for (std::size_t k = 0; k < decl.size(); ++k) {
    INFO(decl[k].name);
    CHECK(m.*decl[k].value == v++);
    CHECK(std::string(decl[k].unit_translational) != "");
    CHECK(std::string(decl[k].unit_full) != "");
    CHECK(&metrics::declaredMeasure(decl[k].name) == &decl[k]);
    CHECK((decl[k].figure_label == nullptr) == (decl[k].figure_unit_translational == nullptr));
    for (std::size_t j = 0; j < k; ++j) CHECK(std::string(decl[j].name) != decl[k].name);
  }
}
