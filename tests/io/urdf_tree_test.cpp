// The whole tree's masses: links off the chain (a fixed tool beyond the tip, a branch on a chain
// link with its joint held) ride on the chain link they hang from. Oracle: orocos-kdl's tree
// inverse dynamics on kdl_parser's reading of the same URDF (the branch joint at its held
// position, at rest), never armstudy's own lumping.
#include <catch2/catch.hpp>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <map>
#include <random>
#include <string>

#include "dynamics/dynamics.hpp"
#include "io/urdf_io.hpp"
#include "model/model_notes.hpp"
#include "test_support.hpp"

using namespace armstudy;

namespace {

constexpr double kTreeOracleTolerance = 1e-9;  // N m
constexpr double kGravity = 9.81;
constexpr double kBranchHeld = 0.2;  // the head joint's lower limit: q = 0 clamped into [0.2, 1]

std::string inertial(const std::string& m, const std::string& xyz, const std::string& rpy,
                     const std::string& diag) {
  return "<inertial><origin xyz=\"" + xyz + "\" rpy=\"" + rpy + "\"/><mass value=\"" + m +
         "\"/><inertia " + diag + " ixy=\"0.001\" ixz=\"-0.002\" iyz=\"0.0015\"/></inertial>";
}
std::string link(const std::string& n, const std::string& in) {
  return "<link name=\"" + n + "\">" + in + "</link>\n";
}
std::string joint(const std::string& n, const std::string& type, const std::string& p,
                  const std::string& c, const std::string& xyz, const std::string& rpy,
                  const std::string& axis, const std::string& limit) {
  return "<joint name=\"" + n + "\" type=\"" + type + "\"><parent link=\"" + p +
         "\"/><child link=\"" + c + "\"/><origin xyz=\"" + xyz + "\" rpy=\"" + rpy + "\"/>" +
         (axis.empty() ? "" : "<axis xyz=\"" + axis + "\"/>") + limit + "</joint>\n";
}

// Three arm joints base -> l1 -> l2 -> l3 (the tip); beyond it a fixed flange and a 1 kg tool;
// on l1 a 1.5 kg head on a revolute joint limited to [0.2, 1] with a fixed camera under it; on l2
// a fixed 0.3 kg marker.
std::string treeArm() {
  const std::string lim = "<limit lower=\"-3\" upper=\"3\" effort=\"50\" velocity=\"2\"/>";
  const std::string D = "ixx=\"0.02\" iyy=\"0.03\" izz=\"0.025\"";
  return "<robot name=\"tree_arm\">\n" + link("base", inertial("5", "0 0 0.1", "0 0 0", D)) +
         link("l1", inertial("3", "0.01 0.02 0.15", "0.1 0.2 0.3", D)) +
         link("l2", inertial("2", "0.2 0 0.01", "0 0.3 0", D)) +
         link("l3", inertial("1.2", "0.15 0.01 0", "0.2 0 0.1", D)) + link("flange", "") +
         link("tool", inertial("1", "0 0.02 0.08", "0.3 -0.2 0.5", D)) +
         link("head", inertial("1.5", "0.05 0 0.1", "0 0 0.4", D)) +
         link("camera", inertial("0.2", "0.02 0 0", "0 0 0", D)) +
         link("marker", inertial("0.3", "0 0.05 0", "0 0 0", D)) +
         joint("j1", "revolute", "base", "l1", "0 0 0.3", "0 0 0", "0 0 1", lim) +
         joint("j2", "revolute", "l1", "l2", "0 0.05 0.25", "0.3 0 0", "0 1 0", lim) +
         joint("j3", "revolute", "l2", "l3", "0.4 0 0", "0 0 0.2", "1 0 0", lim) +
         joint("flange_joint", "fixed", "l3", "flange", "0.1 0 0", "0 1.5707963 0", "", "") +
         joint("tool_joint", "fixed", "flange", "tool", "0 0 0.05", "0.2 0 0", "", "") +
         joint("neck", "revolute", "l1", "head", "0 -0.1 0.2", "0 0 0.5", "0 1 0",
               "<limit lower=\"0.2\" upper=\"1\" effort=\"5\" velocity=\"1\"/>") +
         joint("camera_joint", "fixed", "head", "camera", "0.1 0 0.05", "0 0 0", "", "") +
         joint("marker_joint", "fixed", "l2", "marker", "0.2 0.05 0", "0 0 0", "", "") +
         "</robot>\n";
}

}  // namespace

TEST_CASE(
    "URDF tree masses: joint torques with a fixed tool and a side branch equal KDL's tree "
    "inverse dynamics") {
  const std::string text = treeArm();
  UrdfOptions o;
  o.collision = false;
  o.base_link = "base";
  o.tip_link = "l3";
  const Model m = importUrdfText(text, "tree_arm.urdf", o);
  REQUIRE(m.dof() == 3);
  // What was lumped, by name: the tool and flange beyond the tip, head and camera on l1 with the
  // neck held at 0.2, the marker on l2.
  std::string lumped;
  for (const auto& l : notes::all(m, notes::kLumped)) lumped += l + "\n";
  INFO(lumped);
  REQUIRE(notes::all(m, notes::kLumped).size() ==
          4);  // tool, head, camera, marker (the flange has no mass)
  REQUIRE(lumped.find("'head' (1.5 kg) onto 'l1'") != std::string::npos);
  REQUIRE(lumped.find("'neck' at 0.2") != std::string::npos);
  REQUIRE(lumped.find("'tool' (1 kg) onto 'l3'") != std::string::npos);
  REQUIRE(m.inertias.size() == 3);
  CHECK(m.inertias[0].mass_kg == Approx(3 + 1.5 + 0.2).epsilon(1e-15));
  CHECK(m.inertias[1].mass_kg == Approx(2 + 0.3).epsilon(1e-15));
  CHECK(m.inertias[2].mass_kg == Approx(1.2 + 1).epsilon(1e-15));

  KDL::Tree tree;
  REQUIRE(kdl_parser::treeFromString(text, tree));
  KDL::TreeIdSolver_RNE id(tree, KDL::Vector(0, 0, -kGravity));
  std::map<std::string, unsigned> qnr;  // joint name -> KDL index
  for (const auto& [name, e] : tree.getSegments()) {
    const KDL::Joint& j = GetTreeElementSegment(e).getJoint();
    if (j.getType() != KDL::Joint::None) qnr[j.getName()] = GetTreeElementQNr(e);
  }
  REQUIRE(qnr.size() == 4);
  DynamicsOptions dopt;
  dopt.g_W = Eigen::Vector3d(0, 0, -kGravity);
  const RigidBodyModel rbm = makeRigidBodyModel(m, dopt);
  DynamicsWorkspace ws(rbm);
  std::mt19937_64 rng(46);
  std::uniform_real_distribution<double> u(-1, 1);
  double worst = 0;
  for (int k = 0; k < 20; ++k) {
    const Eigen::VectorXd q = test::randomConfiguration(m, rng);
    Eigen::VectorXd qd(3), qdd(3), tau(3);
    for (int i = 0; i < 3; ++i) qd[i] = u(rng), qdd[i] = 2 * u(rng);
    inverseDynamics(rbm, ws, q, qd, qdd, tau);
    const unsigned n = tree.getNrOfJoints();
    KDL::JntArray kq(n), kqd(n), kqdd(n), kt(n);
    for (int i = 0; i < 3; ++i) {
      const unsigned at = qnr.at(m.joints[i].name);
      kq(at) = q[i], kqd(at) = qd[i], kqdd(at) = qdd[i];
    }
    kq(qnr.at("neck")) = kBranchHeld;
    REQUIRE(id.CartToJnt(kq, kqd, kqdd, KDL::WrenchMap(), kt) >= 0);
    for (int i = 0; i < 3; ++i)
      worst = std::max(worst, std::abs(kt(qnr.at(m.joints[i].name)) - tau[i]));
  }
  INFO("largest |tau - tau_KDL tree| " << worst << " N m");
  CHECK(worst < kTreeOracleTolerance);
}
