// [[collision]] and [[collision_allowed]] design sections: parsing, and bad input reported as
// InputError with file, line and key.
#include <catch2/catch.hpp>

#include "collision/collision_model.hpp"
#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;

namespace {

// A minimal two-joint design; `extra` is appended (its first line is line 27 of the text).
std::string design(const std::string& extra) {
  return "[design]\n"      // 1
         "name = \"t\"\n"  // 2
         "[[joint]]\n"     // 3
         "name = \"j1\"\ntype = \"revolute\"\nx = 0\ny = 0\nz = 0\nalpha = 0\nbeta = 0\ngamma = 0\n"
         "min = -1\nmax = 1\n"  // 4-13
         "[[joint]]\n"          // 14
         "name = \"j2\"\ntype = \"revolute\"\nx = 0.3\ny = 0\nz = 0\nalpha = 0\nbeta = 0\ngamma = "
         "0\n"
         "min = -1\nmax = 1\n"  // 15-24
         "[tcp]\nx = 0.2\n"     // 25-26
         + extra;               // 27-
}

void expectError(const std::string& extra, int line, const std::string& key,
                 const std::string& words) {
  try {
    parseDesign(design(extra), "bad.toml");
    FAIL("expected an InputError for: " << extra);
  } catch (const InputError& e) {
    INFO(e.what());
    CHECK(e.file() == "bad.toml");
    CHECK(e.line() == line);
    CHECK(e.key() == key);
    CHECK(std::string(e.what()).find(words) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("collision volumes and allowed pairs are parsed in link frames with units") {
  const Model m =
      parseDesign(design("[[collision]]\n"
                         "link = \"base\"\nname = \"column\"\ntype = \"line\"\n"
                         "points = [[0, 0, 0], [0, 0, \"1200 mm\"]]\nradius = \"60 mm\"\n"
                         "[[collision]]\n"
                         "link = \"j2\"\ntype = \"triangle\"\n"
                         "points = [[0, 0, 0], [0.2, 0, 0], [0, 0.1, 0]]\nradius = 0.01\n"
                         "[[collision]]\n"
                         "link = \"j1\"\ntype = \"point\"\npoints = [[0.1, 0, 0]]\nradius = 0\n"
                         "[[collision_allowed]]\nlinks = [\"j2\", \"base\"]\nreason = \"test\"\n"),
                  "ok.toml");
  REQUIRE(m.collision.volumes.size() == 3);
  const auto& c = m.collision.volumes[0];
  CHECK(c.link == -1);
  CHECK(c.name == "column");
  CHECK(c.type == SsvType::Line);
  CHECK(c.p_L[1].z() == Approx(1.2).epsilon(test::kHandCheckTolerance));
  CHECK(c.radius_m == Approx(0.06).epsilon(test::kHandCheckTolerance));
  CHECK(c.source_line == 27);
  CHECK(m.collision.volumes[1].link == 1);
  CHECK(m.collision.volumes[1].type == SsvType::Triangle);
  CHECK(m.collision.volumes[2].type == SsvType::Point);
  REQUIRE(m.collision.allowed_pairs.size() == 1);
  CHECK(m.collision.allowed_pairs[0] == std::array<int, 2>{-1, 1});
  CHECK_FALSE(collision::isCollisionPair(m, -1, 1));
  CHECK_FALSE(collision::isCollisionPair(m, 0, 1));  // neighbours
}

TEST_CASE("bad collision input is an InputError naming file, line and key") {
  const std::string v = "[[collision]]\nlink = \"j1\"\n";  // lines 27, 28
  expectError(v + "type = \"point\"\npoints = [[0, 0, 0]]\nradius = \"-5 mm\"\n", 31,
              "collision[0].radius", "negative");
  expectError(v + "type = \"line\"\npoints = [[0.1, 0, 0], [0.1, 0, 0]]\nradius = 0.05\n", 30,
              "collision[0].points", "coincide");
  expectError(
      v + "type = \"triangle\"\npoints = [[0, 0, 0], [0.1, 0, 0], [0.1, 0, 0]]\nradius = 0.05\n",
      30, "collision[0].points", "coincide");
  expectError(
      v + "type = \"triangle\"\npoints = [[0, 0, 0], [0.1, 0, 0], [0.2, 0, 0]]\nradius = 0.05\n",
      30, "collision[0].points", "collinear");
  expectError(
      "[[collision]]\nlink = \"j7\"\ntype = \"point\"\npoints = [[0, 0, 0]]\nradius = 0.05\n", 28,
      "collision[0].link", "no link named 'j7'");
  expectError(v + "type = \"line\"\npoints = [[0, 0, 0]]\nradius = 0.05\n", 30,
              "collision[0].points", "needs 2 points");
  expectError(v + "type = \"box\"\npoints = [[0, 0, 0]]\nradius = 0.05\n", 29, "collision[0].type",
              "unknown SSV type");
  expectError(v + "type = \"point\"\npoints = [[0, 0]]\nradius = 0.05\n", 30, "collision[0].points",
              "[x, y, z]");
  expectError(v + "type = \"point\"\npoints = [[0, 0, 0]]\nradius = 0.05\ncolour = \"red\"\n", 32,
              "collision[0].colour", "unknown key");
  expectError(v + "type = \"point\"\npoints = [[0, 0, \"3 deg\"]]\nradius = 0.05\n", 30,
              "collision[0].points", "");
  expectError("[[collision_allowed]]\nlinks = [\"j1\", \"elbow\"]\n", 28,
              "collision_allowed[0].links", "no link named 'elbow'");
  expectError("[[collision_allowed]]\nlinks = [\"j1\", \"j1\"]\n", 28, "collision_allowed[0].links",
              "itself");
  expectError("[[collision_allowed]]\nlinks = [\"j1\"]\n", 28, "collision_allowed[0].links",
              "two link names");
}
