// End-to-end: the `dynamics` and `approach` commands against the library they wrap, and their
// handling of bad arguments (exit code 2, message naming the argument).
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "dynamics/dynamics.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"
#include "trajectory/approach_planner.hpp"

using namespace armstudy;
using namespace armstudy::test;

namespace {
constexpr double kPrintedTolerance = 1e-9;  // JSON doubles round-trip; relative
}

TEST_CASE("armstudy dynamics prints Q and g(q) equal to the library's", "[dynamics][cli]") {
  const std::string design = sourcePath("designs/final_prototype_9dof.toml");
  std::string out;
  const int rc = runCommand(
      binaryPath() + " dynamics " + design +
          " --q 0.1,0.2,0.3,-0.4,0.5,0.6,-0.7,0.8,0.9 --qd 0.1,0.1,0.1,0.1,0.1,0.1,0.1,0.1,0.1"
          " --qdd 1,1,1,1,1,1,1,1,1 --gravity 0.5,0,-9.8 --json 2>/dev/null",
      out);
  REQUIRE(rc == 0);
  const auto j = nlohmann::json::parse(out);
  const Model m = loadDesign(design);
  DynamicsOptions opt;
  opt.g_W = Eigen::Vector3d(0.5, 0, -9.8);
  const RigidBodyModel rbm = makeRigidBodyModel(m, opt);
  DynamicsWorkspace ws(rbm);
  Eigen::VectorXd q(9), qd = Eigen::VectorXd::Constant(9, 0.1), qdd = Eigen::VectorXd::Ones(9),
                        Q(9), g(9);
  q << 0.1, 0.2, 0.3, -0.4, 0.5, 0.6, -0.7, 0.8, 0.9;
  inverseDynamics(rbm, ws, q, qd, qdd, Q);
  gravityForces(rbm, ws, q, g);
  REQUIRE(j["joints"].size() == 9);
  for (int i = 0; i < 9; ++i) {
    CHECK(j["joints"][i]["Q"].get<double>() == Approx(Q[i]).epsilon(kPrintedTolerance));
    CHECK(j["joints"][i]["gravity"].get<double>() == Approx(g[i]).epsilon(kPrintedTolerance));
  }
  CHECK(j["joints"][0]["unit"] == "N");
  CHECK(j["joints"][1]["unit"] == "N m");
}

TEST_CASE("armstudy dynamics and approach reject bad arguments with exit code 2",
          "[dynamics][cli][input]") {
  std::string out;
  CHECK(runCommand(binaryPath() + " dynamics " + sourcePath("designs/final_prototype_9dof.toml") +
                       " --q 0,0,0",
                   out) == 2);
  CHECK(out.find("9 joints") != std::string::npos);
  const std::string approach =
      binaryPath() + " approach --start 0.55,0.79,1.0 --stem 0.43,0.8 --fruit 0.43,0.762,0.9";
  CHECK(runCommand(approach + " --duration 0", out) == 2);
  CHECK(out.find("duration") != std::string::npos);
  CHECK(runCommand(approach + " --duration 2 --s-a 0.9", out) == 2);
  CHECK(out.find("s_a") != std::string::npos);
  // Plannable input but impossible geometry is an outcome (exit 3), not an input error.
  CHECK(runCommand(binaryPath() +
                       " approach --start 0.45,0.81,1.0 --stem 0.43,0.8 --fruit 0.43,0.762,0.9 "
                       "--duration 2",
                   out) == 3);
  CHECK(out.find("start_inside_plant_circle") != std::string::npos);
}

TEST_CASE("armstudy approach writes the planned trajectory as CSV (thesis Fig. 5.8 scene)",
          "[trajectory][cli]") {
  std::string out;
  const std::string csv =
      (std::filesystem::temp_directory_path() / "armstudy_approach_fig58_test.csv").string();
  std::remove(csv.c_str());
  const int rc =
      runCommand(binaryPath() +
                     " approach --start 0.55,0.79,1.0 --stem 0.43,0.8 --fruit 0.43,0.762,0.9"
                     " --duration 2 --rate 50 --out " +
                     csv,
                 out);
  REQUIRE(rc == 0);
  CHECK(out.find("entry time") != std::string::npos);
  std::ifstream is(csv);
  REQUIRE(is.good());
  std::string line;
  std::getline(is, line);
  CHECK(line.rfind("t,s,x,y,z,alpha,beta,gamma,", 0) == 0);
  std::vector<std::vector<double>> rows;
  while (std::getline(is, line)) {
    std::vector<double> r;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) r.push_back(std::stod(c));
    REQUIRE(r.size() == 20);
    rows.push_back(r);
  }
  REQUIRE(rows.size() == 101);
  ApproachProblem pb;
  pb.p_start_W = Eigen::Vector3d(0.55, 0.79, 1.0);
  pb.stem_xy_W = Eigen::Vector2d(0.43, 0.8);
  pb.fruit_W = Eigen::Vector3d(0.43, 0.762, 0.9);
  ApproachPlannerOptions opt;
  opt.duration_s = 2;
  const ApproachTrajectory tr = planApproach(pb, opt);
  for (const auto& r : rows) {
    const TaskSample w = tr.sample(r[0]);
    for (int c = 0; c < 6; ++c) CHECK(r[2 + c] == Approx(w.w[c]).margin(1e-10));
  }
  CHECK(rows.back()[2] == Approx(0.43).margin(1e-10));
  CHECK(rows.back()[3] == Approx(0.762).margin(1e-10));
}
