// The default tool axis of a URDF arm: the last joint's axis in the TCP frame when the TCP lies on
// it, else a refusal with the candidates. Oracle: the fixtures' axes and tool frames written by
// hand (axis x, y, z of the last link; a tool frame turned by a fixed joint's rpy), never the
// importer's own frames.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/errors.hpp"
#include "engine/study_file.hpp"
#include "io/urdf_arm.hpp"
#include "io/urdf_io.hpp"
#include "model/model_notes.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace armstudy;

namespace {

constexpr double kExact = 1e-12;  // a snapped axis is exactly a TCP axis

// A 3-joint arm: shoulder (z), elbow (y), wrist with `axis` in its link, then a fixed tool frame
// at `xyz` / `rpy` in the wrist link.
std::string arm(const std::string& axis, const std::string& xyz, const std::string& rpy = "0 0 0") {
  auto link = [](const std::string& n) {
    return "<link name=\"" + n +
           "\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" "
           "iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\n";
  };
  auto joint = [](const std::string& n, const std::string& p, const std::string& c,
                  const std::string& o, const std::string& a) {
    return "<joint name=\"" + n + "\" type=\"revolute\"><parent link=\"" + p +
           "\"/><child link=\"" + c + "\"/><origin xyz=\"" + o + "\"/><axis xyz=\"" + a +
           "\"/><limit lower=\"-3\" upper=\"3\" effort=\"10\" velocity=\"1\"/></joint>\n";
  };
  return "<robot name=\"axis_arm\">\n" + link("base") + link("upper") + link("fore") +
         link("wrist") + "<link name=\"tool\"/>\n" +
         joint("j1", "base", "upper", "0 0 0.3", "0 0 1") +
         joint("j2", "upper", "fore", "0 0 0.2", "0 1 0") +
         joint("j3", "fore", "wrist", "0.4 0 0", axis) +
         "<joint name=\"tool_joint\" type=\"fixed\"><parent link=\"wrist\"/><child "
         "link=\"tool\"/><origin xyz=\"" +
         xyz + "\" rpy=\"" + rpy + "\"/></joint>\n</robot>\n";
}

Model load(const std::string& text, const std::string& tip = "") {
  UrdfOptions o;
  o.collision = false;
  o.tip_link = tip;
  return importUrdfText(text, "axis_arm.urdf", o);
}

void requireAxis(const Model& m, const Eigen::Vector3d& expected) {
  INFO("tool axis " << m.tool_axis_T.transpose() << " from " << notes::toolAxisFrom(m));
  REQUIRE(notes::toolAxisOpen(m).empty());
  REQUIRE((m.tool_axis_T - expected).norm() <= kExact);
  REQUIRE(notes::toolAxisFrom(m).find("last joint's axis") != std::string::npos);
}

// A study with the arm at `urdf` and one spraying grid; `entry` adds keys to the [[design]].
std::string sprayStudy(const std::string& urdf, const std::string& entry) {
  return "[study]\nname = \"axis\"\n[[design]]\nfile = \"" + urdf + "\"\ntip_link = \"tool\"\n" +
         entry +
         "\n[reach]\ntask_space = \"spraying\"\n[[reach.grid]]\nname = \"g\"\nx = \"0.3 m\"\n"
         "y = \"0.3 m\"\nz = \"0.5 m\"\nalpha = \"0 deg\"\ngamma = \"0 deg\"\n";
}

}  // namespace

TEST_CASE("URDF tool axis: the last joint's axis x or y or z of the TCP frame is the default") {
  // The wrist turns about x, y or z of its link; the TCP 0.1 m along that axis.
  requireAxis(load(arm("1 0 0", "0.1 0 0"), "tool"), Eigen::Vector3d::UnitX());
  requireAxis(load(arm("0 1 0", "0 0.1 0"), "tool"), Eigen::Vector3d::UnitY());
  requireAxis(load(arm("0 0 1", "0 0 0.1"), "tool"), Eigen::Vector3d::UnitZ());
  // The TCP behind the joint's origin along the axis: the tool points that way.
  requireAxis(load(arm("0 0 1", "0 0 -0.1"), "tool"), -Eigen::Vector3d::UnitZ());
  // The TCP within 1 mm of the axis (0.9 mm off) still lies on it.
  requireAxis(load(arm("0 1 0", "0.0009 0.1 0"), "tool"), Eigen::Vector3d::UnitY());
}

TEST_CASE("URDF tool axis: a tool frame turned by a fixed joint's rpy carries the axis along") {
  // Like UR's tool0: the wrist turns about its link's y, the tool frame is turned by Rx(-pi/2),
  // so the joint's axis y is the tool frame's z (Rx(-pi/2) e_z = e_y).
  requireAxis(load(arm("0 1 0", "0 0.0823 0", "-1.5707963267948966 0 0"), "tool"),
              Eigen::Vector3d::UnitZ());
  // Turned by Rz(pi/2): the link's x is the tool frame's -y.
  requireAxis(load(arm("1 0 0", "0.05 0 0", "0 0 1.5707963267948966"), "tool"),
              -Eigen::Vector3d::UnitY());
  // An axis no TCP axis matches: the direction itself, R^T e_y = Rx(0.3) e_y in the tool frame.
  const Model m = load(arm("0 1 0", "0 0.1 0", "-0.3 0 0"), "tool");
  requireAxis(m, Eigen::Vector3d(0, std::cos(0.3), std::sin(0.3)));
}

TEST_CASE(
    "URDF tool axis: a TCP off the last joint's axis leaves it open and a spraying study "
    "refuses with the candidates") {
  const fs::path dir = test::emptyTempDir("urdf_tool_axis");
  const std::string off = arm("0 0 1", "0.05 0 0.1");  // 50 mm off the wrist's axis
  const Model m = load(off, "tool");
  const std::string open = notes::toolAxisOpen(m);
  INFO(open);
  REQUIRE(!open.empty());
  REQUIRE(open.find("50.0 mm off") != std::string::npos);
  REQUIRE(open.find("candidates: \"z\"") != std::string::npos);
  REQUIRE(open.find("tool_axis") != std::string::npos);
  std::ofstream(dir / "off.urdf") << off;
  std::string why;
  try {
    loadStudyText(sprayStudy("off.urdf", ""), (dir / "s.toml").string(), dir.string());
  } catch (const InputError& e) {
    why = e.what();
  }
  INFO(why);
  REQUIRE(why.find("points the tool axis") != std::string::npos);
  REQUIRE(why.find("50.0 mm off the last joint's axis ('j3'") != std::string::npos);
  REQUIRE(why.find("[reach.tool_axis]") != std::string::npos);
  // Named in the entry, the study loads with that axis.
  const Study s = loadStudyText(sprayStudy("off.urdf", "tool_axis = \"x\""),
                                (dir / "s.toml").string(), dir.string());
  REQUIRE((s.designs[0].model.tool_axis_T - Eigen::Vector3d::UnitX()).norm() <= kExact);
  // The entry's TCP offset puts the TCP back on the axis (50 mm back along the tool x): loads.
  const Study back = loadStudyText(sprayStudy("off.urdf", "tcp = { x = \"-50 mm\" }"),
                                   (dir / "s.toml").string(), dir.string());
  REQUIRE(notes::toolAxisOpen(back.designs[0].model).empty());
  REQUIRE((back.designs[0].model.tool_axis_T - Eigen::Vector3d::UnitZ()).norm() <= kExact);
}

TEST_CASE("URDF tool axis: the UR5 gets its flange axis at its default tip and at tool0") {
  const std::string ur5 = std::string(ARMSTUDY_ROBOTS_DIR) + "/ur_description/urdf/ur5_robot.urdf";
  UrdfOptions o;
  o.collision = false;
  o.base_link = "base_link";
  const Model tip = importUrdf(ur5, o);  // wrist_3_link: the flange axis is its y
  INFO(tip.source << ": " << notes::toolAxisFrom(tip));
  requireAxis(tip, Eigen::Vector3d::UnitY());
  o.tip_link = "tool0";
  requireAxis(importUrdf(ur5, o), Eigen::Vector3d::UnitZ());
  // The shipped study names no tool axis: both UR5 entries take the flange axis.
  const Study s = loadStudy(test::sourcePath("studies/ur5_vs_first_prototype.toml"));
  for (const StudyDesign& d : s.designs)
    if (d.model.name.rfind("ur5", 0) == 0) requireAxis(d.model, Eigen::Vector3d::UnitZ());
}
