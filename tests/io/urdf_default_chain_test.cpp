// The default chain follows the structure: a wrist joint whose child link is a hand body stays in
// the arm (iCub's r_wrist_yaw -> r_hand, Atlas's l_arm_wry2 -> l_hand), fingers after it do not;
// a file that holds only a finger or a gripper takes its chain, names aside.
#include <catch2/catch.hpp>
#include <string>

#include "io/urdf_io.hpp"

using namespace armstudy;

namespace {

std::string link(const std::string& n) { return "<link name=\"" + n + "\"/>\n"; }

std::string revolute(const std::string& name, const std::string& parent, const std::string& child) {
  return "<joint name=\"" + name + "\" type=\"revolute\"><parent link=\"" + parent +
         "\"/><child link=\"" + child +
         "\"/><origin xyz=\"0 0 0.1\"/><axis xyz=\"0 0 1\"/>"
         "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n";
}

UrdfInfo importInfo(const std::string& body, Model* model = nullptr) {
  UrdfOptions o;
  o.collision = false;
  UrdfInfo info;
  const Model m = importUrdfText("<robot name=\"r\">\n" + body + "</robot>\n", "r.urdf", o, &info);
  if (model) *model = m;
  return info;
}

}  // namespace

TEST_CASE("URDF default chain: the joint that moves a hand body is a wrist joint", "[io][urdf]") {
  // An iCub-like arm: shoulder, elbow, wrist to r_hand; two fingers on the hand.
  const std::string arm =
      link("base") + link("upper") + link("fore") + link("r_hand") + link("f1") + link("f2") +
      link("f1b") + revolute("r_shoulder", "base", "upper") + revolute("r_elbow", "upper", "fore") +
      revolute("r_wrist_yaw", "fore", "r_hand") + revolute("r_index_finger_1", "r_hand", "f1") +
      revolute("r_index_finger_2", "f1", "f1b") + revolute("r_thumb_1", "r_hand", "f2");
  Model m;
  const UrdfInfo info = importInfo(arm, &m);
  CHECK(m.dof() == 3);
  CHECK(info.tcp_link == "r_hand");
  CHECK(m.joints.back().name == "r_wrist_yaw");
}

TEST_CASE("URDF default chain: a finger on its own is its own chain", "[io][urdf]") {
  // finger_edu-like: every movable joint is named as a finger joint.
  const std::string finger = link("palm") + link("finger_link_1") + link("finger_link_2") +
                             link("finger_tip") +
                             revolute("finger_joint_1", "palm", "finger_link_1") +
                             revolute("finger_joint_2", "finger_link_1", "finger_link_2") +
                             revolute("finger_joint_3", "finger_link_2", "finger_tip");
  Model m;
  const UrdfInfo info = importInfo(finger, &m);
  CHECK(m.dof() == 3);
  CHECK(info.tcp_link == "finger_tip");
  // An arm with fingers still leaves the fingers out.
  const std::string arm_with_gripper = link("base") + link("a") + link("b") + link("gripper_left") +
                                       revolute("shoulder", "base", "a") +
                                       revolute("elbow", "a", "b") +
                                       revolute("gripper_left_joint", "b", "gripper_left");
  Model m2;
  const UrdfInfo info2 = importInfo(arm_with_gripper, &m2);
  CHECK(m2.dof() == 2);
  CHECK(info2.tcp_link == "b");
}

TEST_CASE("URDF default tip: frames on the last joint's axis, not side markers", "[io][urdf]") {
  auto fixed = [](const std::string& name, const std::string& parent, const std::string& child,
                  const std::string& xyz) {
    return "<joint name=\"" + name + "\" type=\"fixed\"><parent link=\"" + parent +
           "\"/><child link=\"" + child + "\"/><origin xyz=\"" + xyz + "\"/></joint>\n";
  };
  const std::string arm = link("base") + link("a") + link("flange") +
                          revolute("shoulder", "base", "a") + revolute("roll", "a", "flange");
  // A single fixed frame off the axis is still the path (a tool offset sideways).
  const UrdfInfo offset =
      importInfo(arm + link("tool") + fixed("t", "flange", "tool", "0.04 0 0.1"));
  CHECK(offset.tcp_link == "tool");
  // A tool on the axis beside a marker off it: the tool, then its own frame on the axis.
  const UrdfInfo tool =
      importInfo(arm + link("marker") + link("tool") + link("tcp") +
                 fixed("m", "flange", "marker", "0.04 0 0") +
                 fixed("t", "flange", "tool", "0 0 0.1") + fixed("c", "tool", "tcp", "0 0 0.05"));
  CHECK(tool.tcp_link == "tcp");
  // Two frames on the axis: ambiguous, the chain's end.
  const UrdfInfo two =
      importInfo(arm + link("t1") + link("t2") + fixed("a1", "flange", "t1", "0 0 0.1") +
                 fixed("a2", "flange", "t2", "0 0 0.2"));
  CHECK(two.tcp_link == "flange");
}
