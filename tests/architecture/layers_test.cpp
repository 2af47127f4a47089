// Layers you can check (docs/architecture.md): every file under src/ includes project headers only
// from its own layer or a lower one; there are no exceptions. The layer table below is the one in
// docs/architecture.md; keep the two equal. The scan is checked too: the table names exactly the
// folders of src/, the scan finds the includes between layers, and it flags an upward include
// planted in a scratch tree.
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
    {"cli", "python"},
};

int layerOf(const std::string& folder) {
  for (std::size_t i = 0; i < kLayers.size(); ++i)
    if (std::find(kLayers[i].begin(), kLayers[i].end(), folder) != kLayers[i].end())
      return static_cast<int>(i);
  return -1;
}

std::string srcDir() { return std::string(ARMSTUDY_SOURCE_DIR) + "/src"; }

// What a scan of a source tree found: its files, its project includes ("folder/header" of a folder
// in kLayers), how many of those cross into a lower layer, and every include from a higher layer.
struct IncludeScan {
  long files = 0, project_includes = 0, downward_includes = 0;
  std::vector<std::string> upward;  // "src/<file>:<line>: includes ... from a higher layer (...)"
};

IncludeScan scanIncludes(const fs::path& root) {
  const std::regex include_re(R"(^\s*#\s*include\s*"([a-z_0-9]+)/([^"]+)\")");
  IncludeScan scan;
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& p : files) {
    ++scan.files;
    const std::string rel = fs::relative(p, root).generic_string();
    const std::string folder = rel.substr(0, rel.find('/'));
    const int own = layerOf(folder);
    if (own < 0) continue;  // reported by "every src/ folder has a layer"
    std::ifstream in(p);
    std::string line;
    for (int line_no = 1; std::getline(in, line); ++line_no) {
      std::smatch m;
      if (!std::regex_search(line, m, include_re)) continue;
      const int to = layerOf(m[1].str());
      if (to < 0) continue;  // not a project folder
      ++scan.project_includes;
      if (to < own) ++scan.downward_includes;
      if (to <= own) continue;
      scan.upward.push_back("src/" + rel + ":" + std::to_string(line_no) + ": includes " +
                            m[1].str() + "/" + m[2].str() + " from a higher layer (" + folder +
                            " is layer " + std::to_string(own) + ", " + m[1].str() + " is layer " +
                            std::to_string(to) + ")");
    }
  }
  return scan;
}

}  // namespace

TEST_CASE("every src/ folder has a layer, and every layer folder is in src/", "[architecture]") {
  std::set<std::string> folders;
  for (const auto& e : fs::directory_iterator(srcDir()))
    if (e.is_directory()) folders.insert(e.path().filename().string());
  REQUIRE(folders.size() >= kLayers.size());
  for (const std::string& f : folders) {
    INFO("src/" << f << " is missing from kLayers (and docs/architecture.md)");
    CHECK(layerOf(f) >= 0);
  }
  for (const auto& layer : kLayers)
    for (const std::string& f : layer) {
      if (f == "armstudy") continue;  // generated into the build folder
      INFO("kLayers names " << f << ", which is not a folder of src/");
      CHECK(folders.count(f) == 1);
    }
}

TEST_CASE("no file in src/ includes a header from a higher layer", "[architecture]") {
  const IncludeScan scan = scanIncludes(srcDir());
  INFO(scan.files << " files, " << scan.project_includes << " project includes, "
                  << scan.downward_includes << " into a lower layer");
  // The scan saw the tree: every layer above the lowest includes lower ones.
  REQUIRE(scan.files > 50);
  REQUIRE(scan.downward_includes > 100);
  REQUIRE(scan.project_includes > scan.downward_includes);
  for (const std::string& v : scan.upward) UNSCOPED_INFO(v);
  CHECK(scan.upward.empty());
}

TEST_CASE("the layer scan flags an upward include and only that one", "[architecture]") {
  // A scratch tree: a lowest-layer header that includes the CLI, and legal includes around it.
  const fs::path root = fs::temp_directory_path() / "armstudy_layers_scan";
  fs::remove_all(root);
  fs::create_directories(root / "common");
  fs::create_directories(root / "cli");
  std::ofstream(root / "common/errors.hpp") << "#pragma once\n#include \"common/units.hpp\"\n";
  std::ofstream(root / "common/bad.hpp")
      << "#pragma once\n#include <vector>\n  #  include \"cli/main.hpp\"\n";
  std::ofstream(root / "cli/main.cpp")
      << "#include \"common/errors.hpp\"\n#include \"cli/args.hpp\"\n";
  const IncludeScan scan = scanIncludes(root);
  fs::remove_all(root);
  CHECK(scan.files == 3);
  CHECK(scan.project_includes == 4);
  CHECK(scan.downward_includes == 1);
  REQUIRE(scan.upward.size() == 1);
  CHECK(scan.upward[0].rfind("src/common/bad.hpp:3: includes cli/main.hpp from a higher layer",
                             0) == 0);
}

TEST_CASE(
    "every folder under src/stages/ is one registry line, and the registry names no other stage",
    "[architecture]") {
  // Adding a stage means a folder under src/stages/ and its FunctionStage in the list of
  // src/engine/registry.cpp (docs/architecture.md, "Stages"); nothing else in src/ may name a
  // concrete stage.
  std::set<std::string> folders;
  for (const auto& e : fs::directory_iterator(srcDir() + "/stages"))
    if (e.is_directory()) folders.insert(e.path().filename().string());
  REQUIRE(folders.size() >= 5);
  std::ifstream in(srcDir() + "/engine/registry.cpp");
  std::stringstream text;
  text << in.rdbuf();
  const std::string registry = text.str();
  const std::regex line_re(R"(&(\w+)_stage,)");
  std::set<std::string> listed;
  for (std::sregex_iterator it(registry.begin(), registry.end(), line_re), end; it != end; ++it)
    listed.insert((*it)[1].str());
  CHECK(listed == folders);
  // Only the registry includes the stages' headers.
  const std::regex include_re(R"(#\s*include\s*"stages/)");
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

namespace {

// Compiles `source` (syntax only) against the include roots of `layers` (their folders under the
// build's layer_include/) and the generated headers; returns the exit status and the diagnostics.
std::pair<int, std::string> compileWithLayers(const std::string& source,
                                              const std::vector<std::string>& layers) {
  const fs::path dir = fs::temp_directory_path() / "armstudy_layer_compile";
  fs::create_directories(dir);
  const fs::path file = dir / "probe.cpp", log = dir / "probe.log";
  std::ofstream(file) << source;
  std::string cmd = std::string(ARMSTUDY_CXX) + " -std=c++20 -fsyntax-only";
  for (const std::string& l : layers) cmd += " -I" + std::string(ARMSTUDY_LAYER_INCLUDE) + "/" + l;
  cmd += " -I" + std::string(ARMSTUDY_GENERATED) + " " + file.string() + " > " + log.string() +
         " 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  fs::remove_all(dir);
  return {status, text.str()};
}

}  // namespace

TEST_CASE("each layer compiles against its own include root: an upward include does not compile",
          "[architecture]") {
  // Every layer's root holds exactly its folders (symbolic links into src/).
  const std::vector<std::string> target_names = {
      "common", "model",     "kinematics", "tasks",    "metrics", "ik",
      "drive",  "collision", "trajectory", "dynamics", "io",      "report",
      "study",  "reach",     "stages",     "engine",   "cli"};
  REQUIRE(target_names.size() == kLayers.size());
  for (std::size_t i = 0; i < kLayers.size(); ++i) {
    const fs::path root = fs::path(ARMSTUDY_LAYER_INCLUDE) / target_names[i];
    INFO(root.string());
    REQUIRE(fs::is_directory(root));
    std::set<std::string> in_root, expected;
    for (const auto& e : fs::directory_iterator(root)) {
      CHECK(fs::is_symlink(e.path()));
      in_root.insert(e.path().filename().string());
    }
    for (const std::string& f : kLayers[i])
      if (f != "armstudy") expected.insert(f);
    CHECK(in_root == expected);
  }
  // A lower layer's header compiles in a higher layer; a higher layer's header does not compile
  // in a lower one, and the compiler says it cannot find it.
  const auto [ok, ok_log] =
      compileWithLayers("#include \"common/errors.hpp\"\n", {"model", "common"});
  INFO(ok_log);
  CHECK(ok == 0);
  const auto [bad, bad_log] = compileWithLayers(
      "#include \"common/errors.hpp\"\n#include \"study/stage.hpp\"\n", {"common"});
  INFO(bad_log);
  CHECK(bad != 0);
  CHECK(bad_log.find("study/stage.hpp: No such file or directory") != std::string::npos);
}
