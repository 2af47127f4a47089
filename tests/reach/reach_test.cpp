// Reachability sweeps and the study stage: bit-identical results for 1 and 2 threads, every
// written VTK file read back with VTK's own XML readers (dimensions, origin, spacing, values, and
// FK of the stored joint solutions as an independent check), the CGAL boundary surface against a
// closed-form box volume and the divergence theorem, and each bad-input rule of the [reach]
// section.
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <random>

#include "common/errors.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "reach/boundary_surface.hpp"
#include "reach/reach_sweep.hpp"
#include "stages/reach/reach_config.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

constexpr double kVolumeTolerance = 1e-9;    // m^3, closed-form box volume
constexpr double kStoredValueTolerance = 0;  // Float64 arrays round-trip exactly

fs::path reachDir(const std::string& name) { return test::emptyTempDir("reach_test_" + name); }

void writeText(const fs::path& p, const std::string& s) { std::ofstream(p) << s; }

std::string reachStudyText(const std::string& name, const std::string& reach) {
  return "[study]\nname = \"" + name + "\"\n[[design]]\nfile = \"" +
         sourcePath("designs/first_prototype_6dof.toml") + "\"\n[[design]]\nfile = \"" +
         sourcePath("designs/final_prototype_7dof.toml") + "\"\n" + reach;
}

const char* kSmallReach = R"(
[reach]
task_space = "spraying"
[[reach.grid]]
name = "row"
x = { from = "-0.6 m", to = "0.6 m", step = "0.1 m" }
y = { from = "0.4 m", to = "1.0 m", step = "0.1 m" }
z = "1.2 m"
alpha = 0
gamma = ["-40 deg", "40 deg"]
[[reach.grid]]
name = "box"
task_space = "position"
x = { from = "-0.4 m", to = "0.4 m", step = "0.2 m" }
y = { from = "0.2 m", to = "1.0 m", step = "0.2 m" }
z = { from = "0.6 m", to = "1.4 m", step = "0.2 m" }
[[reach.poses]]
name = "list"
file = "poses.csv"
task_space = "position"
)";

}  // namespace

TEST_CASE("sweeps are bit-identical for 1 and 2 threads and from run to run",
          "[reach][determinism]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_6dof.toml"));
  TaskGrid g;
  g.name = "g";
  g.task_space = TaskSpace::spraying();
  g.axes = {AxisRange{-0.78, 0.78, 0.04}, AxisRange{0.3, 1.2, 0.05}, AxisRange{1.2, 1.2, 1}};
  g.orientations = {{0, 0, -0.7}, {0, 0, 0.7}};
  IkOptions o = ReachConfig::studyDefaults();
  const PoseSweep a = sweepGrid(m, g, o, 1, nullptr);
  const PoseSweep b = sweepGrid(m, g, o, 2, nullptr);
  const PoseSweep c = sweepGrid(m, g, o, 2, nullptr);
  CHECK(a.countReachable() > 0);
  CHECK(a.countReachable() < a.size);
  for (const PoseSweep* s : {&b, &c}) {
    CHECK(s->status == a.status);
    CHECK(s->starts == a.starts);
    CHECK(s->q == a.q);
    CHECK(s->position_error_m == a.position_error_m);
    CHECK(s->orientation_error_rad == a.orientation_error_rad);
    CHECK(s->manipulability == a.manipulability);
    CHECK(s->joint_limit_margin == a.joint_limit_margin);
  }
}

TEST_CASE("alpha-shape volume of a sampled box equals the box volume, facets face outwards",
          "[reach][oracle]") {
  std::vector<Eigen::Vector3d> pts;
  const double h = 0.1;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 6; ++k) pts.emplace_back(i * h, 0.3 + j * h, -0.2 + k * h);
  const BoundarySurface s = alphaShapeSurface(pts, gridAlphaRadius({h, h, h}));
  const double box = (4 * h) * (3 * h) * (5 * h);
  CHECK(s.volume_m3 == Approx(box).margin(kVolumeTolerance));
  // Divergence theorem: sum of signed tetrahedra (origin, facet) = enclosed volume when the
  // facets are consistently oriented outwards.
  double v = 0;
  for (const auto& t : s.triangles)
    v += s.vertices[t[0]].dot(s.vertices[t[1]].cross(s.vertices[t[2]])) / 6.0;
  CHECK(v == Approx(box).margin(kVolumeTolerance));
  // 2 x (4x3 + 3x5 + 4x5) squares on the box surface, two triangles each.
  CHECK(s.triangles.size() == 2u * 2u * (4 * 3 + 3 * 5 + 4 * 5));
}

TEST_CASE("boundary surfaces are canonical: the same point set in any order gives the same surface",
          "[reach]") {
  // An L-shaped block of grid points (degenerate for Delaunay: many co-spherical points), given
  // in two different orders. CGAL iterates cells in memory order; the output must not depend on it.
  const double h = 0.1;
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 4; ++k)
        if (i < 3 || j < 2) pts.emplace_back(i * h, j * h, k * h);
  std::vector<Eigen::Vector3d> shuffled = pts;
  std::mt19937 rng(7);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  const BoundarySurface a = alphaShapeSurface(pts, gridAlphaRadius({h, h, h}));
  const BoundarySurface b = alphaShapeSurface(shuffled, gridAlphaRadius({h, h, h}));
  REQUIRE_FALSE(a.triangles.empty());
  CHECK(a.triangles == b.triangles);
  CHECK(a.vertices == b.vertices);
  CHECK(a.volume_m3 == b.volume_m3);  // bit for bit: summed in a canonical order
  // The sorted, re-indexed triangles still enclose the solid: divergence theorem.
  double v = 0;
  for (const auto& t : a.triangles)
    v += a.vertices[t[0]].dot(a.vertices[t[1]].cross(a.vertices[t[2]])) / 6.0;
  CHECK(v == Approx(a.volume_m3).margin(kVolumeTolerance));
}

TEST_CASE("a study writes VTK files that VTK's readers load with the right grid and values",
          "[reach][oracle]") {
  const fs::path dir = reachDir("e2e");
  writeText(dir / "poses.csv", "x,y,z\n0.0,0.8,1.0\n0.3,0.6,1.2\n5,5,5\n");
  writeText(dir / "s.toml", reachStudyText("e2e", kSmallReach));
  const Study study = loadStudy((dir / "s.toml").string());
  RunOptions ro;
  ro.output_root = (dir / "out").string();
  ro.threads = 2;
  ro.progress = false;
  const RunSummary rs = runStudy(study, ro);
  const fs::path out = dir / "out" / "e2e";
  nlohmann::json summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  REQUIRE(fs::exists(out / "report.md"));
  REQUIRE(fs::exists(out / "reach" / "report.md"));
  int vti = 0, vtp = 0;
  for (const std::string& rel : rs.files_written) {
    const fs::path p = out / rel;
    REQUIRE(fs::exists(p));
    if (p.extension() == ".vti") {
      ++vti;
      vtkNew<vtkXMLImageDataReader> r;
      r->SetFileName(p.c_str());
      r->Update();
      vtkImageData* img = r->GetOutput();
      int dims[3];
      img->GetDimensions(dims);
      const bool row = rel.find("reach/row/") == 0;
      const TaskGrid& g = stageSettings<ReachConfig>(study, "reach")->grids[row ? 0 : 1];
      CHECK(dims[0] == g.dims()[0]);
      CHECK(dims[1] == g.dims()[1]);
      CHECK(dims[2] == g.dims()[2]);
      double origin[3], spacing[3];
      img->GetOrigin(origin);
      img->GetSpacing(spacing);
      for (int a = 0; a < 3; ++a) {
        CHECK(origin[a] == g.axes[a].from);
        if (g.axes[a].count() > 1) CHECK(spacing[a] == g.axes[a].step);
      }
      if (rel.find("comparison") != std::string::npos) {
        CHECK(img->GetPointData()->GetArray(row ? "reached_by_mask_o0" : "reached_by_mask"));
        continue;
      }
      // Reachable count per file equals summary.json; stored q reproduces the pose by FK.
      const std::string design = p.stem().string();
      const Model m = loadDesign(sourcePath("designs/" + design + ".toml"));
      KinematicsWorkspace kin(m);
      long reachable = 0;
      std::vector<double> manip;  // manipulability at the reachable poses, from the file
      const int no = static_cast<int>(g.orientations.size());
      for (int k = 0; k < no; ++k) {
        const std::string sfx = no > 1 ? "_o" + std::to_string(k) : "";
        vtkDataArray* reach = img->GetPointData()->GetArray(("reachable" + sfx).c_str());
        vtkDataArray* q = img->GetPointData()->GetArray(("q" + sfx).c_str());
        vtkDataArray* pe = img->GetPointData()->GetArray(("position_error_m" + sfx).c_str());
        REQUIRE(reach);
        REQUIRE(q);
        REQUIRE(pe);
        vtkDataArray* mu = img->GetPointData()->GetArray(("manipulability" + sfx).c_str());
        REQUIRE(mu);
        CHECK(q->GetNumberOfComponents() == m.dof());
        for (vtkIdType p = 0; p < reach->GetNumberOfTuples(); ++p) {
          if (reach->GetTuple1(p) == 0) continue;
          ++reachable;
          manip.push_back(mu->GetTuple1(p));
          Eigen::VectorXd qv(m.dof());
          for (int c = 0; c < m.dof(); ++c) qv[c] = q->GetComponent(p, c);
          forwardKinematics(m, kin, qv);
          double xyz[3];
          img->GetPoint(p, xyz);
          const double err = (kin.p_WT - Eigen::Vector3d(xyz[0], xyz[1], xyz[2])).norm();
          CHECK(err <= stageSettings<ReachConfig>(study, "reach")->ik.position_tolerance_m);
          CHECK(std::abs(err - pe->GetTuple1(p)) <= 1e-9);
        }
      }
      // The map's summary metrics (exploration objectives) from the file's values: mean, lowest and
      // 5th percentile (nearest rank) of the reachable poses' manipulability.
      REQUIRE_FALSE(manip.empty());
      const std::string key = "reach/" + g.name + "/" + design + "/manipulability_";
      const std::size_t rank = static_cast<std::size_t>(std::ceil(0.05 * manip.size())) - 1;
      std::nth_element(manip.begin(), manip.begin() + rank, manip.end());
      CHECK(rs.metrics.scalars.at(key + "p5") == Approx(manip[rank]).epsilon(1e-12));
      CHECK(rs.metrics.scalars.at(key + "min") ==
            Approx(*std::min_element(manip.begin(), manip.end())).epsilon(1e-12));
      CHECK(rs.metrics.scalars.at(key + "mean") ==
            Approx(std::accumulate(manip.begin(), manip.end(), 0.0) / manip.size()).epsilon(1e-9));
      for (const auto& jg : summary["reach"]["grids"])
        if (jg["name"] == g.name)
          for (const auto& jd : jg["designs"])
            if (jd["design"] == design) CHECK(jd["reachable"].get<long>() == reachable);
    } else if (p.extension() == ".vtp") {
      ++vtp;
      vtkNew<vtkXMLPolyDataReader> r;
      r->SetFileName(p.c_str());
      r->Update();
      vtkPolyData* poly = r->GetOutput();
      if (rel.find("_surface") != std::string::npos) {
        CHECK(poly->GetNumberOfPolys() > 0);
        continue;
      }
      if (rel.find("_robot_best") != std::string::npos) {  // the arm (tests/study/scene_test.cpp)
        CHECK(poly->GetNumberOfLines() == 1);
        continue;
      }
      REQUIRE(poly->GetNumberOfPoints() == 3);
      CHECK(poly->GetNumberOfVerts() == 3);
      vtkDataArray* line = poly->GetPointData()->GetArray("line");
      REQUIRE(line);
      CHECK(line->GetTuple1(2) == 4);
      CHECK(poly->GetPointData()->GetArray("reachable")->GetTuple1(2) == 0);  // (5, 5, 5) m
      CHECK(poly->GetPointData()->GetArray("status")->GetTuple1(2) ==
            double(ReachStatus::OutOfReach));
      double xyz[3];
      poly->GetPoint(1, xyz);
      CHECK(xyz[1] == 0.6 + kStoredValueTolerance);
    }
  }
  CHECK(vti == 2 + 2 + 2);  // (6-DoF, 7-DoF, comparison) x 2 grids
  CHECK(vtp >= 2 + 1);      // 2 pose lists + at least one surface
  CHECK(summary["reach"]["grids"][0]["comparison"]["pairs"].size() == 1);
  fs::remove_all(dir);
}

TEST_CASE("bad [reach] input is an InputError naming file, line and key, nothing is written",
          "[reach][bad-input]") {
  const fs::path dir = reachDir("bad");
  writeText(dir / "poses.csv", "x,y,z\n0.1,0.2,0.3\n0.1,zz,0.3\n");
  struct Case {
    std::string what, reach, key;
    int line;
  };
  const std::string grid = "[[reach.grid]]\nname = \"g\"\n";
  // reachStudyText puts 6 lines before the [reach] section, which starts on line 7.
  const std::vector<Case> cases = {
      {"zero step", "[reach]\n" + grid + "x = { from = 0, to = 1, step = 0 }\ny = 0.5\nz = 1\n",
       "reach.grid[0].x", 10},
      {"negative step",
       "[reach]\n" + grid + "x = { from = 0, to = 1, step = \"-1 cm\" }\ny = 0.5\nz = 1\n",
       "reach.grid[0].x", 10},
      {"empty range", "[reach]\n" + grid + "x = 0\ny = { from = 1, to = 0.5, step = 0.1 }\nz = 1\n",
       "reach.grid[0].y", 11},
      {"unknown task-space component",
       "[reach]\ntask_space = \"x,y,z,roll\"\n" + grid + "x = 0\ny = 0.5\nz = 1\n",
       "reach.task_space", 8},
      {"zero tolerance",
       "[reach]\nposition_tolerance = \"0 mm\"\n" + grid + "x = 0\ny = 0.5\nz = 1\n",
       "reach.position_tolerance", 8},
      {"negative tolerance",
       "[reach]\norientation_tolerance = \"-0.5 deg\"\n" + grid + "x = 0\ny = 0.5\nz = 1\n",
       "reach.orientation_tolerance", 8},
      {"beta in the spraying space", "[reach]\n" + grid + "x = 0\ny = 0.5\nz = 1\nbeta = 0\n",
       "reach.grid[0].beta", 13},
      {"unknown key", "[reach]\n" + grid + "x = 0\ny = 0.5\nz = 1\nspeed = 1\n",
       "reach.grid[0].speed", 13},
      {"negative collision starts",
       "[reach]\n[reach.search]\ncollision_starts = -1\n" + grid + "x = 0\ny = 0.5\nz = 1\n",
       "reach.search.collision_starts", 9},
      {"unknown sweep order",
       "[reach]\n[reach.search]\norder = \"random\"\n" + grid + "x = 0\ny = 0.5\nz = 1\n",
       "reach.search.order", 9},
      {"zero audit starts",
       "[reach]\n[reach.audit]\nstarts = 0\n" + grid + "x = 0\ny = 0.5\nz = 1\n",
       "reach.audit.starts", 9},
      {"unknown audit key",
       "[reach]\n[reach.audit]\ncells = 5\n" + grid + "x = 0\ny = 0.5\nz = 1\n",
       "reach.audit.cells", 9},
      {"malformed CSV row",
       "[reach]\n[[reach.poses]]\nname = \"p\"\nfile = \"poses.csv\"\ntask_space = \"position\"\n",
       "y", 3},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    writeText(dir / "s.toml", reachStudyText("bad", c.reach));
    bool thrown = false;
    try {
      loadStudy((dir / "s.toml").string());
    } catch (const InputError& e) {
      thrown = true;
      CHECK(e.key() == c.key);
      CHECK(e.line() == c.line);
      CHECK(e.file().find(c.what == "malformed CSV row" ? "poses.csv" : "s.toml") !=
            std::string::npos);
    }
    CHECK(thrown);
    // Through the CLI: exit status 2 and no output folder.
    std::string log;
    CHECK(runCommand(binaryPath() + " run " + (dir / "s.toml").string() + " --output " +
                         (dir / "out").string(),
                     log) == 2);
    CHECK_FALSE(fs::exists(dir / "out"));
  }
  fs::remove_all(dir);
}

TEST_CASE("a design that reaches nothing in a grid is a warning in the report and summary",
          "[reach][io]") {
  const fs::path dir = reachDir("nothing");
  writeText(dir / "s.toml", reachStudyText("nothing", R"(
[reach]
task_space = "position"
[[reach.grid]]
name = "far"
x = { from = "50 m", to = "50.1 m", step = "0.1 m" }
y = 0.5
z = 1
)"));
  std::string out;
  REQUIRE(runCommand(binaryPath() + " run " + (dir / "s.toml").string() + " --threads 2 --output " +
                         (dir / "out").string(),
                     out) == 0);
  const std::string text =
      "`first_prototype_6dof`, `final_prototype_7dof` reach none of the 2 poses of grid `far`";
  CHECK_THAT(out, Catch::Contains("warning: " + text));
  const fs::path o = dir / "out" / "nothing";
  std::ifstream in(o / "reach" / "report.md");
  const std::string md((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK_THAT(md, Catch::Contains("**Warning:** " + text));
  // The study's report lists it under its warnings, above the details.
  const std::string top = readFileOrThrow((o / "report.md").string());
  const std::size_t warnings = top.find("## Warnings"), details = top.find("## Details");
  REQUIRE(warnings != std::string::npos);
  const std::size_t at =
      top.find("`first_prototype_6dof` reaches none of the 2 poses of grid `far`");
  CHECK(at > warnings);
  CHECK(at < details);
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(o / "summary.json"));
  CHECK(summary["reach"]["grids"][0]["designs_reaching_nothing"].size() == 2);
  fs::remove_all(dir);
}

TEST_CASE("a design's reference_reach_m is compared with the largest reach found on each grid",
          "[reach][io]") {
  const fs::path dir = reachDir("reference");
  const std::string design = "[study]\nname = \"ref\"\n[[design]]\nfile = \"" +
                             sourcePath("designs/first_prototype_6dof.toml") + "\"\n";
  const std::string reach = R"(
[reach]
task_space = "position"
[[reach.grid]]
name = "line"
x = { from = "0.2 m", to = "1.6 m", step = "0.05 m" }
y = 0
z = 1
)";
  writeText(dir / "s.toml", design + "reference_reach_m = \"850 mm\"\n" + reach);
  std::string out;
  REQUIRE(runCommand(binaryPath() + " run " + (dir / "s.toml").string() + " --threads 2 --output " +
                         (dir / "out").string(),
                     out) == 0);
  const fs::path o = dir / "out" / "ref";
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(o / "summary.json"));
  const auto& g = summary["reach"]["grids"][0];
  // Oracle: the base stands at the origin (the design has no [base]), the line runs along +x
  // through its z axis, so the largest reach found is the largest reachable x.
  const double largest_x = g["designs"][0]["extent"]["x_m"][1].get<double>();
  REQUIRE(g["reference_reach"].size() == 1);
  CHECK(g["reference_reach"][0]["reference_reach_m"].get<double>() == Approx(0.85).epsilon(1e-15));
  CHECK(g["reference_reach"][0]["largest_reach_found_m"].get<double>() ==
        Approx(largest_x).epsilon(1e-12));
  CHECK(g["reference_reach"][0]["difference_m"].get<double>() ==
        Approx(largest_x - 0.85).epsilon(1e-12));
  std::ifstream in(o / "reach" / "report.md");
  const std::string md((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK_THAT(md, Catch::Contains("against the design's `reference_reach_m`") &&
                     Catch::Contains("| first_prototype_6dof | 0.850 |"));
  // a reference of 0 is refused at its line
  writeText(dir / "bad.toml", design + "reference_reach_m = 0\n" + reach);
  CHECK(runCommand(binaryPath() + " check " + (dir / "bad.toml").string(), out) == 2);
  CHECK_THAT(out, Catch::Contains("bad.toml:5") && Catch::Contains("reference_reach_m"));
  fs::remove_all(dir);
}
