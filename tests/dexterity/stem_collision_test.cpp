// Stem maps with collisions: every reason a cell can have, each on a case constructed so that the
// verdict is known without the map's code (a stem that swallows the TCP, a base volume placed on
// the TCP, a stem beyond the arm's longest stretch, a lift narrowed below what a cell needs), and
// the .vti, report and summary.json carrying the statuses.
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataReader.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "collision/collision_model.hpp"
#include "dexterity/dexterity_map.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::dexterity;
using namespace armstudy::test;

namespace {
constexpr double kStemRadiusOverTcp = 0.16;  // [m] > the circle radius 0.15: the TCP is inside
constexpr double kBlockRadius = 0.06;        // [m] a base volume centred on the TCP target
constexpr int kStemOracleStarts = 100;       // independent random starts per cell
constexpr double kStemOnPose = 1e-6;         // [m and rad] a start that reached the pose
constexpr double kNarrowLift = 0.02;         // [m] lift range +- this (design: +- 0.5 m)
constexpr int kCollisionStarts = 3;          // further starts per cell still in collision

DexterityOptions rowOptions() {
  DexterityOptions o;
  o.grid.stem_x_m = 0.225;
  o.grid.stem_y_m = 0.7;
  o.grid.radius_m = 0.15;
  o.grid.gamma_rad = {-M_PI / 3, M_PI / 3, 3};
  o.grid.z_m = {0.9, 1.1, 2};
  o.w_joint_limits = 0.1;
  o.w_manipulability = 1.0;
  o.seed_stride = 1;
  o.collision.self = true;
  return o;
}

// Distance from point p to the core of volume v (point or line), in v's link frame.
double coreDistance(const CollisionVolume& v, const Eigen::Vector3d& p) {
  if (v.type == SsvType::Point) return (p - v.p_L[0]).norm();
  const Eigen::Vector3d d = v.p_L[1] - v.p_L[0];
  const double t = std::clamp((p - v.p_L[0]).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (v.p_L[0] + t * d)).norm();
}

// True when a volume of the last body contains the TCP: then every posture on a pose puts that
// volume around the pose's point.
bool endEffectorContainsTcp(const Model& m) {
  const Eigen::Vector3d p_tcp = m.T_NT.translation();
  for (const CollisionVolume& v : m.collision.volumes)
    if (v.link == m.dof() - 1 && v.type != SsvType::Triangle &&
        coreDistance(v, p_tcp) <= v.radius_m)
      return true;
  return false;
}

// An upper bound on |p_WT - p_WB| over every configuration: the chain's offsets, the prismatic
// joints' largest travel and the TCP offset, end to end.
double reachBound(const Model& m) {
  double b = m.T_NT.translation().norm();
  for (const Joint& j : m.joints) {
    b += j.T_PJ0.translation().norm();
    if (j.type == JointType::Prismatic)
      b += std::max(std::abs(j.limits.q_min), std::abs(j.limits.q_max));
  }
  return b;
}

// Starts of kStemOracleStarts random configurations (own generator) that reach the cell's pose.
int startsOnPose(const Model& m, const StemGrid::Cell& cell) {
  IkWorkspace ws(m);
  std::mt19937_64 rng(20261126);
  int n = 0;
  for (int s = 0; s < kStemOracleStarts; ++s) {
    const JointVector q0 = randomConfiguration(m, rng);
    const IkResult p = solvePose(m, ws, cell.target, IkOptions::exactPose(), 0, &q0);
    n += p.position_error_m <= kStemOnPose && p.orientation_error_rad <= kStemOnPose;
  }
  return n;
}
}  // namespace

TEST_CASE("a cell blocked only by the stem is obstacle_collision, reachable without the stem",
          "[dexterity][collision]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  REQUIRE(endEffectorContainsTcp(m));  // so a stem around the TCP blocks every posture
  DexterityOptions o = rowOptions();
  const DexterityMap free_map = computeDexterityMap(m, o, 2);
  REQUIRE(free_map.collision);
  StemRow row;
  row.stem = true;
  row.radius_m = kStemRadiusOverTcp;
  o.collision.obstacles = rowObstacles(o.grid, row);
  o.collision_starts = kCollisionStarts;  // every cell in collision gets them; none can be freed
  const DexterityMap map = computeDexterityMap(m, o, 2);
  CHECK(map.search.collision_cells == o.grid.size());
  CHECK(map.search.collision_tries == long(kCollisionStarts) * o.grid.size());
  CHECK(map.search.collision_freed == 0);
  for (std::size_t i = 0; i < map.cells.size(); ++i) {
    INFO("cell " << i);
    REQUIRE(free_map.cells[i].status == ReachStatus::Reachable);  // only the stem blocks it
    CHECK(map.cells[i].status == ReachStatus::ObstacleCollision);
    CHECK_FALSE(map.cells[i].reachable);
    REQUIRE(map.cells[i].colliding_pair >= 0);
    CHECK(map.pair_names[map.cells[i].colliding_pair].find("obstacle:stem") != std::string::npos);
    CHECK(map.cells[i].min_distance_m < 0);
  }
}

TEST_CASE("a cell blocked only by the arm's own base volume is self_collision",
          "[dexterity][collision]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  REQUIRE(endEffectorContainsTcp(m));
  DexterityOptions o = rowOptions();
  o.grid.gamma_rad = {0, 0, 1};
  o.grid.z_m = {1.0, 1.0, 1};
  const StemGrid::Cell cell = o.grid.cell(0, 0);
  Model blocked = m;  // a base volume on the TCP target: every posture on the pose touches it
  CollisionVolume block;
  block.name = "block";
  block.link = -1;
  block.type = SsvType::Point;
  block.p_L[0] = m.T_WB.inverse() * cell.target.p_WT;
  block.radius_m = kBlockRadius;
  blocked.collision.volumes.push_back(block);
  REQUIRE(collision::isCollisionPair(blocked, -1, blocked.dof() - 1));
  const DexterityMap free_map = computeDexterityMap(m, o, 1);
  REQUIRE(free_map.cells[0].status == ReachStatus::Reachable);
  const DexterityMap map = computeDexterityMap(blocked, o, 1);
  CHECK(map.cells[0].status == ReachStatus::SelfCollision);
  REQUIRE(map.cells[0].colliding_pair >= 0);
  CHECK(map.pair_names[map.cells[0].colliding_pair].rfind("base-", 0) == 0);
  // Without self-collision checks the same design reaches the cell.
  o.collision.self = false;
  CHECK(computeDexterityMap(blocked, o, 1).cells[0].status == ReachStatus::Reachable);
}

TEST_CASE("a stem beyond the arm's longest stretch is out_of_reach, a narrowed lift joint_limits",
          "[dexterity][collision]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  DexterityOptions far = rowOptions();
  far.grid.gamma_rad = {0, 0, 1};
  far.grid.z_m = {1.0, 1.0, 1};
  far.grid.stem_y_m = reachBound(m) + far.grid.radius_m + m.T_WB.translation().norm() + 0.1;
  const DexterityMap out = computeDexterityMap(m, far, 1);
  CHECK(out.cells[0].status == ReachStatus::OutOfReach);
  CHECK(startsOnPose(m, far.grid.cell(0, 0)) == 0);

  // The lift narrowed to +- 2 cm: high cells the design reaches with its +- 0.5 m lift.
  Model narrow = m;
  REQUIRE(narrow.joints[0].type == JointType::Prismatic);
  narrow.joints[0].limits.q_min = -kNarrowLift;
  narrow.joints[0].limits.q_max = kNarrowLift;
  DexterityOptions low = rowOptions();
  low.grid.gamma_rad = {0, 0, 1};
  low.grid.z_m = {1.8, 2.0, 2};
  const DexterityMap wide_map = computeDexterityMap(m, low, 1);
  const DexterityMap narrow_map = computeDexterityMap(narrow, low, 1);
  int joint_limits = 0;
  for (std::size_t i = 0; i < narrow_map.cells.size(); ++i) {
    if (narrow_map.cells[i].status != ReachStatus::JointLimits) continue;
    ++joint_limits;
    INFO("z " << low.grid.z_m.value(static_cast<int>(i)));
    CHECK(wide_map.cells[i].status == ReachStatus::Reachable);  // a posture beyond the limits
    CHECK(startsOnPose(narrow, low.grid.cell(0, static_cast<int>(i))) == 0);  // none within
  }
  CHECK(joint_limits > 0);  // the scenario happened
}

TEST_CASE("the .vti, report and summary.json carry every cell's status and the colliding pair",
          "[dexterity][collision]") {
  const auto dir = std::filesystem::temp_directory_path() / "armstudy_stem_collision_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string study = (dir / "study.toml").string();
  std::ofstream(study) << "[study]\nname = \"t\"\n[[design]]\nfile = \""
                       << sourcePath("designs/first_prototype_9dof.toml") << "\"\n"
                       << R"([dexterity]
stem_x = "0.225 m"
stem_y = "0.7 m"
radius = "0.15 m"
gamma = { min = "-60 deg", max = "60 deg", step = "60 deg" }
z = { value = "1.0 m" }
ellipsoids = false
[dexterity.row]
stem = true
neighbours = 0
stem_radius = "0.16 m"
)";
  std::string out;
  const int rc = runCommand(
      binaryPath() + " run " + study + " --output " + (dir / "out").string() + " --threads 2", out);
  INFO(out);
  REQUIRE(rc == 0);
  const std::string base = (dir / "out/t/dexterity/").string();
  vtkNew<vtkXMLImageDataReader> r;
  r->SetFileName((base + "first_prototype_9dof.vti").c_str());
  r->Update();
  vtkDataArray* st = r->GetOutput()->GetPointData()->GetArray("status");
  vtkDataArray* pair = r->GetOutput()->GetPointData()->GetArray("colliding_pair");
  REQUIRE(st);
  REQUIRE(pair);
  REQUIRE(st->GetNumberOfTuples() == 3);
  for (vtkIdType i = 0; i < 3; ++i) {
    CHECK(st->GetTuple1(i) == static_cast<double>(ReachStatus::ObstacleCollision));
    CHECK(pair->GetTuple1(i) >= 0);
  }
  const nlohmann::json js = nlohmann::json::parse(readFileOrThrow(base + "summary.json"));
  const auto& s = js["designs"][0]["status"];
  CHECK(s["collision_checked"] == true);
  CHECK(s["near_half"]["obstacle_collision"] == 3);
  CHECK(s["near_half"]["reachable"] == 0);
  CHECK(s["near_half"]["limited_by"].get<std::string>().rfind("the stem itself", 0) == 0);
  const std::string report = readFileOrThrow(base + "report.md");
  CHECK(report.find("| obstacle_collision | 1 (100.0 %) | 2 (100.0 %) | 3 (100.0 %)") !=
        std::string::npos);
  // A stem no cell can approach: "-" for the means of nothing, not 0.
  CHECK(report.find("| first_prototype_9dof | 9 | 0.0 % | 0.0 % | 0.0 % | - | - | - |") !=
        std::string::npos);
}
