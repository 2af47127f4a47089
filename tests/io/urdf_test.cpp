// URDF in and out. Oracle: orocos-kdl built from the same URDF by kdl_parser (an
// independent URDF implementation), never armstudy's own reading of the file.
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "collision/collision.hpp"
#include "collision/ssv_fit.hpp"
#include "common/errors.hpp"
#include "dynamics/dynamics.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "io/urdf_io.hpp"
#include "kinematics/kinematics.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace armstudy;

namespace {

// Agreement with kdl_parser + KDL ("to 1e-9 m/rad").
constexpr double kUrdfOracleTolerance = 1e-9;
constexpr double kKdlGravity = 9.81;
constexpr int kRandomConfigurations = 20;
// assimp holds meshes in single precision (ai_real = float): a vertex written as 30 cm in a DAE is
// 0.30000001 m there. Vertices given in double by the test are inside to this tolerance.
constexpr double kSinglePrecisionMesh_m = 1e-6;

std::string robotsDir() { return ARMSTUDY_ROBOTS_DIR; }
// The real arms must be there (CI has ../shared): a missing file fails the test, never skips it.
std::string robotFile(const std::string& rel) {
  const std::string p = robotsDir() + "/" + rel;
  INFO("robot description " << p << " (ARMSTUDY_ROBOTS_DIR) is missing");
  REQUIRE(fs::is_regular_file(p));
  return p;
}
std::string ur5() { return robotFile("ur_description/urdf/ur5_robot.urdf"); }
std::string panda() { return robotFile("panda_description/urdf/panda.urdf"); }

UrdfOptions chain(const std::string& base, const std::string& tip, bool collision = false) {
  UrdfOptions o;
  o.base_link = base;
  o.tip_link = tip;
  o.collision = collision;
  return o;
}

struct KdlOracle {
  KDL::Chain chain;
  explicit KdlOracle(const KDL::Tree& tree, const std::string& base, const std::string& tip) {
    REQUIRE(tree.getChain(base, tip, chain));
  }
};

KDL::Tree kdlTreeFromFile(const std::string& path) {
  KDL::Tree t;
  REQUIRE(kdl_parser::treeFromFile(path, t));
  return t;
}

KDL::JntArray toJnt(const Eigen::VectorXd& q) {
  KDL::JntArray a(static_cast<unsigned>(q.size()));
  for (int i = 0; i < q.size(); ++i) a(i) = q[i];
  return a;
}

Eigen::Isometry3d fromKdl(const KDL::Frame& f) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T.linear()(r, c) = f.M(r, c);
    T.translation()[r] = f.p[r];
  }
  return T;
}

// Largest FK (position [m], rotation-matrix entry), Jacobian and inverse-dynamics differences over
// random configurations between the armstudy model and the KDL chain.
struct Errors {
  double fk = 0, jac = 0, id = 0;
};

// The chain joints' torques from KDL's inverse dynamics of the whole tree: the links off the chain
// ride along (joints off the chain at q = 0, at rest), as armstudy lumps them.
KDL::JntArray treeTorques(const KDL::Tree& tree, const KDL::Chain& chain, const KDL::JntArray& q,
                          const KDL::JntArray& qd, const KDL::JntArray& qdd) {
  std::map<std::string, unsigned> qnr;
  for (const auto& [name, e] : tree.getSegments()) {
    const KDL::Joint& j = GetTreeElementSegment(e).getJoint();
    if (j.getType() != KDL::Joint::None) qnr[j.getName()] = GetTreeElementQNr(e);
  }
  const unsigned n = tree.getNrOfJoints();
  KDL::JntArray tq(n), tqd(n), tqdd(n), tt(n), out(chain.getNrOfJoints());
  std::vector<unsigned> at;
  for (const KDL::Segment& s : chain.segments)
    if (s.getJoint().getType() != KDL::Joint::None) at.push_back(qnr.at(s.getJoint().getName()));
  for (unsigned i = 0; i < at.size(); ++i)
    tq(at[i]) = q(i), tqd(at[i]) = qd(i), tqdd(at[i]) = qdd(i);
  KDL::TreeIdSolver_RNE id(tree, KDL::Vector(0, 0, -kKdlGravity));
  REQUIRE(id.CartToJnt(tq, tqd, tqdd, KDL::WrenchMap(), tt) >= 0);
  for (unsigned i = 0; i < at.size(); ++i) out(i) = tt(at[i]);
  return out;
}

Errors compareWithKdl(const Model& m, const KDL::Chain& chain, bool dynamics, std::uint64_t seed,
                      const KDL::Tree* tree = nullptr) {
  REQUIRE(static_cast<int>(chain.getNrOfJoints()) == m.dof());
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  KDL::ChainIdSolver_RNE id(chain, KDL::Vector(0, 0, -kKdlGravity));
  KinematicsWorkspace ws(m);
  DynamicsOptions dopt;
  dopt.g_W = Eigen::Vector3d(0, 0, -kKdlGravity);
  std::unique_ptr<RigidBodyModel> rbm;
  if (dynamics) rbm = std::make_unique<RigidBodyModel>(makeRigidBodyModel(m, dopt));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Errors e;
  for (int k = 0; k < kRandomConfigurations; ++k) {
    const Eigen::VectorXd q = test::randomConfiguration(m, rng);
    forwardKinematicsAndJacobian(m, ws, q);
    KDL::Frame F;
    REQUIRE(fk.JntToCart(toJnt(q), F) >= 0);
    const Eigen::Isometry3d T = fromKdl(F);
    e.fk = std::max({e.fk, (T.translation() - ws.p_WT).cwiseAbs().maxCoeff(),
                     (T.linear() - ws.R_WT).cwiseAbs().maxCoeff()});
    KDL::Jacobian J(chain.getNrOfJoints());
    REQUIRE(jac.JntToJac(toJnt(q), J) >= 0);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < m.dof(); ++c)
        e.jac = std::max(e.jac, std::abs(J(r, c) - ws.J_W_tcp(r, c)));
    if (dynamics) {
      Eigen::VectorXd qd(m.dof()), qdd(m.dof()), tau(m.dof());
      for (int i = 0; i < m.dof(); ++i) qd[i] = u(rng), qdd[i] = 2 * u(rng);
      DynamicsWorkspace dws(*rbm);
      inverseDynamics(*rbm, dws, q, qd, qdd, tau);
      KDL::JntArray tk(chain.getNrOfJoints());
      KDL::Wrenches f(chain.getNrOfSegments(), KDL::Wrench::Zero());
      if (tree)
        tk = treeTorques(*tree, chain, toJnt(q), toJnt(qd), toJnt(qdd));
      else
        REQUIRE(id.CartToJnt(toJnt(q), toJnt(qd), toJnt(qdd), f, tk) >= 0);
      for (int i = 0; i < m.dof(); ++i) e.id = std::max(e.id, std::abs(tk(i) - tau[i]));
    }
  }
  return e;
}

void checkAgainstKdl(const std::string& file, const std::string& base, const std::string& tip,
                     int dof) {
  const Model m = importUrdf(file, chain(base, tip));
  REQUIRE(m.dof() == dof);
  const KDL::Tree tree = kdlTreeFromFile(file);
  const KdlOracle kdl(tree, base, tip);
  const Errors e = compareWithKdl(m, kdl.chain, true, 14, &tree);
  INFO(file << " " << base << " -> " << tip << ": max |FK| " << e.fk << ", |J| " << e.jac
            << ", |ID| " << e.id);
  CHECK(e.fk < kUrdfOracleTolerance);
  CHECK(e.jac < kUrdfOracleTolerance);
  CHECK(e.id < kUrdfOracleTolerance);
  WARN("max error vs KDL (" << fs::path(file).filename().string() << ", " << base << " -> " << tip
                            << "): FK " << e.fk << ", Jacobian " << e.jac << ", inverse dynamics "
                            << e.id << " N m");
}

template <class Fn>
InputError expectInputError(Fn fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e;
  }
  FAIL("no InputError thrown");
  throw std::logic_error("unreachable");
}

// A small valid arm: base -> j1 (revolute about x) -> j2 (prismatic along y) -> tool (fixed).
std::string smallArm(const std::string& j1_extra = "", const std::string& j1_type = "revolute",
                     const std::string& j1_origin = "0 0 0.1",
                     const std::string& j2_parent = "l1") {
  return R"(<?xml version="1.0"?>
<robot name="small">
  <link name="base"/>
  <link name="l1"><inertial><origin xyz="0.01 0 0.05" rpy="0.1 0.2 0.3"/><mass value="1.5"/>
    <inertia ixx="0.01" ixy="0.001" ixz="0" iyy="0.02" iyz="0" izz="0.015"/></inertial>
    <collision><origin xyz="0 0 0.05"/><geometry><box size="0.05 0.06 0.1"/></geometry></collision></link>
  <link name="l2"><inertial><origin xyz="0 0.02 0"/><mass value="0.5"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
    <collision><origin xyz="0 0 0.03" rpy="1.5707963267948966 0 0"/><geometry><cylinder radius="0.02" length="0.06"/></geometry></collision>
    <collision><geometry><sphere radius="0.03"/></geometry></collision></link>
  <link name="tool"/>
  <joint name="j1" type=")" +
         j1_type + R"(">
    <parent link="base"/><child link="l1"/>
    <origin xyz=")" +
         j1_origin + R"(" rpy="0 0.3 0"/>
    <axis xyz="1 0 0"/>
    <limit lower="-2" upper="2" effort="20" velocity="1.5"/>)" +
         j1_extra + R"(
  </joint>
  <joint name="j2" type="prismatic">
    <parent link=")" +
         j2_parent + R"("/><child link="l2"/>
    <origin xyz="0 0 0.2" rpy="0.4 0 -0.2"/>
    <axis xyz="0 -0.6 0.8"/>
    <limit lower="-0.1" upper="0.3" effort="100" velocity="0.2"/>
  </joint>
  <joint name="tool_joint" type="fixed">
    <parent link="l2"/><child link="tool"/>
    <origin xyz="0 0 0.05" rpy="0 0 1.0"/>
  </joint>
</robot>
)";
}

// One scratch folder per test process (ctest runs the cases in parallel processes), removed when
// the process ends.
const fs::path& scratchDir() {
  struct Dir {
    fs::path path =
        fs::temp_directory_path() / ("armstudy_urdf_test_" + std::to_string(::getpid()));
    Dir() { fs::create_directories(path); }
    ~Dir() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  };
  static const Dir d;
  return d.path;
}

std::string tempPath(const std::string& name) { return (scratchDir() / name).string(); }

void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }
// Largest signed distance [m] (<= 0: inside) of the points p_W (in W) from the volumes of body
// `body` (-1 = base) placed by armstudy's forward kinematics in `ws`.
double farthestOutside(const Model& m, const KinematicsWorkspace& ws, int body,
                       const std::vector<Eigen::Vector3d>& p_W) {
  std::vector<collision::FittedSsv> vols;
  for (const CollisionVolume& v : m.collision.volumes) {
    if (v.link != body) continue;
    collision::FittedSsv s;
    s.type = v.type;
    s.radius_m = v.radius_m;
    for (int k = 0; k < 3; ++k)
      s.p[k] = body < 0 ? Eigen::Vector3d(v.p_L[k])
                        : Eigen::Vector3d(ws.R_WF[body] * v.p_L[k] + ws.p_WF[body]);
    vols.push_back(s);
  }
  REQUIRE(!vols.empty());
  double worst = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& x : p_W) {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& s : vols) d = std::min(d, collision::ssvSignedDistance(s, x));
    worst = std::max(worst, d);
  }
  return worst;
}

}  // namespace

TEST_CASE(
    "URDF UR5 base_link to tool0: FK, TCP Jacobian and inverse dynamics match kdl_parser to 1e-9",
    "[urdf]") {
  checkAgainstKdl(ur5(), "base_link", "tool0", 6);
}

TEST_CASE("URDF UR5 default chain is world to wrist_3_link and matches KDL", "[urdf]") {
  UrdfOptions o;
  o.collision = false;
  UrdfInfo info;
  const Model m = importUrdf(ur5(), o, &info);
  CHECK(info.base_link == "world");
  CHECK(info.tcp_link == "wrist_3_link");
  const KdlOracle kdl(kdlTreeFromFile(ur5()), "world", "wrist_3_link");
  const Errors e = compareWithKdl(m, kdl.chain, true, 3);
  CHECK(e.fk < kUrdfOracleTolerance);
  CHECK(e.jac < kUrdfOracleTolerance);
  CHECK(e.id < kUrdfOracleTolerance);
  CHECK(info.joints[0].effort_max == 150.0);
  CHECK(m.joints[0].limits.qd_max == 3.15);
}

TEST_CASE(
    "URDF Panda panda_link0 to panda_hand: FK, TCP Jacobian and inverse dynamics match kdl_parser",
    "[urdf]") {
  checkAgainstKdl(panda(), "panda_link0", "panda_hand", 7);
}

TEST_CASE("URDF Panda to the left finger: a prismatic joint along y on the chain matches KDL",
          "[urdf]") {
  checkAgainstKdl(panda(), "panda_link0", "panda_leftfinger", 8);
}

TEST_CASE("URDF small arm with oblique axes, rotated inertial origin and fixed tool matches KDL",
          "[urdf]") {
  const std::string f = tempPath("small.urdf");
  writeText(f, smallArm());
  checkAgainstKdl(f, "base", "tool", 2);
  UrdfInfo info;
  importUrdf(f, chain("", ""), &info);
  // default tip: the end of the longest chain (l2), on along its one path of fixed joints
  CHECK(info.tcp_link == "tool");
}

TEST_CASE("URDF Panda default tip is the hand TCP, the fingers are left out", "[urdf]") {
  UrdfOptions o;
  o.collision = false;
  UrdfInfo info;
  const Model m = importUrdf(panda(), o, &info);
  CHECK(m.dof() == 7);
  CHECK(info.tcp_link == "panda_hand_tcp");
  const UrdfChains c = findUrdfChains(panda(), o);
  REQUIRE(c.ends.size() == 1);
  CHECK(c.ends[0].link == "panda_link7");
  CHECK(c.ends[0].joints == 7);
  CHECK(c.ends[0].left_out ==
        std::vector<std::string>{"panda_finger_joint1 (gripper or finger joint)",
                                 "panda_finger_joint2 (mimic joint)"});
  CHECK_THAT(c.reason, Catch::Contains("panda_hand_tcp"));
}

namespace {
const char* kTwoArms = R"(<robot name="two">
  <link name="base"/><link name="a"/><link name="b"/>
  <joint name="ja" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="jb" type="revolute"><parent link="base"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>)";
}  // namespace

TEST_CASE("URDF two arms of equal length: the error lists both tips and asks for --tip",
          "[urdf][bad]") {
  const InputError e =
      expectInputError([&] { importUrdfText(kTwoArms, "two.urdf", chain("", "")); });
  CHECK(e.key() == "tip_link");
  CHECK_THAT(e.message(), Catch::Contains("a, b") && Catch::Contains("--tip"));
}

TEST_CASE("URDF import notes the branches off the chain", "[urdf]") {
  std::vector<std::string> warnings;
  importUrdf(panda(), chain("panda_link0", "panda_hand"), nullptr, &warnings);
  std::string all;
  for (const auto& w : warnings) all += w + "\n";
  CHECK_THAT(all, Catch::Contains("panda_leftfinger") && Catch::Contains("panda_hand_tcp"));
}

// ---- round trips ----

TEST_CASE(
    "URDF round trip UR5 URDF to TOML to URDF keeps FK identical to 1e-9 and loads in kdl_parser",
    "[urdf]") {
  UrdfInfo info, info_back;
  const Model m = importUrdf(ur5(), chain("base_link", "tool0", true), &info);
  const std::string toml = designToToml(m, info);
  const Model back = parseDesignWithUrdfInfo(toml, "ur5_roundtrip.toml", &info_back);
  REQUIRE(back.dof() == 6);
  CHECK(back.collision.volumes.size() == m.collision.volumes.size());
  REQUIRE(info_back.joints.size() == 6);
  CHECK(info_back.joints[3].effort_max == 28.0);
  CHECK(info_back.joints[3].link == "wrist_1_link");
  CHECK(info_back.base_link == "base_link");
  CHECK(info_back.tcp_link == "tool0");
  const std::string urdf = exportUrdf(back, info_back);
  KDL::Tree t;
  REQUIRE(kdl_parser::treeFromString(urdf, t));
  UrdfInfo info_again;
  const Model again = importUrdfText(urdf, "ur5_roundtrip.urdf", chain("", "tool0"), &info_again);
  // Limits survive URDF -> TOML -> URDF -> import unchanged (17 significant digits both ways).
  REQUIRE(again.dof() == m.dof());
  for (int i = 0; i < m.dof(); ++i) {
    CHECK(again.joints[i].name == m.joints[i].name);
    CHECK(again.joints[i].limits.q_min == m.joints[i].limits.q_min);
    CHECK(again.joints[i].limits.q_max == m.joints[i].limits.q_max);
    CHECK(again.joints[i].limits.qd_max == m.joints[i].limits.qd_max);
    CHECK(info_again.joints[i].effort_max == info.joints[i].effort_max);
    CHECK(info_again.joints[i].link == info.joints[i].link);
  }
  // Against KDL of the original file, for the model read from the exported file and for KDL of it.
  const KdlOracle original(kdlTreeFromFile(ur5()), "base_link", "tool0");
  const KdlOracle exported(t, "base_link", "tool0");
  const Errors e1 = compareWithKdl(again, original.chain, true, 5);
  const Errors e2 = compareWithKdl(m, exported.chain, true, 6);
  INFO("again vs original KDL: " << e1.fk << " " << e1.jac << " " << e1.id
                                 << "; import vs exported KDL: " << e2.fk << " " << e2.jac << " "
                                 << e2.id);
  CHECK(e1.fk < kUrdfOracleTolerance);
  CHECK(e1.jac < kUrdfOracleTolerance);
  CHECK(e1.id < kUrdfOracleTolerance);
  CHECK(e2.fk < kUrdfOracleTolerance);
  CHECK(e2.id < kUrdfOracleTolerance);
  WARN("UR5 round trip URDF->TOML->URDF, max FK error vs KDL of the original file: " << e1.fk);
}

TEST_CASE("URDF round trip Panda with a continuous joint keeps the joint type and FK", "[urdf]") {
  std::ifstream in(panda());
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  REQUIRE(!text.empty());
  const std::string from = R"(<joint name="panda_joint7" type="revolute">)";
  REQUIRE(text.find(from) != std::string::npos);
  text.replace(text.find(from), from.size(), R"(<joint name="panda_joint7" type="continuous">)");
  const std::string f = tempPath("panda_continuous.urdf");
  writeText(f, text);
  UrdfInfo info, info_back;
  const Model m = importUrdf(f, chain("panda_link0", "panda_hand"), &info);
  CHECK(info.joints[6].continuous);
  CHECK(m.joints[6].limits.q_max == defaults::kContinuousJointRange_rad);
  const Model back = parseDesignWithUrdfInfo(designToToml(m, info), "panda.toml", &info_back);
  CHECK(info_back.joints[6].continuous);
  const std::string urdf = exportUrdf(back, info_back);
  CHECK(urdf.find("type=\"continuous\"") != std::string::npos);
  KDL::Tree t;
  REQUIRE(kdl_parser::treeFromString(urdf, t));
  const KDL::Tree tree = kdlTreeFromFile(f);
  const KdlOracle original(tree, "panda_link0", "panda_hand");
  // The fingers beyond the hand ride on it (exported with its mass): KDL's whole tree.
  const Errors e = compareWithKdl(importUrdfText(urdf, "p.urdf", chain("", "panda_hand")),
                                  original.chain, true, 9, &tree);
  CHECK(e.fk < kUrdfOracleTolerance);
  CHECK(e.id < kUrdfOracleTolerance);
}

TEST_CASE("URDF export of every shipped design loads in kdl_parser with the same FK and dynamics",
          "[urdf]") {
  for (const std::string& rel : test::shippedDesigns()) {
    const Model m = loadDesign(test::sourcePath(rel));
    const std::string urdf = exportUrdf(m);
    KDL::Tree t;
    REQUIRE(kdl_parser::treeFromString(urdf, t));
    const std::string root = t.getRootSegment()->first;
    const std::string tip = "tcp";
    const KdlOracle kdl(t, root, tip);
    const Errors e = compareWithKdl(m, kdl.chain, !m.inertias.empty(), 11);
    INFO(rel << ": FK " << e.fk << " J " << e.jac << " ID " << e.id);
    CHECK(e.fk < kUrdfOracleTolerance);
    CHECK(e.jac < kUrdfOracleTolerance);
    CHECK(e.id < kUrdfOracleTolerance);
    // and back: the URDF read by armstudy gives the same TCP as the design
    const Model back = importUrdfText(urdf, rel + ".urdf", chain(root, tip));
    KinematicsWorkspace w1(m), w2(back);
    std::mt19937_64 rng(2);
    for (int k = 0; k < 5; ++k) {
      const Eigen::VectorXd q = test::randomConfiguration(m, rng);
      forwardKinematics(m, w1, q);
      forwardKinematics(back, w2, q);
      CHECK((w1.p_WT - w2.p_WT).norm() < kUrdfOracleTolerance);
      CHECK((w1.R_WT - w2.R_WT).cwiseAbs().maxCoeff() < kUrdfOracleTolerance);
    }
  }
}

// ---- collision volumes from the links' geometry ----

namespace {
// Independent binary/ASCII-free STL vertex reader (the robots' meshes are binary STL).
std::vector<Eigen::Vector3d> readBinaryStlVertices(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in);
  char header[80];
  in.read(header, 80);
  std::uint32_t n = 0;
  in.read(reinterpret_cast<char*>(&n), 4);
  std::vector<Eigen::Vector3d> v;
  for (std::uint32_t t = 0; t < n; ++t) {
    float f[12];
    in.read(reinterpret_cast<char*>(f), 48);
    char attr[2];
    in.read(attr, 2);
    REQUIRE(in);
    for (int k = 1; k < 4; ++k) v.emplace_back(f[3 * k], f[3 * k + 1], f[3 * k + 2]);
  }
  return v;
}

// Every vertex of each link's collision mesh, placed by KDL's FK of that link, lies inside the
// link's fitted volumes placed by armstudy's FK.
void checkMeshesInsideVolumes(const std::string& file, const std::string& base,
                              const std::string& tip,
                              const std::vector<std::pair<std::string, std::string>>& link_meshes) {
  UrdfOptions o = chain(base, tip, true);
  o.packages = {{"example-robot-data", fs::path(robotsDir()).parent_path().string()}};
  UrdfInfo info;
  const Model m = importUrdf(file, o, &info);
  const KDL::Tree tree = kdlTreeFromFile(file);
  KinematicsWorkspace ws(m);
  std::mt19937_64 rng(7);
  for (int k = 0; k < 3; ++k) {
    const Eigen::VectorXd q = test::randomConfiguration(m, rng);
    forwardKinematics(m, ws, q);
    for (const auto& [link, mesh] : link_meshes) {
      // body index: the joint whose child link is `link`, or -1 for the base body
      int body = -1;
      for (int i = 0; i < m.dof(); ++i)
        if (info.joints[i].link == link) body = i;
      KDL::Chain c;
      REQUIRE(tree.getChain(base, link, c));
      KDL::ChainFkSolverPos_recursive fk(c);
      KDL::Frame F;
      REQUIRE(fk.JntToCart(toJnt(q.head(c.getNrOfJoints())), F) >= 0);
      const Eigen::Isometry3d T_WL = fromKdl(F);
      const auto verts = readBinaryStlVertices(fs::path(robotsDir()).string() + "/" + mesh);
      std::vector<Eigen::Vector3d> p_W;
      for (const Eigen::Vector3d& pv : verts) p_W.push_back(T_WL * pv);
      const double worst = farthestOutside(m, ws, body, p_W);
      INFO(link << " (" << verts.size() << " vertices): farthest vertex " << worst
                << " m from the volumes' surface");
      CHECK(worst <= 1e-9);
    }
  }
}
}  // namespace

TEST_CASE("URDF UR5 collision volumes contain every vertex of every collision mesh",
          "[urdf][collision]") {
  checkMeshesInsideVolumes(ur5(), "base_link", "tool0",
                           {{"base_link", "ur_description/meshes/ur5/collision/base.stl"},
                            {"shoulder_link", "ur_description/meshes/ur5/collision/shoulder.stl"},
                            {"upper_arm_link", "ur_description/meshes/ur5/collision/upperarm.stl"},
                            {"forearm_link", "ur_description/meshes/ur5/collision/forearm.stl"},
                            {"wrist_1_link", "ur_description/meshes/ur5/collision/wrist1.stl"},
                            {"wrist_2_link", "ur_description/meshes/ur5/collision/wrist2.stl"},
                            {"wrist_3_link", "ur_description/meshes/ur5/collision/wrist3.stl"}});
}

TEST_CASE("URDF Panda collision volumes contain every vertex of every collision mesh",
          "[urdf][collision]") {
  std::vector<std::pair<std::string, std::string>> lm;
  for (int i = 0; i <= 7; ++i)
    lm.push_back({"panda_link" + std::to_string(i),
                  "panda_description/meshes/collision/link" + std::to_string(i) + ".stl"});
  checkMeshesInsideVolumes(panda(), "panda_link0", "panda_link7", lm);
}

TEST_CASE("URDF primitives: box, cylinder and sphere become volumes that contain them",
          "[urdf][collision]") {
  const Model m = importUrdfText(smallArm(), "small.urdf", chain("base", "tool", true));
  // l1 (body 0): a box 0.05 x 0.06 x 0.1 at z = 0.05 in the link frame; its corners must be inside.
  int box = 0, cyl = 0, sph = 0;
  for (const auto& v : m.collision.volumes) {
    if (v.link == 0) ++box;
    if (v.link == 1 && v.type == SsvType::Line) ++cyl;
    if (v.link == 1 && v.type == SsvType::Point) ++sph;
  }
  CHECK(box >= 1);
  CHECK(cyl == 1);
  CHECK(sph == 1);
  // Corners of the box, in world coordinates through KDL at q = 0 (link l1 frame), inside.
  const std::string f = tempPath("small_prims.urdf");
  writeText(f, smallArm());
  const KDL::Tree tree = kdlTreeFromFile(f);
  KDL::Chain c;
  REQUIRE(tree.getChain("base", "l1", c));
  KDL::ChainFkSolverPos_recursive fk(c);
  KinematicsWorkspace ws(m);
  const Eigen::VectorXd q = Eigen::Vector2d(0.7, 0.1);
  forwardKinematics(m, ws, q);
  KDL::Frame F;
  REQUIRE(fk.JntToCart(toJnt(q.head(1)), F) >= 0);
  const Eigen::Isometry3d T_WL = fromKdl(F);
  std::vector<Eigen::Vector3d> corners_W;
  for (int k = 0; k < 8; ++k)
    corners_W.push_back(T_WL * Eigen::Vector3d((k & 1 ? 0.025 : -0.025), (k & 2 ? 0.03 : -0.03),
                                               0.05 + (k & 4 ? 0.05 : -0.05)));
  CHECK(farthestOutside(m, ws, 0, corners_W) <= 1e-9);
}

TEST_CASE(
    "URDF OBJ mesh by relative path with scale and origin: every vertex inside, placed by KDL",
    "[urdf][collision]") {
  // An L-shaped prism in millimetres (OBJ through assimp), on a link behind an oblique joint.
  const fs::path dir = fs::path(tempPath("objarm"));
  fs::create_directories(dir / "meshes");
  const double P[12][3] = {{0, 0, 0},    {80, 0, 0},   {80, 20, 0},   {20, 20, 0},
                           {20, 120, 0}, {0, 120, 0},  {0, 0, 30},    {80, 0, 30},
                           {80, 20, 30}, {20, 20, 30}, {20, 120, 30}, {0, 120, 30}};
  std::ostringstream obj;
  for (const auto& p : P) obj << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
  // bottom/top as fans, sides as quads (assimp triangulates)
  obj << "f 1 6 5 4 3 2\nf 7 8 9 10 11 12\n";
  for (int k = 0; k < 6; ++k) {
    const int a = k + 1, b = (k + 1) % 6 + 1;
    obj << "f " << a << " " << b << " " << b + 6 << " " << a + 6 << "\n";
  }
  writeText((dir / "meshes" / "part.obj").string(), obj.str());
  const std::string urdf = R"(<robot name="objarm">
  <link name="base"/>
  <link name="l1"><collision><origin xyz="0.01 -0.02 0.05" rpy="0.3 -0.2 0.5"/>
    <geometry><mesh filename="meshes/part.obj" scale="0.001 0.001 0.001"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1" rpy="0 0.4 0"/><axis xyz="0.6 0 0.8"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>)";
  const std::string f = (dir / "objarm.urdf").string();
  writeText(f, urdf);
  std::vector<std::string> warnings;
  const Model m = importUrdf(f, chain("", "", true), nullptr, &warnings);
  CHECK(warnings.empty());
  REQUIRE(!m.collision.volumes.empty());
  KDL::Chain c;
  REQUIRE(kdlTreeFromFile(f).getChain("base", "l1", c));
  KDL::ChainFkSolverPos_recursive fk(c);
  KinematicsWorkspace ws(m);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 0.9);
  forwardKinematics(m, ws, q);
  KDL::Frame F;
  REQUIRE(fk.JntToCart(toJnt(q), F) >= 0);
  const Eigen::Isometry3d T_WC = fromKdl(F) * Eigen::Translation3d(0.01, -0.02, 0.05) *
                                 Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());  // URDF rpy
  std::vector<Eigen::Vector3d> p_W;
  for (const auto& p : P) p_W.push_back(T_WC * (1e-3 * Eigen::Vector3d(p[0], p[1], p[2])));
  const double worst = farthestOutside(m, ws, 0, p_W);
  INFO("farthest OBJ vertex from the volumes' surface: " << worst);
  CHECK(worst <= 1e-9);
}

TEST_CASE("URDF DAE mesh: unit scale applied, up axis ignored, every vertex inside",
          "[urdf][collision]") {
  // A tetrahedron in centimetres with <up_axis>Y_UP</up_axis>: armstudy applies the unit (0.01)
  // and ignores the up axis (assumption, as ROS tools do), so the vertices are 0.1 m along x,
  // 0.2 m along y and 0.3 m along z of the link frame.
  const fs::path dir = fs::path(tempPath("daearm"));
  fs::create_directories(dir);
  writeText((dir / "tri.dae").string(), std::string(R"DAE(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="g" name="g">
      <mesh>
        <source id="g-pos">
          <float_array id="g-pos-array" count="12">0 0 0 10 0 0 0 20 0 0 0 30</float_array>
          <technique_common><accessor source="#g-pos-array" count="4" stride="3">
            <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
          </accessor></technique_common>
        </source>
        <vertices id="g-vtx"><input semantic="POSITION" source="#g-pos"/></vertices>
        <triangles count="4"><input semantic="VERTEX" source="#g-vtx" offset="0"/>
          <p>0 2 1 0 1 3 0 3 2 1 2 3</p></triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="s"><node id="n"><instance_geometry url="#g"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)DAE"));
  writeText((dir / "a.urdf").string(), R"(<robot name="daearm">
  <link name="base"/>
  <link name="l1"><collision><geometry><mesh filename="tri.dae"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>)");
  std::vector<std::string> warnings;
  const Model m = importUrdf((dir / "a.urdf").string(), chain("", "", true), nullptr, &warnings);
  CHECK(warnings.empty());
  REQUIRE(!m.collision.volumes.empty());
  const Eigen::Vector3d V[4] = {{0, 0, 0}, {0.1, 0, 0}, {0, 0.2, 0}, {0, 0, 0.3}};
  KinematicsWorkspace ws(m);
  forwardKinematics(m, ws, Eigen::VectorXd::Zero(1));  // q = 0: body frame = link frame (axis z)
  const double worst = farthestOutside(m, ws, 0, {V, V + 4});
  double farthest_core = 0;
  for (const auto& v : m.collision.volumes)
    for (int k = 0; k < static_cast<int>(v.type); ++k)
      farthest_core = std::max(farthest_core, v.p_L[k].norm());
  INFO("farthest DAE vertex from the volumes' surface: " << worst);
  CHECK(worst <= kSinglePrecisionMesh_m);
  CHECK(farthest_core < 0.3);  // metres, not centimetres
}

TEST_CASE("URDF missing mesh is a warning and that link gets no volume", "[urdf][collision]") {
  std::string text = smallArm();
  const std::string box = R"(<box size="0.05 0.06 0.1"/>)";
  text.replace(text.find(box), box.size(), R"(<mesh filename="package://nowhere/meshes/l1.stl"/>)");
  std::vector<std::string> warnings;
  const Model m =
      importUrdfText(text, "missing_mesh.urdf", chain("base", "tool", true), nullptr, &warnings);
  for (const auto& v : m.collision.volumes) CHECK(v.link != 0);
  REQUIRE(warnings.size() >= 1);
  CHECK_THAT(warnings.front(), Catch::Contains("l1") && Catch::Contains("package://nowhere"));
  // what was looked for and where: the package, the packages given, the folders searched
  CHECK_THAT(warnings.front(), Catch::Contains("package 'nowhere' not found") &&
                                   Catch::Contains("packages given: none") &&
                                   Catch::Contains("nowhere/meshes/l1.stl"));
}

// ---- bad files: one test per case, each naming the file, line and element ----

TEST_CASE("URDF bad: unknown tip link", "[urdf][bad]") {
  const InputError e =
      expectInputError([] { importUrdfText(smallArm(), "bad.urdf", chain("base", "nosuch")); });
  CHECK(e.file() == "bad.urdf");
  CHECK(e.key() == "tip_link");
  CHECK_THAT(e.message(), Catch::Contains("nosuch"));
  // what exists: the file's links
  CHECK_THAT(e.message(), Catch::Contains("in bad.urdf; its 4 links: base, l1, l2, tool"));
}

TEST_CASE("URDF bad: unknown base link", "[urdf][bad]") {
  const InputError e =
      expectInputError([] { importUrdfText(smallArm(), "bad.urdf", chain("nobase", "")); });
  CHECK(e.key() == "base_link");
}

TEST_CASE("URDF bad: tip not below the base", "[urdf][bad]") {
  const InputError e =
      expectInputError([] { importUrdfText(smallArm(), "bad.urdf", chain("l2", "l1")); });
  CHECK_THAT(e.message(), Catch::Contains("not below"));
}

TEST_CASE("URDF bad: missing parent link", "[urdf][bad]") {
  const InputError e = expectInputError([] {
    importUrdfText(smallArm("", "revolute", "0 0 0.1", "ghost"), "bad.urdf", chain("", ""));
  });
  CHECK(e.file() == "bad.urdf");
  CHECK(e.line() == 19);  // <parent link="ghost"/> of joint j2
  CHECK_THAT(e.key(), Catch::Contains("joint 'j2'"));
  CHECK_THAT(e.message(), Catch::Contains("ghost"));
}

TEST_CASE("URDF bad: a cycle of joints", "[urdf][bad]") {
  const std::string text = R"(<robot name="cyc">
  <link name="a"/>
  <link name="b"/>
  <link name="c"/>
  <joint name="ab" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="bc" type="revolute"><parent link="b"/><child link="c"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="cb" type="revolute"><parent link="c"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>)";
  const InputError e = expectInputError([&] { importUrdfText(text, "cycle.urdf", chain("", "")); });
  CHECK(e.file() == "cycle.urdf");
  CHECK(e.line() == 9);  // <joint name="cb">: b's second parent closes the cycle b -> c -> b
  CHECK(e.key() == "joint 'cb'");
  CHECK_THAT(e.message(), Catch::Contains("two parent joints"));
}

TEST_CASE("URDF bad: a cycle without a second parent", "[urdf][bad]") {
  const std::string text = R"(<robot name="cyc">
  <link name="a"/>
  <link name="b"/>
  <joint name="ab" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="ba" type="revolute"><parent link="b"/><child link="a"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>)";
  const InputError e =
      expectInputError([&] { importUrdfText(text, "cycle2.urdf", chain("", "")); });
  CHECK(e.file() == "cycle2.urdf");
  CHECK_THAT(e.message(), Catch::Contains("cycle"));
  CHECK(e.key() == "joint 'ab'");
  CHECK(e.line() == 4);
}

TEST_CASE("URDF bad: NaN in a joint origin", "[urdf][bad]") {
  const InputError e = expectInputError(
      [] { importUrdfText(smallArm("", "revolute", "0 nan 0.1"), "nan.urdf", chain("", "")); });
  CHECK(e.file() == "nan.urdf");
  CHECK(e.line() == 14);  // <origin xyz="0 nan 0.1" .../> of joint j1
  CHECK(e.key() == "joint 'j1'/origin@xyz");
  CHECK_THAT(e.message(), Catch::Contains("nan"));
}

TEST_CASE("URDF bad: unknown joint type", "[urdf][bad]") {
  const InputError e = expectInputError(
      [] { importUrdfText(smallArm("", "spherical"), "type.urdf", chain("", "")); });
  CHECK(e.line() == 12);
  CHECK(e.key() == "joint 'j1'@type");
  CHECK_THAT(e.message(), Catch::Contains("spherical"));
}

TEST_CASE("URDF bad: mimic joint on the chain", "[urdf][bad]") {
  const InputError e =
      expectInputError([] { importUrdf(panda(), chain("panda_link0", "panda_rightfinger")); });
  CHECK(e.file() == panda());
  CHECK(e.line() == 342);  // <joint name="panda_finger_joint2"> in panda.urdf
  CHECK(e.key() == "joint 'panda_finger_joint2'/mimic");
}

TEST_CASE("URDF bad: floating joint on the chain", "[urdf][bad]") {
  const InputError e = expectInputError(
      [] { importUrdfText(smallArm("", "floating"), "float.urdf", chain("base", "tool")); });
  CHECK(e.line() == 12);
  CHECK(e.key() == "joint 'j1'");
}

TEST_CASE("URDF bad: malformed XML names the line", "[urdf][bad]") {
  const InputError e = expectInputError(
      [] { importUrdfText("<robot name=\"x\">\n<link name=\"a\">\n</robot>", "xml.urdf", {}); });
  CHECK(e.file() == "xml.urdf");
  CHECK(e.key() == "xml");
}

// ---- CLI ----

TEST_CASE("URDF CLI fk of the UR5 agrees with KDL and convert round-trips", "[urdf][cli]") {
  const std::string pkg =
      " --package example-robot-data=" + fs::path(robotsDir()).parent_path().string();
  std::string out;
  REQUIRE(test::runCommand(test::binaryPath() + " fk " + ur5() +
                               " --base base_link --tip tool0 --q 0.1,-1.2,0.8,0.3,-0.4,0.5 --json",
                           out) == 0);
  const KdlOracle kdl(kdlTreeFromFile(ur5()), "base_link", "tool0");
  KDL::ChainFkSolverPos_recursive fk(kdl.chain);
  Eigen::VectorXd q(6);
  q << 0.1, -1.2, 0.8, 0.3, -0.4, 0.5;
  KDL::Frame F;
  fk.JntToCart(toJnt(q), F);
  // the "tcp" frame row of the JSON
  const auto pos = out.find("\"frame\": \"tcp\"");
  REQUIRE(pos != std::string::npos);
  auto value = [&](const std::string& key) {
    const auto k = out.find("\"" + key + "\":", pos);
    return std::stod(out.substr(k + key.size() + 3));
  };
  CHECK(std::abs(value("x_m") - F.p.x()) < kUrdfOracleTolerance);
  CHECK(std::abs(value("y_m") - F.p.y()) < kUrdfOracleTolerance);
  CHECK(std::abs(value("z_m") - F.p.z()) < kUrdfOracleTolerance);
  // Joint rows are the URDF child link frames: wrist_1_joint's row is wrist_1_link.
  {
    const auto wpos = out.find("\"frame\": \"wrist_1_joint\"");
    REQUIRE(wpos != std::string::npos);
    auto wvalue = [&](const std::string& key) {
      const auto k = out.find("\"" + key + "\":", wpos);
      return std::stod(out.substr(k + key.size() + 3));
    };
    KDL::Chain c;
    REQUIRE(kdlTreeFromFile(ur5()).getChain("base_link", "wrist_1_link", c));
    KDL::ChainFkSolverPos_recursive fkw(c);
    KDL::Frame Fw;
    fkw.JntToCart(toJnt(q.head(4)), Fw);
    const Eigen::Isometry3d Tw = fromKdl(Fw);
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(wvalue("alpha"), Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(wvalue("beta"), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(wvalue("gamma"), Eigen::Vector3d::UnitZ()))
                                  .toRotationMatrix();
    CHECK((R - Tw.linear()).cwiseAbs().maxCoeff() < kUrdfOracleTolerance);
    CHECK(std::abs(wvalue("x_m") - Tw.translation().x()) < kUrdfOracleTolerance);
  }

  const std::string toml = tempPath("ur5.toml"), urdf = tempPath("ur5_back.urdf");
  REQUIRE(test::runCommand(test::binaryPath() + " convert " + ur5() + " " + toml +
                               " --base base_link --tip tool0" + pkg,
                           out) == 0);
  REQUIRE(test::runCommand(test::binaryPath() + " convert " + toml + " " + urdf, out) == 0);
  // urdfdom's own checker (liburdfdom-tools) accepts the export
  CHECK(test::runCommand("check_urdf " + urdf, out) == 0);
  CHECK_THAT(out, Catch::Contains("Successfully Parsed XML"));
  const Model back = importUrdf(urdf, chain("", "tool0"));
  const Errors e = compareWithKdl(back, kdl.chain, true, 4);
  CHECK(e.fk < kUrdfOracleTolerance);
  CHECK(e.id < kUrdfOracleTolerance);
  const Model t = loadDesign(toml);
  CHECK(t.collision.volumes.size() >= 7);

  // a bad file: exit 2, message names the file
  const std::string bad = tempPath("bad_cli.urdf");
  writeText(bad, smallArm("", "spherical"));
  CHECK(test::runCommand(test::binaryPath() + " describe " + bad, out) == 2);
  CHECK_THAT(out, Catch::Contains(bad) && Catch::Contains("spherical"));
}

// ---- studies ----

TEST_CASE("URDF designs in the shipped studies load with their chain, placement, TCP and volumes",
          "[urdf][study]") {
  const Study s = loadStudy(test::sourcePath("studies/ur5_vs_first_prototype.toml"));
  REQUIRE(s.designs.size() == 3);
  const Model& ur5m = s.designs[1].model;
  CHECK(ur5m.name == "ur5");
  CHECK(ur5m.dof() == 6);
  CHECK(ur5m.base.z == 1.1);
  CHECK(ur5m.T_WB.translation().z() == 1.1);
  CHECK(ur5m.collision.volumes.size() >= 7);  // one or more per UR5 collision mesh
  // The study's tcp = {z = 100 mm} is an offset from the tip link frame tool0, along its z axis,
  // the tool axis (the nozzle along the flange axis).
  const Model& flange = s.designs[2].model;
  CHECK(flange.name == "ur5_flange");
  const Eigen::Isometry3d expected = flange.T_NT * Eigen::Translation3d(0, 0, 0.1);
  CHECK((ur5m.T_NT.matrix() - expected.matrix()).cwiseAbs().maxCoeff() < kUrdfOracleTolerance);
  CHECK(ur5m.tool_axis_T == Eigen::Vector3d::UnitZ());
  const Study p = loadStudy(test::sourcePath("studies/stem_heatmap_panda.toml"));
  REQUIRE(p.designs.size() == 1);
  CHECK(p.designs[0].model.dof() == 7);
  CHECK(p.designs[0].model.collision.volumes.size() >= 8);
}

TEST_CASE("URDF keys on a TOML design in a study are an input error", "[urdf][study][bad]") {
  const std::string f = tempPath("study_bad.toml");
  writeText(f, "[study]\nname = \"x\"\n[[design]]\nfile = \"" +
                   test::sourcePath("designs/first_prototype_6dof.toml") +
                   "\"\ntip_link = \"tool0\"\n");
  const InputError e = expectInputError([&] { loadStudy(f); });
  CHECK(e.file() == f);
  CHECK(e.line() == 5);
  CHECK_THAT(e.key(), Catch::Contains("tip_link"));
}

namespace {
// Largest coordinate `axis` of the reachable extent of `design` on grid `grid` in a run's summary.
double largestReach(const nlohmann::json& summary, const std::string& grid,
                    const std::string& design, const std::string& axis) {
  for (const auto& g : summary["reach"]["grids"])
    if (g["name"] == grid)
      for (const auto& d : g["designs"])
        if (d["design"] == design) return d["extent"][axis][1].get<double>();
  FAIL("no grid " << grid << " / design " << design << " in the summary");
  return 0;
}
}  // namespace

TEST_CASE("URDF studies run end to end and the largest reach found matches the datasheets",
          "[urdf][study]") {
  // Datasheets: UR5 850 mm, Panda 855 mm (../shared/robots/README.md). The reach line runs at
  // shoulder height; the UR5 flange point reaches beyond 850 mm there (its wrist offsets), the
  // Panda's hand TCP is 0.1034 m beyond its flange.
  constexpr double kUr5Datasheet_m = 0.850, kPandaDatasheet_m = 0.855, kPandaHandTcp_m = 0.1034;
  constexpr double kPandaReachTolerance_m = 0.02;  // 5 mm grid + the definition of "reach"
  constexpr double kUr5WristOffsets_m = 0.093 + 0.09465 + 0.0823;  // most the wrist can add
  const std::string out_dir = tempPath("study_out");
  std::string out;
  for (const char* study : {"ur5_vs_first_prototype", "stem_heatmap_panda"}) {
    INFO(study);
    REQUIRE(test::runCommand(test::binaryPath() + " run " +
                                 test::sourcePath(std::string("studies/") + study + ".toml") +
                                 " --threads 2 --overwrite --output " + out_dir,
                             out) == 0);
  }
  nlohmann::json ur5s, pandas;
  std::ifstream(out_dir + "/ur5_vs_first_prototype/summary.json") >> ur5s;
  std::ifstream(out_dir + "/stem_heatmap_panda/summary.json") >> pandas;
  const double ur5_reach = largestReach(ur5s, "reach_line", "ur5_flange", "x_m");
  CHECK(ur5_reach >= kUr5Datasheet_m);
  CHECK(ur5_reach <= kUr5Datasheet_m + kUr5WristOffsets_m);
  const double panda_reach = largestReach(pandas, "reach_line", "panda", "y_m") - kPandaHandTcp_m;
  CHECK(std::abs(panda_reach - kPandaDatasheet_m) < kPandaReachTolerance_m);
  WARN("largest reach found: UR5 flange "
       << ur5_reach << " m (datasheet 0.850), Panda flange about " << panda_reach
       << " m (datasheet 0.855)");
  // Both arms were checked for self-collision with their own volumes on the Fig. 3.8 row.
  for (const auto& g : ur5s["reach"]["grids"])
    if (g["name"] == "fig3_8")
      for (const auto& d : g["designs"]) CHECK(d["fraction"].get<double>() > 0.3);
  std::ifstream report(out_dir + "/ur5_vs_first_prototype/reach/report.md");
  const std::string md((std::istreambuf_iterator<char>(report)), std::istreambuf_iterator<char>());
  CHECK_THAT(
      md, Catch::Contains("Self-collision: on") && Catch::Contains("UR5 datasheet: reach 850 mm"));
}

TEST_CASE("URDF collision models of the UR5 and the Panda: home posture free, no permanent contact",
          "[urdf][collision]") {
  // The pairs touching at q = 0 (clamped) become allowed pairs (assumption, docs/design-format.md);
  // every other pair must be free in the home posture and somewhere in a random sample, or the
  // import left a structural contact in the self-collision check.
  const std::pair<std::string, UrdfOptions> arms[] = {
      {ur5(), chain("base_link", "tool0", true)},
      {panda(), chain("panda_link0", "panda_hand", true)}};
  std::mt19937_64 rng(5);
  for (const auto& [file, o] : arms) {
    const Model m = importUrdf(file, o);
    INFO(m.name);
    REQUIRE(!m.collision.empty());
    KinematicsWorkspace kin(m);
    collision::CollisionWorkspace ws(m);
    REQUIRE(ws.num_self > 0);
    std::vector<bool> free(ws.num_self, false);
    for (int s = 0; s < 2000; ++s) {
      Eigen::VectorXd q = test::randomConfiguration(m, rng);
      if (s == 0)
        for (int i = 0; i < m.dof(); ++i)
          q[i] = std::clamp(0.0, m.joints[i].limits.q_min, m.joints[i].limits.q_max);
      forwardKinematics(m, kin, q);
      collision::collisionDistances(m, kin, {}, ws);
      if (s == 0) {
        INFO("home posture");
        CHECK(collision::minSelfDistance(ws) > 0);
      }
      for (int i = 0; i < ws.num_self; ++i)
        if (ws.self[i].distance_m > 0) free[i] = true;
    }
    for (int i = 0; i < ws.num_self; ++i) {
      INFO(collision::pairName(m, ws.self[i], false));
      CHECK(free[i]);
    }
  }
}

TEST_CASE("URDF effort limits reach the dynamics command: Q above <limit effort> is flagged",
          "[urdf][cli]") {
  std::string out;
  // Panda wrist joints 5-7 have effort 12 N m; 50 rad/s^2 on every joint exceeds it somewhere.
  REQUIRE(test::runCommand(test::binaryPath() + " dynamics " + panda() +
                               " --base panda_link0 --tip panda_hand --q 0,-0.5,0,-2,0,1.5,0.7"
                               " --qdd 50,50,50,50,50,50,50 --json",
                           out) == 0);
  const auto j = nlohmann::json::parse(out.substr(out.find('{')));
  REQUIRE(j["joints"].size() == 7);
  int over = 0;
  for (const auto& row : j["joints"]) {
    REQUIRE(row.contains("effort_limit"));
    const bool expect = std::abs(row["Q"].get<double>()) > row["effort_limit"].get<double>();
    CHECK(row["over_effort_limit"].get<bool>() == expect);
    over += expect ? 1 : 0;
  }
  CHECK(j["joints"][0]["effort_limit"].get<double>() == 87.0);
  CHECK(over > 0);
}

TEST_CASE("URDF package:// resolution: --package first, then the folders above the URDF file",
          "[urdf][collision]") {
  std::vector<std::string> warnings;
  // No --package: example-robot-data/robots/... is found above
  // ../shared/robots/ur_description/urdf.
  const Model found = importUrdf(ur5(), chain("base_link", "tool0", true), nullptr, &warnings);
  CHECK(warnings.size() == 2);  // the two branches, no mesh warning
  CHECK(found.collision.volumes.size() >= 7);
  // A --package pointing elsewhere wins over the search: every mesh is missing, a warning each.
  UrdfOptions o = chain("base_link", "tool0", true);
  o.packages = {{"example-robot-data", tempPath("no_meshes_here")}};
  const Model missing = importUrdf(ur5(), o, nullptr, &warnings);
  CHECK(missing.collision.empty());
  int mesh_warnings = 0;
  for (const auto& w : warnings)
    mesh_warnings += w.find("mesh file not found") != std::string::npos ? 1 : 0;
  CHECK(mesh_warnings == 7);
  // each names the path it tried
  CHECK_THAT(warnings.back(), Catch::Contains("tried " + tempPath("no_meshes_here")));
  // The kinematics do not depend on the meshes.
  CHECK(missing.dof() == found.dof());
  CHECK((missing.joints[3].T_PJ0.matrix() - found.joints[3].T_PJ0.matrix()).norm() == 0.0);
}

// ---- the design-format keys that carry URDF facts ----

namespace {
std::string oneJointDesign(const std::string& joint_extra, const std::string& type = "revolute") {
  return "[design]\nname = \"d\"\n[[joint]]\nname = \"j1\"\ntype = \"" + type +
         "\"\nx = 0\ny = 0\nz = 0\nalpha = 0\nbeta = 0\ngamma = 0\n" + joint_extra + "\n[tcp]\n";
}
}  // namespace

TEST_CASE("Design TOML: a continuous joint gets the stand-in range unless min/max are given",
          "[urdf][design]") {
  UrdfInfo info;
  const Model m = parseDesignWithUrdfInfo(
      oneJointDesign("continuous = true\nlink = \"l1\"\nmax_effort = 3"), "c.toml", &info);
  CHECK(m.joints[0].limits.q_min == -defaults::kContinuousJointRange_rad);
  CHECK(m.joints[0].limits.q_max == defaults::kContinuousJointRange_rad);
  REQUIRE(info.joints.size() == 1);
  CHECK(info.joints[0].continuous);
  CHECK(info.joints[0].link == "l1");
  CHECK(info.joints[0].effort_max == 3.0);
}

TEST_CASE("Design TOML bad: continuous on a prismatic joint", "[urdf][design][bad]") {
  const InputError e = expectInputError([] {
    parseDesign(oneJointDesign("continuous = true\nmin = -1\nmax = 1", "prismatic"), "bad.toml");
  });
  CHECK(e.file() == "bad.toml");
  CHECK(e.key() == "joint[0].continuous");
  CHECK(e.line() == 12);  // the key's line
}

TEST_CASE("Design TOML bad: negative max_effort", "[urdf][design][bad]") {
  const InputError e = expectInputError(
      [] { parseDesign(oneJointDesign("min = -1\nmax = 1\nmax_effort = -2"), "bad.toml"); });
  CHECK(e.key() == "joint[0].max_effort");
  CHECK(e.line() == 14);
}

TEST_CASE("Design TOML writer: every shipped design written and read back is the same model",
          "[urdf][design]") {
  for (const std::string& rel : test::shippedDesigns()) {
    INFO(rel);
    const Model a = loadDesign(test::sourcePath(rel));
    const Model b = parseDesign(designToToml(a), rel + ".written.toml");
    CHECK(b.name == a.name);
    CHECK(b.assumptions == a.assumptions);
    REQUIRE(b.dof() == a.dof());
    for (int i = 0; i < a.dof(); ++i) {
      CHECK(b.joints[i].type == a.joints[i].type);
      CHECK(b.joints[i].T_PJ0.matrix() == a.joints[i].T_PJ0.matrix());
      CHECK(b.joints[i].limits.q_min == a.joints[i].limits.q_min);
      CHECK(b.joints[i].limits.q_max == a.joints[i].limits.q_max);
      CHECK(b.joints[i].limits.qd_max == a.joints[i].limits.qd_max);
    }
    CHECK(b.T_NT.matrix() == a.T_NT.matrix());
    CHECK(b.T_WB.matrix() == a.T_WB.matrix());
    REQUIRE(b.inertias.size() == a.inertias.size());
    for (std::size_t i = 0; i < a.inertias.size(); ++i) {
      CHECK(b.inertias[i].given == a.inertias[i].given);
      CHECK(b.inertias[i].mass_kg == a.inertias[i].mass_kg);
      CHECK(b.inertias[i].p_com_m == a.inertias[i].p_com_m);
      CHECK(b.inertias[i].I_com_kgm2 == a.inertias[i].I_com_kgm2);
    }
    CHECK(b.payload_kg == a.payload_kg);
    CHECK(b.p_payload_com_T == a.p_payload_com_T);
    REQUIRE(b.drives.size() == a.drives.size());
    for (std::size_t i = 0; i < a.drives.size(); ++i) {
      CHECK(b.drives[i].joint == a.drives[i].joint);
      CHECK(b.drives[i].gear_ratio == a.drives[i].gear_ratio);
      CHECK(b.drives[i].torque_constant_NmpA == a.drives[i].torque_constant_NmpA);
      CHECK(b.drives[i].rotor_inertia_kgm2 == a.drives[i].rotor_inertia_kgm2);
      CHECK(b.drives[i].peak_current_A == a.drives[i].peak_current_A);
      CHECK(b.drives[i].friction_law == a.drives[i].friction_law);
      CHECK(b.drives[i].friction == a.drives[i].friction);
    }
    CHECK(b.effects == a.effects);
    REQUIRE(b.collision.volumes.size() == a.collision.volumes.size());
    for (std::size_t i = 0; i < a.collision.volumes.size(); ++i) {
      CHECK(b.collision.volumes[i].link == a.collision.volumes[i].link);
      CHECK(b.collision.volumes[i].type == a.collision.volumes[i].type);
      CHECK(b.collision.volumes[i].radius_m == a.collision.volumes[i].radius_m);
      CHECK(b.collision.volumes[i].p_L == a.collision.volumes[i].p_L);
    }
    CHECK(b.collision.allowed_pairs == a.collision.allowed_pairs);
  }
}

// ---- URDF arms as people bring them (tests/io/urdf/arm6_gripper.urdf) ----

namespace {
std::string arm6() { return test::sourcePath("tests/io/urdf/arm6_gripper.urdf"); }
std::string readText(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
// `text` with the first `from` replaced by `to` (which must be there).
std::string edited(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// Largest difference (position [m] and rotation-matrix entry) between the frames that the link
// names `links` denote in two KDL trees (each from `base`), at random joint values.
double largestFrameDifference(const KDL::Tree& a, const KDL::Tree& b, const std::string& base,
                              const std::vector<std::string>& links, const Model& m) {
  std::mt19937_64 rng(38);
  double worst = 0;
  for (int k = 0; k < kRandomConfigurations; ++k) {
    const Eigen::VectorXd q = test::randomConfiguration(m, rng);
    for (const std::string& link : links) {
      KDL::Chain ca, cb;
      INFO("link " << link);
      REQUIRE(a.getChain(base, link, ca));
      REQUIRE(b.getChain(base, link, cb));
      REQUIRE(ca.getNrOfJoints() == cb.getNrOfJoints());
      KDL::Frame Fa, Fb;
      KDL::ChainFkSolverPos_recursive(ca).JntToCart(toJnt(q.head(ca.getNrOfJoints())), Fa);
      KDL::ChainFkSolverPos_recursive(cb).JntToCart(toJnt(q.head(cb.getNrOfJoints())), Fb);
      const Eigen::Isometry3d Ta = fromKdl(Fa), Tb = fromKdl(Fb);
      worst = std::max({worst, (Ta.translation() - Tb.translation()).cwiseAbs().maxCoeff(),
                        (Ta.linear() - Tb.linear()).cwiseAbs().maxCoeff()});
    }
  }
  return worst;
}

const std::vector<std::string> kArm6Links = {"link1", "link2", "link3", "link4", "link5", "link6"};
}  // namespace

TEST_CASE("URDF vendor elements inside links and joints are ignored, as urdfdom does", "[urdf]") {
  // <verbose value="Yes"/> (PR2), <selfCollide value="true"/> (ABB), <provideFeedback> in a joint
  const std::string text = readText(arm6());
  REQUIRE(text.find("<verbose value=\"Yes\"/>") != std::string::npos);
  REQUIRE(text.find("<selfCollide value=\"true\"/>") != std::string::npos);
  UrdfInfo info;
  const Model m = importUrdf(arm6(), chain("", ""), &info);
  CHECK(m.dof() == 6);
  checkAgainstKdl(arm6(), "base_link", "tool0", 6);
}

TEST_CASE("URDF numbers are still checked where URDF defines them", "[urdf][bad]") {
  const std::string text = edited(readText(arm6()), "<mass value=\"3\"/>", "<mass value=\"Yes\"/>");
  const InputError e = expectInputError([&] { importUrdfText(text, "arm6.urdf", chain("", "")); });
  CHECK(e.key() == "link 'link2'/mass@value");
  CHECK_THAT(e.message(), Catch::Contains("'Yes' is not a finite number"));
}

TEST_CASE("URDF default chain leaves the gripper out and ends in the one path of fixed frames",
          "[urdf]") {
  UrdfInfo info;
  const Model m = importUrdf(arm6(), chain("", ""), &info);
  CHECK(m.dof() == 6);
  CHECK(info.base_link == "base_link");
  CHECK(info.tcp_link == "tool0");
  const UrdfChains c = findUrdfChains(arm6(), chain("", ""));
  REQUIRE(c.ends.size() == 1);
  CHECK(c.ends[0].link == "link6");
  CHECK(c.ends[0].joints == 6);
  CHECK(c.ends[0].fixed_frames == std::vector<std::string>{"flange", "tool0"});
  CHECK(c.ends[0].left_out ==
        std::vector<std::string>{"gripper_finger_joint_left (gripper or finger joint)",
                                 "gripper_finger_joint_right (mimic joint)"});
  CHECK(c.chosen == "tool0");
}

namespace {
// Two arm joints, then a hand frame 0.16 m out and two fingers written as fixed joints (as the
// Kinova JACO2 j2s6s200 of example-robot-data writes them, with a zero axis and zero limits on
// its fixed mounting joint).
const char* kFixedFingers = R"(<robot name="fixed_fingers">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="mount"/>
  <joint name="base_to_mount" type="fixed"><parent link="base"/><child link="mount"/>
    <axis xyz="0 0 0"/><limit effort="0" lower="0" upper="0" velocity="0"/></joint>
  <joint name="j1" type="revolute"><parent link="mount"/><child link="l1"/><axis xyz="0 0 1"/>
    <origin xyz="0 0 0.2"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/><axis xyz="0 1 0"/>
    <origin xyz="0 0 0.3"/><limit lower="-6.28" upper="6.28" effort="1" velocity="1"/></joint>
  <link name="end_effector"/>
  <joint name="joint_end_effector" type="fixed"><parent link="l2"/><child link="end_effector"/>
    <origin rpy="3.14159265359 1.57079632679 0" xyz="0 0 -0.16"/></joint>
  <link name="link_finger_1"/><link name="link_finger_tip_1"/><link name="link_finger_2"/>
  <joint name="joint_finger_1" type="fixed"><parent link="l2"/><child link="link_finger_1"/>
    <axis xyz="0 0 1"/><origin xyz="0 0.03 -0.11"/>
    <limit effort="2" lower="0" upper="1.51" velocity="1"/></joint>
  <joint name="joint_finger_tip_1" type="fixed"><parent link="link_finger_1"/>
    <child link="link_finger_tip_1"/><origin xyz="0.044 -0.003 0"/></joint>
  <joint name="joint_finger_2" type="fixed"><parent link="l2"/><child link="link_finger_2"/>
    <axis xyz="0 0 1"/><origin xyz="0 -0.03 -0.11"/></joint>
</robot>)";
}  // namespace

TEST_CASE("URDF default tip: finger frames on fixed joints do not hide the hand frame", "[urdf]") {
  const std::string f = tempPath("fixed_fingers.urdf");
  writeText(f, kFixedFingers);
  const UrdfChains c = findUrdfChains(f, chain("", ""));
  REQUIRE(c.ends.size() == 1);
  CHECK(c.ends[0].link == "l2");
  CHECK(c.ends[0].joints == 2);
  CHECK(c.chosen == "end_effector");
  CHECK_THAT(c.reason, Catch::Contains("finger, sensor and off-axis frames aside") &&
                           Catch::Contains("link_finger_1, link_finger_2"));
  UrdfInfo info;
  const Model m = importUrdf(f, chain("", ""), &info);
  CHECK(m.dof() == 2);
  CHECK(info.tcp_link == "end_effector");
  // The TCP is the hand frame: 0.16 m along -z of l2, which at q = 0 is 0.5 - 0.16 m up.
  KinematicsWorkspace ws(m);
  forwardKinematics(m, ws, Eigen::VectorXd::Zero(2));
  CHECK(ws.p_WT.z() == Approx(0.34).margin(kUrdfOracleTolerance));
  // The fingers stay reachable with --tip, and a finger frame is still a tip of its own.
  CHECK(importUrdf(f, chain("", "link_finger_tip_1")).dof() == 2);
}

TEST_CASE("URDF default tip: sensor frames on the palm do not hide the tool frame", "[urdf]") {
  // As the PR2's gripper palm: an LED frame, an accelerometer and the tool frame 0.18 m out, all
  // on fixed joints, besides the finger joints.
  const std::string f = tempPath("palm_sensors.urdf");
  writeText(f, R"(<robot name="palm">
  <link name="base"/><link name="l1"/><link name="palm"/><link name="r_gripper_led_frame"/>
  <link name="r_gripper_motor_accelerometer_link"/><link name="r_gripper_tool_frame"/>
  <link name="finger"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="palm_joint" type="fixed"><parent link="l1"/><child link="palm"/></joint>
  <joint name="r_gripper_led_joint" type="fixed"><parent link="palm"/>
    <child link="r_gripper_led_frame"/><origin xyz="0.0513 0.0 .0244"/></joint>
  <joint name="r_gripper_motor_accelerometer_joint" type="fixed"><parent link="palm"/>
    <child link="r_gripper_motor_accelerometer_link"/></joint>
  <joint name="r_gripper_tool_joint" type="fixed"><parent link="palm"/>
    <child link="r_gripper_tool_frame"/><origin xyz="0.18 0 0"/></joint>
  <joint name="r_gripper_l_finger_joint" type="revolute"><parent link="palm"/><child link="finger"/>
    <axis xyz="0 0 1"/><limit lower="0" upper="0.548" effort="1" velocity="1"/></joint>
</robot>)");
  const UrdfChains c = findUrdfChains(f, chain("", ""));
  REQUIRE(c.ends.size() == 1);
  CHECK(c.chosen == "r_gripper_tool_frame");
  CHECK_THAT(c.reason, Catch::Contains("r_gripper_led_frame, r_gripper_motor_accelerometer_link"));
  UrdfInfo info;
  const Model m = importUrdf(f, chain("", ""), &info);
  CHECK(info.tcp_link == "r_gripper_tool_frame");
  KinematicsWorkspace ws(m);
  forwardKinematics(m, ws, Eigen::VectorXd::Zero(1));
  CHECK(ws.p_WT.x() == Approx(0.18).margin(kUrdfOracleTolerance));
}

TEST_CASE("URDF default chain stops before a mimic joint inside the arm", "[urdf]") {
  // A parallel linkage joint that follows joint 5 (as the ABB IRB 5400's joint_5b): not an arm
  // joint, so the default chain ends at link5 instead of refusing the chain it chose.
  const std::string text =
      edited(readText(arm6()), "<limit lower=\"-2.7\" upper=\"2.7\" effort=\"10\" velocity=\"3\"/>",
             "<limit lower=\"-2.7\" upper=\"2.7\" effort=\"10\" velocity=\"3\"/>"
             "<mimic joint=\"joint5\"/>");
  UrdfInfo info;
  const Model m = importUrdfText(text, "mimic.urdf", chain("", ""), &info);
  CHECK(m.dof() == 5);
  CHECK(info.tcp_link == "link5");
}

TEST_CASE("URDF a floating joint below the root ends the chain and asks for --base",
          "[urdf][bad]") {
  const std::string text =
      edited(readText(arm6()), "<link name=\"base_link\"/>",
             "<link name=\"world\"/><link name=\"base_link\"/><joint name=\"float\" "
             "type=\"floating\"><parent link=\"world\"/><child link=\"base_link\"/></joint>");
  const InputError e = expectInputError([&] { importUrdfText(text, "f.urdf", chain("", "")); });
  CHECK_THAT(e.message(), Catch::Contains("float (floating joint)") && Catch::Contains("--base"));
  CHECK(importUrdfText(text, "f.urdf", chain("base_link", "")).dof() == 6);
}

TEST_CASE("URDF a joint without lower and upper gets its own message", "[urdf][bad]") {
  const std::string text =
      edited(readText(arm6()), "<limit lower=\"-2.8\" upper=\"0\" effort=\"20\" velocity=\"3\"/>",
             "<limit effort=\"20\" velocity=\"3\"/>");
  const InputError e = expectInputError([&] { importUrdfText(text, "nl.urdf", chain("", "")); });
  CHECK(e.key() == "joint 'joint3'/limit");
  CHECK_THAT(e.message(), Catch::Contains("no lower or upper") && Catch::Contains("continuous"));
}

TEST_CASE("URDF round trip: every link name of the export denotes the original frame", "[urdf]") {
  const KDL::Tree original = kdlTreeFromFile(arm6());
  for (const std::string tip : {"tool0", "link6"}) {
    INFO("tip " << tip);
    UrdfInfo info;
    const Model m = importUrdf(arm6(), chain("", tip), &info);
    std::vector<std::string> links = kArm6Links;
    if (tip == "tool0") links.push_back("tool0");
    // URDF -> URDF, and URDF -> TOML -> URDF
    UrdfInfo info_back;
    const Model back = parseDesignWithUrdfInfo(designToToml(m, info), "arm6.toml", &info_back);
    for (const std::string& urdf : {exportUrdf(m, info), exportUrdf(back, info_back)}) {
      KDL::Tree exported;
      REQUIRE(kdl_parser::treeFromString(urdf, exported));
      const double d = largestFrameDifference(original, exported, "base_link", links, m);
      INFO("largest frame difference " << d);
      CHECK(d < kUrdfOracleTolerance);
      // read back with the default chain: the same tip
      UrdfInfo again;
      importUrdfText(urdf, "back.urdf", chain("", ""), &again);
      CHECK(again.tcp_link == tip);
    }
  }
}

TEST_CASE("URDF CLI describe lists the chains, the tip chosen and why, and the other tips",
          "[urdf][cli]") {
  std::string out;
  REQUIRE(test::runCommand(test::binaryPath() + " describe " + arm6(), out) == 0);
  CHECK_THAT(out, Catch::Contains("chains below 'base_link'"));
  CHECK_THAT(out, Catch::Contains("link6") && Catch::Contains(" 6 joints"));
  CHECK_THAT(out, Catch::Contains("fixed frames after it: flange, tool0"));
  CHECK_THAT(out, Catch::Contains("left out: gripper_finger_joint_left (gripper or finger joint)"));
  CHECK_THAT(out,
             Catch::Contains("tip      'tool0' (default: the longest chain of arm joints (6)"));
  CHECK_THAT(out, Catch::Contains("other tips: --tip link6, --tip flange"));
  // an ambiguous default: describe still lists the chains, then fails with exit 2
  const std::string two = tempPath("two_arms.urdf");
  writeText(two, kTwoArms);
  REQUIRE(test::runCommand(test::binaryPath() + " describe " + two, out) == 2);
  CHECK_THAT(out, Catch::Contains("tip      none by default") &&
                      Catch::Contains("other tips: --tip a, --tip b"));
  // a base that is not there: what was looked for, in which file, and the links it has
  REQUIRE(test::runCommand(test::binaryPath() + " describe " + arm6() + " --base nosuch", out) ==
          2);
  CHECK_THAT(out, Catch::Contains("no link named 'nosuch' (--base; base_link in a study) in " +
                                  arm6() + "; its 11 links: base_link, finger_left, finger_right"));
}

namespace {
// describe --json of a URDF (stderr left out): its exit status and the JSON it printed.
nlohmann::json describeJson(const std::string& args, int& status) {
  std::string out;
  status = test::runCommand("(" + test::binaryPath() + " describe " + args + " --json 2>/dev/null)",
                            out);
  INFO(out);
  return nlohmann::json::parse(out);
}
}  // namespace

TEST_CASE("URDF CLI describe --json lists the chains, the tip chosen and why, and the other tips",
          "[urdf][cli]") {
  struct Expected {
    std::string file, base, end, tip;
    int joints;
    std::vector<std::string> fixed_frames;
    std::size_t left_out;
  };
  const std::vector<Expected> arms = {
      {arm6(), "base_link", "link6", "tool0", 6, {"flange", "tool0"}, 2},
      {ur5(), "world", "wrist_3_link", "wrist_3_link", 6, {"ee_link", "tool0"}, 0},
      {panda(),
       "panda_link0",
       "panda_link7",
       "panda_hand_tcp",
       7,
       {"panda_link8", "panda_hand", "panda_hand_tcp"},
       2}};
  for (const Expected& e : arms) {
    INFO(e.file);
    int status = -1;
    const nlohmann::json j = describeJson(e.file, status);
    REQUIRE(status == 0);
    const nlohmann::json& c = j.at("urdf_chains");
    CHECK(c.at("base") == e.base);
    REQUIRE(c.at("chains").size() == 1);
    CHECK(c["chains"][0].at("end") == e.end);
    CHECK(c["chains"][0].at("joints") == e.joints);
    CHECK(c["chains"][0].at("fixed_frames") == e.fixed_frames);
    CHECK(c["chains"][0].at("left_out").size() == e.left_out);
    CHECK(c.at("tip") == e.tip);
    CHECK(c.at("tip_from") == "default");
    CHECK(c.at("default_tip") == e.tip);
    CHECK(c.at("default_reason").get<std::string>().find(e.end) != std::string::npos);
    CHECK(j.at("dof") == e.joints);  // the design describe loaded is the chain it names
    // Every other tip it offers loads with --tip: the same joints, the chain's end or a frame
    // fixed after it.
    std::vector<std::string> others = c.at("other_tips");
    std::vector<std::string> all = e.fixed_frames;
    all.insert(all.begin(), e.end);
    all.erase(std::find(all.begin(), all.end(), e.tip));
    CHECK(others == all);
    for (const std::string& tip : others) {
      INFO(tip);
      const nlohmann::json k = describeJson(e.file + " --tip " + tip, status);
      REQUIRE(status == 0);
      CHECK(k.at("dof") == e.joints);
      CHECK(k.at("urdf_chains").at("tip") == tip);
      CHECK(k.at("urdf_chains").at("tip_from") == "--tip");
      CHECK(std::count(k["urdf_chains"]["other_tips"].begin(), k["urdf_chains"]["other_tips"].end(),
                       e.tip) == 1);
    }
  }
  // An ambiguous default: the chains as JSON, then exit 2.
  const std::string two = tempPath("two_arms_json.urdf");
  writeText(two, kTwoArms);
  int status = -1;
  const nlohmann::json j = describeJson(two, status);
  CHECK(status == 2);
  const nlohmann::json& c = j.at("urdf_chains");
  CHECK(c.at("tip").is_null());
  CHECK(c.at("tip_from") == "none");
  CHECK(c.at("chains").size() == 2);
  CHECK(c.at("other_tips") == std::vector<std::string>{"a", "b"});
  // A design file has no URDF chains.
  CHECK_FALSE(describeJson(test::sourcePath("designs/first_prototype_6dof.toml"), status)
                  .contains("urdf_chains"));
}

TEST_CASE("URDF CLI convert both ways keeps the tip and every frame fk prints", "[urdf][cli]") {
  const std::string toml = tempPath("arm6.toml"), urdf = tempPath("arm6_back.urdf");
  std::string out, fk_a, fk_b;
  REQUIRE(test::runCommand(test::binaryPath() + " convert " + arm6() + " " + toml, out) == 0);
  REQUIRE(test::runCommand(test::binaryPath() + " convert " + toml + " " + urdf, out) == 0);
  REQUIRE(test::runCommand(test::binaryPath() + " describe " + urdf, out) == 0);
  CHECK_THAT(out, Catch::Contains("tip      'tool0' (default"));
  const std::string q = " --q 0.3,-0.7,-1.1,0.9,0.4,-1.3 --json";
  REQUIRE(test::runCommand(test::binaryPath() + " fk " + arm6() + q, fk_a) == 0);
  REQUIRE(test::runCommand(test::binaryPath() + " fk " + urdf + q, fk_b) == 0);
  const auto ja = nlohmann::json::parse(fk_a)["frames"], jb = nlohmann::json::parse(fk_b)["frames"];
  REQUIRE(ja.size() == jb.size());
  for (std::size_t r = 0; r < ja.size(); ++r)
    for (const char* k : {"x_m", "y_m", "z_m", "alpha", "beta", "gamma"}) {
      INFO(ja[r]["frame"] << " " << k);
      CHECK(std::abs(ja[r][k].get<double>() - jb[r][k].get<double>()) < kUrdfOracleTolerance);
    }
}

TEST_CASE("URDF CLI --package to a missing folder is exit 2 naming the folder",
          "[urdf][cli][bad]") {
  std::string out;
  CHECK(test::runCommand(
            test::binaryPath() + " describe " + arm6() + " --package arm=/nonexistent/armstudy_dir",
            out) == 2);
  CHECK_THAT(out, Catch::Contains("/nonexistent/armstudy_dir") &&
                      Catch::Contains("package 'arm'") && Catch::Contains("does not exist"));
}

TEST_CASE("URDF CLI fk values that look like degrees without --deg get a hint", "[urdf][cli]") {
  std::string out;
  REQUIRE(test::runCommand(test::binaryPath() + " fk " + arm6() + " --q 0,90,-90,0,45,0", out) ==
          0);
  CHECK_THAT(out, Catch::Contains("joint2, joint3, joint5 are beyond a full turn") &&
                      Catch::Contains("add --deg"));
  REQUIRE(test::runCommand(test::binaryPath() + " fk " + arm6() + " --q 0,1,-1,0,0.5,0", out) == 0);
  CHECK_THAT(out, !Catch::Contains("--deg"));
}

TEST_CASE("URDF CLI fk --json angles are exact in the Cardan band short of the singularity",
          "[urdf][cli]") {
  // R = Rx(q) Ry(1.5707965) Rz(0.4), cos(beta) = -1.7e-7: inside the band |cos beta| < 1e-6 the
  // reach solver treats as singular, yet the angles are defined (a URDF rpy written as 1.5707965).
  const std::string f = tempPath("near_singular.urdf");
  writeText(f, R"(<robot name="ns">
  <link name="base"/><link name="l1"/><link name="tip"/>
  <link name="mid"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="1 0 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="t1" type="fixed"><parent link="l1"/><child link="mid"/>
    <origin xyz="0.1 0 0" rpy="0 1.5707965 0"/></joint>
  <joint name="t2" type="fixed"><parent link="mid"/><child link="tip"/>
    <origin xyz="0 0 0" rpy="0 0 0.4"/></joint>
</robot>)");
  std::string out;
  REQUIRE(test::runCommand(test::binaryPath() + " fk " + f + " --q 0.3 --json", out) == 0);
  const auto tcp = nlohmann::json::parse(out)["frames"].back();
  CHECK(tcp["cardan_singular"].get<bool>());
  const Eigen::Matrix3d R = rotationFromCardan(
      tcp["alpha"].get<double>(), tcp["beta"].get<double>(), tcp["gamma"].get<double>());
  KDL::Chain c;
  REQUIRE(kdlTreeFromFile(f).getChain("base", "tip", c));
  KDL::Frame F;
  Eigen::VectorXd q(1);
  q << 0.3;
  KDL::ChainFkSolverPos_recursive(c).JntToCart(toJnt(q), F);
  CHECK((R - fromKdl(F).linear()).cwiseAbs().maxCoeff() < kUrdfOracleTolerance);
}

// ---- URDF designs in studies ----

namespace {
std::string urdfStudy(const std::string& entry) {
  return "[study]\nname = \"s\"\n[[design]]\nfile = \"" + arm6() + "\"\n" + entry;
}
}  // namespace

TEST_CASE("URDF error in a study names the study's line and the URDF's", "[urdf][study][bad]") {
  const std::string f = tempPath("study_tip.toml");
  writeText(f, urdfStudy("tip_link = \"end_effector\"\n"));
  const InputError e = expectInputError([&] { loadStudy(f); });
  CHECK(e.file() == f);
  CHECK(e.line() == 5);
  CHECK_THAT(e.key(), Catch::Contains("tip_link"));
  CHECK_THAT(e.message(), Catch::Contains(arm6()) && Catch::Contains("'end_effector'") &&
                              Catch::Contains("link6"));
  writeText(f, urdfStudy("packages = { arm = \"no_such_folder\" }\n"));
  const InputError p = expectInputError([&] { loadStudy(f); });
  CHECK(p.line() == 5);
  CHECK_THAT(p.message(), Catch::Contains("no_such_folder") && Catch::Contains("does not exist"));
}

TEST_CASE("URDF placement in a study: a length string needs its unit and is range-checked",
          "[urdf][study][bad]") {
  const std::string f = tempPath("study_units.toml");
  writeText(f, urdfStudy("base = { z = \"924.5\" }\n"));
  const InputError e = expectInputError([&] { loadStudy(f); });
  CHECK(e.file() == f);
  CHECK(e.line() == 5);
  CHECK_THAT(e.message(), Catch::Contains("needs its unit") && Catch::Contains("'924.5 mm'"));
  writeText(f, urdfStudy("base = { z = \"924.5 mm\" }\n"));
  CHECK(loadStudy(f).designs[0].model.base.z == Approx(0.9245).epsilon(1e-15));
  for (const char* z : {"2000", "\"2000 m\""}) {
    writeText(f, urdfStudy(std::string("base = { z = ") + z + " }\n"));
    const InputError big = expectInputError([&] { loadStudy(f); });
    CHECK_THAT(big.message(), Catch::Contains("not plausible"));
  }
  writeText(f, urdfStudy("base = { gamma = \"pi/2\" }\n"));  // angles keep their meaning
  CHECK(loadStudy(f).designs[0].model.base.gamma == Approx(M_PI / 2).epsilon(1e-15));
}

TEST_CASE("URDF CLI draw writes the arm as an SVG at q = 0 or a given q", "[urdf][cli]") {
  const std::string svg = tempPath("arm6.svg");
  std::string out;
  REQUIRE(test::runCommand(
              test::binaryPath() + " draw " + arm6() + " --deg --q 0,30,-60,0,45,0 --out " + svg,
              out) == 0);
  CHECK_THAT(out, Catch::Contains("wrote " + svg + " (arm6_gripper, 6 joints)"));
  const std::string text = readText(svg);
  CHECK_THAT(text, Catch::Contains("<svg"));
  CHECK(text.size() > 1000);
  REQUIRE(test::runCommand(test::binaryPath() + " draw " + arm6() + " --out " + svg, out) == 0);
  CHECK(test::runCommand(test::binaryPath() + " draw " + arm6() + " --q 0,1 --out " + svg, out) ==
        2);
  CHECK_THAT(out, Catch::Contains("got 2 joint values, design 'arm6_gripper' has 6 joints"));
}

TEST_CASE("URDF the shipped robots keep their default tip and link frames through convert",
          "[urdf]") {
  for (const std::string& file : {ur5(), panda()}) {
    INFO(file);
    UrdfInfo info, info_back, again;
    const Model m = importUrdf(file, chain("", ""), &info);
    const Model back = parseDesignWithUrdfInfo(designToToml(m, info), "r.toml", &info_back);
    const std::string urdf = exportUrdf(back, info_back);
    importUrdfText(urdf, "r.urdf", chain("", ""), &again);
    CHECK(again.base_link == info.base_link);
    CHECK(again.tcp_link == info.tcp_link);
    std::vector<std::string> links{info.tcp_link};
    for (const auto& j : info.joints) links.push_back(j.link);
    KDL::Tree exported;
    REQUIRE(kdl_parser::treeFromString(urdf, exported));
    const double d =
        largestFrameDifference(kdlTreeFromFile(file), exported, info.base_link, links, m);
    INFO("largest frame difference " << d);
    CHECK(d < kUrdfOracleTolerance);
  }
}

// ---- hostile input: XML structure, mesh files and mesh content ----

namespace {

// The TX40 read through convert (URDF -> TOML -> URDF) agrees with the URDF to this, in m and in
// rotation-matrix entries: the numbers travel with 17 significant digits.
constexpr double kRoundTripTolerance = 1e-12;

// A binary STL of the corners `v` (indices into them, 3 per triangle).
void writeBinaryStl(const std::string& path, const std::vector<Eigen::Vector3f>& v,
                    const std::vector<std::array<int, 3>>& tris) {
  std::ofstream out(path, std::ios::binary);
  const std::string header(80, ' ');
  out.write(header.data(), 80);
  const std::uint32_t n = static_cast<std::uint32_t>(tris.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : tris) {
    const float normal[3] = {0, 0, 0};
    out.write(reinterpret_cast<const char*>(normal), 12);
    for (int k : t) out.write(reinterpret_cast<const char*>(v[k].data()), 12);
    const char attr[2] = {0, 0};
    out.write(attr, 2);
  }
}

// An ASCII STL of the corners written as the strings `v` ("x y z").
void writeAsciiStl(const std::string& path, const std::vector<std::string>& v,
                   const std::vector<std::array<int, 3>>& tris) {
  std::ofstream out(path);
  out << "solid part\n";
  for (const auto& t : tris) {
    out << "facet normal 0 0 0\nouter loop\n";
    for (int k : t) out << "vertex " << v[k] << "\n";
    out << "endloop\nendfacet\n";
  }
  out << "endsolid part\n";
}

// The 12 triangles of a box with corners k (bit 0 = +x, bit 1 = +y, bit 2 = +z).
const std::vector<std::array<int, 3>> kBoxTriangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                                       {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                                       {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};

// Corners of a 0.1 m cube, corner 0 moved to x0 along x.
std::vector<Eigen::Vector3f> cubeCorners(float x0 = 0) {
  std::vector<Eigen::Vector3f> v;
  for (int k = 0; k < 8; ++k)
    v.emplace_back(k & 1 ? 0.1f : 0.f, k & 2 ? 0.1f : 0.f, k & 4 ? 0.1f : 0.f);
  v[0].x() = x0;
  return v;
}

// A one-joint arm whose link l1 (line 3) has one collision element: `geometry` at `origin_xyz`.
std::string meshArm(const std::string& geometry, const std::string& origin_xyz = "0 0 0") {
  return "<robot name=\"mesharm\">\n  <link name=\"base\"/>\n  <link "
         "name=\"l1\"><collision><origin "
         "xyz=\"" +
         origin_xyz + "\"/><geometry>" + geometry +
         "</geometry></collision></link>\n"
         "  <joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"l1\"/>"
         "<axis xyz=\"0 0 1\"/><limit lower=\"-2\" upper=\"2\" effort=\"1\" velocity=\"1\"/>"
         "</joint>\n</robot>\n";
}
std::string meshElement(const std::string& path) { return "<mesh filename=\"" + path + "\"/>"; }

// The InputError of importing `urdf` (written to a file of that name in the scratch folder) with
// collision volumes: it names the file, the link l1 (line 3) and its collision element.
InputError meshImportError(const std::string& name, const std::string& urdf) {
  const std::string f = tempPath(name);
  writeText(f, urdf);
  const InputError e = expectInputError([&] { importUrdf(f, chain("", "", true)); });
  INFO(e.what());
  CHECK(e.file() == f);
  CHECK(e.line() == 3);
  CHECK(e.key() == "link 'l1'/collision");
  return e;
}

}  // namespace

TEST_CASE("URDF bad: elements nested 60,000 deep are refused before the XML parser recurses",
          "[urdf][bad][hardening]") {
  std::string deep = "<robot name=\"deep\">\n  <link name=\"a\"/>\n";
  for (int k = 0; k < 60000; ++k) deep += "<x>";
  for (int k = 0; k < 60000; ++k) deep += "</x>";
  deep += "\n</robot>\n";
  const InputError e = expectInputError([&] { importUrdfText(deep, "deep.urdf", {}); });
  CHECK(e.file() == "deep.urdf");
  CHECK(e.line() == 3);
  CHECK(e.key() == "xml");
  CHECK_THAT(e.message(), Catch::Contains("nested more than 256"));
  // 256 levels (the <robot> element and 255 below it) are still read by the XML parser.
  std::string ok = smallArm();
  std::string nest;
  for (int k = 0; k < 253; ++k) nest += "<x>";
  for (int k = 0; k < 253; ++k) nest += "</x>";
  ok.replace(ok.find("<link name=\"base\"/>"), 19,
             "<link name=\"base\"><v>" + nest + "</v></link>");
  CHECK(importUrdfText(ok, "deep_ok.urdf", chain("base", "tool")).dof() == 2);
}

TEST_CASE("URDF bad: XML syntax errors name the line, also where TinyXML gives none",
          "[urdf][bad][hardening]") {
  struct Case {
    std::string text;
    int line;
  };
  const std::string head = "<robot name=\"x\">\n<link name=\"a\"/>\n";
  const Case cases[] = {
      {head + "<!-- a comment never closed\n</robot>\n", 3},
      {head + "<![CDATA[ never closed\n</robot>\n", 3},
      {head + "<\n</robot>\n", 3},
      {head + "<link name=\"b\">\n</robot", 4},
      {head + "<link name=\"b\">\n</lnk>\n</robot>\n", 4},
      {head + "<link name=\"b\" foo/>\n</robot>\n", 3},
      {"\n\n", 1},
  };
  for (const Case& c : cases) {
    INFO(c.text);
    const InputError e = expectInputError([&] { importUrdfText(c.text, "syntax.urdf", {}); });
    INFO(e.what());
    CHECK(e.file() == "syntax.urdf");
    CHECK(e.key() == "xml");
    CHECK(e.line() == c.line);
  }
}

TEST_CASE("URDF bad: mesh vertices that are not finite or not plausible, and far origins",
          "[urdf][bad][collision][hardening]") {
  // The same cube imports when its vertices are plausible: only the vertex or origin differs.
  const std::string good = tempPath("cube.stl");
  writeBinaryStl(good, cubeCorners(), kBoxTriangles);
  REQUIRE(importUrdfText(meshArm(meshElement(good)), "cube.urdf", chain("", "", true))
              .collision.volumes.size() >= 1);

  const std::string nan = tempPath("nan.stl"), far = tempPath("far.stl");
  writeBinaryStl(nan, cubeCorners(std::numeric_limits<float>::quiet_NaN()), kBoxTriangles);
  writeBinaryStl(far, cubeCorners(1e30f), kBoxTriangles);
  std::vector<std::string> ascii;
  for (const auto& p : cubeCorners())
    ascii.push_back(std::to_string(p.x()) + " " + std::to_string(p.y()) + " " +
                    std::to_string(p.z()));
  ascii[0] = "1e308 0 0";
  const std::string huge = tempPath("huge_ascii.stl");
  writeAsciiStl(huge, ascii, kBoxTriangles);
  CHECK_THAT(meshImportError("nan.urdf", meshArm(meshElement(nan))).message(),
             Catch::Contains("nan.stl") && Catch::Contains("not finite"));
  CHECK_THAT(meshImportError("far.urdf", meshArm(meshElement(far))).message(),
             Catch::Contains("far.stl") && Catch::Contains("not plausible"));
  // 1e308 in an ASCII STL is infinite in assimp's single precision.
  CHECK_THAT(meshImportError("huge.urdf", meshArm(meshElement(huge))).message(),
             Catch::Contains("huge_ascii.stl") && Catch::Contains("not finite"));
  // A plausible mesh (and a box) placed 1e308 m away by the <collision> origin, and primitives
  // of implausible size: refused where the XML gives the number, before any fit.
  struct Case {
    std::string urdf, key;
  };
  for (const Case& c :
       {Case{meshArm(meshElement(good), "0 0 1e308"), "link 'l1'/origin@xyz"},
        Case{meshArm("<box size=\"0.1 0.1 0.1\"/>", "0 0 1e308"), "link 'l1'/origin@xyz"},
        Case{meshArm("<box size=\"0.1 1e30 0.1\"/>"), "link 'l1'/box@size"},
        Case{meshArm("<sphere radius=\"1e300\"/>"), "link 'l1'/sphere@radius"}}) {
    const InputError e =
        expectInputError([&] { importUrdfText(c.urdf, "far.urdf", chain("", "", true)); });
    INFO(e.what());
    CHECK(e.file() == "far.urdf");
    CHECK(e.line() == 3);
    CHECK(e.key() == c.key);
    CHECK_THAT(e.message(), Catch::Contains("not plausible"));
  }

  // fit-ssv refuses the same vertices with the same check (exit 2 naming the mesh file).
  const std::string design = tempPath("fit_design.toml"), out = tempPath("fit_out.toml");
  fs::copy_file(test::sourcePath("designs/first_prototype_6dof.toml"), design,
                fs::copy_options::overwrite_existing);
  std::string log;
  REQUIRE(test::runCommand(test::binaryPath() + " fit-ssv " + design + " --link base --mesh " +
                               good + " --out " + out,
                           log) == 0);
  fs::remove(out);
  for (const std::string& mesh : {nan, far, huge}) {
    INFO(mesh);
    CHECK(test::runCommand(test::binaryPath() + " fit-ssv " + design + " --link base --mesh " +
                               mesh + " --out " + out,
                           log) == 2);
    INFO(log);
    CHECK_THAT(log, Catch::Contains(mesh) &&
                        (Catch::Contains("not finite") || Catch::Contains("not plausible")));
    CHECK_FALSE(fs::exists(out));
  }
}

TEST_CASE("URDF bad: a FIFO, an empty file or an oversized file as a mesh is refused, not read",
          "[urdf][bad][collision][hardening]") {
  const fs::path dir = scratchDir() / "special_meshes";
  fs::create_directories(dir);
  const std::string fifo = (dir / "link.stl").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);  // the scenario needs the FIFO: fail without it
  REQUIRE(fs::is_fifo(fifo));
  const std::string empty = (dir / "empty.stl").string();
  std::ofstream(empty).close();
  const std::string big = (dir / "big.stl").string();
  fs::resize_file((std::ofstream(big), big), defaults::kMaxMeshFileBytes + 1);  // sparse
  struct Case {
    std::string mesh, words;
  };
  for (const Case& c : {Case{fifo, "not a regular file"}, Case{empty, "empty"},
                        Case{big, "exceeds the limit for a collision mesh"}}) {
    const std::string urdf = (dir / ("arm_" + fs::path(c.mesh).stem().string() + ".urdf")).string();
    writeText(urdf, meshArm(meshElement(c.mesh)));
    std::string log;
    // `timeout` turns a read that blocks on the FIFO into a failure, not a hung suite.
    CHECK(test::runCommand("timeout 20 " + test::binaryPath() + " describe " + urdf, log) == 2);
    INFO(log);
    CHECK_THAT(log, Catch::Contains(urdf + ":3") && Catch::Contains("link 'l1'/collision") &&
                        Catch::Contains(c.mesh) && Catch::Contains(c.words));
  }
}

TEST_CASE("URDF the shipped TX40 converts to TOML and back with the same FK as the URDF",
          "[urdf][cli]") {
  const std::string tx40 = robotFile("../datasets/staubli_tx40/urdf/tx40_mdh_modified.urdf");
  const std::string toml = tempPath("tx40.toml"), back = tempPath("tx40_back.urdf");
  std::string log;
  REQUIRE(test::runCommand(test::binaryPath() + " convert " + tx40 + " " + toml, log) == 0);
  INFO(log);
  REQUIRE(test::runCommand(test::binaryPath() + " convert " + toml + " " + back, log) == 0);
  const Model a = importUrdf(tx40, chain("", "", false));
  const Model t = loadDesign(toml);
  const Model b = importUrdf(back, chain("", "", false));
  REQUIRE(t.dof() == 6);
  REQUIRE(b.dof() == 6);
  KinematicsWorkspace wa(a), wt(t), wb(b);
  std::mt19937_64 rng(40);
  double worst = 0;
  for (int k = 0; k < kRandomConfigurations; ++k) {
    const Eigen::VectorXd q = test::randomConfiguration(a, rng);
    forwardKinematics(a, wa, q);
    forwardKinematics(t, wt, q);
    forwardKinematics(b, wb, q);
    for (const KinematicsWorkspace* w : {&wt, &wb})
      worst = std::max({worst, (w->p_WT - wa.p_WT).cwiseAbs().maxCoeff(),
                        (w->R_WT - wa.R_WT).cwiseAbs().maxCoeff()});
  }
  INFO("largest FK difference from the URDF " << worst);
  CHECK(worst < kRoundTripTolerance);
  // The TOML design against KDL on the URDF, dynamics included (link_6 is a point mass).
  const KdlOracle kdl(kdlTreeFromFile(tx40), "base_link", "tool0");
  const Errors e = compareWithKdl(t, kdl.chain, true, 40);
  CHECK(e.fk < kUrdfOracleTolerance);
  CHECK(e.id < kUrdfOracleTolerance);
}

TEST_CASE("URDF bad: joint origins and limits beyond the plausible magnitudes are refused",
          "[urdf][bad][hardening]") {
  struct Case {
    std::string urdf, key;
  };
  std::string limit = smallArm();
  limit.replace(limit.find("upper=\"2\""), 9, "upper=\"1e300\"");
  for (const Case& c : {Case{smallArm("", "revolute", "0 0 1e308"), "joint 'j1'/origin@xyz"},
                        Case{limit, "joint 'j1'/limit@upper"}}) {
    const InputError e =
        expectInputError([&] { importUrdfText(c.urdf, "far.urdf", chain("base", "tool")); });
    INFO(e.what());
    CHECK(e.file() == "far.urdf");
    CHECK(e.line() > 0);
    CHECK(e.key() == c.key);
    CHECK_THAT(e.message(), Catch::Contains("not plausible"));
  }
}

TEST_CASE("URDF bad: a DAE mesh nested 100,000 deep is refused before assimp parses it",
          "[urdf][bad][collision][hardening]") {
  std::string dae =
      "<?xml version=\"1.0\"?>\n<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" "
      "version=\"1.4.1\">\n<library_visual_scenes><visual_scene id=\"s\">\n";
  for (int k = 0; k < 100000; ++k) dae += "<node>";
  for (int k = 0; k < 100000; ++k) dae += "</node>";
  dae += "</visual_scene></library_visual_scenes>\n</COLLADA>\n";
  const std::string mesh = tempPath("deep.dae");
  writeText(mesh, dae);
  const InputError e = meshImportError("deep_dae.urdf", meshArm(meshElement(mesh)));
  CHECK_THAT(e.message(), Catch::Contains(mesh + ":4") && Catch::Contains("nested more than 256"));
}
