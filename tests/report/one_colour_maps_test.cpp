// No map that shows nothing: in the shipped stem_ellipsoids and regression studies (whose reach and
// dexterity maps include ones where every cell has the same status), no figure's cell map is a
// single colour; the reports say "100 % of the N cells ..." instead, and what the reports, the
// manifest and the study page point to exists.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>

#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/files.hpp"
#include "plot_checks.hpp"
#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

constexpr int kMapFrame = 2;  // [px] renderCellMap's grey frame around the cells

std::string unbase64(const std::string& s) {
  static const std::string abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  int bits = 0, acc = 0;
  for (char c : s) {
    const auto v = abc.find(c);
    if (v == std::string::npos) continue;  // padding
    acc = (acc << 6) | static_cast<int>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xff));
    }
  }
  return out;
}

// The distinct colours inside the frame of each cell map an SVG embeds (as a PNG data URI).
std::vector<std::set<unsigned>> mapColours(const std::string& svg) {
  std::vector<std::set<unsigned>> out;
  const std::string key = "xlink:href=\"data:image/png;base64,";
  for (auto at = svg.find(key); at != std::string::npos; at = svg.find(key, at + 1)) {
    const auto b = at + key.size();
    const test::Pixels px = test::decode(unbase64(svg.substr(b, svg.find('"', b) - b)));
    std::set<unsigned> colours;
    for (int y = kMapFrame; y < px.h - kMapFrame; ++y)
      for (int x = kMapFrame; x < px.w - kMapFrame; ++x) {
        const report::Rgb c = px.at(x, y);
        colours.insert((unsigned{c.r} << 16) | (unsigned{c.g} << 8) | c.b);
      }
    out.push_back(colours);
  }
  return out;
}

}  // namespace

TEST_CASE(
    "no map that shows nothing: a map of one status is said in words, not drawn in one colour, "
    "and the reports point only to files that exist",
    "[report][study]") {
  // The fixtures "shipped: <study>" run the studies once per suite (tests/CMakeLists.txt).
  const std::vector<fs::path> outs = {test::shippedOutput("stem_ellipsoids"),
                                      test::shippedOutput("regression")};
  int maps = 0;
  for (const fs::path& out : outs)
    for (const auto& e : fs::recursive_directory_iterator(out)) {
      if (e.path().extension() != ".svg") continue;
      for (const auto& colours : mapColours(readFileOrThrow(e.path().string()))) {
        INFO(e.path().string());
        CHECK(colours.size() >= 2);
        ++maps;
      }
    }
  CHECK(maps > 10);
  // Where a map was left out, the report says what it would have shown.
  static const std::regex said(R"(100 % of the ([0-9]+) cells reachable)");
  CHECK(std::regex_search(readFileOrThrow((outs[0] / "dexterity/report.md").string()), said));
  CHECK(std::regex_search(readFileOrThrow((outs[1] / "reach/report.md").string()), said));
  // Every image a Markdown report shows and every file the manifest lists exists.
  static const std::regex image(R"(!\[[^\]]*\]\(([^)]+)\))");
  for (const fs::path& out : outs) {
    for (const auto& e : fs::recursive_directory_iterator(out)) {
      if (e.path().extension() != ".md") continue;
      const std::string md = readFileOrThrow(e.path().string());
      for (auto it = std::sregex_iterator(md.begin(), md.end(), image);
           it != std::sregex_iterator(); ++it) {
        INFO(e.path().string() << ": " << (*it)[1]);
        CHECK(fs::exists(e.path().parent_path() / (*it)[1].str()));
      }
    }
    const auto manifest = nlohmann::json::parse(readFileOrThrow((out / "manifest.json").string()));
    REQUIRE(manifest.contains("files"));
    for (const auto& f : manifest["files"]) {
      const std::string rel = f.is_string() ? f.get<std::string>() : f["path"].get<std::string>();
      INFO(rel);
      CHECK(fs::exists(out / rel));
    }
  }
}

TEST_CASE(
    "a design that reaches no stem cell gets no manipulability or transmission maps (they would "
    "be all grey): the report says so, and shows only files that exist",
    "[report][study][dexterity]") {
  const fs::path root = test::emptyTempDir("no_reachable_cell");
  const fs::path study = root / "far.toml";
  {
    std::ofstream f(study);
    f << "[study]\nname = \"far\"\n\n[[design]]\nfile = \""
      << test::sourcePath("designs/first_prototype_9dof.toml")
      << "\"\n\n[dexterity]\nstem_x = \"5 m\"\nstem_y = \"0.7 m\"\nradius = \"0.15 m\"\n"
         "gamma = { min = \"-pi/2\", max = \"pi/2\", step = \"45 deg\" }\n"
         "z = { min = \"0.8 m\", max = \"1.0 m\", step = \"0.1 m\" }\n";
  }
  RunOptions ro;
  ro.output_root = (root / "out").string();
  ro.threads = 2;
  ro.progress = false;
  (void)runStudy(loadStudy(study.string()), ro);
  const fs::path out = root / "out" / "far" / "dexterity";
  const nlohmann::json summary =
      nlohmann::json::parse(readFileOrThrow((out / "summary.json").string()));
  REQUIRE(summary["designs"][0]["reachable"].get<int>() == 0);  // the scenario: nothing reached
  int value_maps = 0;
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string name = e.path().filename().string();
    value_maps += name.find("_manipulability_") != std::string::npos ||
                  name.find("_transmission_") != std::string::npos;
  }
  CHECK(value_maps == 0);
  const std::string md = readFileOrThrow((out / "report.md").string());
  CHECK(md.find("no manipulability or transmission map is drawn") != std::string::npos);
  static const std::regex image(R"(!\[[^\]]*\]\(([^)]*)\))");
  for (auto it = std::sregex_iterator(md.begin(), md.end(), image); it != std::sregex_iterator();
       ++it) {
    INFO((*it)[1]);
    CHECK(!(*it)[1].str().empty());
    CHECK(fs::exists(out / (*it)[1].str()));
  }
  fs::remove_all(root);
}
