// What a URDF that armstudy cannot import is told: joint limits missing, 0/0 or swapped, and xacro
// files, each with the joint or line and what to write instead.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/errors.hpp"
#include "io/urdf_arm.hpp"
#include "io/urdf_io.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace armstudy;

namespace {

// One joint 'elbow' with `limit` (an element or "").
std::string oneJoint(const std::string& limit) {
  return "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n"
         "<joint name=\"elbow\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>"
         "<axis xyz=\"0 0 1\"/>" +
         limit + "</joint>\n</robot>\n";
}

// The InputError of importing `text`, as "key: message" ("" when it imports).
std::string importError(const std::string& text) {
  UrdfOptions o;
  o.collision = false;
  try {
    importUrdfText(text, "r.urdf", o);
  } catch (const InputError& e) {
    return e.key() + ": " + e.message() + " @" + std::to_string(e.line());
  }
  return "";
}

}  // namespace

TEST_CASE("URDF limits: a missing <limit> or 0/0 or swapped limits name the joint and the fix") {
  const std::string none = importError(oneJoint(""));
  INFO(none);
  CHECK(none.find("joint 'elbow'/limit") == 0);
  CHECK(none.find("needs <limit lower=") != std::string::npos);
  CHECK(none.find("type=\"continuous\"") != std::string::npos);
  CHECK(none.find("@4") != std::string::npos);  // the joint's line
  const std::string zero =
      importError(oneJoint("<limit lower=\"0\" upper=\"0\" effort=\"1\" velocity=\"1\"/>"));
  INFO(zero);
  CHECK(zero.find("joint 'elbow'/limit") == 0);
  CHECK(zero.find("lower = 0, upper = 0") != std::string::npos);
  CHECK(zero.find("cannot move") != std::string::npos);
  CHECK(zero.find("type=\"fixed\"") != std::string::npos);
  const std::string swapped =
      importError(oneJoint("<limit lower=\"1.5\" upper=\"-1.5\" effort=\"1\" velocity=\"1\"/>"));
  INFO(swapped);
  CHECK(swapped.find("joint 'elbow'/limit") == 0);
  CHECK(swapped.find("swapped: write lower=\"-1.5") != std::string::npos);
  CHECK(importError(oneJoint("<limit lower=\"-1.5\" upper=\"1.5\" effort=\"1\" velocity=\"1\"/>"))
            .empty());
}

TEST_CASE("URDF xacro: a .urdf.xacro file gets the xacro command and no TOML syntax error") {
  const fs::path dir = test::emptyTempDir("urdf_xacro");
  const std::string xacro =
      "<?xml version=\"1.0\"?>\n<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\" "
      "name=\"r\">\n<xacro:property name=\"l\" value=\"0.3\"/>\n<link name=\"a\"/>\n</robot>\n";
  const std::string f = (dir / "arm.urdf.xacro").string();
  std::ofstream(f) << xacro;
  std::string why;
  try {
    loadAnyDesign(f, UrdfOptions{});
  } catch (const InputError& e) {
    why = e.what();
  }
  INFO(why);
  CHECK(why.find(":3") != std::string::npos);  // the first xacro element's line
  CHECK(why.find("`xacro " + f + " -o " + (dir / "arm.urdf").string() + "`") != std::string::npos);
  CHECK(why.find("TOML") == std::string::npos);
  // The same text named .urdf: the xacro elements tell.
  const std::string u = (dir / "arm.urdf").string();
  std::ofstream(u) << xacro;
  why.clear();
  try {
    loadAnyDesign(u, UrdfOptions{});
  } catch (const InputError& e) {
    why = e.what();
  }
  INFO(why);
  CHECK(why.find("xacro file") != std::string::npos);
}
