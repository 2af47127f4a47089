// A tracking entry with a position_axis task refuses a URDF arm whose tool axis is open (its TCP
// off the last joint's axis), as the reach and dexterity stages do, naming the candidates.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/errors.hpp"
#include "engine/study_file.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace armstudy;

namespace {

// Four revolute joints (z, y, y, z) with sphere collisions; a fixed tool frame `tool_xyz` from the
// last link (on its z axis when x = y = 0).
std::string arm(const std::string& tool_xyz) {
  auto link = [](const std::string& n) {
    return "<link name=\"" + n +
           "\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" "
           "iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial><collision><geometry><sphere "
           "radius=\"0.03\"/></geometry></collision></link>\n";
  };
  auto joint = [](const std::string& n, const std::string& p, const std::string& c,
                  const std::string& o, const std::string& a) {
    return "<joint name=\"" + n + "\" type=\"revolute\"><parent link=\"" + p +
           "\"/><child link=\"" + c + "\"/><origin xyz=\"" + o + "\"/><axis xyz=\"" + a +
           "\"/><limit lower=\"-3\" upper=\"3\" effort=\"10\" velocity=\"1\"/></joint>\n";
  };
  return "<robot name=\"axis_arm\">\n" + link("base") + link("l1") + link("l2") + link("l3") +
         link("l4") + "<link name=\"tool\"/>\n" + joint("j1", "base", "l1", "0 0 0.3", "0 0 1") +
         joint("j2", "l1", "l2", "0 0 0.2", "0 1 0") + joint("j3", "l2", "l3", "0.4 0 0", "0 1 0") +
         joint("j4", "l3", "l4", "0.3 0 0", "0 0 1") +
         "<joint name=\"tool_joint\" type=\"fixed\"><parent link=\"l4\"/><child "
         "link=\"tool\"/><origin xyz=\"" +
         tool_xyz + "\"/></joint>\n</robot>\n";
}

std::string trackingStudy(const std::string& file, const std::string& task) {
  return "[study]\nname = \"t\"\n[[design]]\nfile = \"" + file +
         "\"\ntip_link = \"tool\"\n"
         "[[tracking]]\nname = \"line\"\ndesign = \"axis_arm\"\nq0 = [0, 0.3, 0.5, 0]\n"
         "task_space = \"" +
         task + "\"\ndelta = [\"0.05 m\", 0, 0]\nduration = 1.0\nrate = 100\n";
}

std::string loadError(const fs::path& dir, const std::string& file, const std::string& task) {
  try {
    loadStudyText(trackingStudy(file, task), (dir / "s.toml").string(), dir.string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("tracking: a position_axis entry refuses a URDF arm whose tool axis is open",
          "[tracking]") {
  const fs::path dir = test::emptyTempDir("tracking_tool_axis");
  std::ofstream(dir / "off.urdf") << arm("0.05 0 0.1");  // 50 mm off j4's axis
  const std::string why = loadError(dir, "off.urdf", "position_axis");
  INFO(why);
  CHECK(why.find("position_axis task holds the tool axis") != std::string::npos);
  CHECK(why.find("50.0 mm off the last joint's axis") != std::string::npos);
  CHECK(loadError(dir, "off.urdf", "position").empty());  // a position task needs no axis
  std::ofstream(dir / "on.urdf") << arm("0 0 0.1");       // on the axis: the axis is known
  const std::string on = loadError(dir, "on.urdf", "position_axis");
  INFO(on);  // a 4-DoF arm has no redundancy for it: that error, not the tool axis
  CHECK(on.find("no redundancy") != std::string::npos);
  CHECK(on.find("tool axis") == std::string::npos);
  fs::remove_all(dir);
}
