// Crashes, hangs and deletions outside the output folder found by hand-made bad
// inputs, each kept as a regression test. Every case: exit 2 (input error), a message naming what
// is wrong, and nothing written.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "io/files.hpp"
#include "report/image.hpp"
#include "test_support.hpp"

using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {
fs::path hardeningDir(const std::string& name) {
  return armstudy::test::emptyTempDir("hardening_" + name);
}
}  // namespace

TEST_CASE("out-of-range command-line values are input errors and write nothing",
          "[cli][hardening]") {
  const fs::path d = hardeningDir("cli");
  const std::string study = sourcePath("studies/regression.toml"), out = (d / "out").string();
  struct Case {
    std::string args, message;
  };
  const Case cases[] = {
      {"run " + study + " --threads 100000 --output " + out, "--threads"},
      {"run " + study + " --threads 20000 --output " + out, "--threads"},
      {"run " + study + " --threads -1 --output " + out, "--threads"},
      {"run " + study + " --unit-size 99999999999 --output " + out, "--unit-size"},
      {"check " + study + " --threads 100000 --output " + out, "--threads"},
      {"fit " + sourcePath("designs/final_prototype_9dof.toml") + " --drive j6 --data " +
           sourcePath("studies/data/drive_testbed_module_b2.csv") +
           " --speed-bins 100000000 --load-bins 100000000 --out " + out,
       "--speed-bins"},
      {"fit " + sourcePath("designs/final_prototype_9dof.toml") + " --drive j6 --data " +
           sourcePath("studies/data/drive_testbed_module_b2.csv") + " --folds 127 --out " + out,
       "folds"},
      {"fit " + sourcePath("designs/final_prototype_9dof.toml") + " --drive j6 --data " +
           sourcePath("studies/data/drive_testbed_module_b2.csv") + " --folds 1 --out " + out,
       "--folds"},
  };
  for (const Case& c : cases) {
    INFO(c.args);
    std::string log;
    CHECK(runCommand(binaryPath() + " " + c.args, log) == 2);
    INFO(log);
    CHECK(log.find(c.message) != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  }
}

TEST_CASE("special and oversized files are refused instead of read forever", "[cli][hardening]") {
  const fs::path d = hardeningDir("files");
  const std::string out = (d / "out").string();
  const std::string fifo = (d / "design.fifo").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  for (const std::string& path : {std::string("/dev/zero"), fifo, d.string()}) {
    INFO(path);
    std::string log;
    // `timeout` turns a blocking read (the old behaviour on a FIFO) into a failure, not a hung
    // suite.
    CHECK(runCommand("timeout 20 " + binaryPath() + " describe " + path, log) == 2);
    CHECK(log.find("not a regular file") != std::string::npos);
    CHECK(runCommand("timeout 20 " + binaryPath() + " run " + path + " --output " + out, log) == 2);
    CHECK_FALSE(fs::exists(out));
  }
  // A regular file over the input limit (sparse: no disk space used).
  const fs::path big = d / "big.toml";
  fs::resize_file((std::ofstream(big), big), 300ull << 20);
  std::string log;
  CHECK(runCommand(binaryPath() + " describe " + big.string(), log) == 2);
  CHECK(log.find("exceeds the input limit") != std::string::npos);
}

TEST_CASE("overwriting never removes files outside the output folder a manifest lists",
          "[cli][hardening]") {
  const fs::path d = hardeningDir("overwrite");
  // The study `regression` writes into <out>/regression; a sibling folder that shares its prefix.
  const fs::path out = d / "out", mine = out / "regression", other = out / "regression_other";
  fs::create_directories(mine);
  fs::create_directories(other);
  std::ofstream(other / "keep.txt") << "not armstudy's\n";
  std::ofstream(d / "outside.txt") << "not armstudy's\n";
  fs::create_directory_symlink(other, mine / "link");
  std::ofstream(mine / "manifest.json")
      << R"({"files": ["../regression_other/keep.txt", "../../outside.txt", "link/keep.txt", "/etc/hostname"]})";
  const std::string run = binaryPath() + " run " + sourcePath("studies/regression.toml") +
                          " --overwrite --threads 2 --output " + out.string();
  std::string log;
  // A link inside the output folder stops the run before anything is removed or written.
  CHECK(runCommand(run, log) == 2);
  CHECK(log.find((mine / "link").string()) != std::string::npos);
  CHECK(fs::exists(other / "keep.txt"));
  fs::remove(mine / "link");
  REQUIRE(runCommand(run, log) == 0);
  CHECK(fs::exists(other / "keep.txt"));
  CHECK(fs::exists(d / "outside.txt"));
  CHECK(fs::exists(mine / "manifest.json"));  // the new run's
}

TEST_CASE("the tick generator ends on ranges narrower than the values' resolution",
          "[report][hardening]") {
  // Constant data plus rounding: a step below one ulp of the values made `v += step` loop forever.
  const double lo = 1e6, hi = std::nextafter(1e6, 2e6);
  const std::vector<double> t = armstudy::report::niceTicks(lo, hi, 5);
  CHECK(t.size() <= 2);
  const std::vector<double> u = armstudy::report::niceTicks(0.0, 1.0, 5);  // an ordinary range
  CHECK(u.size() == 6);
  CHECK(u.front() == 0.0);
  CHECK(u.back() == Approx(1.0));
}

TEST_CASE(
    "one run per output folder, stale temporaries of a killed run removed, uncreatable folders "
    "named",
    "[cli][hardening]") {
  const fs::path d = hardeningDir("lock");
  const fs::path out = d / "out", mine = out / "regression";
  fs::create_directories(mine / "reach");
  // A killed run's temporaries (writeFileAtomic: <name>.tmp.<pid>) and a file that only looks
  // alike.
  std::ofstream(mine / "reach" / "summary.json.tmp.4242") << "half";
  std::ofstream(mine / "notes.tmp.txt") << "a user's file";
  // Another process holds the folder's lock: this test process, like a concurrent run.
  const std::string lock = (mine / ".armstudy.lock").string();
  const int fd = ::open(lock.c_str(), O_RDWR | O_CREAT, 0644);
  REQUIRE(fd >= 0);
  REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);
  const std::string run = binaryPath() + " run " + sourcePath("studies/regression.toml") +
                          " --threads 2 --output " + out.string();
  std::string log;
  CHECK(runCommand(run, log) == 2);
  CHECK(log.find("another armstudy run is writing") != std::string::npos);
  CHECK(fs::exists(mine / "reach" / "summary.json.tmp.4242"));  // untouched while locked
  ::close(fd);                                                  // the other run ends
  CHECK(runCommand(run, log) == 0);
  CHECK_FALSE(fs::exists(mine / "reach" / "summary.json.tmp.4242"));
  CHECK(fs::exists(mine / "notes.tmp.txt"));
  CHECK(fs::exists(mine / "manifest.json"));
  // An output root below a regular file: an input error naming the path, not a raw filesystem
  // error.
  std::ofstream(d / "file.txt") << "x";
  CHECK(runCommand(binaryPath() + " run " + sourcePath("studies/regression.toml") + " --output " +
                       (d / "file.txt" / "sub").string(),
                   log) == 2);
  CHECK(log.find("cannot create the output folder") != std::string::npos);
}

namespace {
// ulimit -f of the failing fit, in the 512-byte blocks of POSIX sh (16 kB): above the small files
// of a tcp fit of 30 rows (residuals, history, calibrated design, VTK files) but below its larger
// ones (the plots, 50-100 kB, and result.json, 50 kB), so the fit fails part-way through writing
// its new result.
constexpr int kFileSizeLimitBlocks = 32;

// Every file below `dir` by relative path.
std::map<std::string, std::string> files(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file())
      out[fs::relative(e.path(), dir).string()] = armstudy::readFileOrThrow(e.path().string());
  return out;
}
}  // namespace

TEST_CASE(
    "a fit that fails mid-way leaves the previous result whole, a complete fit replaces the folder "
    "at once",
    "[cli][hardening][calibration]") {
  const fs::path d = hardeningDir("fit_swap");
  const std::string design = sourcePath("designs/final_prototype_7dof.toml"),
                    data = (d / "tcp.csv").string();
  const fs::path res = d / "res";
  std::string log;
  REQUIRE(runCommand(binaryPath() + " synth " + design +
                         " --kind tcp --rows 30 --noise 2e-4 --out " + data,
                     log) == 0);
  const std::string fit =
      binaryPath() + " fit " + design + " --kind tcp --data " + data + " --out " + res.string();
  REQUIRE(runCommand(fit, log) == 0);
  std::ofstream(res / "notes.txt") << "a user's note";
  const auto before = files(res);
  REQUIRE(before.count("result.json") == 1);
  REQUIRE(before.count("final_prototype_7dof_calibrated.toml") == 1);

  // Mid-way: under a file-size limit (SIGXFSZ ignored, so a longer write fails with EFBIG) the fit
  // fails while writing its result into the staging folder.
  CHECK(runCommand("sh -c 'trap \"\" XFSZ; ulimit -f " + std::to_string(kFileSizeLimitBlocks) +
                       "; exec " + fit + "'",
                   log) == 1);
  INFO(log);
  CHECK(log.find("res.staging.") != std::string::npos);  // failed while writing the new result
  CHECK(files(res) == before);                           // history.csv included
  for (const auto& e : fs::directory_iterator(d))
    CHECK(e.path().filename().string().find(".staging.") == std::string::npos);

  // The staging folder of a killed fit (a process id no process has) goes with the next fit, which
  // publishes its result as one folder: the same files, one more history row, the note kept. A
  // folder in the way of one of its files (which stopped the file-by-file moves half-way, after the
  // plots and before residuals.csv and history.csv) is replaced with the rest.
  fs::create_directories(d / "res.staging.999999999");
  fs::remove(res / "residuals.csv");
  fs::create_directories(res / "residuals.csv");
  std::ofstream(res / "residuals.csv" / "in_the_way.txt") << "x";
  REQUIRE(runCommand(fit, log) == 0);
  CHECK(fs::is_regular_file(res / "residuals.csv"));
  const auto after = files(res);
  CHECK_FALSE(fs::exists(d / "res.staging.999999999"));
  CHECK(after.size() == before.size());
  for (const auto& [name, text] : before) CHECK(after.count(name) == 1);
  CHECK(after.at("notes.txt") == "a user's note");
  const std::string& h0 = before.at("history.csv");
  const std::string& h1 = after.at("history.csv");
  CHECK(std::count(h1.begin(), h1.end(), '\n') == std::count(h0.begin(), h0.end(), '\n') + 1);
  CHECK(h1.rfind(h0, 0) == 0);  // appended, the earlier rows as they were

  // A second fit into the folder while one is running (here: this process holds the fit's lock,
  // <out>.lock beside the folder, which is swapped as a whole) stops at once with an input error
  // naming the folder; nothing in it changes. Without the lock both would read the same history
  // and the later commit would drop the other's row.
  {
    const int fd = ::open((d / "res.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    REQUIRE(fd >= 0);
    REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);
    CHECK(runCommand(fit, log) == 2);
    INFO(log);
    CHECK(log.find("another armstudy run is writing") != std::string::npos);
    CHECK(log.find(res.string()) != std::string::npos);
    CHECK(files(res) == after);
    ::close(fd);
  }
  REQUIRE(runCommand(fit, log) == 0);  // the lock released: the next fit runs
  const std::string h2 = files(res).at("history.csv");
  CHECK(std::count(h2.begin(), h2.end(), '\n') == std::count(h1.begin(), h1.end(), '\n') + 1);
}

namespace {
// What is at `path` (not following a link): the file type bits and, for a device, its number.
std::pair<mode_t, dev_t> nodeKind(const fs::path& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return {0, 0};
  return {st.st_mode & S_IFMT, st.st_rdev};
}

// Every entry below `dir` (links not followed), by relative path.
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    out.push_back(fs::relative(e.path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}
}  // namespace

TEST_CASE("an --out onto a FIFO, a device or a folder leaves the node as it was",
          "[cli][hardening][writer]") {
  const fs::path d = hardeningDir("writer_nodes");
  const std::string design = sourcePath("designs/first_prototype_6dof.toml");
  // The test's own nodes (never the system's): a FIFO, a character device like /dev/null (1, 3;
  // the suite runs as root: a failing mknod fails the test) and a folder, each under names the
  // commands accept.
  const std::vector<std::string> names = {"fifo", "null", "folder"};
  for (const std::string& n : names) {
    for (const std::string ext : {".svg", ".toml", ".csv", ""}) {
      const fs::path p = d / (n + ext);
      if (n == "fifo") REQUIRE(::mkfifo(p.c_str(), 0600) == 0);
      if (n == "null") REQUIRE(::mknod(p.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0);
      if (n == "folder") REQUIRE(fs::create_directory(p));
    }
  }
  std::string log;
  const std::string tcp = (d / "data" / "tcp.csv").string();
  fs::create_directories(d / "data");
  REQUIRE(runCommand(binaryPath() + " synth " + sourcePath("designs/final_prototype_7dof.toml") +
                         " --kind tcp --rows 20 --out " + tcp,
                     log) == 0);
  const auto before = entries(d);
  for (const std::string& n : names) {
    const std::string at = (d / n).string();
    std::vector<std::string> commands = {
        "draw " + design + " --out " + at + ".svg",
        "convert " + design + " " + at + ".toml",
        "synth " + design + " --kind tcp --rows 5 --out " + at + ".csv",
    };
    if (n != "folder")  // a fit's --out is a folder
      commands.push_back("fit " + sourcePath("designs/final_prototype_7dof.toml") +
                         " --kind tcp --data " + tcp + " --out " + at);
    for (const std::string& c : commands) {
      INFO(c);
      const std::string target = c.substr(c.rfind(' ') + 1);
      const auto kind = nodeKind(target);
      CHECK(runCommand("timeout 60 " + binaryPath() + " " + c, log) == 2);
      INFO(log);
      CHECK(log.find(target) != std::string::npos);
      CHECK(nodeKind(target) == kind);
    }
  }
  CHECK(entries(d) == before);  // no temporaries, no lock file beside a refused --out
  CHECK(nodeKind(d / "null.svg") == std::make_pair(mode_t(S_IFCHR), makedev(1, 3)));
  CHECK(nodeKind(d / "fifo.csv").first == S_IFIFO);
}

TEST_CASE("a run never writes through a symbolic link planted inside its output folder",
          "[cli][hardening][writer]") {
  const fs::path d = hardeningDir("writer_links");
  const fs::path out = d / "out", mine = out / "regression", outside = d / "outside";
  const std::string run = binaryPath() + " run " + sourcePath("studies/regression.toml") +
                          " --threads 2 --output " + out.string();
  // A link at a result file's path, at a subfolder's path, at the checkpoint store's and at the
  // lock file's, each pointing outside the output folder.
  const std::vector<std::pair<std::string, bool>> plants = {
      {"designs.json", false}, {"reach", true}, {".partial", true}, {".armstudy.lock", false}};
  for (const auto& [rel, folder] : plants) {
    INFO(rel);
    fs::remove_all(d);
    fs::create_directories(mine);
    fs::create_directories(outside / "folder");
    std::ofstream(outside / "file.json") << "not armstudy's\n";
    if (folder)
      fs::create_directory_symlink(outside / "folder", mine / rel);
    else
      fs::create_symlink(outside / "file.json", mine / rel);
    const auto outside_before = entries(outside);
    std::string log;
    CHECK(runCommand(run, log) == 2);
    INFO(log);
    CHECK(log.find((mine / rel).string()) != std::string::npos);
    CHECK(log.find("symbolic link") != std::string::npos);
    CHECK(entries(outside) == outside_before);
    CHECK(armstudy::readFileOrThrow((outside / "file.json").string()) == "not armstudy's\n");
    CHECK(fs::is_symlink(mine / rel));  // left for the user to remove
    CHECK_FALSE(fs::exists(mine / "manifest.json"));
  }
}

TEST_CASE(
    "a run with --overwrite and a manifest that lists the folder itself or a subfolder goes on",
    "[cli][hardening][writer]") {
  const fs::path d = hardeningDir("writer_manifest");
  const fs::path out = d / "out", mine = out / "regression";
  fs::create_directories(mine / "notes");
  std::ofstream(mine / "notes" / "keep.txt") << "a user's note\n";
  std::ofstream(mine / "manifest.json") << R"({"files": [".", "", "notes", "./", "reach/.."]})";
  std::string log;
  const std::string run = binaryPath() + " run " + sourcePath("studies/regression.toml") +
                          " --overwrite --threads 2 --output " + out.string();
  CHECK(runCommand(run, log) == 0);
  INFO(log);
  CHECK(fs::exists(mine / "notes" / "keep.txt"));
  const std::string manifest = armstudy::readFileOrThrow((mine / "manifest.json").string());
  CHECK(manifest.find("designs.json") != std::string::npos);  // the new run's
}
