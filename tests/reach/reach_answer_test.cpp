// The reach answer calls designs level when their reachable counts differ by less than the grid
// resolves (half the poses on their reach boundaries), and says what each reaches alone.
// boundaryPoses is checked against a disc's boundary counted by brute force here.
#include "stages/reach/reach_answer.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

using namespace armstudy;
using namespace armstudy::reach_report;

namespace {

DesignCoverage designEntry(const std::string& name, long reachable, long poses, long boundary) {
  return {name, reachable, 0, double(reachable) / double(poses), boundary};
}

std::string answerFor(long poses, const std::vector<DesignCoverage>& designs,
                      const std::vector<PairCoverage>& pairs) {
  ReachFacts facts;
  facts.sets.push_back({"grid `row`", poses, designs, pairs, {}, {}});
  std::vector<std::string> answer, warnings;
  reach_report::reachAnswer(facts, answer, warnings);
  REQUIRE(answer.size() == 1);
  return answer[0];
}

}  // namespace

TEST_CASE("boundaryPoses counts the reachable poses beside an unreachable one", "[reach]") {
  TaskGrid g;
  const int n = 21;
  g.axes[0] = {0.0, 2.0, 0.1};
  g.axes[1] = {0.0, 2.0, 0.1};
  g.axes[2] = {0.0, 0.0, 1.0};
  g.orientations = {Orientation{}, Orientation{}};
  REQUIRE(g.dims()[0] == n);
  PoseSweep s;
  s.size = g.size();
  s.status.assign(static_cast<std::size_t>(s.size),
                  static_cast<std::uint8_t>(ReachStatus::OutOfReach));
  auto inside = [](int i, int j) { return std::hypot(i - 10, j - 10) <= 7.5; };
  for (int o = 0; o < 2; ++o)  // the second orientation reaches nothing
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        if (o == 0 && inside(i, j))
          s.status[static_cast<std::size_t>(j * n + i)] =
              static_cast<std::uint8_t>(ReachStatus::Reachable);
  long expected = 0;  // brute force on (i, j): a 4-neighbour outside the disc
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (inside(i, j) &&
          (!inside(i - 1, j) || !inside(i + 1, j) || !inside(i, j - 1) || !inside(i, j + 1)))
        ++expected;
  CHECK(expected > 20);
  CHECK(reach_report::boundaryPoses(g, s) == expected);
  // A region that fills the grid has no boundary: its edge is the grid's, and the other
  // orientation (which reaches nothing) is not a neighbour.
  std::fill(s.status.begin(), s.status.begin() + n * n,
            static_cast<std::uint8_t>(ReachStatus::Reachable));
  CHECK(reach_report::boundaryPoses(g, s) == 0);
}

TEST_CASE("reach answer: a difference inside the boundary's resolution is level", "[reach]") {
  // ur5_vs_first_prototype's Fig. 3.8 row: 4002 and 3944 of 7268 poses, boundaries 214 and 212.
  const std::vector<PairCoverage> pairs = {{"six", "ur5", 763, 705}};
  const std::string a =
      answerFor(7268,
                {designEntry("six", 4002, 7268, 214), designEntry("ur5", 3944, 7268, 212),
                 designEntry("flange", 3478, 7268, 190)},
                pairs);
  INFO(a);
  CHECK(a.find("Level at the top") != std::string::npos);
  CHECK(a.find("reaches the most") == std::string::npos);
  CHECK(a.find("only `six` reaches 763, only `ur5` 705") != std::string::npos);
  CHECK(a.find("then `flange`") != std::string::npos);
  // Twice the difference beyond the two boundaries: a winner.
  const std::string b = answerFor(
      7268, {designEntry("six", 4002, 7268, 50), designEntry("ur5", 3944, 7268, 50)}, pairs);
  INFO(b);
  CHECK(b.find("`six` reaches the most") != std::string::npos);
  CHECK(b.find("Level") == std::string::npos);
}

TEST_CASE("reach answer: a largest reach off its reference by more than a grid step is a warning",
          "[reach]") {
  auto run = [](double found, double step) {
    ReachFacts facts;
    facts.sets.push_back({"grid `line`",
                          101,
                          {designEntry("ur5", 70, 101, 1)},
                          {},
                          {},
                          {{"ur5", 0.85, found, step}}});
    std::vector<std::string> answer, warnings;
    reach_report::reachAnswer(facts, answer, warnings);
    return std::make_pair(answer, warnings);
  };
  const auto [answer, warnings] = run(0.95, 0.005);  // the shipped UR5 line: +100 mm at 5 mm
  REQUIRE(answer.size() == 2);
  CHECK(answer[1].find("950 mm against the reference 850 mm (+100 mm, +11.8 %") !=
        std::string::npos);
  REQUIRE(warnings.size() == 1);
  CHECK(warnings[0].find("larger than the grid resolves") != std::string::npos);
  CHECK(run(0.853, 0.005).second.empty());  // within one step: no warning
}
