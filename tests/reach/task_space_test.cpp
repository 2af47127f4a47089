// The spraying task is a physical task for every arm: checked from the joint values a study stores
// in its .vti maps, with orocos-kdl's forward kinematics and Jacobian (independent of the solver
// and of armstudy's kinematics):
//  - the design's tool axis (named here per design, not read from the model) points along the
//    spray direction d = Rx(alpha) Rz(gamma) e_y within the orientation tolerance;
//  - the stored manipulability equals sqrt(det(J_t J_t^T)) of KDL's Jacobian rows the task
//    constrains (3 position rows, 2 angular rows perpendicular to the tool axis), and the stored
//    translational and rotational parts equal those rows alone;
// and the relation to the thesis' Cardan value at alpha = gamma = 0 (|cos beta| times it).
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
#include <iterator>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <map>
#include <nlohmann/json.hpp>

#include "common/errors.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "ik/reach_solver.hpp"
#include "io/design_io.hpp"
#include "kdl_support.hpp"
#include "kinematics/kinematics.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kOrientationTolerance_rad = 0.5 * kPi / 180.0;  // the study's tolerance below
constexpr double kAngleSlack_rad = 1e-9;                         // rounding on top of it
constexpr double kManipulabilityRelTolerance = 1e-6;             // the issue's bar against KDL
constexpr double kCardanRelationTolerance = 1e-9;

// Four arms with different tool axes: the 6-DoF nozzle (TCP y), the 7-/9-DoF gripper axis (TCP
// z) and a UR5 from its URDF with a 100 mm nozzle along the flange axis (tool0 z).
std::string studyText() {
  const std::string robots = std::string(ARMSTUDY_SOURCE_DIR) + "/../shared/robots";
  return "[study]\nname = \"task_space\"\n"
         "[[design]]\nfile = \"" +
         sourcePath("designs/first_prototype_6dof.toml") +
         "\"\n"
         "[[design]]\nfile = \"" +
         sourcePath("designs/final_prototype_7dof.toml") +
         "\"\n"
         "[[design]]\nfile = \"" +
         sourcePath("designs/final_prototype_9dof.toml") +
         "\"\n"
         "[[design]]\nfile = \"" +
         robots +
         "/ur_description/urdf/ur5_robot.urdf\"\n"
         "base_link = \"base_link\"\ntip_link = \"tool0\"\nname = \"ur5_spray\"\n"
         "packages = { \"example-robot-data\" = \"" +
         robots +
         "/..\" }\n"
         "base = { z = \"1.1 m\" }\ntcp = { z = \"100 mm\" }\n"
         R"(
[reach]
task_space = "spraying"
self_collision = false
position_tolerance = "1 mm"
orientation_tolerance = "0.5 deg"
[[reach.grid]]
name = "wall"
x = { from = "-0.6 m", to = "0.6 m", step = "0.15 m" }
y = "0.7 m"
z = { from = "0.5 m", to = "1.7 m", step = "0.15 m" }
alpha = ["0 deg", "20 deg"]
gamma = ["-40 deg", "0 deg", "40 deg"]
)";
}

// The tool axis each design names (TCP frame), stated here independently of the model.
const std::map<std::string, Eigen::Vector3d>& expectedToolAxes() {
  static const std::map<std::string, Eigen::Vector3d> a = {
      {"first_prototype_6dof", Eigen::Vector3d::UnitY()},
      {"final_prototype_7dof", Eigen::Vector3d::UnitZ()},
      {"final_prototype_9dof", Eigen::Vector3d::UnitZ()},
      {"ur5_spray", Eigen::Vector3d::UnitZ()}};
  return a;
}

vtkDataArray* requireArray(vtkImageData* img, const std::string& name) {
  vtkDataArray* a = img->GetPointData()->GetArray(name.c_str());
  INFO("array " << name);
  REQUIRE(a != nullptr);
  return a;
}

// sqrt(det(A A^T)) of the rows of A.
double rowsMeasure(const Eigen::MatrixXd& A) {
  return std::sqrt((A * A.transpose()).determinant());
}

}  // namespace

TEST_CASE(
    "spraying: at every stored q the tool axis points along the spray direction and the "
    "manipulability is that of KDL's Jacobian rows the task constrains",
    "[reach][oracle]") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_task_space_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "s.toml") << studyText();
  const Study study = loadStudy((dir / "s.toml").string());
  RunOptions ro;
  ro.output_root = (dir / "out").string();
  ro.threads = 2;
  ro.progress = false;
  runStudy(study, ro);
  const std::vector<std::pair<double, double>> alpha_gamma = {{0, -40},  {0, 0},  {0, 40},
                                                              {20, -40}, {20, 0}, {20, 40}};
  REQUIRE(study.designs.size() == expectedToolAxes().size());
  for (const StudyDesign& sd : study.designs) {
    const Model& m = sd.model;
    INFO("design " << m.name);
    const Eigen::Vector3d axis_T = expectedToolAxes().at(m.name);
    vtkNew<vtkXMLImageDataReader> reader;
    const fs::path vti = dir / "out" / "task_space" / "reach" / "wall" / (m.name + ".vti");
    REQUIRE(fs::exists(vti));
    reader->SetFileName(vti.c_str());
    reader->Update();
    vtkImageData* img = reader->GetOutput();
    const KDL::Chain chain = toKdlChain(m);
    KDL::ChainFkSolverPos_recursive fk(chain);
    KDL::ChainJntToJacSolver jac(chain);
    const int n = m.dof();
    REQUIRE(static_cast<int>(chain.getNrOfJoints()) == n);
    int checked_turned = 0, checked = 0;
    for (std::size_t k = 0; k < alpha_gamma.size(); ++k) {
      const std::string sfx = "_o" + std::to_string(k);
      vtkDataArray* status = requireArray(img, "status" + sfx);
      vtkDataArray* q = requireArray(img, "q" + sfx);
      vtkDataArray* w = requireArray(img, "manipulability" + sfx);
      vtkDataArray* wt = requireArray(img, "manipulability_translation" + sfx);
      vtkDataArray* wr = requireArray(img, "manipulability_rotation" + sfx);
      const double a = alpha_gamma[k].first * kPi / 180, g = alpha_gamma[k].second * kPi / 180;
      const Eigen::Vector3d d(-std::sin(g), std::cos(a) * std::cos(g), std::sin(a) * std::cos(g));
      for (vtkIdType p = 0; p < status->GetNumberOfTuples(); ++p) {
        if (status->GetTuple1(p) != 0) continue;
        KDL::JntArray qk(n);
        for (int c = 0; c < n; ++c) qk(c) = q->GetComponent(p, c);
        KDL::Frame F;
        REQUIRE(fk.JntToCart(qk, F) >= 0);
        Eigen::Matrix3d R;
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) R(r, c) = F.M(r, c);
        const Eigen::Vector3d axis_W = R * axis_T;
        CHECK(std::acos(std::clamp(axis_W.dot(d), -1.0, 1.0)) <=
              kOrientationTolerance_rad + kAngleSlack_rad);
        KDL::Jacobian J(n);
        REQUIRE(jac.JntToJac(qk, J) >=
                0);  // reference point: the TCP, axes of the base (world) frame
        Eigen::MatrixXd Jt(5, n);
        const Eigen::Vector3d b1 = axis_W.unitOrthogonal(), b2 = axis_W.cross(b1);
        for (int c = 0; c < n; ++c) {
          const Eigen::Vector3d v(J(0, c), J(1, c), J(2, c)), om(J(3, c), J(4, c), J(5, c));
          Jt.col(c) << v, b1.dot(om), b2.dot(om);
        }
        CHECK(w->GetTuple1(p) == Approx(rowsMeasure(Jt)).epsilon(kManipulabilityRelTolerance));
        CHECK(wt->GetTuple1(p) ==
              Approx(rowsMeasure(Jt.topRows(3))).epsilon(kManipulabilityRelTolerance));
        CHECK(wr->GetTuple1(p) ==
              Approx(rowsMeasure(Jt.bottomRows(2))).epsilon(kManipulabilityRelTolerance));
        ++checked;
        checked_turned += g != 0;
      }
    }
    // The scenario happened: every arm reached poses, also with the spray direction turned.
    CHECK(checked > 0);
    CHECK(checked_turned > 0);
  }
}

TEST_CASE(
    "at alpha = gamma = 0 the tool-axis manipulability is |cos beta| times the thesis' Cardan "
    "value",
    "[reach][oracle]") {
  // Derivation (docs/reachability.md): with R = Rx(a) Ry(b) Rz(0) the beta rate turns about the
  // tool axis y_T, so the Cardan rows (alpha, gamma) and the two angular rows perpendicular to the
  // axis differ by a 2 x 2 map of determinant cos(beta). The relation needs gamma = 0 exactly; a
  // solution meets the task only to its tolerance (|gamma| ~ 1e-5 rad), so at each solution q the
  // TCP frame is turned by Rz(-gamma) about its own z axis (Cardan gamma 0 at the unchanged q), its
  // y axis then the tool axis: within the orientation tolerance of the solution's axis.
  const Model m = loadDesign(sourcePath("designs/first_prototype_6dof.toml"));
  IkWorkspace ws(m);
  KinematicsWorkspace kin(m);
  IkOptions o;
  int checked = 0;
  for (double x : {-0.4, 0.0, 0.3})
    for (double y : {0.4, 0.7, 1.0})
      for (double z : {0.4, 1.0, 1.6}) {
        TaskVector6 w_d;
        w_d << x, y, z, 0, 0, 0;
        const PoseTask t = taskTarget(TaskSpace::spraying(), w_d);
        const IkResult r = solvePose(m, ws, t, o, static_cast<std::uint64_t>(checked + 100));
        if (!r.reachable()) continue;
        forwardKinematicsAndJacobian(m, kin, r.q);
        const double g = cardanFromRotation(kin.R_WT).gamma;
        Model turned =
            m;  // T_NT' = T_NT Rz(-g) (the 6-DoF TCP has alpha = beta = 0), tool axis y_T'
        turned.tcp.gamma -= g;
        turned.finalize();
        KinematicsWorkspace k2(turned);
        forwardKinematicsAndJacobian(turned, k2, r.q);
        const CardanAngles c = cardanFromRotation(k2.R_WT);
        INFO("pose " << x << " " << y << " " << z << ", gamma of the solution " << g << ", turned "
                     << c.gamma);
        CHECK(std::abs(c.gamma) < kCardanRelationTolerance);
        CHECK(std::abs(std::acos(std::clamp(k2.a_WT.dot(kin.a_WT), -1.0, 1.0))) <=
              o.orientation_tolerance_rad);
        const double cardan = cardanManipulability(k2, TaskSpace::spraying());
        CHECK(taskManipulability(k2, t) ==
              Approx(std::abs(std::cos(c.beta)) * cardan).epsilon(kCardanRelationTolerance));
        ++checked;
      }
  CHECK(checked > 10);
}

TEST_CASE(
    "the reach stage evaluates the designs its section names, and an unknown name lists the study "
    "designs",
    "[reach][input]") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_reach_designs_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string head = "[study]\nname = \"pick\"\n[[design]]\nfile = \"" +
                           sourcePath("designs/first_prototype_6dof.toml") +
                           "\"\n[[design]]\nfile = \"" +
                           sourcePath("designs/final_prototype_7dof.toml") + "\"\n";
  const std::string grid =
      "[[reach.grid]]\nname = \"g\"\nx = 0\ny = 0.7\nz = { from = \"0.8 m\", to = \"1.2 m\", step "
      "= \"0.2 m\" }\nalpha = 0\ngamma = 0\n";
  std::ofstream(dir / "s.toml") << head << "[reach]\ndesigns = [\"final_prototype_7dof\"]\n"
                                << grid;
  const Study study = loadStudy((dir / "s.toml").string());
  RunOptions ro;
  ro.output_root = (dir / "out").string();
  ro.threads = 1;
  ro.progress = false;
  runStudy(study, ro);
  const nlohmann::json summary =
      nlohmann::json::parse(std::ifstream(dir / "out" / "pick" / "summary.json"));
  const auto& designs = summary["reach"]["grids"][0]["designs"];
  REQUIRE(designs.size() == 1);
  CHECK(designs[0]["design"] == "final_prototype_7dof");
  CHECK_FALSE(fs::exists(dir / "out" / "pick" / "reach" / "g" / "first_prototype_6dof.vti"));

  // [reach.tool_axis] turns a design's tool axis for this stage only (the report states it).
  std::ofstream(dir / "axis.toml") << head << "[reach]\ndesigns = [\"final_prototype_7dof\"]\n"
                                   << "[reach.tool_axis]\nfinal_prototype_7dof = \"y\"\n"
                                   << grid;
  ro.output_root = (dir / "out_axis").string();
  runStudy(loadStudy((dir / "axis.toml").string()), ro);
  std::ifstream axis_report(dir / "out_axis" / "pick" / "reach" / "report.md");
  const std::string axis_text((std::istreambuf_iterator<char>(axis_report)),
                              std::istreambuf_iterator<char>());
  CHECK(axis_text.find("`final_prototype_7dof` TCP (0.000, 1.000, 0.000)") != std::string::npos);
  std::ofstream(dir / "bad_axis.toml") << head << "[reach]\ndesigns = [\"final_prototype_7dof\"]\n"
                                       << "[reach.tool_axis]\nfirst_prototype_6dof = \"y\"\n"
                                       << grid;
  CHECK_THROWS_WITH(
      loadStudy((dir / "bad_axis.toml").string()),
      Catch::Contains(
          "'first_prototype_6dof' is not evaluated by this stage (designs: final_prototype_7dof)"));

  std::ofstream(dir / "bad.toml") << head << "[reach]\ndesigns = [\"ur10\"]\n" << grid;
  try {
    loadStudy((dir / "bad.toml").string());
    FAIL("an unknown design name must be an input error");
  } catch (const InputError& e) {
    const std::string what = e.what();
    CHECK(what.find("reach.designs") != std::string::npos);
    CHECK(what.find("'ur10' is not part of the study (designs: first_prototype_6dof, "
                    "final_prototype_7dof)") != std::string::npos);
  }
}
