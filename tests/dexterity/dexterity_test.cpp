// The dexterity stage: stem-grid geometry (Fig. 3.4), per-cell invariants (tool on the pose, plain
// and optimised both valid, optimisation never worse), determinism across thread counts, VTK
// read-back with VTK's own readers (VTI, VTP and the PNG map images), and bad [dexterity] input.
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkStructuredGrid.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLStructuredGridReader.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "common/errors.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "io/vtk_io.hpp"
#include "report/image.hpp"
#include "stages/dexterity/dexterity_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::dexterity;
using namespace armstudy::test;

namespace {
constexpr double kGeometryTolerance = 1e-12;
constexpr double kOnPoseTolerance = 1e-6;  // [m and rad] the tool stays on the pose
constexpr double kAngleTolerance = 1e-7;   // [rad] two formulas of the same angle (acos vs atan2)
constexpr int kMinMapPixels = 480;         // report::renderCellMap defaults
constexpr int kMapBorderPixels = 2;

DexterityOptions smallOptions() {
  DexterityOptions o;
  o.grid.stem_x_m = 0.225;
  o.grid.stem_y_m = 0.7;
  o.grid.radius_m = 0.15;
  o.grid.gamma_rad = {-M_PI / 2, M_PI / 2, 13};
  o.grid.z_m = {0.2, 1.4, 7};
  o.w_joint_limits = 0.1;
  o.w_manipulability = 1.0;
  o.w_transmission = 0.05;
  return o;
}

std::string tempDir(const std::string& name) {
  return test::emptyTempDir("dexterity_test_" + name).string();
}

std::string writeStudy(const std::string& dir, const std::string& body) {
  const std::string path = dir + "/study.toml";
  std::ofstream(path) << "[study]\nname = \"t\"\n[[design]]\nfile = \"" +
                             sourcePath("designs/first_prototype_9dof.toml") + "\"\n" + body;
  return path;
}
}  // namespace

TEST_CASE("stem grid places the TCP on the circle with the tool axis through the stem (Fig. 3.4)",
          "[dexterity][grid]") {
  DexterityOptions o = smallOptions();
  o.grid.task = PoseTaskKind::FullPose;
  o.grid.roll_rad = 0.3;
  for (int ig = 0; ig < o.grid.gamma_rad.count; ++ig) {
    const auto c = o.grid.cell(ig, 2);
    const Eigen::Vector3d stem(0.225, 0.7, c.z);
    CHECK(std::abs((c.target.p_WT - stem).norm() - 0.15) < kGeometryTolerance);
    CHECK((c.u_W - (stem - c.target.p_WT).normalized()).norm() < kGeometryTolerance);
    CHECK((c.target.R_WT.col(2) - c.u_W).norm() < kGeometryTolerance);
    CHECK(std::abs(c.target.R_WT.determinant() - 1.0) < kGeometryTolerance);
    CHECK((c.target.R_WT.transpose() * c.target.R_WT - Eigen::Matrix3d::Identity()).norm() <
          kGeometryTolerance);
  }
  // gamma = 0: straight from the robot side (-y of the stem), gamma = +90 deg from -x.
  const auto c0 = o.grid.cell(6, 0);
  CHECK((c0.target.p_WT - Eigen::Vector3d(0.225, 0.55, 0.2)).norm() < kGeometryTolerance);
  const auto c90 = o.grid.cell(12, 0);
  CHECK((c90.target.p_WT - Eigen::Vector3d(0.075, 0.7, 0.2)).norm() < kGeometryTolerance);
}

TEST_CASE("every reachable cell: plain and optimised on the pose, optimisation never worse",
          "[dexterity][invariant]") {
  for (const char* rel :
       {"designs/first_prototype_9dof.toml", "designs/final_prototype_7dof.toml"}) {
    const Model m = loadDesign(sourcePath(rel));
    const DexterityOptions o = smallOptions();
    const DexterityMap map = computeDexterityMap(m, o, 2);
    KinematicsWorkspace ws(m);
    int reachable = 0;
    for (int iz = 0; iz < o.grid.z_m.count; ++iz)
      for (int ig = 0; ig < o.grid.gamma_rad.count; ++ig) {
        const CellResult& c = map.cells[o.grid.index(ig, iz)];
        if (!c.reachable) continue;
        ++reachable;
        const auto cell = o.grid.cell(ig, iz);
        // Reachable = within the study tolerances (a pose pressed against a joint limit may stay
        // up to that far away); the optimised configuration is no further from the pose than the
        // plain one (or than the null-space pose tolerance).
        forwardKinematicsAndJacobian(m, ws, c.q_plain);
        const auto pp = poseError(ws, cell.target);
        CHECK(pp.position_m <= o.position_tolerance_m);
        CHECK(pp.orientation_rad <= o.orientation_tolerance_rad);
        CHECK(ik::withinLimits(m, c.q_plain));
        forwardKinematicsAndJacobian(m, ws, c.q_opt);
        const auto po = poseError(ws, cell.target);
        CHECK(po.position_m <= std::max(pp.position_m, kOnPoseTolerance));
        CHECK(po.orientation_rad <= std::max(pp.orientation_rad, kOnPoseTolerance));
        CHECK(ik::withinLimits(m, c.q_opt));
        // Recomputed measures match the stored ones (second evaluation path).
        const auto d = metrics::tcpMeasures(ws, o.measure_space, cell.u_W, true);
        CHECK(std::abs(d.manipulability - c.opt.manipulability) < 1e-12);
        CHECK(c.H_opt <= c.H_plain);
      }
    INFO(rel << " reachable " << reachable);
    CHECK(reachable > 0);
  }
}

TEST_CASE("a stem cell's pose error is the distance and angle the cell's pose means",
          "[dexterity][oracle]") {
  // Oracle: the pose error of a stem cell's task at random configurations equals the distance of
  // the TCP to the cell's point and the angle (acos formula) between the tool axes for the
  // harvesting task, between the frames for the full pose, computed here from the FK alone; a cell
  // solved from no warm start lands on the pose.
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  DexterityOptions o = smallOptions();
  std::mt19937_64 rng(5);
  KinematicsWorkspace ws(m);
  for (const PoseTaskKind kind :
       {PoseTaskKind::Position, PoseTaskKind::PositionAxis, PoseTaskKind::FullPose}) {
    o.grid.task = kind;
    for (int k = 0; k < 20; ++k) {
      const StemGrid::Cell cell = o.grid.cell(k % o.grid.gamma_rad.count, k % o.grid.z_m.count);
      forwardKinematics(m, ws, randomConfiguration(m, rng));
      const PoseError e = poseError(ws, cell.target);
      double angle = 0;
      if (kind == PoseTaskKind::PositionAxis)
        angle = std::acos(std::clamp(ws.a_WT.dot(cell.target.axis_W), -1.0, 1.0));
      else if (kind == PoseTaskKind::FullPose)
        angle = std::acos(
            std::clamp(0.5 * ((cell.target.R_WT.transpose() * ws.R_WT).trace() - 1.0), -1.0, 1.0));
      CHECK(e.position_m == Approx((ws.p_WT - cell.target.p_WT).norm()).margin(kGeometryTolerance));
      CHECK(e.orientation_rad == Approx(angle).margin(kAngleTolerance));
    }
  }
  o.grid.task = PoseTaskKind::PositionAxis;
  IkWorkspace ik_ws(m);
  ik::ObjectiveContext ctx(m, ws);
  const ik::WeightedObjective objective = o.buildObjective(m);
  const StemGrid::Cell cell = o.grid.cell(3, 2);
  const CellResult r = solveCell(m, ws, ik_ws, ctx, objective, o, cell, 0, nullptr, nullptr);
  REQUIRE(r.reachable);
  forwardKinematics(m, ws, r.q_plain);
  const PoseError e = poseError(ws, cell.target);
  CHECK(e.position_m < kOnPoseTolerance);
  CHECK(e.orientation_rad < kOnPoseTolerance);
}

TEST_CASE("dexterity maps are identical with 1 and 2 threads", "[dexterity][determinism]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  const DexterityOptions o = smallOptions();
  const DexterityMap a = computeDexterityMap(m, o, 1), b = computeDexterityMap(m, o, 2);
  REQUIRE(a.cells.size() == b.cells.size());
  for (std::size_t i = 0; i < a.cells.size(); ++i) {
    CHECK(a.cells[i].reachable == b.cells[i].reachable);
    if (!a.cells[i].reachable) continue;
    CHECK((a.cells[i].q_opt == b.cells[i].q_opt));  // bit-identical
    CHECK((a.cells[i].q_plain == b.cells[i].q_plain));
    CHECK(a.cells[i].opt.manipulability == b.cells[i].opt.manipulability);
  }
}

TEST_CASE("a study run writes VTK files that VTK's readers read back", "[dexterity][io][oracle]") {
  const std::string dir = tempDir("vtk");
  const std::string study = writeStudy(dir, R"(
[dexterity]
stem_x = "225 mm"
stem_y = 0.7
radius = "0.15 m"
gamma = { min = "-90 deg", max = "90 deg", step = "30 deg" }
z = { min = 0.5, max = 1.1, count = 4 }
[dexterity.objective]
manipulability = 1
transmission = 0.05
)");
  std::string out;
  const int rc =
      runCommand(binaryPath() + " run " + study + " --output " + dir + "/out --threads 2", out);
  INFO(out);
  REQUIRE(rc == 0);
  const std::string base = dir + "/out/t/dexterity/";
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  const Study s = loadStudy(study);
  REQUIRE(stageSettings<dexterity::DexterityOptions>(s, "dexterity"));
  const DexterityMap map =
      computeDexterityMap(m, *stageSettings<dexterity::DexterityOptions>(s, "dexterity"), 1);
  const MapFields f = mapFields(map);

  vtkNew<vtkXMLImageDataReader> ir;
  ir->SetFileName((base + "first_prototype_9dof.vti").c_str());
  ir->Update();
  vtkImageData* img = ir->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  CHECK(dims[0] == 7);
  CHECK(dims[1] == 4);
  CHECK(dims[2] == 1);
  double origin[3], spacing[3];
  img->GetOrigin(origin);
  img->GetSpacing(spacing);
  CHECK(std::abs(origin[0] + M_PI / 2) < kGeometryTolerance);
  CHECK(std::abs(origin[1] - 0.5) < kGeometryTolerance);
  CHECK(std::abs(spacing[0] - M_PI / 6) < kGeometryTolerance);
  CHECK(std::abs(spacing[1] - 0.2) < kGeometryTolerance);
  vtkDataArray* mn = img->GetPointData()->GetArray("manipulability_optimised_normalised");
  vtkDataArray* re = img->GetPointData()->GetArray("reachable");
  REQUIRE(mn);
  REQUIRE(re);
  double best = 0;
  for (vtkIdType i = 0; i < mn->GetNumberOfTuples(); ++i) {
    CHECK(re->GetTuple1(i) == f.reachable[i]);
    if (f.reachable[i] == 0) {
      CHECK(std::isnan(mn->GetTuple1(i)));
      continue;
    }
    CHECK(mn->GetTuple1(i) ==
          f.manipulability().opt_norm[i]);  // the run and the in-process map agree bitwise
    best = std::max(best, mn->GetTuple1(i));
  }
  CHECK(best <= 1.0);
  CHECK(std::abs(std::max(best,
                          [&] {
                            double b = 0;
                            vtkDataArray* p =
                                img->GetPointData()->GetArray("manipulability_plain_normalised");
                            for (vtkIdType i = 0; i < p->GetNumberOfTuples(); ++i)
                              if (!std::isnan(p->GetTuple1(i))) b = std::max(b, p->GetTuple1(i));
                            return b;
                          }()) -
                 1.0) < kGeometryTolerance);

  vtkNew<vtkXMLPolyDataReader> pr;
  pr->SetFileName((base + "first_prototype_9dof_ellipsoids_optimised.vtp").c_str());
  pr->Update();
  vtkPolyData* poly = pr->GetOutput();
  CHECK(poly->GetNumberOfPoints() == map.reachable());
  vtkDataArray* tensor = poly->GetPointData()->GetArray("ellipsoid_tensor");
  REQUIRE(tensor);
  CHECK(tensor->GetNumberOfComponents() == 9);
  vtkIdType k = 0;
  for (std::size_t i = 0; i < map.cells.size(); ++i) {
    if (!map.cells[i].reachable) continue;
    // Tensor = U diag(sigma) U^T: its square is J_T J_T^T at the optimised configuration.
    Eigen::Matrix3d T;
    double t9[9];
    tensor->GetTuple(k, t9);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) T(r, c) = t9[3 * r + c];
    KinematicsWorkspace ws(m);
    forwardKinematicsAndJacobian(m, ws, map.cells[i].q_opt);
    const Eigen::Matrix3d A = ws.J_W_tcp.topRows<3>() * ws.J_W_tcp.topRows<3>().transpose();
    CHECK((T * T - A).norm() < 1e-9);
    double p[3];
    poly->GetPoint(k, p);
    const auto cell = map.grid.cell(static_cast<int>(i) % 7, static_cast<int>(i) / 7);
    CHECK((Eigen::Vector3d(p[0], p[1], p[2]) - cell.target.p_WT).norm() < kGeometryTolerance);
    ++k;
  }
  // PNG of the normalised optimised manipulability figure, read back with vtkPNGReader: the cell
  // map (found by its 2 px grey frame, a run of frame-grey pixels as wide as the map) holds cell
  // (i_gamma, i_z) as a square block (gamma to the right, z upwards) in viridis of its value, grey
  // where it is not reachable; the colour bar right of the map ends in viridis(0) at the bottom.
  // The reachable figure exists only when it has two colours (some cells reachable, some not).
  long reachable = 0;
  for (double r : f.reachable) reachable += r > 0;
  CHECK(std::filesystem::exists(base + "first_prototype_9dof_reachable.png") ==
        (reachable > 0 && reachable < static_cast<long>(f.reachable.size())));
  vtkNew<vtkPNGReader> png;
  png->SetFileName((base + "first_prototype_9dof_manipulability_optimised_normalised.png").c_str());
  png->Update();
  vtkImageData* pi = png->GetOutput();
  int pd[3];
  pi->GetDimensions(pd);
  const int G = map.grid.gamma_rad.count, Z = map.grid.z_m.count;
  const int block = (kMinMapPixels + std::max(G, Z) - 1) / std::max(G, Z);
  auto pixel = [&](int x, int y_top) {  // VTK image rows start at the bottom
    std::array<int, 3> c{};
    for (int k = 0; k < 3; ++k)
      c[k] = static_cast<int>(pi->GetScalarComponentAsDouble(x, pd[1] - 1 - y_top, 0, k));
    return c;
  };
  const std::array<int, 3> frame{128, 128, 128};
  int x0 = -1, y0 = -1, run = 0;
  for (int y = 0; y < pd[1] && x0 < 0; ++y)
    for (int x = 0, n = 0; x < pd[0]; ++x) {
      n = pixel(x, y) == frame ? n + 1 : 0;
      if (n >= G * block) {
        x0 = x - n + 1, y0 = y;
        while (x + 1 < pd[0] && pixel(x + 1, y) == frame) ++x, ++n;
        run = n;
        break;
      }
    }
  REQUIRE(x0 >= 0);
  REQUIRE(run == G * block + 2 * kMapBorderPixels);
  REQUIRE(pd[1] > y0 + Z * block + 2 * kMapBorderPixels);
  for (int j = 0; j < Z; ++j)
    for (int i = 0; i < G; ++i) {
      const auto c = pixel(x0 + kMapBorderPixels + i * block + block / 2,
                           y0 + kMapBorderPixels + (Z - 1 - j) * block + block / 2);
      const double v = f.manipulability().opt_norm[static_cast<std::size_t>(map.grid.index(i, j))];
      const report::Rgb want = std::isnan(v) ? report::Rgb{160, 160, 160} : report::viridis(v);
      CHECK(c == std::array<int, 3>{want.r, want.g, want.b});
    }
  // The colour bar: the first column right of the map whose bottom pixel is (close to) viridis(0).
  const int map_bottom = y0 + Z * block + 2 * kMapBorderPixels - 2;
  bool bar = false;
  for (int x = x0 + run; x < pd[0] && !bar; ++x) {
    const auto c = pixel(x, map_bottom);
    bar = std::abs(c[0] - 68) <= 2 && std::abs(c[1] - 1) <= 3 && std::abs(c[2] - 84) <= 3;
  }
  CHECK(bar);
  CHECK(std::filesystem::exists(base + "report.md"));
  CHECK(std::filesystem::exists(base + "summary.json"));
}

TEST_CASE(
    "the map on its cylinder around the stem: world metres, the .vti's arrays, the arm at the best "
    "cell",
    "[dexterity][io][oracle]") {
  const std::string dir = tempDir("cylinder");
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  const DexterityOptions o = smallOptions();
  const DexterityMap map = computeDexterityMap(m, o, 2);
  const MapFields f = mapFields(map);
  const std::vector<std::string> files = writeMapVtk(map, f, m, o.measure_space, false, dir);
  CHECK(files == std::vector<std::string>{"first_prototype_9dof.vti",
                                          "first_prototype_9dof_cylinder.vts",
                                          "first_prototype_9dof_robot_best.vtp"});
  vtkNew<vtkXMLStructuredGridReader> sr;
  sr->SetFileName((dir + "/first_prototype_9dof_cylinder.vts").c_str());
  sr->Update();
  vtkStructuredGrid* cyl = sr->GetOutput();
  vtkNew<vtkXMLImageDataReader> ir;
  ir->SetFileName((dir + "/first_prototype_9dof.vti").c_str());
  ir->Update();
  vtkImageData* img = ir->GetOutput();
  const int G = o.grid.gamma_rad.count, Z = o.grid.z_m.count;
  REQUIRE(cyl->GetNumberOfPoints() == G * Z);
  for (int j = 0; j < Z; ++j)
    for (int i = 0; i < G; ++i) {
      // Fig. 3.4 written out here: the TCP at gamma from +y towards +x, r from the stem axis.
      const double g = -M_PI / 2 + i * M_PI / (G - 1), z = 0.2 + j * 1.2 / (Z - 1);
      const Eigen::Vector3d expect(0.225 - 0.15 * std::sin(g), 0.7 - 0.15 * std::cos(g), z);
      double p[3];
      cyl->GetPoint(j * G + i, p);
      CHECK((Eigen::Vector3d(p[0], p[1], p[2]) - expect).norm() < kGeometryTolerance);
    }
  // Every array of the (gamma, z) image is on the cylinder with the same values (NaN alike).
  vtkPointData* ip = img->GetPointData();
  REQUIRE(ip->GetNumberOfArrays() >= 15);
  for (int a = 0; a < ip->GetNumberOfArrays(); ++a) {
    vtkDataArray* x = ip->GetArray(a);
    vtkDataArray* y = cyl->GetPointData()->GetArray(x->GetName());
    INFO(x->GetName());
    REQUIRE(y);
    for (vtkIdType k = 0; k < x->GetNumberOfTuples(); ++k) {
      if (std::isnan(x->GetTuple1(k)))
        CHECK(std::isnan(y->GetTuple1(k)));
      else
        CHECK(x->GetTuple1(k) == y->GetTuple1(k));
    }
  }
  auto field = [](vtkDataObject* d, const char* name) {
    auto* s = vtkStringArray::SafeDownCast(d->GetFieldData()->GetAbstractArray(name));
    return s ? std::string(s->GetValue(0)) : std::string();
  };
  CHECK(field(cyl, "coordinates") == io::kWorldMetres);
  CHECK(field(img, "coordinates").rfind("parameter plane", 0) == 0);
  CHECK(field(img, "legend").rfind("reachable 0", 0) == 0);
  // The arm at the cell of the best optimised manipulability: its skeleton ends at that cell's TCP.
  int best = -1;
  for (std::size_t i = 0; i < map.cells.size(); ++i)
    if (map.cells[i].reachable &&
        (best < 0 || map.cells[i].opt.manipulability > map.cells[best].opt.manipulability))
      best = static_cast<int>(i);
  REQUIRE(best >= 0);
  vtkNew<vtkXMLPolyDataReader> rr;
  rr->SetFileName((dir + "/first_prototype_9dof_robot_best.vtp").c_str());
  rr->Update();
  vtkPolyData* robot = rr->GetOutput();
  REQUIRE(robot->GetNumberOfLines() >= 1);
  double tcp[3];
  robot->GetPoint(m.dof() + 1, tcp);  // skeleton: base, one point per joint frame, TCP
  CHECK((Eigen::Vector3d(tcp[0], tcp[1], tcp[2]) - map.grid.cell(best % G, best / G).target.p_WT)
            .norm() < kOnPoseTolerance);
}

TEST_CASE("bad [dexterity] input is rejected with file, line and key before any work",
          "[dexterity][input]") {
  const std::string dir = tempDir("bad");
  const std::string good = R"(
[dexterity]
stem_x = 0.225
stem_y = 0.7
radius = 0.15
gamma = { min = "-90 deg", max = "90 deg", step = "30 deg" }
z = { min = 0.5, max = 1.1, count = 4 }
)";
  REQUIRE_NOTHROW(loadStudy(writeStudy(dir, good)));
  struct Case {
    std::string from, to, append, key;
  };
  const Case cases[] = {
      {"radius = 0.15", "radius = 0", "", "dexterity.radius"},
      {"radius = 0.15", "radius = -0.1", "", "dexterity.radius"},
      {"radius = 0.15", "radius = 0.15\ndirection = [0, 0, 0]", "", "dexterity.direction"},
      {"radius = 0.15", "radius = 0.15\ndirection = [0, 2, 0]", "", "dexterity.direction"},
      {"", "", "[dexterity.objective]\nmanipulability = -1\n",
       "dexterity.objective.manipulability"},
      {"", "", "[dexterity.objective]\njoint_limits = nan\n", "dexterity.objective.joint_limits"},
      {"", "", "[dexterity.solver]\ndamping = -0.1\n", "dexterity.solver.damping"},
      {"", "", "[dexterity.solver]\njoint_weights = [1, 1]\n", "dexterity"},
      {"step = \"30 deg\"", "step = \"0 deg\"", "", "dexterity.gamma.step"},
      {"step = \"30 deg\"", "step = \"7 deg\"", "", "dexterity.gamma.step"},
      {"radius = 0.15", "radius = 0.15\nradiu = 3", "", "dexterity.radiu"},
      {"", "", "[dexterity.search]\nseed_starts = -1\n", "dexterity.search.seed_starts"},
      {"", "", "[dexterity.search]\nseed_stride = 0\n", "dexterity.search.seed_stride"},
      {"", "", "[dexterity.search]\norder = \"sideways\"\n", "dexterity.search.order"},
      {"", "", "[dexterity.audit]\nstarts = 0\n", "dexterity.audit.starts"},
      {"", "", "[dexterity.audit]\nposes = 10\n", "dexterity.audit.poses"},
      {"", "", "[dexterity.row]\nneighbours = 1\n", "dexterity.row.neighbours"},
      {"", "", "[dexterity.row]\nspacing = \"10 mm\"\n", "dexterity.row.spacing"},
      {"", "", "[dexterity.row]\nspacing = \"0.192 m\"\nspacing_sweep = [\"5 mm\"]\n",
       "dexterity.row.spacing_sweep"},
      {"", "", "[dexterity.row]\nspacing = \"0.192 m\"\nstem_radiu = \"5 mm\"\n",
       "dexterity.row.stem_radiu"},
      {"radius = 0.15", "radius = 0.15\nobstacles = true", "", "dexterity.obstacles"},
      {"radius = 0.15", "radius = 0.15\nself_collision = false",
       "[dexterity.objective]\ncollision = 1\n", "dexterity.objective.collision"},
      {"radius = 0.15", "radius = 0.15\nclearance = \"-1 mm\"", "", "dexterity.clearance"},
  };
  for (const Case& c : cases) {
    std::string body = good;
    if (!c.from.empty()) body.replace(body.find(c.from), c.from.size(), c.to);
    body += c.append;
    const std::string path = writeStudy(dir, body);
    INFO(c.to << c.append);
    try {
      loadStudy(path);
      FAIL("no InputError");
    } catch (const InputError& e) {
      INFO(e.what());
      CHECK(e.file() == path);
      CHECK(e.line() > 0);
      CHECK(e.key() == c.key);
    }
  }
  // Through the CLI: exit 2 and nothing written.
  std::string body = good;
  body.replace(body.find("radius = 0.15"), 13, "radius = 0");
  const std::string path = writeStudy(dir, body);
  std::string out;
  CHECK(runCommand(binaryPath() + " run " + path + " --output " + dir + "/out", out) == 2);
  CHECK(!std::filesystem::exists(dir + "/out/t"));
}

TEST_CASE("a stem out of reach is a warning in the report, with - for the means of nothing",
          "[dexterity][io]") {
  const std::string dir = tempDir("far");
  const std::string study = writeStudy(dir, R"(
[dexterity]
stem_x = "20 m"
stem_y = 0.7
radius = "0.15 m"
gamma = { min = "-30 deg", max = "30 deg", step = "30 deg" }
z = { min = 0.8, max = 1.0, count = 2 }
)");
  std::string out;
  REQUIRE(runCommand(binaryPath() + " run " + study + " --output " + dir + "/out --threads 2",
                     out) == 0);
  CHECK_THAT(out,
             Catch::Contains("warning: first_prototype_9dof reaches none of the 6 stem cells"));
  const std::string md = readFileOrThrow(dir + "/out/t/dexterity/report.md");
  CHECK_THAT(md,
             Catch::Contains("**Warning:** first_prototype_9dof reaches none of the 6 stem cells"));
  CHECK_THAT(md, Catch::Contains(
                     "| first_prototype_9dof | 9 | 0.0 % | 0.0 % | 0.0 % | - | - | - | - | - |"));
  CHECK_THAT(md, Catch::Contains("Best manipulability (normalisation value): -. Valley of the "
                                 "optimised map (the row of lowest mean): -. Mean null-space "
                                 "iterations: - ("));
  CHECK_THAT(md, Catch::Contains("| manipulability, optimised (normalised) | - | - | - | - |"));
}

TEST_CASE(
    "the dexterity stage evaluates the designs its section names, with the tool axes it gives them",
    "[dexterity][input]") {
  const std::string dir = tempDir("designs");
  // The 6-DoF first prototype's nozzle is its TCP y axis; the 9-DoF's gripper axis is z.
  auto study = [&](const std::string& name, const std::string& design_extra,
                   const std::string& section_extra) {
    const std::string path = dir + "/" + name + ".toml";
    std::ofstream(path) << "[study]\nname = \"" << name << "\"\n[[design]]\nfile = \""
                        << sourcePath("designs/first_prototype_6dof.toml") << "\"\n"
                        << design_extra << "[[design]]\nfile = \""
                        << sourcePath("designs/first_prototype_9dof.toml") << "\"\n"
                        << R"([dexterity]
stem_x = "0.225 m"
stem_y = "0.7 m"
radius = "0.15 m"
gamma = { min = "-pi/2", max = "pi/2", step = "30 deg" }
z = { min = "0.4 m", max = "1.4 m", step = "0.25 m" }
ellipsoids = false
self_collision = false
)" << section_extra;
    return path;
  };
  auto run = [&](const std::string& path, const std::string& name) {
    std::string log;
    REQUIRE(runCommand(binaryPath() + " run " + path + " --output " + dir + "/out --threads 2",
                       log) == 0);
    return nlohmann::json::parse(readFileOrThrow(dir + "/out/" + name + "/dexterity/summary.json"));
  };
  // designs = [...]: only the 6-DoF is evaluated.
  const auto only = run(study("only", "", "designs = [\"first_prototype_6dof\"]\n"), "only");
  REQUIRE(only["designs"].size() == 1);
  CHECK(only["designs"][0]["design"] == "first_prototype_6dof");
  // [dexterity.tool_axis] gives the same map as the [[design]] entry's tool_axis (a second way to
  // the same model), and another map than the design's own axis (the override took effect).
  const auto stage_axis = run(study("stage_axis", "",
                                    "designs = [\"first_prototype_6dof\"]\n[dexterity.tool_axis]\n"
                                    "first_prototype_6dof = \"z\"\n"),
                              "stage_axis");
  const auto entry_axis =
      run(study("entry_axis", "tool_axis = \"z\"\n", "designs = [\"first_prototype_6dof\"]\n"),
          "entry_axis");
  REQUIRE(stage_axis["designs"].size() == 1);
  CHECK(stage_axis["designs"][0]["reachable"] == entry_axis["designs"][0]["reachable"]);
  CHECK(stage_axis["designs"][0].dump() == entry_axis["designs"][0].dump());
  CHECK(stage_axis["designs"][0]["reachable"] != only["designs"][0]["reachable"]);
  // An unknown design, or a tool axis for a design the stage does not evaluate: input errors that
  // list the designs there are.
  std::string log;
  CHECK(runCommand(binaryPath() + " run " + study("bad", "", "designs = [\"ur10\"]\n") +
                       " --output " + dir + "/out",
                   log) == 2);
  CHECK_THAT(log, Catch::Contains("dexterity.designs"));
  CHECK_THAT(log, Catch::Contains("'ur10' is not part of the study (designs: "
                                  "first_prototype_6dof, first_prototype_9dof)"));
  CHECK(runCommand(binaryPath() + " run " +
                       study("bad_axis", "",
                             "designs = [\"first_prototype_9dof\"]\n[dexterity.tool_axis]\n"
                             "first_prototype_6dof = \"z\"\n") +
                       " --output " + dir + "/out",
                   log) == 2);
  CHECK_THAT(log, Catch::Contains("'first_prototype_6dof' is not evaluated by this stage "
                                  "(designs: first_prototype_9dof)"));
}
