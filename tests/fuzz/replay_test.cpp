// The readers' fuzz targets (fuzz_targets.hpp) in every test run: each seed of the
// corpus (the shipped files plus tests/fuzz/corpus/<target>/, where findings are kept as
// regression inputs) and a fixed number of seeded mutations of them (byte flips, deletions,
// duplications, dictionary tokens such as nan, 1e308, quotes and brackets). A reader must accept
// an input or throw InputError naming the file; any other exception fails the test and the input
// is saved under output/fuzz-findings/; a crash leaves it there as <target>-last-input.
// The libFuzzer binaries of the same targets run on demand (README "Fuzzing").
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "fuzz_targets.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace armstudy;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> seeds(const std::string& target,
                               const std::vector<std::pair<std::string, std::string>>& globs) {
  std::vector<fs::path> files;
  auto add = [&](const fs::path& dir, const std::string& suffix) {
    if (!fs::is_directory(dir)) return;
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string name = e.path().filename().string();
      if (e.is_regular_file() && name.size() >= suffix.size() &&
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
        files.push_back(e.path());
    }
  };
  for (const auto& [dir, suffix] : globs)
    add(fs::path(dir).is_absolute() ? fs::path(dir) : fs::path(test::sourcePath(dir)), suffix);
  add(test::sourcePath("tests/fuzz/corpus/" + target), "");
  std::sort(files.begin(), files.end());  // a fixed order: the same mutations on every machine
  std::vector<std::string> out;
  for (const fs::path& f : files) out.push_back(slurp(f));
  return out;
}

const std::vector<std::string> kTokens = {"nan",
                                          "inf",
                                          "-inf",
                                          "1e308",
                                          "-1e308",
                                          "1e-320",
                                          "0",
                                          "-1",
                                          "99999999999999999999",
                                          "=",
                                          "\"",
                                          "[",
                                          "]",
                                          "[[",
                                          "]]",
                                          "{",
                                          "}",
                                          ",",
                                          "#",
                                          "\n",
                                          "true",
                                          "deg",
                                          "mm",
                                          "\xff",
                                          std::string(1, '\0')};

std::string mutate(std::string s, std::mt19937_64& rng) {
  auto pick = [&](std::size_t n) {
    return n == 0 ? std::size_t{0} : static_cast<std::size_t>(rng() % n);
  };
  const int ops = 1 + static_cast<int>(rng() % 4);
  for (int k = 0; k < ops; ++k) {
    switch (rng() % 6) {
      case 0:  // flip a byte
        if (!s.empty()) s[pick(s.size())] = static_cast<char>(rng() & 0xff);
        break;
      case 1: {  // delete a range
        const std::size_t a = pick(s.size() + 1),
                          n = std::min<std::size_t>(1 + pick(16), s.size() - a);
        s.erase(a, n);
        break;
      }
      case 2: {  // duplicate a range
        const std::size_t a = pick(s.size() + 1),
                          n = std::min<std::size_t>(1 + pick(64), s.size() - a);
        s.insert(pick(s.size() + 1), s.substr(a, n));
        break;
      }
      case 3:  // insert a token
        s.insert(pick(s.size() + 1), kTokens[pick(kTokens.size())]);
        break;
      default: {  // replace a number (or the text after a '=' or ',') with a token
        const std::size_t at = pick(s.size() + 1);
        const std::size_t b = s.find_first_of("0123456789", at);
        if (b == std::string::npos) break;
        const std::size_t e = s.find_first_not_of("0123456789.eE+-", b);
        s.replace(b, (e == std::string::npos ? s.size() : e) - b, kTokens[pick(9)]);
      }
    }
  }
  return s;
}

// The first `lines` lines of `text` (all of it when it has fewer).
std::string firstLines(const std::string& text, int lines) {
  std::size_t end = 0;
  for (int k = 0; k < lines && end != std::string::npos; ++k) {
    end = text.find('\n', end);
    if (end != std::string::npos) ++end;
  }
  return end == std::string::npos ? text : text.substr(0, end);
}

// Runs `target` on every seed and `mutations` mutations of the seeds (of `mutation_seeds` where
// given); returns the findings (message per input).
std::vector<std::string> replay(const std::string& name,
                                const std::function<void(const std::uint8_t*, std::size_t)>& target,
                                const std::vector<std::string>& corpus, int mutations,
                                const std::vector<std::string>& mutation_seeds = {}) {
  const fs::path dir = test::sourcePath("output/fuzz-findings/" + name);
  fs::create_directories(dir);
  std::vector<std::string> findings;
  std::mt19937_64 rng(0xa5f00d ^ std::hash<std::string>{}(name));
  const bool trace = std::getenv("ARMSTUDY_FUZZ_TRACE") != nullptr;
  auto run = [&](const std::string& input) {
    if (trace) {  // the mutations are the same on every run: rerun with the variable set after a
                  // crash
      std::ofstream last(dir / (name + "-last-input"), std::ios::binary | std::ios::trunc);
      last << input;
    }
    try {
      target(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
    } catch (const std::exception& e) {
      const fs::path saved = dir / (name + "-" + std::to_string(std::hash<std::string>{}(input)));
      std::ofstream(saved, std::ios::binary) << input;
      findings.push_back(std::string(e.what()) + " (input saved to " + saved.string() + ")");
    }
  };
  for (const std::string& s : corpus) run(s);
  const std::vector<std::string>& from = mutation_seeds.empty() ? corpus : mutation_seeds;
  for (int k = 0; k < mutations; ++k) run(mutate(from[rng() % from.size()], rng));
  fs::remove(dir / (name + "-last-input"));
  return findings;
}

// `seed_lines` > 0: the mutations start from each seed's first `seed_lines` lines (the whole seeds
// are read unmutated), so that a mutation's cost does not grow with the length of a data file whose
// rows all take the same path through the reader.
void check(const std::string& name,
           const std::function<void(const std::uint8_t*, std::size_t)>& target,
           const std::vector<std::pair<std::string, std::string>>& globs, int mutations,
           int seed_lines = 0) {
  const std::vector<std::string> corpus = seeds(name, globs);
  REQUIRE(corpus.size() >= 2);
  std::vector<std::string> mutation_seeds;
  if (seed_lines > 0)
    for (const std::string& s : corpus) mutation_seeds.push_back(firstLines(s, seed_lines));
  const std::vector<std::string> findings = replay(name, target, corpus, mutations, mutation_seeds);
  for (const std::string& f : findings) UNSCOPED_INFO(f);
  CHECK(findings.empty());
}

}  // namespace

TEST_CASE(
    "fuzz design reader: shipped designs and 15000 mutations accepted or rejected naming the file",
    "[fuzz]") {
  check("design", fuzz::design, {{"designs", ".toml"}}, 15000);
}

#ifndef ARMSTUDY_CORE_ONLY  // the study reader needs every stage: not in the sanitizer subset's
                            // library
TEST_CASE("fuzz study reader: shipped studies and 800 mutations accepted or rejected naming a file",
          "[fuzz]") {
  check("study", fuzz::study, {{"studies", ".toml"}}, 800);
}

TEST_CASE(
    "fuzz joint-log reader: seed logs and 3000 mutations accepted or rejected naming the log or "
    "the study",
    "[fuzz]") {
  // Seeds: tests/fuzz/corpus/joint_log/ (a smooth log, one with jitter, and a one-row log that
  // crashed the reader with a time column).
  check("joint_log", fuzz::jointLog, {}, 3000);
}
#endif

TEST_CASE("fuzz CSV reader: shipped data and 30000 mutations accepted or rejected naming the file",
          "[fuzz]") {
  // The seeds are read whole; the mutations start from each file's header and first rows (every row
  // takes the same path through the reader). The scenario: mutated rows reach the cell checks and
  // past them (more than 1 % of the mutations are accepted), and most mutations are rejected.
  constexpr int kCsvSeedLines = 12, kMutations = 30000;
  const std::vector<std::pair<std::string, std::string>> data = {{"studies/data", ".csv"}};
  int accepted = 0, inputs = 0;
  check(
      "csv",
      [&](const std::uint8_t* bytes, std::size_t size) {
        ++inputs;
        accepted += fuzz::csv(bytes, size) ? 1 : 0;
      },
      data, kMutations, kCsvSeedLines);
  const int seed_count = static_cast<int>(seeds("csv", data).size());
  INFO(accepted << " of " << inputs << " inputs accepted, " << seed_count << " of them seeds");
  CHECK(inputs == seed_count + kMutations);
  CHECK(accepted - seed_count > kMutations / 100);
  CHECK(accepted < inputs / 2);
}

TEST_CASE(
    "fuzz baseline reader: shipped baselines and 30000 mutations accepted or rejected naming the "
    "file",
    "[fuzz]") {
  check("baseline", fuzz::baseline, {{"studies", ".baseline.json"}}, 30000);
}

TEST_CASE("fuzz URDF reader: the real arms and 5000 mutations accepted or rejected naming the file",
          "[fuzz]") {
  // The arms of ../shared/robots, read in place (tests/CMakeLists.txt, ARMSTUDY_ROBOTS_DIR).
  check("urdf", fuzz::urdf,
        {{ARMSTUDY_ROBOTS_DIR "/panda_description/urdf", ".urdf"},
         {ARMSTUDY_ROBOTS_DIR "/ur_description/urdf", ".urdf"}},
        5000);
}

TEST_CASE(
    "fuzz URDF mesh reading: a binary and an ASCII STL and 2000 mutations accepted or rejected "
    "naming the URDF",
    "[fuzz]") {
  // Seeds: tests/fuzz/corpus/urdf_mesh/ (a 50 mm cube in millimetres, binary and ASCII). Flipped
  // bytes of a binary STL give NaN, infinite and huge vertices and wrong triangle counts.
  check("urdf_mesh", fuzz::urdf_mesh, {}, 2000);
}

TEST_CASE("fuzz harness: a reader that throws anything but a named InputError is a finding",
          "[fuzz]") {
  // The oracle of the tests above can fail: a target throwing std::out_of_range, and one whose
  // InputError names another file, are both reported.
  const std::vector<std::string> corpus = {"a", "b"};
  auto wrong_exception = [](const std::uint8_t*, std::size_t) { throw std::out_of_range("boom"); };
  CHECK(replay("selftest", wrong_exception, corpus, 3).size() == 5);
  auto unnamed = [](const std::uint8_t*, std::size_t) {
    try {
      throw InputError("other.toml", 1, "k", "bad");
    } catch (const InputError& e) {
      fuzz::requireNamed(e, "fuzz_design.toml");
    }
  };
  CHECK(replay("selftest", unnamed, corpus, 0).size() == 2);
  auto fine = [](const std::uint8_t*, std::size_t) {};
  CHECK(replay("selftest", fine, corpus, 3).empty());
  fs::remove_all(test::sourcePath("output/fuzz-findings/selftest"));
}
