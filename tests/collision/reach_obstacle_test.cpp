// Environment obstacles in reachability studies ("Environment obstacles given in the task
// frame ... checked against the arm's volumes the same way"): [[obstacle]] entries of a study file
// are parsed with units, the sweep classifies poses reachable only in contact with an obstacle,
// and every stored classification is re-checked with the collision module on the joint solution
// read back from the .vti with VTK's reader. Independent geometric fact used as an oracle: the
// final prototype's end-effector capsule contains the TCP, so no pose whose target lies within
// (obstacle radius + end-effector radius) of an obstacle's core can be collision-free.
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataReader.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "collision/distance.hpp"
#include "collision/reach_collision.hpp"
#include "common/errors.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/files.hpp"
#include "stages/reach/reach_stage.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::collision;
namespace fs = std::filesystem;

namespace {

constexpr double kParseTolerance = 1e-15;

const char* kStudy = R"(
[study]
name = "obstacles"
[[design]]
file = "DESIGN"
[[obstacle]]
name = "stem"
type = "capsule"
points = [[0, 0.7, 0.5], [0, 0.7, "1800 mm"]]
radius = "50 mm"
[[obstacle]]
name = "fruit"
type = "sphere"
points = [[0.25, 0.55, 1.2]]
radius = "40 mm"
[[obstacle]]
name = "wall"
type = "triangle"
points = [[-1, 1.05, 0], [1, 1.05, 0], [0, 1.05, 2]]
radius = 0
[reach]
task_space = "position"
[[reach.grid]]
name = "plane"
x = { from = "-0.3 m", to = "0.3 m", step = "0.1 m" }
y = { from = "0.5 m", to = "1.0 m", step = "0.1 m" }
z = "1.2 m"
)";

fs::path writeStudy(const fs::path& dir, const std::string& name, std::string text) {
  const std::string key = "DESIGN";
  text.replace(text.find(key), key.size(), test::sourcePath("designs/final_prototype_9dof.toml"));
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p;
}

// The study text with `from` replaced by `to` (first occurrence; must exist).
std::string edited(const std::string& from, const std::string& to) {
  std::string s = kStudy;
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("[[obstacle]] entries are read with units into the task frame",
          "[collision][reach][input]") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_reach_obstacle_parse";
  const Study s = loadStudy(writeStudy(dir, "s.toml", kStudy).string());
  REQUIRE(s.obstacles.size() == 3);
  CHECK(s.obstacles[0].name == "stem");
  CHECK(s.obstacles[0].type == SsvType::Line);
  CHECK(s.obstacles[0].p_W[1].z() == Approx(1.8).margin(kParseTolerance));
  CHECK(s.obstacles[0].radius_m == Approx(0.05).margin(kParseTolerance));
  CHECK(s.obstacles[1].type == SsvType::Point);
  CHECK(s.obstacles[1].p_W[0].isApprox(Eigen::Vector3d(0.25, 0.55, 1.2)));
  CHECK(s.obstacles[2].type == SsvType::Triangle);
  CHECK(s.obstacles[2].radius_m == 0);
  // The reach stage checks them (default on when obstacles exist) along with self-collision.
  CHECK(stageSettings<ReachConfig>(s, "reach")->collision.self);
  CHECK(stageSettings<ReachConfig>(s, "reach")->collision.obstacles.size() == 3);
  // obstacles = false keeps them out of the sweeps.
  const Study off = loadStudy(writeStudy(dir, "off.toml",
                                         edited("task_space = \"position\"\n",
                                                "task_space = \"position\"\nobstacles = false\n"))
                                  .string());
  CHECK(stageSettings<ReachConfig>(off, "reach")->collision.obstacles.empty());
  CHECK(off.obstacles.size() == 3);
}

TEST_CASE("bad [[obstacle]] entries are input errors naming file, line and key",
          "[collision][reach][input]") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_reach_obstacle_bad";
  struct Case {
    std::string from, to, key, words;
  };
  const std::vector<Case> cases = {
      {"radius = \"50 mm\"", "radius = \"-5 mm\"", "obstacle[0].radius", "radius"},
      {"points = [[0, 0.7, 0.5], [0, 0.7, \"1800 mm\"]]", "points = [[0, 0.7, 0.5], [0, 0.7, 0.5]]",
       "obstacle[0].points", "coincide"},
      {"points = [[0, 0.7, 0.5], [0, 0.7, \"1800 mm\"]]", "points = [[0, 0.7, 0.5]]",
       "obstacle[0].points", "needs 2 points"},
      {"type = \"capsule\"", "type = \"cylinder\"", "obstacle[0].type", "unknown SSV type"},
      {"name = \"fruit\"", "name = \"stem\"", "obstacle[1].name", "defined twice"},
      {"name = \"fruit\"", "name = \"fruit\"\ncolour = \"red\"", "obstacle[1].colour",
       "unknown key"},
      {"radius = \"40 mm\"", "radius = \"40 deg\"", "obstacle[1].radius", "length"},
      {"points = [[-1, 1.05, 0], [1, 1.05, 0], [0, 1.05, 2]]",
       "points = [[-1, 1.05, 0], [1, 1.05, 0], [0, 1.05, 0]]", "obstacle[2].points", "collinear"},
  };
  for (const Case& c : cases) {
    INFO(c.to);
    const fs::path p = writeStudy(dir, "bad.toml", edited(c.from, c.to));
    try {
      loadStudy(p.string());
      FAIL("expected an InputError");
    } catch (const InputError& e) {
      const std::string what = e.what();
      INFO(what);
      CHECK(what.find(p.string() + ":") != std::string::npos);
      CHECK(what.find(c.key) != std::string::npos);
      CHECK(what.find(c.words) != std::string::npos);
    }
  }
  // obstacles = true without any [[obstacle]].
  std::string none = kStudy;
  none.erase(none.find("[[obstacle]]"), none.find("[reach]") - none.find("[[obstacle]]"));
  none.replace(none.find("task_space = \"position\"\n"), 24,
               "task_space = \"position\"\nobstacles = true\n");
  const fs::path p = writeStudy(dir, "none.toml", none);
  try {
    loadStudy(p.string());
    FAIL("expected an InputError");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("reach.obstacles") != std::string::npos);
  }
}

TEST_CASE(
    "reach sweeps with obstacles: poses reachable only in contact are classified, named and "
    "re-checked",
    "[collision][reach]") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_reach_obstacle_sweep";
  fs::remove_all(dir);
  const Study study = loadStudy(writeStudy(dir, "s.toml", kStudy).string());
  const Model& m = study.designs[0].model;
  const TaskGrid& g = stageSettings<ReachConfig>(study, "reach")->grids[0];
  const std::vector<Obstacle>& obstacles = study.obstacles;

  auto run = [&](const std::string& sub, int threads) {
    RunOptions ro;
    ro.threads = threads;
    ro.progress = false;
    runStage(study, "reach", (dir / sub).string(), ro);
    return dir / sub;
  };
  const fs::path one = run("t1", 1), two = run("t2", 2);
  const fs::path vti = one / "reach" / g.name / (m.name + ".vti");
  REQUIRE(fs::exists(vti));
  CHECK(readFileOrThrow(vti.string()) ==
        readFileOrThrow((two / "reach" / g.name / (m.name + ".vti")).string()));

  vtkNew<vtkXMLImageDataReader> r;
  r->SetFileName(vti.c_str());
  r->Update();
  vtkImageData* img = r->GetOutput();
  const long points = g.points();
  REQUIRE(img->GetNumberOfPoints() == points);
  vtkDataArray* status = img->GetPointData()->GetArray("status");
  vtkDataArray* qa = img->GetPointData()->GetArray("q");
  vtkDataArray* dist = img->GetPointData()->GetArray("min_distance");
  vtkDataArray* odist = img->GetPointData()->GetArray("obstacle_distance");
  vtkDataArray* pair = img->GetPointData()->GetArray("colliding_pair");
  REQUIRE(status);
  REQUIRE(qa);
  REQUIRE(dist);
  REQUIRE(odist);
  REQUIRE(pair);

  // The end-effector volume contains the TCP (the oracle's premise, checked here).
  double ee_radius = 0;
  for (const CollisionVolume& v : m.collision.volumes)
    if (v.link == m.dof() - 1 && v.type == SsvType::Line && v.p_L[1].isApprox(m.T_NT.translation()))
      ee_radius = v.radius_m;
  REQUIRE(ee_radius > 0);

  const std::vector<std::string> names = collisionPairNames(m, obstacles, true);
  IkWorkspace ws(m);
  CollisionWorkspace cws(m);
  long n_obstacle = 0, n_free = 0, n_forced = 0;
  std::map<std::string, long> per_pair;
  for (long p = 0; p < points; ++p) {
    const auto st = static_cast<ReachStatus>(static_cast<int>(status->GetComponent(p, 0)));
    const Eigen::Vector3d target = g.position(p);
    // Oracle: a target within reach of an obstacle's core cannot be reached collision-free.
    bool forced = false;
    for (const Obstacle& o : obstacles) {
      Core core;
      core.n = static_cast<int>(o.type);
      for (int i = 0; i < core.n; ++i) core.p[i] = o.p_W[i];
      Core pt;
      pt.n = 1;
      pt.p[0] = target;
      Eigen::Vector3d ca, cb;
      forced |= std::sqrt(squaredDistanceCores(pt, core, ca, cb)) < o.radius_m + ee_radius;
    }
    n_forced += forced;
    if (forced) CHECK(st != ReachStatus::Reachable);
    if (st != ReachStatus::Reachable && st != ReachStatus::SelfCollision &&
        st != ReachStatus::ObstacleCollision) {
      CHECK(std::isnan(dist->GetComponent(p, 0)));
      CHECK(std::isnan(odist->GetComponent(p, 0)));
      continue;
    }
    JointVector q(m.dof());
    for (int c = 0; c < m.dof(); ++c) q[c] = qa->GetComponent(p, c);
    forwardKinematics(m, ws.kin, q);
    CHECK((ws.kin.p_WT - target).norm() <=
          stageSettings<ReachConfig>(study, "reach")->ik.position_tolerance_m);
    collisionDistances(m, ws.kin, obstacles, cws);
    const double ds = minSelfDistance(cws), de = minEnvironmentDistance(cws);
    CHECK(odist->GetComponent(p, 0) == de);
    CHECK(dist->GetComponent(p, 0) == std::min(ds, de));
    if (st == ReachStatus::ObstacleCollision) {
      ++n_obstacle;
      CHECK(de <= 0);
      CHECK(de <= ds);
      const int idx = static_cast<int>(pair->GetComponent(p, 0));
      REQUIRE(idx >= 0);
      REQUIRE(idx < static_cast<int>(names.size()));
      CHECK(names[idx] == pairName(m, cws.env[cws.closest_env], true, obstacles));
      ++per_pair[names[idx]];
    } else if (st == ReachStatus::Reachable) {
      ++n_free;
      CHECK(ds > 0);
      CHECK(de > 0);
      CHECK(pair->GetComponent(p, 0) == -1);
    }
  }
  INFO("free " << n_free << ", in contact with an obstacle " << n_obstacle << ", forced "
               << n_forced);
  CHECK(n_forced >= 5);
  CHECK(n_obstacle >= n_forced);
  CHECK(n_free >= points / 3);  // (measured: 20 of 42 free, 19 in contact, 16 forced)

  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(one / "summary.json"));
  const auto& jd = summary["reach"]["grids"][0]["designs"][0];
  CHECK(jd["status_counts"]["obstacle_collision"].get<long>() == n_obstacle);
  CHECK(jd["reachable"].get<long>() == n_free);
  for (const auto& [name, count] : per_pair)
    CHECK(jd["colliding_pairs"][name].get<long>() == count);
  CHECK(jd["min_obstacle_distance_m"].get<double>() > 0);
  CHECK(summary["reach"]["settings"]["obstacles"].size() == 3);
  CHECK(summary["reach"]["settings"]["obstacles"][0]["name"] == "stem");
}
