// Task grids and CSV pose lists: counts against the thesis' grid (eq. 3.3), index layout against
// an explicit loop, and every bad-input rule with its line number.
#include "tasks/task_grid.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "common/errors.hpp"
#include "io/pose_list_io.hpp"

using namespace armstudy;

namespace {
constexpr double kExact = 1e-12;
TaskGrid fig38() {
  TaskGrid g;
  g.name = "fig3_8";
  g.axes = {AxisRange{-0.78, 0.78, 0.01}, AxisRange{0.3, 1.2, 0.01}, AxisRange{1.2, 1.2, 1}};
  g.orientations = {{0, 0, -40 * M_PI / 180}, {0, 0, 40 * M_PI / 180}};
  return g;
}
}  // namespace

TEST_CASE("the grid of thesis eq. 3.3 has 157 x 91 x 2 = 28,574 poses", "[tasks]") {
  const TaskGrid g = fig38();
  CHECK(g.validate().empty());
  CHECK(g.dims() == std::array<int, 3>{157, 91, 1});
  CHECK(g.size() == 28574);
  CHECK(g.spatialDimension() == 2);
  CHECK(g.lineLength() == 157);
  CHECK(g.axes[0].value(156) == Approx(0.78).margin(kExact));
}

TEST_CASE("flat pose index follows x fastest, then y, z, orientation", "[tasks]") {
  TaskGrid g;
  g.axes = {AxisRange{0, 0.2, 0.1}, AxisRange{1, 1.3, 0.1}, AxisRange{-1, -0.5, 0.25}};
  g.orientations = {{0.1, 0, 0}, {0.2, 0, 0}};
  long idx = 0;
  for (int o = 0; o < 2; ++o)
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 3; ++i, ++idx) {
          const TaskVector6 w = g.pose(idx);
          CHECK(w[0] == Approx(0.1 * i).margin(kExact));
          CHECK(w[1] == Approx(1 + 0.1 * j).margin(kExact));
          CHECK(w[2] == Approx(-1 + 0.25 * k).margin(kExact));
          CHECK(w[3] == Approx(0.1 * (o + 1)).margin(kExact));
        }
  CHECK(idx == g.size());
}

TEST_CASE("a line along y when x has a single value", "[tasks]") {
  TaskGrid g;
  g.axes = {AxisRange{0, 0, 1}, AxisRange{0, 1, 0.5}, AxisRange{0, 1, 0.25}};
  g.orientations = {{}};
  CHECK(g.lineLength() == 3);
  CHECK(g.lines() == 5);
}

TEST_CASE("axis ranges: non-positive step and empty range are rejected", "[tasks][bad-input]") {
  CHECK_FALSE(AxisRange{0, 1, 0}.validate().empty());
  CHECK_FALSE(AxisRange{0, 1, -0.1}.validate().empty());
  CHECK_FALSE(AxisRange{1, 0, 0.1}.validate().empty());
  CHECK(AxisRange{1, 1, 0.1}.count() == 1);
}

TEST_CASE("CSV pose lists: header order, comments and orientation columns", "[tasks]") {
  const PoseList l =
      parsePoseCsv("# poses\nz,x,y,gamma,beta,alpha\n1,2,3,0.3,0.2,0.1\n\n4,5,6,0,0,0\n", "p.csv",
                   TaskSpace::fullPose());
  REQUIRE(l.poses.size() == 2);
  CHECK(l.poses[0][0] == 2);
  CHECK(l.poses[0][2] == 1);
  CHECK(l.poses[0][3] == Approx(0.1));
  CHECK(l.poses[0][5] == Approx(0.3));
  CHECK(l.lines == std::vector<int>{3, 5});
  const PoseList p = parsePoseCsv("x,y,z\n0.1,0.2,0.3\n", "q.csv", TaskSpace::position());
  CHECK_FALSE(p.has_orientation);
}

TEST_CASE("CSV pose lists: a malformed row is reported with its line number",
          "[tasks][bad-input]") {
  auto lineOf = [](const std::string& text, const TaskSpace& ts) {
    try {
      parsePoseCsv(text, "bad.csv", ts);
    } catch (const InputError& e) {
      CHECK(e.file() == "bad.csv");
      return e.line();
    }
    return -1;
  };
  CHECK(lineOf("x,y,z\n1,2,3\n1,2,oops\n", TaskSpace::position()) == 3);
  CHECK(lineOf("x,y,z\n1,2\n", TaskSpace::position()) == 2);
  CHECK(lineOf("x,y,z\n\n1,2,3,4\n", TaskSpace::position()) == 3);
  CHECK(lineOf("x,y,z\n1,2,nan\n", TaskSpace::position()) == 2);
  CHECK(lineOf("x,y,w\n1,2,3\n", TaskSpace::position()) == 1);
  CHECK(lineOf("x,y,z,alpha\n1,2,3,4\n", TaskSpace::fullPose()) == 1);
  CHECK(lineOf("x,y,z\n1,2,3\n", TaskSpace::spraying()) == 1);
  CHECK(lineOf("x,y,z\n", TaskSpace::position()) > 0);
}
