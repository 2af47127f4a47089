// Self-collision reachability sweeps ("In the engine"): a grid of full poses for a variant
// of the first prototype whose collision volumes are inflated, so that some poses are reachable
// only in self-collision. Every classification is re-checked with the collision module on the
// joint solution read back from the .vti with VTK's own reader, and the sweep is bit-identical for
// 1 and 2 threads.
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataReader.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "collision/collision.hpp"
#include "common/errors.hpp"
#include "engine/registry.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "reach/reach_sweep.hpp"
#include "stages/reach/reach_stage.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::collision;
namespace fs = std::filesystem;

namespace {

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// The first prototype with every collision volume `extra_m` thicker (a design variant).
Model inflated(double extra_m) {
  Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  for (CollisionVolume& v : m.collision.volumes) v.radius_m += extra_m;
  m.name = "first_prototype_6dof_inflated";
  return m;
}

TaskGrid smallGrid() {
  TaskGrid g;
  g.name = "near";
  g.task_space = TaskSpace::fullPose();
  g.axes = {AxisRange{-0.4, 0.4, 0.2}, AxisRange{0.3, 0.9, 0.2}, AxisRange{0.6, 1.4, 0.2}};
  const double deg = 3.14159265358979323846 / 180;
  g.orientations = {{-90 * deg, 0, 0}, {-90 * deg, 0, 30 * deg}};
  return g;
}

long countStatus(const PoseSweep& s, ReachStatus st) {
  long n = 0;
  for (long i = 0; i < s.size; ++i) n += s.status[i] == static_cast<std::uint8_t>(st);
  return n;
}

}  // namespace

TEST_CASE(
    "self-collision sweeps classify poses, store the distance in the VTK fields and are "
    "thread-independent",
    "[collision][reach]") {
  const TaskGrid g = smallGrid();
  REQUIRE(g.validate().empty());
  const IkOptions o = ReachConfig::studyDefaults();
  // The smallest inflation that gives poses reachable only in collision next to collision-free
  // ones.
  Model m;
  PoseSweep a;
  bool found = false;
  for (double extra : {0.0, 0.03, 0.06, 0.1, 0.15}) {
    m = inflated(extra);
    a = sweepGrid(m, g, o, 1, nullptr, SweepCollision{true, {}});
    if (countStatus(a, ReachStatus::SelfCollision) > 0 && a.countReachable() > 0) {
      found = true;
      break;
    }
  }
  REQUIRE(found);
  INFO("reachable " << a.countReachable() << ", in collision "
                    << countStatus(a, ReachStatus::SelfCollision) << " of " << a.size);
  REQUIRE(a.collision);
  REQUIRE(a.min_distance_m.size() == static_cast<std::size_t>(a.size));
  REQUIRE_FALSE(a.pair_names.empty());

  // (c) 1 vs 2 threads (and run to run): every column bit-identical.
  const PoseSweep b = sweepGrid(m, g, o, 2, nullptr, SweepCollision{true, {}});
  CHECK(b.status == a.status);
  CHECK(b.starts == a.starts);
  CHECK(sameBits(b.q, a.q));
  CHECK(sameBits(b.position_error_m, a.position_error_m));
  CHECK(sameBits(b.orientation_error_rad, a.orientation_error_rad));
  CHECK(sameBits(b.manipulability, a.manipulability));
  CHECK(sameBits(b.joint_limit_margin, a.joint_limit_margin));
  CHECK(sameBits(b.min_distance_m, a.min_distance_m));
  CHECK(b.colliding_pair == a.colliding_pair);
  CHECK(b.pair_names == a.pair_names);
  // The stage searches the whole grid after the sweep: compare the stage with that.
  searchGridSweep(m, g, o, 2, SweepCollision{true, {}}, SweepSearch{}, a);

  // The stage writes the fields; read them back with VTK's reader.
  const fs::path dir = fs::temp_directory_path() / "armstudy_reach_sweep_collision_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  Study study;
  study.name = "sc";
  study.designs.push_back({m, m.name, {}});
  ReachConfig cfg;
  cfg.enabled = true;
  cfg.ik = o;
  cfg.grids = {g};
  cfg.outputs = ReachOutputs{true, false, false};
  cfg.collision.self = true;
  study.sections.push_back(
      {&registeredStage("reach"), std::make_shared<SettingsOf<ReachConfig>>(cfg)});
  RunOptions ro;
  ro.threads = 2;
  ro.progress = false;
  runStage(study, "reach", dir.string(), ro);

  vtkNew<vtkXMLImageDataReader> r;
  const fs::path vti = dir / "reach" / g.name / (m.name + ".vti");
  REQUIRE(fs::exists(vti));
  r->SetFileName(vti.c_str());
  r->Update();
  vtkImageData* img = r->GetOutput();
  const long points = g.points();
  REQUIRE(img->GetNumberOfPoints() == points);

  IkWorkspace ws(m);
  CollisionWorkspace cws(m);
  long n_collision = 0, n_free = 0;
  for (int k = 0; k < static_cast<int>(g.orientations.size()); ++k) {
    const std::string sfx = "_o" + std::to_string(k);
    vtkDataArray* status = img->GetPointData()->GetArray(("status" + sfx).c_str());
    vtkDataArray* qa = img->GetPointData()->GetArray(("q" + sfx).c_str());
    vtkDataArray* dist = img->GetPointData()->GetArray(("min_distance" + sfx).c_str());
    vtkDataArray* pair = img->GetPointData()->GetArray(("colliding_pair" + sfx).c_str());
    REQUIRE(status);
    REQUIRE(qa);
    REQUIRE(dist);
    REQUIRE(pair);
    REQUIRE(qa->GetNumberOfComponents() == m.dof());
    for (long p = 0; p < points; ++p) {
      const long i = static_cast<long>(k) * points + p;
      const auto st = static_cast<ReachStatus>(static_cast<int>(status->GetComponent(p, 0)));
      CHECK(static_cast<std::uint8_t>(st) == a.status[i]);
      const double stored = dist->GetComponent(p, 0);
      if (st != ReachStatus::Reachable && st != ReachStatus::SelfCollision) {
        CHECK(std::isnan(stored));
        CHECK(pair->GetComponent(p, 0) == -1);
        continue;
      }
      // Independent re-check of the stored joint solution.
      JointVector q(m.dof());
      for (int c = 0; c < m.dof(); ++c) q[c] = qa->GetComponent(p, c);
      forwardKinematics(m, ws.kin, q);
      collisionDistances(m, ws.kin, {}, cws);
      const double d = minSelfDistance(cws);
      CHECK(d == stored);
      if (st == ReachStatus::SelfCollision) {
        ++n_collision;
        // (a) negative distance, the pair named.
        CHECK(d < 0);
        REQUIRE(cws.closest_self >= 0);
        const int idx = static_cast<int>(pair->GetComponent(p, 0));
        REQUIRE(idx >= 0);
        REQUIRE(idx < static_cast<int>(a.pair_names.size()));
        CHECK(a.pair_names[idx] == pairName(m, cws.self[cws.closest_self], false));
        CHECK(a.colliding_pair[i] == idx);
      } else {
        ++n_free;
        // (b) collision-free, and the field holds the recomputed distance.
        CHECK(d >= 0);
        CHECK(pair->GetComponent(p, 0) == -1);
      }
    }
  }
  CHECK(n_collision == countStatus(a, ReachStatus::SelfCollision));
  CHECK(n_free == a.countReachable());

  // summary.json counts the new status.
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  const auto& jd = summary["reach"]["grids"][0]["designs"][0];
  CHECK(jd["status_counts"]["self_collision"].get<long>() == n_collision);
  CHECK(jd["reachable"].get<long>() == n_free);
  long pairs = 0;
  for (const auto& [name, count] : jd["colliding_pairs"].items()) pairs += count.get<long>();
  CHECK(pairs == n_collision);
  CHECK(summary["reach"]["settings"]["self_collision"].get<bool>());
}

TEST_CASE(
    "self_collision = true for a design without a collision model is an input error naming the key",
    "[collision][reach][input]") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_reach_sweep_collision_input";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // A copy of the 6-DoF design without its [[collision]] volumes.
  std::ifstream in(test::sourcePath("designs/first_prototype_6dof.toml"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string stripped;
  bool skip = false;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    const std::string line = text.substr(pos, eol - pos);
    pos = eol + 1;
    if (line.rfind("[", 0) == 0) skip = line.rfind("[[collision", 0) == 0;
    if (!skip) stripped += line + "\n";
  }
  std::ofstream(dir / "bare.toml") << stripped;
  const std::string study_head =
      "[study]\nname = \"s\"\n[[design]]\nfile = \"bare.toml\"\n[reach]\ntask_space = "
      "\"position\"\n";
  const std::string grid =
      "[[reach.grid]]\nname = \"g\"\nx = \"0 m\"\ny = \"0.6 m\"\nz = \"1.0 m\"\n";
  std::ofstream(dir / "on.toml") << study_head << "self_collision = true\n" << grid;
  std::ofstream(dir / "default.toml") << study_head << grid;
  try {
    loadStudy((dir / "on.toml").string());
    FAIL("expected an InputError");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("self_collision") != std::string::npos);
  }
  const Study s = loadStudy((dir / "default.toml").string());
  CHECK_FALSE(stageSettings<ReachConfig>(s, "reach")->collision.self);
  // Every shipped design has a collision model: the default is on.
  std::ofstream(dir / "shipped.toml") << "[study]\nname = \"t\"\n[[design]]\nfile = \""
                                      << test::sourcePath("designs/first_prototype_6dof.toml")
                                      << "\"\n[reach]\ntask_space = \"position\"\n"
                                      << grid;
  CHECK(stageSettings<ReachConfig>(loadStudy((dir / "shipped.toml").string()), "reach")
            ->collision.self);
}
