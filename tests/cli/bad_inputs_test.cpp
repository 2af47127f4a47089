// The catalogue of bad inputs (tests/cli/bad_inputs.toml, 100+ cases: design files,
// study files, measurement data and command lines). Every case must end with the expected exit
// code (2: input error), a message holding every expected part (the file, the key or element, the
// reason), and nothing written to the output folder. The catalogue is data, read here with toml++.
// In expected message parts, {name} is the edited file's name, {line} the line of the edit and
// {next_line} the line after it.
#include <toml++/toml.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "test_support.hpp"

using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string replaceAll(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Case {
  std::string name, base, command;
  std::optional<std::string> find, replace;
  int exit = 2;
  std::vector<std::string> message;
};

std::vector<Case> catalogue() {
  const toml::table t = toml::parse_file(sourcePath("tests/cli/bad_inputs.toml"));
  std::vector<Case> out;
  for (const toml::node& n : *t["case"].as_array()) {
    const toml::table& c = *n.as_table();
    Case k;
    k.name = c["name"].value_or(std::string());
    k.base = c["base"].value_or(std::string());
    k.command = c["command"].value_or(std::string());
    if (auto f = c["find"].value<std::string>()) k.find = *f;
    if (auto r = c["replace"].value<std::string>()) k.replace = *r;
    k.exit = c["exit"].value_or(2);
    for (const toml::node& m : *c["message"].as_array())
      k.message.push_back(m.value_or(std::string()));
    out.push_back(k);
  }
  return out;
}

// A scratch copy of the repository's layout: designs/ and studies/data link to the sources, so a
// study copied into studies/ finds its designs and data; other copies sit at the top.
fs::path scratch() {
  const fs::path root = fs::temp_directory_path() / "armstudy_bad_inputs";
  fs::remove_all(root);
  fs::create_directories(root / "studies");
  fs::create_directory_symlink(sourcePath("designs"), root / "designs");
  fs::create_directory_symlink(sourcePath("studies/data"), root / "studies" / "data");
  return root;
}

}  // namespace

TEST_CASE("the catalogue of bad inputs: exit code, message parts, nothing written",
          "[cli][hardening][catalogue]") {
  const std::vector<Case> cases = catalogue();
  REQUIRE(cases.size() >= 100);
  const fs::path root = scratch();
  int failed = 0;
  std::string report;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const fs::path out = root / ("out" + std::to_string(i));
    std::string file;
    int line = 0;  // 1-based line of the edit in the copy
    if (!c.base.empty()) {
      std::string text = slurp(sourcePath(c.base));
      if (c.find) {
        const std::size_t at = text.find(*c.find);
        INFO(c.name << ": `find` text not in " << c.base);
        REQUIRE(at != std::string::npos);  // the catalogue follows the shipped files
        text.replace(at, c.find->size(), c.replace.value_or(""));
        line = 1 + static_cast<int>(
                       std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
      } else {
        text = c.replace.value_or("");
      }
      const fs::path rel = fs::path(c.base).filename();
      const fs::path where =
          c.base.rfind("studies/", 0) == 0 && c.base.find("/data/") == std::string::npos
              ? root / "studies" / rel
              : root / rel;
      std::ofstream(where, std::ios::binary) << text;
      file = where.string();
    }
    std::string cmd =
        replaceAll(replaceAll(replaceAll(c.command, "{file}", file), "{out}", out.string()),
                   "{src}", sourcePath(""));
    std::string log;
    const int code = runCommand(binaryPath() + " " + cmd, log);
    std::vector<std::string> missing;
    for (std::string m : c.message) {
      m = replaceAll(m, "{name}", fs::path(c.base).filename().string());
      m = replaceAll(m, "{next_line}", std::to_string(line + 1));
      m = replaceAll(m, "{line}", std::to_string(line));
      if (lower(log).find(lower(m)) == std::string::npos) missing.push_back(m);
    }
    const bool wrote = fs::exists(out);
    if (code != c.exit || !missing.empty() || wrote) {
      ++failed;
      std::ostringstream why;
      why << "case '" << c.name << "': exit " << code << " (expected " << c.exit << ")";
      for (const std::string& m : missing) why << ", message lacks '" << m << "'";
      if (wrote) why << ", wrote " << out.string();
      why << "\n  $ armstudy " << cmd << "\n  " << log;
      report += why.str() + "\n";
    }
  }
  INFO(failed << " of " << cases.size() << " cases failed\n" << report);
  CHECK(failed == 0);
  fs::remove_all(root);
}
