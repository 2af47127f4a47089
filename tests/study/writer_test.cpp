// Writer (study/writer.hpp): files written and files other writers wrote are listed in call order,
// hold exactly their content, and a write that fails throws at once (the oracle: the files read
// back, and a path that cannot be created).
#include "study/writer.hpp"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("armstudy-writer-test-" + std::to_string(::getpid()) + "-" + name);
  fs::remove_all(dir);
  return dir;
}

}  // namespace

TEST_CASE("files are listed in call order and hold their content, with no temporaries left",
          "[writer]") {
  const fs::path dir = scratch("order");
  {
    Writer w(dir.string());
    w.text("a.txt", "first");
    std::vector<std::pair<std::string, std::string>> batch;
    for (int i = 0; i < 50; ++i)
      batch.emplace_back("sub/f" + std::to_string(i) + ".bin",
                         std::string(1000 + i, char('a' + i % 26)));
    for (const auto& [rel, content] : batch) w.text(rel, content);
    w.add("c.vti");
    w.text("d.txt", "last");
    REQUIRE(w.files().size() == 53);
    CHECK(w.files()[0] == "a.txt");
    CHECK(w.files()[1] == "sub/f0.bin");
    CHECK(w.files()[50] == "sub/f49.bin");
    CHECK(w.files()[51] == "c.vti");
    CHECK(w.files()[52] == "d.txt");
    for (const auto& [rel, content] : batch) CHECK(slurp(dir / rel) == content);
    CHECK(slurp(dir / "d.txt") == "last");
    for (const auto& e : fs::recursive_directory_iterator(dir))
      CHECK(e.path().string().find(".tmp.") == std::string::npos);
  }
  fs::remove_all(dir);
}

TEST_CASE("a write that fails throws and is not listed", "[writer]") {
  const fs::path dir = scratch("fail");
  fs::create_directories(dir);
  std::ofstream(dir / "blocker") << "a file where a folder would have to be";
  Writer w(dir.string());
  w.text("ok.txt", "fine");
  CHECK_THROWS(w.text("blocker/inside.txt", "cannot be written"));
  CHECK(slurp(dir / "ok.txt") == "fine");
  CHECK(w.files() == std::vector<std::string>{"ok.txt"});
  fs::remove_all(dir);
}
