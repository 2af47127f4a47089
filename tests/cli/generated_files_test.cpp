// Names and user text in what a run generates: a joint name that would give a variant a name that
// is not plain is refused (exit 2, nothing written); scene.py holds file and study names as Python
// string literals, so running it with python3 never runs a name as code; report.html keeps a study
// description's Markdown links and images only where they stay inside the output folder.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/files.hpp"
#include "report/html_report.hpp"
#include "study/scene.hpp"
#include "test_support.hpp"

using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

// A joint name that is Python code when pasted between double quotes: it touches MARKER in the
// folder python3 runs in.
const std::string kHostileJoint = R"(j2",getattr(__import__("os"),"system")("touch MARKER"),")";

// `s` as a TOML basic string.
std::string tomlString(const std::string& s) {
  std::string o = "\"";
  for (const char c : s) o += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
  return o + "\"";
}

std::string hex(const std::string& bytes) {
  static const char* digits = "0123456789abcdef";
  std::string o;
  for (const char c : bytes) {
    o += digits[static_cast<unsigned char>(c) >> 4];
    o += digits[static_cast<unsigned char>(c) & 15];
  }
  return o;
}

// The shipped 6-DoF design with joint j2 renamed to `joint`, as <dir>/hostile.toml.
void writeDesign(const fs::path& dir, const std::string& joint) {
  std::string text = armstudy::readFileOrThrow(sourcePath("designs/first_prototype_6dof.toml"));
  int renamed = 0;
  for (std::size_t at = text.find("\"j2\""); at != std::string::npos;
       at = text.find("\"j2\"", at + 1), ++renamed)
    text.replace(at, 4, tomlString(joint));
  REQUIRE(renamed >= 2);  // the joint and what refers to it
  std::ofstream(dir / "hostile.toml") << text;
}

// A small reach study of that design; `extra` is appended (e.g. a [[variant]]).
std::string writeStudy(const fs::path& dir, const std::string& description,
                       const std::string& extra) {
  const fs::path study = dir / "hostile_names.toml";
  std::ofstream(study) << "[study]\nname = \"hostile_names\"\ndescription = "
                       << tomlString(description) << "\n\n[[design]]\nfile = \"hostile.toml\"\n\n"
                       << extra
                       << "\n[reach]\ntask_space = \"position\"\nself_collision = false\n\n"
                          "[[reach.grid]]\nname = \"tiny\"\n"
                          "x = { from = \"-0.4 m\", to = \"0.4 m\", step = \"0.4 m\" }\n"
                          "y = \"0.6 m\"\nz = \"1.0 m\"\n";
  return study.string();
}

// Runs `python3 scene.py` in `dir` (a copy of the script there; without ParaView it stops at
// `import paraview`, after its lists), then reads the script's FILES with ast.literal_eval (never
// running it) and returns each entry's file-system bytes in hex, one a line.
std::string runSceneWithPython(const fs::path& script, const fs::path& dir) {
  std::string log;
  REQUIRE(runCommand("command -v python3", log) == 0);  // the check needs python3
  if (script != dir / "scene.py") fs::copy_file(script, dir / "scene.py");
  runCommand("cd " + dir.string() + " && timeout 60 python3 scene.py", log);
  INFO(log);
  CHECK_FALSE(fs::exists(dir / "MARKER"));
  const std::string list =
      "import ast, os, sys\n"
      "tree = ast.parse(open(sys.argv[1], encoding='utf-8').read())\n"
      "for node in tree.body:\n"
      "    if isinstance(node, ast.Assign) and node.targets[0].id == 'FILES':\n"
      "        print('\\n'.join(os.fsencode(f).hex() for f in ast.literal_eval(node.value)))\n";
  std::ofstream(dir / "list_files.py") << list;
  std::string names;
  REQUIRE(runCommand("python3 " + (dir / "list_files.py").string() + " " +
                         (dir / "scene.py").string() + " 2>/dev/null",
                     names) == 0);
  return names;
}

}  // namespace

TEST_CASE("a variant whose joint name would not be a plain name is refused, nothing written",
          "[cli][hardening][names]") {
  const fs::path d = emptyTempDir("hostile_variant");
  writeDesign(d, kHostileJoint);
  const std::string study =
      writeStudy(d, "plain",
                 "[[variant]]\nof = \"first_prototype_6dof\"\nsweep = { " +
                     tomlString("joint." + kHostileJoint + ".x") + " = [\"0.3 m\"] }\n");
  const fs::path out = d / "out";
  std::string log;
  const int rc = runCommand(binaryPath() + " run " + study + " --output " + out.string(), log);
  INFO(log);
  CHECK(rc == 2);
  CHECK(log.find("hostile_names.toml") != std::string::npos);  // the file
  CHECK(log.find("joint.j2\"") != std::string::npos);          // the key
  CHECK(log.find("plain name") != std::string::npos);          // the reason
  CHECK_FALSE(fs::exists(out));
  // Were a scene written all the same, it must not run the name.
  for (const auto& e : fs::recursive_directory_iterator(d))
    if (e.path().filename() == "scene.py") runSceneWithPython(e.path(), d);
  CHECK_FALSE(fs::exists(d / "MARKER"));
}

TEST_CASE("a run with a hostile joint name and description writes them as text, never as code",
          "[cli][hardening][names]") {
  const fs::path d = emptyTempDir("hostile_text");
  writeDesign(d, kHostileJoint);
  fs::create_directories(d / "elsewhere");
  const std::string secret = "<svg xmlns=\"http://www.w3.org/2000/svg\"><text>SECRET</text></svg>";
  std::ofstream(d / "elsewhere" / "secret.svg") << secret;
  const std::string description =
      "See [the notes](javascript:alert.name) and [more](JaVaScRiPt:alert.name), "
      "![a](" +
      (d / "elsewhere/secret.svg").string() + ") and ![b](../../elsewhere/secret.svg).";
  const std::string study = writeStudy(
      d, description,
      "[[variant]]\nof = \"first_prototype_6dof\"\nsweep = { \"base.y\" = [\"-0.1 m\"] }\n");
  const fs::path out = d / "out";
  std::string log;
  REQUIRE(runCommand(binaryPath() + " run " + study + " --output " + out.string(), log) == 0);
  const fs::path run = out / "hostile_names";
  REQUIRE(fs::exists(run / "scene.py"));

  // scene.py: run by python3, then its list read as literals: the spatial files of the run.
  const std::string listed = runSceneWithPython(run / "scene.py", run);
  CHECK(listed.find(hex("reach/")) != std::string::npos);
  CHECK(listed.find(hex("first_prototype_6dof+base.y=-0.1")) != std::string::npos);

  // report.html: the description's links and images as text.
  const std::string html = armstudy::readFileOrThrow((run / "report.html").string());
  std::string lower = html;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  CHECK(lower.find("javascript:") == std::string::npos);
  CHECK(html.find("See the notes and more, a and b.") != std::string::npos);
  CHECK(html.find("SECRET") == std::string::npos);
  CHECK(html.find(armstudy::report::base64(secret)) == std::string::npos);
  CHECK(html.find("elsewhere") == std::string::npos);
}

TEST_CASE("scene.py holds names as Python string literals: python3 runs none of them",
          "[cli][hardening][names]") {
  const fs::path d = emptyTempDir("hostile_scene");
  const std::vector<std::string> names = {
      "reach/a\"+__import__('os').system('touch MARKER')+\".vti",
      "reach/" + kHostileJoint + ".vtp",
      "reach/b\\\",__import__(\"os\").system(\"touch MARKER\"),\"\\.vti",
      "reach/c\"\"\"\n__import__('os').system('touch MARKER')\n\"\"\".vts",
      "reach/d'''\r__import__('os').system('touch MARKER')#.pvd",
      "reach/\xe5\x90\x8d\xc3\xa9 \xff\xfe\x01.vti",  // UTF-8, then bytes that are not
      "reach/plain_name+j4.x=0.35.vti"};
  const std::string script =
      armstudy::scene::sceneScript("s\nimport os; os.system('touch MARKER')  # \"\\", names);
  std::ofstream(d / "scene.py", std::ios::binary) << script;
  std::string expected;
  for (const std::string& n : names) expected += hex(n) + "\n";
  CHECK(runSceneWithPython(d / "scene.py", d) == expected);
  CHECK(script.find("    \"reach/plain_name+j4.x=0.35.vti\",\n") != std::string::npos);
}

TEST_CASE("an explore parameter over a joint whose name is not plain is refused at once",
          "[cli][hardening][names]") {
  const fs::path d = emptyTempDir("hostile_explore");
  fs::create_directories(d / "studies");
  fs::create_directory_symlink(sourcePath("designs"), d / "designs");
  std::string design = armstudy::readFileOrThrow(sourcePath("designs/final_prototype_7dof.toml"));
  std::string study = armstudy::readFileOrThrow(sourcePath("studies/explore_final_prototype.toml"));
  auto replaceAll = [](std::string& s, const std::string& from, const std::string& to) {
    int n = 0;
    for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
      s.replace(at, from.size(), to), ++n;
    return n;
  };
  REQUIRE(replaceAll(design, "\"j4\"", tomlString(kHostileJoint)) >= 1);
  REQUIRE(replaceAll(study, "\"../designs/final_prototype_7dof.toml\"", "\"hostile7.toml\"") == 1);
  REQUIRE(replaceAll(study, "\"joint.j4.x\"", tomlString("joint." + kHostileJoint + ".x")) >= 1);
  std::ofstream(d / "studies" / "hostile7.toml") << design;
  std::ofstream(d / "studies" / "explore_hostile.toml") << study;
  const fs::path out = d / "out";
  std::string log;
  const int rc = runCommand("cd " + d.string() + " && timeout 120 " + binaryPath() +
                                " run studies/explore_hostile.toml --output " + out.string(),
                            log);
  INFO(log);
  CHECK(rc == 2);
  CHECK(log.find("explore_hostile.toml") != std::string::npos);
  CHECK(log.find("joint.j2\"") != std::string::npos);
  CHECK(log.find("plain name") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
}
