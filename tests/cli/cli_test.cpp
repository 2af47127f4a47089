// End-to-end: the armstudy executable as a user runs it.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "drive/friction.hpp"
#include "io/files.hpp"
#include "test_support.hpp"

using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {
std::string cli(const std::string& args, int& status) {
  std::string out;
  status = runCommand(binaryPath() + " " + args, out);
  return out;
}
fs::path freshDir(const std::string& name) { return armstudy::test::emptyTempDir("cli_" + name); }
}  // namespace

TEST_CASE("fit --help lists every declared friction effect once", "[cli]") {
  int st = 0;
  const std::string help = cli("fit --help", st);
  REQUIRE(st == 0);
  const std::size_t at = help.find("  drive:");
  REQUIRE(at != std::string::npos);
  const std::string line = help.substr(at, help.find('\n', at) - at) + " ";
  int listed = 0;
  for (const armstudy::drive::EffectDeclaration& d : armstudy::drive::effectDeclarations()) {
    INFO("effect " << d.name << " in: " << line);
    CHECK(line.find(std::string(" ") + d.name + " ") != std::string::npos);
    ++listed;
  }
  CHECK(listed == static_cast<int>(std::count(line.begin(), line.end(), ' ')) - 3);
}

TEST_CASE("armstudy --help teaches the commands", "[cli]") {
  int st = 0;
  const std::string out = cli("--help", st);
  CHECK(st == 0);
  for (const char* cmd : {"describe", "fk", "run"}) CHECK(out.find(cmd) != std::string::npos);
  const std::string fk = cli("fk --help", st);
  CHECK(st == 0);
  CHECK(fk.find("--q") != std::string::npos);
  CHECK(fk.find("Example") != std::string::npos);
  // Every default is shown; empty lists and required options show none.
  const std::string run = cli("run --help", st);
  CHECK(run.find("--threads INT:INT in [0 - 256]=0") != std::string::npos);
  CHECK(run.find("--output TEXT=output") != std::string::npos);
  CHECK(cli("fit --help", st).find("--folds INT:INT in [2 - 1000000]=5") != std::string::npos);
  const std::string approach = cli("approach --help", st);
  CHECK(approach.find("--entry-radius FLOAT=0.1") != std::string::npos);
  CHECK(approach.find("=[]") == std::string::npos);
  CHECK(approach.find("--duration FLOAT REQUIRED") != std::string::npos);
}

TEST_CASE("the progress bar on a terminal shows elapsed time and an ETA", "[cli][study]") {
  // `script` gives the run a pseudo-terminal (the bar is drawn only on a terminal).
  REQUIRE(std::system("command -v script >/dev/null 2>&1") == 0);  // bsdutils: essential in Debian
  const fs::path out = freshDir("progress_eta");
  const fs::path log = out / "tty.log";
  // A coarser copy of the shipped spraying_row study (both grids, about 2,700 poses instead of
  // 46,000, and a smaller audit): the bar is the same, its ETA shown from 2 % of the poses on.
  std::string study = armstudy::readFileOrThrow(sourcePath("studies/spraying_row.toml"));
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"../designs/", sourcePath("designs") + "/"},
        {"step = \"0.01 m\"", "step = \"0.04 m\""},
        {"step = \"0.05 m\"", "step = \"0.15 m\""},
        {"poses = 100", "poses = 4"},
        {"starts = 200", "starts = 20"}}) {
    INFO(from);
    REQUIRE(study.find(from) != std::string::npos);  // the shipped file holds what is replaced
    for (std::size_t at = study.find(from); at != std::string::npos;
         at = study.find(from, at + to.size()))
      study.replace(at, from.size(), to);
  }
  std::ofstream(out / "spraying_row.toml") << study;
  const std::string cmd = "script -qec \"" + binaryPath() + " run " +
                          (out / "spraying_row.toml").string() + " --threads 2 --output " +
                          (out / "o").string() + "\" " + log.string() + " >/dev/null 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(text.find("reachability spraying_row") != std::string::npos);
  CHECK(text.find("ETA ") != std::string::npos);
  CHECK(text.find("100.0 %") != std::string::npos);
  CHECK(text.find("done") != std::string::npos);
}

TEST_CASE("describe prints the table and the assumptions", "[cli]") {
  int st = 0;
  const std::string out = cli(sourcePath("designs/final_prototype_7dof.toml") + " ", st);
  CHECK(st != 0);  // no subcommand given
  const std::string d = cli("describe " + sourcePath("designs/final_prototype_7dof.toml"), st);
  CHECK(st == 0);
  CHECK(d.find("7 DoF") != std::string::npos);
  CHECK(d.find("assumptions") != std::string::npos);
  CHECK(d.find("prismatic") != std::string::npos);
}

TEST_CASE("fk --json reports every frame and the TCP", "[cli]") {
  int st = 0;
  const std::string out =
      cli("fk " + sourcePath("designs/first_prototype_6dof.toml") + " --q 0,0,0,0,0,0 --json", st);
  REQUIRE(st == 0);
  const auto j = nlohmann::json::parse(out);
  REQUIRE(j["frames"].size() == 7);
  CHECK(j["frames"][6]["frame"] == "tcp");
  CHECK(j["frames"][6]["y_m"].get<double>() == Approx(1.03));
  CHECK(j["frames"][6]["z_m"].get<double>() == Approx(1.0));
  // Wrong number of joint values: error, non-zero exit, names the key.
  const std::string bad =
      cli("fk " + sourcePath("designs/first_prototype_6dof.toml") + " --q 0,0", st);
  CHECK(st != 0);
  CHECK(bad.find("joint values") != std::string::npos);
}

TEST_CASE("run writes manifest and resolved designs, refuses to overwrite silently",
          "[cli][study]") {
  const fs::path dir = freshDir("run");
  const fs::path study = dir / "mini.toml";
  std::ofstream(study)
      << "[study]\nname = \"mini\"\n[[design]]\nfile = \""
      << sourcePath("designs/final_prototype_7dof.toml")
      << "\"\n[[variant]]\nof = \"final_prototype_7dof\"\nsweep = { \"base.x\" = [0.0, 0.1] }\n";
  int st = 0;
  std::string out = cli("run " + study.string() + " --output " + (dir / "out").string(), st);
  INFO(out);
  REQUIRE(st == 0);
  const auto man = nlohmann::json::parse(std::ifstream(dir / "out/mini/manifest.json"));
  CHECK(man["study"] == "mini");
  CHECK(man["inputs"].size() == 2);
  CHECK(man["designs"].size() == 3);
  CHECK(man["designs"][2] == "final_prototype_7dof+base.x=0.1");
  CHECK(!man["git_revision"].get<std::string>().empty());
  const auto designs = nlohmann::json::parse(std::ifstream(dir / "out/mini/designs.json"));
  CHECK(designs[2]["base"]["x_m"].get<double>() == Approx(0.1));
  out = cli("run " + study.string() + " --output " + (dir / "out").string(), st);
  CHECK(st != 0);
  CHECK(out.find("--overwrite") != std::string::npos);
  out = cli("run " + study.string() + " --output " + (dir / "out").string() + " --overwrite", st);
  CHECK(st == 0);
  // No temporary files left behind.
  for (const auto& e : fs::recursive_directory_iterator(dir / "out"))
    CHECK(e.path().string().find(".tmp") == std::string::npos);
}

TEST_CASE("a study naming a missing design fails once, names file and key, writes nothing",
          "[cli][study][bad-input]") {
  const fs::path dir = freshDir("bad");
  const fs::path study = dir / "bad.toml";
  std::ofstream(study) << "[study]\nname = \"bad\"\n[[design]]\nfile = \"nope.toml\"\n";
  int st = 0;
  const std::string out = cli("run " + study.string() + " --output " + (dir / "out").string(), st);
  CHECK(st == 2);
  CHECK(out.find("bad.toml:4") != std::string::npos);
  CHECK(out.find("design[0].file") != std::string::npos);
  CHECK(out.find("error") == out.rfind("error"));  // printed once
  CHECK_FALSE(fs::exists(dir / "out"));
}
