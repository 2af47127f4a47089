// Design files: the shipped designs load as the thesis tables say; every kind of bad input gets an
// error naming file, line and key.
#include "io/design_io.hpp"

#include <catch2/catch.hpp>
#include <regex>

#include "common/errors.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;

namespace {

const char* kGood = R"([design]
name = "two_link"
[[joint]]
name = "lift"
type = "prismatic"
x = 0
y = 0
z = 0.5
alpha = 0
beta = 0
gamma = 0
min = "-0.2 m"
max = 0.2
[[joint]]
name = "elbow"
type = "revolute"
x = 0.3
y = 0
z = 0
alpha = "pi/2"
beta = 0
gamma = "90 deg"
min = "-170 deg"
max = "170 deg"
[tcp]
x = "100 mm"
)";

// Replaces the first occurrence of `from` in kGood by `to`.
std::string variantOf(const std::string& from, const std::string& to) {
  std::string s = kGood;
  const auto pos = s.find(from);
  REQUIRE(pos != std::string::npos);
  return s.replace(pos, from.size(), to);
}

// Expects parseDesign to throw an InputError whose line and key match.
void expectError(const std::string& text, int line, const std::string& key,
                 const std::string& message_part) {
  try {
    parseDesign(text, "bad.toml");
    FAIL("expected an InputError for key " << key);
  } catch (const InputError& e) {
    INFO(e.what());
    CHECK(e.file() == "bad.toml");
    if (line > 0) CHECK(e.line() == line);
    CHECK(e.key() == key);
    CHECK(std::string(e.what()).find(message_part) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("a valid design parses with units converted", "[io][design]") {
  const Model m = parseDesign(kGood, "good.toml");
  REQUIRE(m.dof() == 2);
  CHECK(m.joints[0].type == JointType::Prismatic);
  CHECK(m.joints[0].limits.q_min == Approx(-0.2));
  CHECK(m.joints[1].offset.alpha == Approx(M_PI / 2));
  CHECK(m.joints[1].offset.gamma == Approx(M_PI / 2));
  CHECK(m.joints[1].limits.q_max == Approx(170 * M_PI / 180));
  CHECK(m.tcp.x == Approx(0.1));
  CHECK(m.file_hash.rfind("fnv1a64:", 0) == 0);
}

TEST_CASE("shipped designs reproduce the thesis tables", "[io][design]") {
  const Model a = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  REQUIRE(a.dof() == 9);  // Table 3.1
  CHECK(a.joints[0].type == JointType::Prismatic);
  CHECK(a.joints[0].offset.z == 0.75);
  CHECK(a.joints[3].offset.x == 0.23);
  CHECK(a.joints[3].offset.y == 0.15);
  CHECK(a.joints[8].offset.beta == Approx(M_PI / 2));
  const Model b6 = loadDesign(sourcePath("designs/first_prototype_6dof.toml"));
  REQUIRE(b6.dof() == 6);  // Table 3.1, joints 1-6
  for (int i = 0; i < 6; ++i) {
    CHECK(b6.joints[i].offset.x == a.joints[i].offset.x);
    CHECK(b6.joints[i].offset.alpha == a.joints[i].offset.alpha);
  }
  const Model f9 = loadDesign(sourcePath("designs/final_prototype_9dof.toml"));
  REQUIRE(f9.dof() == 9);  // Table 3.2
  CHECK(f9.joints[0].offset.z == 0.796);
  CHECK(f9.joints[1].offset.y == 0.48);
  CHECK(f9.joints[3].offset.alpha == Approx(M_PI));
  const Model f7 = loadDesign(sourcePath("designs/final_prototype_7dof.toml"));
  REQUIRE(f7.dof() == 7);  // Table 3.2 without joints 5, 6; Table 3.3 for 4 -> 7
  CHECK(f7.joints[4].name == "j7");
  CHECK(f7.joints[4].offset.x == 0.4);
  CHECK(f7.joints[4].offset.y == -0.0295);
  CHECK(f7.joints[4].offset.z == -0.043);
  CHECK(f7.joints[4].offset.alpha == Approx(M_PI / 2));
  CHECK(f7.joints[4].offset.beta == Approx(M_PI / 2));
  for (const auto& rel : shippedDesigns())
    CHECK_FALSE(loadDesign(sourcePath(rel)).assumptions.empty());
}

TEST_CASE("bad design input names file, line and key", "[io][design][bad-input]") {
  // Line numbers refer to kGood: joint 2 starts on line 14, its `type` is line 16, `max` line 24.
  SECTION("missing key") { expectError(variantOf("x = 0.3\n", ""), 14, "joint[1].x", "missing"); }
  SECTION("unknown key") {
    expectError(variantOf("x = 0.3\n", "x = 0.3\nlength = 2\n"), 18, "joint[1].length",
                "unknown key");
  }
  SECTION("wrong type") {
    expectError(variantOf("x = 0.3", "x = true"), 17, "joint[1].x", "expected a number");
  }
  SECTION("unknown joint type") {
    expectError(variantOf("\"revolute\"", "\"spherical\""), 16, "joint[1].type",
                "unknown joint type");
  }
  SECTION("inverted limits") {
    expectError(variantOf("max = \"170 deg\"", "max = \"-180 deg\""), 24, "joint[1].max",
                "inverted");
  }
  SECTION("non-finite limit") {
    expectError(variantOf("max = \"170 deg\"", "max = inf"), 24, "joint[1].max", "not finite");
  }
  SECTION("NaN in the table") {
    expectError(variantOf("x = 0.3", "x = nan"), 17, "joint[1].x", "not finite");
  }
  SECTION("duplicate joint names") {
    expectError(variantOf("\"elbow\"", "\"lift\""), 15, "joint[1].name", "duplicate");
  }
  SECTION("empty table") {
    std::string s = kGood;
    s = s.substr(0, s.find("[[joint]]")) + "[tcp]\n";
    expectError(s, 0, "joint", "empty");
  }
  SECTION("wrong unit suffix") {
    expectError(variantOf("gamma = \"90 deg\"", "gamma = \"90 mm\""), 22, "joint[1].gamma",
                "length");
  }
  SECTION("wrong unit for a prismatic limit") {
    expectError(variantOf("min = \"-0.2 m\"", "min = \"-20 deg\""), 12, "joint[0].min", "angle");
  }
  SECTION("missing [tcp]") {
    std::string s = kGood;
    s = s.substr(0, s.find("[tcp]"));
    expectError(s, 0, "tcp", "missing");
  }
  SECTION("TOML syntax error") {
    expectError(variantOf("x = 0.3", "x = = 0.3"), 17, "x", "syntax");
  }  // key: the one written on that line
  SECTION("negative mass") {
    expectError(
        std::string(kGood) + "[[inertia]]\nlink = \"elbow\"\nmass = -1\ninertia = [1,1,1,0,0,0]\n",
        29, "inertia[0].mass", "negative");
  }
  SECTION("inertia breaking the triangle inequality") {
    expectError(
        std::string(kGood) + "[[inertia]]\nlink = \"elbow\"\nmass = 1\ninertia = [1,1,3,0,0,0]\n",
        30, "inertia[0].inertia", "triangle");
  }
  SECTION("inertia with a negative principal moment") {
    expectError(
        std::string(kGood) + "[[inertia]]\nlink = \"elbow\"\nmass = 1\ninertia = [1,1,-1,0,0,0]\n",
        30, "inertia[0].inertia", "positive semidefinite");
  }
  SECTION("zero gear ratio") {
    expectError(std::string(kGood) +
                    "[[drive]]\njoint = \"elbow\"\ngear_ratio = 0\ntorque_constant = 0.1\n",
                29, "drive[0].gear_ratio", "positive");
  }
  SECTION("drive on a joint that does not exist") {
    expectError(std::string(kGood) +
                    "[[drive]]\njoint = \"wrist\"\ngear_ratio = 100\ntorque_constant = 0.1\n",
                28, "drive[0].joint", "no joint");
  }
}

TEST_CASE("a missing design file is an input error", "[io][design][bad-input]") {
  CHECK_THROWS_AS(loadDesign("/nonexistent/design.toml"), InputError);
}

TEST_CASE("setModelEntry edits table entries and refreshes cached transforms", "[io][design]") {
  Model m = parseDesign(kGood, "good.toml");
  std::string err;
  REQUIRE(setModelEntry(m, "joint.elbow.x", 0.4, err));
  CHECK(m.joints[1].T_PJ0.translation().x() == 0.4);
  REQUIRE(setModelEntry(m, "base.y", -0.1, err));
  CHECK(m.T_WB.translation().y() == -0.1);
  CHECK_FALSE(setModelEntry(m, "joint.wrist.x", 0.4, err));
  CHECK(err.find("wrist") != std::string::npos);
  CHECK_FALSE(setModelEntry(m, "joint.elbow.length", 0.4, err));
}
