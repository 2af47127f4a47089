// The shipped thesis row study (studies/stem_row.toml: the Fig. 3.6 stem with its neighbours at
// 0.192 m, Table 2.2) against a search that does not share the map's path: on a sample of cells,
// random starts from this file's own generator, each solved onto the pose, checked against the
// study's obstacles and the design's volumes, and, when in contact, moved along the null space
// down the collision potential alone. A verdict "only in collision" is contradicted by a
// collision-free posture; a "reachable" cell's own posture must be on the pose and clear.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>

#include "collision/collision_term.hpp"
#include "dexterity/dexterity_map.hpp"
#include "engine/study_file.hpp"
#include "study/stage.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::dexterity;
using namespace armstudy::test;

namespace {
constexpr int kSampleCells = 40;            // cells in collision drawn for the oracle
constexpr int kRowOracleStarts = 60;        // random starts per cell
constexpr double kRowRequiredShare = 0.99;  // verdicts the oracle must not contradict
constexpr double kRowOnPose = 1e-6;         // [m and rad] a posture on the pose
constexpr double kEscapeSafety = 0.05;      // [m] d_a of the oracle's own H_c descent

// Smallest checked distance at q (self pairs and obstacles), computed here from the collision
// model alone.
double clearance(const Model& m, KinematicsWorkspace& ws, collision::CollisionWorkspace& cws,
                 const StemCollision& col, const JointVector& q) {
  forwardKinematics(m, ws, q);
  collision::collisionDistances(m, ws, col.obstacles, cws);
  return std::min(collision::minSelfDistance(cws), collision::minEnvironmentDistance(cws));
}

// True when a random start finds a collision-free posture on the cell's pose.
bool oracleFindsClearPosture(const Model& m, const StemCollision& col, const StemGrid::Cell& cell,
                             std::mt19937_64& rng) {
  KinematicsWorkspace ws(m);
  IkWorkspace ik_ws(m);
  collision::CollisionWorkspace cws(m);
  ik::ObjectiveContext ctx(m, ws);
  collision::CollisionPotentialOptions po;
  po.safety_distance_m = kEscapeSafety;
  ik::WeightedObjective h_c;
  h_c.add(1.0, std::make_shared<collision::CollisionTerm>(po, col.obstacles));
  const Eigen::VectorXd w_inv = Eigen::VectorXd::Ones(m.dof());
  for (int s = 0; s < kRowOracleStarts; ++s) {
    const JointVector q0 = randomConfiguration(m, rng);
    const IkResult p = solvePose(m, ik_ws, cell.target, IkOptions::exactPose(), 0, &q0);
    if (p.position_error_m > kRowOnPose || p.orientation_error_rad > kRowOnPose) continue;
    if (clearance(m, ws, cws, col, p.q) > col.clearance_m) return true;
    const ik::NullspaceResult e = ik::optimiseAtPose(m, ws, ctx, cell.target, p.q, h_c, w_inv, {});
    if (e.status != ik::NullspaceStatus::NotOnPose && e.error.position_m <= kRowOnPose &&
        e.error.orientation_rad <= kRowOnPose && clearance(m, ws, cws, col, e.q) > col.clearance_m)
      return true;
  }
  return false;
}
}  // namespace

TEST_CASE("the thesis row study's collision verdicts hold against an independent search",
          "[dexterity][collision][row]") {
  const Study study = loadStudy(sourcePath("studies/stem_row.toml"));
  const DexterityOptions* o = stageSettings<DexterityOptions>(study, "dexterity");
  REQUIRE(o);
  REQUIRE(std::abs(o->row_spacing_m - 0.192) < 1e-12);  // Table 2.2's nominal spacing
  const Model& m = study.designs.at(0).model;
  const StemCollision col = o->collisionFor(m);
  REQUIRE(col.self);
  REQUIRE(col.obstacles.size() == 3);  // the stem and one neighbour on each side
  const DexterityMap map = computeDexterityMap(m, *o, 2);
  KinematicsWorkspace ws(m);
  collision::CollisionWorkspace cws(m);
  std::vector<int> in_collision;
  int reachable = 0, self = 0, obstacle = 0;
  for (int i = 0; i < static_cast<int>(map.cells.size()); ++i) {
    const CellResult& c = map.cells[i];
    if (c.reachable) {
      ++reachable;
      const StemGrid::Cell cell =
          o->grid.cell(i % o->grid.gamma_rad.count, i / o->grid.gamma_rad.count);
      forwardKinematics(m, ws, c.q_opt);
      CHECK((ws.p_WT - cell.target.p_WT).norm() <= o->position_tolerance_m);
      CHECK(clearance(m, ws, cws, col, c.q_opt) > col.clearance_m);
    } else if (c.status == ReachStatus::SelfCollision ||
               c.status == ReachStatus::ObstacleCollision) {
      in_collision.push_back(i);
      (c.status == ReachStatus::SelfCollision ? self : obstacle)++;
    }
  }
  // The scenario: both halves have approachable cells and both kinds of collision verdicts.
  REQUIRE(reachable > 0);
  REQUIRE(self > 0);
  REQUIRE(obstacle > 0);
  std::mt19937_64 rng(20261126);
  std::shuffle(in_collision.begin(), in_collision.end(), rng);
  in_collision.resize(std::min<std::size_t>(in_collision.size(), kSampleCells));
  int contradicted = 0;
  for (int i : in_collision) {
    const StemGrid::Cell cell =
        o->grid.cell(i % o->grid.gamma_rad.count, i / o->grid.gamma_rad.count);
    const bool found = oracleFindsClearPosture(m, col, cell, rng);
    if (found) UNSCOPED_INFO("contradicted: gamma " << cell.gamma << " z " << cell.z);
    contradicted += found;
  }
  const double share = 1.0 - double(contradicted) / in_collision.size();
  INFO(contradicted << " of " << in_collision.size() << " collision verdicts contradicted");
  CHECK(share >= kRowRequiredShare);
}
