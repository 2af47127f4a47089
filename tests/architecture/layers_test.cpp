// Layers you can check (issue 15, docs/architecture.md): every file under src/ includes project
// headers only from its own layer or a lower one. The layer table below is the one in
// docs/architecture.md; keep the two equal. Today's known upward includes are listed explicitly;
// the list may only shrink: an entry that no longer occurs fails too, so it gets deleted.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// Lowest first; folders in one row are one layer (they may include each other).
// "armstudy" is the generated armstudy/version.hpp.
const std::vector<std::vector<std::string>> kLayers = {
    {"common", "armstudy"},
    {"model"},
    {"kinematics"},
    {"tasks"},
    {"metrics"},
    {"ik"},
    {"drive"},
    {"collision"},
    {"trajectory"},
    {"dynamics"},
    {"io"},
    {"report"},
    {"study"},
    {"reach", "dexterity", "calibration"},
    {"stages"},
    {"engine"},
    {"cli"},
};

// Known upward includes as of issue 15, "file -> included header". Only delete from this list.
// None are left (issue 15 removed the last ones); an exception would be listed here with why.
const std::set<std::string> kKnownUpward = {};

int layerOf(const std::string& folder) {
  for (std::size_t i = 0; i < kLayers.size(); ++i)
    if (std::find(kLayers[i].begin(), kLayers[i].end(), folder) != kLayers[i].end()) return static_cast<int>(i);
  return -1;
}

std::string srcDir() { return std::string(ARMSTUDY_SOURCE_DIR) + "/src"; }

}  // namespace

TEST_CASE("every src/ folder has a layer", "[architecture]") {
  for (const auto& e : fs::directory_iterator(srcDir()))
    if (e.is_directory()) {
      INFO("src/" << e.path().filename().string() << " is missing from kLayers (and docs/architecture.md)");
      CHECK(layerOf(e.path().filename().string()) >= 0);
    }
}

TEST_CASE("no file in src/ includes a header from a higher layer", "[architecture]") {
  const std::regex include_re(R"(^\s*#\s*include\s*"([a-z_0-9]+)/([^"]+)\")");
  std::vector<std::string> violations;
  std::set<std::string> seen_known;
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(srcDir()))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  REQUIRE(files.size() > 50);
  for (const fs::path& p : files) {
    const std::string rel = fs::relative(p, srcDir()).generic_string();
    const std::string folder = rel.substr(0, rel.find('/'));
    const int own = layerOf(folder);
    if (own < 0) continue;  // reported by the test above
    std::ifstream in(p);
    std::string line;
    for (int line_no = 1; std::getline(in, line); ++line_no) {
      std::smatch m;
      if (!std::regex_search(line, m, include_re)) continue;
      const int to = layerOf(m[1].str());
      if (to <= own) continue;  // same or lower layer, or not a project folder
      const std::string key = rel + " -> " + m[1].str() + "/" + m[2].str();
      if (kKnownUpward.count(key)) {
        seen_known.insert(key);
        continue;
      }
      violations.push_back("src/" + rel + ":" + std::to_string(line_no) + ": includes " + m[1].str() + "/" +
                           m[2].str() + " from a higher layer (" + folder + " is layer " + std::to_string(own) +
                           ", " + m[1].str() + " is layer " + std::to_string(to) + ")");
    }
  }
  for (const std::string& v : violations) UNSCOPED_INFO(v);
  CHECK(violations.empty());
  std::vector<std::string> stale;
  for (const std::string& k : kKnownUpward)
    if (!seen_known.count(k)) stale.push_back(k);
  for (const std::string& s : stale) UNSCOPED_INFO("no longer included, delete from kKnownUpward: " << s);
  CHECK(stale.empty());
}

TEST_CASE("every folder under src/stages/ is one registry line, and the registry names no other stage",
          "[architecture]") {
  // Adding a stage means a folder under src/stages/ and one line in src/engine/registry.cpp
  // (docs/architecture.md, "Stages"); nothing else in src/ may name a concrete stage.
  std::set<std::string> folders;
  for (const auto& e : fs::directory_iterator(srcDir() + "/stages"))
    if (e.is_directory()) folders.insert(e.path().filename().string());
  REQUIRE(folders.size() >= 5);
  std::ifstream in(srcDir() + "/engine/registry.cpp");
  std::stringstream text;
  text << in.rdbuf();
  const std::string registry = text.str();
  const std::regex line_re(R"(&(\w+)Stage\(\),)");
  std::set<std::string> listed;
  for (std::sregex_iterator it(registry.begin(), registry.end(), line_re), end; it != end; ++it)
    listed.insert((*it)[1].str());
  CHECK(listed == folders);
  // Only the registry includes the stages' entry headers (stages/<name>/stage.hpp).
  const std::regex include_re(R"(#\s*include\s*"stages/\w+/stage\.hpp")");
  for (const auto& e : fs::recursive_directory_iterator(srcDir())) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), srcDir()).generic_string();
    if (rel == "engine/registry.cpp" || rel.rfind("stages/", 0) == 0) continue;
    std::ifstream f(e.path());
    std::stringstream b;
    b << f.rdbuf();
    INFO(rel);
    CHECK_FALSE(std::regex_search(b.str(), include_re));
  }
}
