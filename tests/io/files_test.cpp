// An output folder published as a whole (io/files.hpp makeStagingFolder, publishFolder).
#include "io/files.hpp"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>

#include "common/errors.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

fs::path freshDir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("armstudy_files_" + name + "." + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Every entry below `dir` by relative path: file content, "->target" for a link, "/" for a folder.
std::map<std::string, std::string> tree(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string rel = e.path().lexically_relative(dir).generic_string();
    if (e.is_symlink())
      out[rel] = "->" + fs::read_symlink(e.path()).string();
    else if (e.is_directory())
      out[rel] = "/";
    else
      out[rel] = readFileOrThrow(e.path().string());
  }
  return out;
}

// A process id no process has (above the kernel's pid_max): the staging folder of a killed run.
const std::string kDeadPid = "999999999";

}  // namespace

TEST_CASE("publishFolder swaps the new result in as a whole and keeps what it does not replace",
          "[io][files]") {
  const fs::path d = freshDir("publish");
  const fs::path out = d / "res";
  // A first result into a folder that does not exist yet.
  std::string staging = makeStagingFolder(out.string());
  CHECK(fs::path(staging).parent_path() == fs::weakly_canonical(d));
  writeFileAtomic(staging + "/result.json", "{\"run\": 1}\n");
  writeFileAtomic(staging + "/plots/a.svg", "a1");
  writeFileAtomic(staging + "/plots/old_only.svg", "kept");
  publishFolder(staging, out.string());
  CHECK_FALSE(fs::exists(staging));
  CHECK(tree(out) == std::map<std::string, std::string>{{"plots", "/"},
                                                        {"plots/a.svg", "a1"},
                                                        {"plots/old_only.svg", "kept"},
                                                        {"result.json", "{\"run\": 1}\n"}});

  // A second result: its files replace, the others stay (a user's note, a link, a temporary does
  // not).
  std::ofstream(out / "notes.txt") << "mine";
  fs::create_directory_symlink("plots", out / "figures");
  std::ofstream(out / "result.json.tmp.4242") << "half";
  staging = makeStagingFolder(out.string());
  writeFileAtomic(staging + "/result.json", "{\"run\": 2}\n");
  writeFileAtomic(staging + "/plots/a.svg", "a2");
  writeFileAtomic(staging + "/notes.txt/inside", "a folder where the old result had a file");
  publishFolder(staging, out.string());
  CHECK(tree(out) == std::map<std::string, std::string>{
                         {"figures", "->plots"},
                         {"notes.txt", "/"},
                         {"notes.txt/inside", "a folder where the old result had a file"},
                         {"plots", "/"},
                         {"plots/a.svg", "a2"},
                         {"plots/old_only.svg", "kept"},
                         {"result.json", "{\"run\": 2}\n"}});
  // Nothing but the output folder is left beside it.
  for (const auto& e : fs::directory_iterator(d)) CHECK(e.path().filename() == "res");
}

TEST_CASE(
    "a failed publish leaves the output folder as it was, killed runs' leftovers are cleaned up",
    "[io][files]") {
  const fs::path d = freshDir("publish_fail");
  const fs::path out = d / "res";
  fs::create_directories(out);
  std::ofstream(out / "history.csv") << "old\n";
  const auto before = tree(out);
  CHECK_THROWS(publishFolder((d / "no_such_staging").string(), out.string()));
  CHECK(tree(out) == before);
  // An output folder that is a file: an input error before anything is written.
  std::ofstream(d / "a_file") << "x";
  CHECK_THROWS_AS(makeStagingFolder((d / "a_file").string()), InputError);
  fs::remove(d / "a_file");

  // A staging folder of a killed run, and the previous folder of a run killed between its two
  // renames (a file system without RENAME_EXCHANGE) while the output folder is missing.
  fs::create_directories(d / ("res.staging." + kDeadPid));
  const fs::path other = d / "other";
  fs::create_directories(d / ("other.previous." + kDeadPid));
  std::ofstream(d / ("other.previous." + kDeadPid) / "history.csv") << "other\n";
  const std::string staging = makeStagingFolder(out.string());
  CHECK_FALSE(fs::exists(d / ("res.staging." + kDeadPid)));
  CHECK(fs::is_directory(staging));
  const std::string staging_other = makeStagingFolder(other.string());
  CHECK(readFileOrThrow((other / "history.csv").string()) == "other\n");  // put back
  CHECK_FALSE(fs::exists(d / ("other.previous." + kDeadPid)));
  fs::remove_all(staging);
  fs::remove_all(staging_other);

  // An output folder given as a symbolic link: the folder it names is replaced, the link stays.
  fs::create_directory_symlink("res", d / "link");
  const std::string s = makeStagingFolder((d / "link").string());
  CHECK(fs::path(s).filename().string().rfind("res.staging.", 0) == 0);
  writeFileAtomic(s + "/result.json", "{}\n");
  publishFolder(s, (d / "link").string());
  CHECK(fs::is_symlink(d / "link"));
  CHECK(tree(out) ==
        std::map<std::string, std::string>{{"history.csv", "old\n"}, {"result.json", "{}\n"}});
}
