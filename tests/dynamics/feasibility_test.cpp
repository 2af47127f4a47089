// Drive feasibility, approach tracking and the [harvest] stage (docs/dynamics.md).
// Oracles: hand-computed limits of a one-joint arm, RNEA and the finite-difference gradient of the
// potential energy, the friction law evaluated on its own, forward kinematics of the tracked
// configurations, finite differences of q, and a second run with another thread count.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "common/errors.hpp"
#include "drive/friction.hpp"
#include "dynamics/approach_tracking.hpp"
#include "dynamics/drive_feasibility.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "kinematics/kinematics.hpp"
#include "stages/harvest/harvest_stage.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

constexpr double kTrackingErrorTolerance_m = 1e-4;  // TCP position error along a tracked approach
constexpr double kTrackingErrorTolerance_rad = 1e-3;
constexpr double kEulerConsistency = 1e-9;  // (q_{k+1} - q_k) / dt vs qd_k (rounding only)
constexpr double kSecondDifferenceRelTolerance =
    0.05;                                       // qdd vs second differences of q, rel. to max |qdd|
constexpr double kPotentialFdTolerance = 1e-6;  // [N m or N], central differences of V(q)

// A single revolute joint about the vertical axis: no gravity torque, Q = Izz qdd exactly.
const char* kOneJointDesign = R"(
[design]
name = "one_joint"
[[joint]]
name = "j1"
type = "revolute"
x = 0
y = 0
z = 0
alpha = 0
beta = 0
gamma = 0
min = "-10 rad"
max = "10 rad"
max_velocity = "10 rad/s"
[tcp]
z = 0
[[inertia]]
link = "j1"
mass = 2.0
com = [0, 0, 0]
inertia = [0.1, 0.1, 0.05, 0, 0, 0]
[[drive]]
joint = "j1"
gear_ratio = 50
torque_constant = 0.1
rotor_inertia = 1.0e-4
resistance = 0.5
inductance = 0.001
peak_current = 2.0
continuous_current = 1.0
max_motor_speed = 100.0
max_voltage = 48.0
[drive.friction]
law = "harmonic_drive"
coulomb = 0.05
load_coulomb = 0.001
viscous = 1e-4
load_viscous = 1e-6
)";

// Constant acceleration a from rest over [0, T]: q = a t^2 / 2, qd = a t, qdd = a.
JointTrajectory constantAcceleration(double a, double T, double dt) {
  JointTrajectory jt;
  jt.dt = dt;
  const int ns = static_cast<int>(std::lround(T / dt)) + 1;
  for (int k = 0; k < ns; ++k) {
    const double t = k * dt;
    jt.t.push_back(t);
    JointVector q(1), qd(1), qdd(1);
    q << 0.5 * a * t * t;
    qd << a * t;
    qdd << a;
    jt.q.push_back(q);
    jt.qd.push_back(qd);
    jt.qdd.push_back(qdd);
  }
  return jt;
}

}  // namespace

TEST_CASE("drive feasibility: values, margins and first failures match hand computation") {
  const Model m = parseDesign(kOneJointDesign, "one_joint.toml");
  const RigidBodyModel rbm = makeRigidBodyModel(m);
  DynamicsWorkspace ws(rbm);
  const double N = 50, km = 0.1, Jm = 1e-4, Izz = 0.05, R = 0.5;
  const double a = 0.5, T = 2.0, dt = 1e-3;
  const JointTrajectory jt = constantAcceleration(a, T, dt);
  DriveFeasibilityOptions opt;
  opt.friction = false;
  const DriveFeasibility r = evaluateDriveFeasibility(m, rbm, ws, jt, opt);
  // Hand computation (eq. 3.27a, 4.5, 3.29 with dI/dt = 0).
  const double I =
      (Izz * a / N + Jm * N * a) / km;  // 0.05*0.5/50 + 1e-4*50*0.5 = 0.0030 N m -> 0.030 A
  const double w_end = N * a * T;       // 50 rad/s
  const double U_end = R * I + km * w_end;
  const auto& js = r.joints[0];
  REQUIRE(js.has_drive);
  CHECK(js.check(DriveQuantity::PeakCurrent).value == Approx(I).epsilon(1e-12));
  CHECK(js.check(DriveQuantity::RmsCurrent).value == Approx(I).epsilon(1e-12));
  CHECK(js.check(DriveQuantity::MotorSpeed).value == Approx(w_end).epsilon(1e-12));
  CHECK(js.check(DriveQuantity::Voltage).value == Approx(U_end).epsilon(1e-9));
  CHECK(js.check(DriveQuantity::PeakCurrent).margin == Approx((2.0 - I) / 2.0).epsilon(1e-12));
  CHECK(js.check(DriveQuantity::MotorSpeed).margin ==
        Approx((100.0 - w_end) / 100.0).epsilon(1e-12));
  CHECK(js.check(DriveQuantity::Voltage).margin == Approx((48.0 - U_end) / 48.0).epsilon(1e-9));
  CHECK(r.feasible);

  // Faster: the motor speed limit 100 rad/s is passed at t* = 100 / (N a), the voltage limit later.
  const double a2 = 3.0;
  const JointTrajectory fast = constantAcceleration(a2, T, dt);
  const DriveFeasibility r2 = evaluateDriveFeasibility(m, rbm, ws, fast, opt);
  REQUIRE_FALSE(r2.feasible);
  CHECK(r2.failing_joint == 0);
  CHECK(r2.failing_quantity == DriveQuantity::MotorSpeed);
  const double t_star = 100.0 / (N * a2);
  const int k_star =
      static_cast<int>(std::floor(t_star / dt + 1e-9)) + 1;  // first sample strictly over
  CHECK(r2.failure_time_s == Approx(k_star * dt).margin(1e-12));
  const QuantityCheck& sp = r2.joints[0].check(DriveQuantity::MotorSpeed);
  CHECK(sp.margin == Approx((100.0 - N * a2 * T) / 100.0).epsilon(1e-12));
  CHECK(sp.margin < 0);
  const double I2 = (Izz * a2 / N + Jm * N * a2) / km;
  {  // voltage (eq. 3.29, dI/dt = 0): limit 20 V passed at t = (20 - R I) / (k_m N a)
    Model mv = m;
    mv.drives[0].max_motor_speed_radps = 0;
    mv.drives[0].max_voltage_V = 20.0;
    const double t_volt = (20.0 - R * I2) / (km * N * a2);
    const DriveFeasibility rv = evaluateDriveFeasibility(mv, rbm, ws, fast, opt);
    REQUIRE_FALSE(rv.feasible);
    CHECK(rv.failing_quantity == DriveQuantity::Voltage);
    CHECK(rv.failure_time_s == Approx((std::floor(t_volt / dt + 1e-9) + 1) * dt).margin(1e-9));
    CHECK(rv.joints[0].check(DriveQuantity::Voltage).value ==
          Approx(R * I2 + km * N * a2 * T).epsilon(1e-9));
  }

  // RMS budget: current I during the first half, 0 afterwards; the continuous limit sits between
  // I / sqrt(2) (the RMS) and I: feasible. Below the RMS: fails when the I^2 budget is used up.
  {
    Model m3 = m;
    JointTrajectory half = constantAcceleration(a2, T, dt);
    const int ns = half.size();
    for (int k = ns / 2; k < ns; ++k) half.qdd[k][0] = 0, half.qd[k][0] = 0;
    const double rms = I2 * std::sqrt(static_cast<double>(ns / 2) / ns);
    m3.drives[0].max_motor_speed_radps = 0;
    m3.drives[0].max_voltage_V = 0;
    m3.drives[0].continuous_current_A = 0.99 * rms;
    const DriveFeasibility r3 = evaluateDriveFeasibility(m3, rbm, ws, half, opt);
    REQUIRE_FALSE(r3.feasible);
    CHECK(r3.failing_quantity == DriveQuantity::RmsCurrent);
    CHECK(r3.joints[0].check(DriveQuantity::RmsCurrent).value == Approx(rms).epsilon(1e-12));
    // sum_{j<=k} I^2 > ns * limit^2  <=>  k + 1 > ns * 0.99^2 * (ns/2) / ns
    const double budget_samples = 0.99 * 0.99 * (ns / 2);
    const int k_fail = static_cast<int>(std::floor(budget_samples));  // (k + 1) > budget
    CHECK(r3.failure_time_s == Approx(half.t[k_fail]).margin(1e-12));
    m3.drives[0].continuous_current_A = 1.01 * rms;
    CHECK(evaluateDriveFeasibility(m3, rbm, ws, half, opt).feasible);
  }
  // A limit of 0 is "not given": not checked, margin NaN.
  {
    Model m4 = m;
    m4.drives[0].peak_current_A = 0;
    const DriveFeasibility r4 = evaluateDriveFeasibility(m4, rbm, ws, jt, opt);
    CHECK_FALSE(r4.joints[0].check(DriveQuantity::PeakCurrent).checked);
    CHECK(std::isnan(r4.joints[0].check(DriveQuantity::PeakCurrent).margin));
  }
}

TEST_CASE("drive feasibility: friction on minus off equals the friction law evaluated separately") {
  const Model m = loadDesign(sourcePath("designs/final_prototype_9dof.toml"));
  const RigidBodyModel rbm = makeRigidBodyModel(m);
  DynamicsWorkspace ws(rbm);
  std::mt19937_64 rng(11);
  JointTrajectory jt;
  jt.dt = 1e-3;
  std::normal_distribution<double> nd(0.0, 0.5);
  for (int k = 0; k < 50; ++k) {
    jt.t.push_back(k * jt.dt);
    jt.q.push_back(randomConfiguration(m, rng));
    JointVector qd(m.dof()), qdd(m.dof());
    for (int i = 0; i < m.dof(); ++i) qd[i] = nd(rng), qdd[i] = nd(rng);
    jt.qd.push_back(qd);
    jt.qdd.push_back(qdd);
  }
  DriveFeasibilityOptions on, off;
  on.temperature_C = off.temperature_C = 35;
  off.friction = false;
  const DriveFeasibility a = evaluateDriveFeasibility(m, rbm, ws, jt, on);
  const DriveFeasibility b = evaluateDriveFeasibility(m, rbm, ws, jt, off);
  Eigen::VectorXd Q(m.dof());
  for (int k = 0; k < jt.size(); ++k) {
    inverseDynamics(rbm, ws, jt.q[k], jt.qd[k], jt.qdd[k], Q);
    for (const Drive& d : m.drives) {
      const int i = m.jointIndex(d.joint);
      const double loss = drive::frictionTorque(drive::frictionParams(m, d),
                                                d.gear_ratio * jt.qd[k][i], Q[i], 35.0);
      CHECK(a.current[k][i] - b.current[k][i] ==
            Approx(loss / d.torque_constant_NmpA).margin(1e-12));
      CHECK(a.effort[k][i] == Approx(Q[i]).margin(1e-12));
    }
  }
}

TEST_CASE("static holding load equals RNEA at rest and the gradient of the potential energy") {
  for (const char* name :
       {"designs/final_prototype_9dof.toml", "designs/final_prototype_7dof.toml"}) {
    const Model m = loadDesign(sourcePath(name));
    const RigidBodyModel rbm = makeRigidBodyModel(m);
    DynamicsWorkspace ws(rbm);
    std::mt19937_64 rng(5);
    const int n = m.dof();
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::VectorXd q = randomConfiguration(m, rng);
      const HoldingLoad h = holdingLoad(m, rbm, ws, q);
      Eigen::VectorXd tau(n);
      const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
      inverseDynamics(rbm, ws, q, zero, zero, tau);
      for (int i = 0; i < n; ++i) {
        CHECK(h.effort[i] == Approx(tau[i]).margin(kHandCheckTolerance * 1e3));
        Eigen::VectorXd qp = q, qm = q;
        qp[i] += kFdStep;
        qm[i] -= kFdStep;
        const double dV = (mechanicalEnergy(rbm, ws, qp, zero).potential_J -
                           mechanicalEnergy(rbm, ws, qm, zero).potential_J) /
                          (2 * kFdStep);
        CHECK(h.effort[i] == Approx(dV).margin(kPotentialFdTolerance));
      }
      double max_ratio = 0;
      for (const Drive& d : m.drives) {
        const int i = m.jointIndex(d.joint);
        const double I = tau[i] / (d.gear_ratio * d.torque_constant_NmpA);
        CHECK(h.current_A[i] == Approx(I).margin(1e-12));
        if (d.continuous_current_A > 0)
          max_ratio = std::max(max_ratio, std::abs(I) / d.continuous_current_A);
      }
      CHECK(h.max_ratio == Approx(max_ratio).margin(1e-12));
      CHECK(h.feasible == (max_ratio <= 1.0));
    }
  }
}

TEST_CASE("tracked approach: small TCP error, qd and qdd consistent with q, rest at both ends") {
  const Model m = loadDesign(sourcePath("designs/final_prototype_9dof.toml"));
  IkWorkspace ws(m);
  ik::ObjectiveContext ctx(m, ws.kin);
  ik::WeightedObjective obj;
  obj.add(0.1, std::make_shared<ik::JointLimitTerm>(m, defaults::kJointLimitActivation));
  obj.add(1.0, std::make_shared<ik::ManipulabilityTerm>(metrics::MeasureSpace::Translational));
  ApproachProblem pb;  // thesis Fig. 5.8 geometry, fruit on the robot side of the stem
  pb.stem_xy_W = Eigen::Vector2d(0.43, 0.8);
  pb.p_start_W = Eigen::Vector3d(0.28, 0.8, 0.8);
  pb.fruit_W = Eigen::Vector3d(0.40, 0.78, 0.75);
  ApproachPlannerOptions po;
  po.duration_s = 1.0;
  const ApproachTrajectory appr = planApproach(pb, po);
  REQUIRE(appr.status() == ApproachStatus::Ok);
  ApproachTrackingOptions to;
  to.R_tool = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const TrackedApproach tr = trackApproach(m, ws, ctx, appr, obj, to, 1);
  REQUIRE(tr.status == ApproachTrackingStatus::Ok);
  const JointTrajectory& jt = tr.trajectory;
  REQUIRE(jt.size() == 1001);
  // Independent check of the TCP error: forward kinematics of every 10th q against the planner.
  KinematicsWorkspace kin(m);
  for (int k = 0; k < jt.size(); k += 10) {
    forwardKinematics(m, kin, jt.q[k]);
    const PoseReference ref = poseReference(appr.sample(jt.t[k]), to.R_tool);
    CHECK((kin.p_WT - ref.p_WT).norm() < kTrackingErrorTolerance_m);
    const Eigen::AngleAxisd e(kin.R_WT.transpose() * ref.R_WT);
    CHECK(std::abs(e.angle()) < kTrackingErrorTolerance_rad);
  }
  double qdd_max = 0;
  for (const auto& v : jt.qdd) qdd_max = std::max(qdd_max, v.cwiseAbs().maxCoeff());
  REQUIRE(qdd_max > 0);
  for (int k = 1; k + 1 < jt.size(); ++k) {
    CHECK(((jt.q[k + 1] - jt.q[k]) / jt.dt - jt.qd[k]).cwiseAbs().maxCoeff() < kEulerConsistency);
    const JointVector second = (jt.q[k + 1] - 2 * jt.q[k] + jt.q[k - 1]) / (jt.dt * jt.dt);
    CHECK((second - jt.qdd[k]).cwiseAbs().maxCoeff() < kSecondDifferenceRelTolerance * qdd_max);
  }
  // Rest-to-rest reference: joint speeds at both ends are small against the peak.
  double qd_max = 0;
  for (const auto& v : jt.qd) qd_max = std::max(qd_max, v.cwiseAbs().maxCoeff());
  CHECK(jt.qd.front().cwiseAbs().maxCoeff() < 0.05 * qd_max);
  CHECK(jt.qd.back().cwiseAbs().maxCoeff() < 0.05 * qd_max);
}

namespace {

std::string writeStudy(const fs::path& dir, const std::string& harvest) {
  fs::create_directories(dir);
  const fs::path p = dir / "study.toml";
  std::ofstream(p) << "[study]\nname = \"h\"\n[[design]]\nfile = \""
                   << sourcePath("designs/final_prototype_9dof.toml") << "\"\n"
                   << harvest;
  return p.string();
}

const char* kSmallHarvest = R"([harvest]
plot_fruits = 1
[harvest.row]
seed = 3
stems = 2
first_stem_y = "0.7 m"
fruit_z_mean = "0.8 m"
[harvest.approach]
duration = 0.5
[harvest.grid]
x = { from = "0.3 m", to = "0.9 m", step = "0.2 m" }
y = "0.8 m"
z = { from = "0.3 m", to = "1.2 m", step = "0.3 m" }
)";

}  // namespace

TEST_CASE("harvest stage: identical results with 1 and 2 threads") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_harvest_threads";
  const Study s = loadStudy(writeStudy(dir, kSmallHarvest));
  REQUIRE(stageSettings<harvest::HarvestOptions>(s, "harvest"));
  const GreenhouseRow row =
      sampleGreenhouseRow(stageSettings<harvest::HarvestOptions>(s, "harvest")->row);
  const auto a = harvest::evaluateHarvestDesign(
      s.designs[0].model, *stageSettings<harvest::HarvestOptions>(s, "harvest"), row, 1);
  const auto b = harvest::evaluateHarvestDesign(
      s.designs[0].model, *stageSettings<harvest::HarvestOptions>(s, "harvest"), row, 2);
  REQUIRE(a.fruits.size() == b.fruits.size());
  int evaluated = 0;
  for (size_t f = 0; f < a.fruits.size(); ++f) {
    CHECK(a.fruits[f].status == b.fruits[f].status);
    if (!a.fruits[f].evaluated()) continue;
    ++evaluated;
    CHECK(a.fruits[f].with_friction.feasible == b.fruits[f].with_friction.feasible);
    REQUIRE(a.fruits[f].with_friction.current.size() == b.fruits[f].with_friction.current.size());
    for (size_t k = 0; k < a.fruits[f].with_friction.current.size(); ++k)
      CHECK((a.fruits[f].with_friction.current[k] - b.fruits[f].with_friction.current[k]).norm() ==
            0.0);
  }
  CHECK(evaluated > 0);
  REQUIRE(a.grid.size() == b.grid.size());
  for (size_t p = 0; p < a.grid.size(); ++p) {
    CHECK(a.grid[p].reachable == b.grid[p].reachable);
    if (a.grid[p].reachable)
      CHECK((a.grid[p].holding.effort - b.grid[p].holding.effort).norm() == 0.0);
  }
  fs::remove_all(dir);
}

TEST_CASE("harvest stage: run writes outputs and summary metrics") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_harvest_run";
  fs::remove_all(dir);
  const Study s = loadStudy(writeStudy(dir, kSmallHarvest));
  RunOptions ro;
  ro.output_root = (dir / "out").string();
  ro.threads = 2;
  ro.progress = false;
  const RunSummary sum = runStudy(s, ro);
  const std::string d = "harvest/final_prototype_9dof/";
  REQUIRE(sum.metrics.scalars.count(d + "feasible_fraction"));
  REQUIRE(sum.metrics.scalars.count(d + "j3/peak_current_A"));
  CHECK(sum.metrics.scalars.at(d + "evaluated_fraction") > 0);
  CHECK(sum.metrics.scalars.at(d + "j3/peak_current_A") > 0);
  // The drives' current ratio (an exploration objective): the largest |motor current| over every
  // sample of every evaluated approach, divided by its drive's peak limit, from the raw currents.
  const auto& opts = *stageSettings<harvest::HarvestOptions>(s, "harvest");
  const Model& model = s.designs[0].model;
  const auto raw = harvest::evaluateHarvestDesign(model, opts, sampleGreenhouseRow(opts.row), 1);
  double ratio = 0;
  int limited = 0;
  for (const Drive& dr : model.drives) {
    const int i = model.jointIndex(dr.joint);
    if (i < 0 || dr.peak_current_A <= 0) continue;
    ++limited;
    for (const auto& f : raw.fruits)
      if (f.evaluated())
        for (const auto& c : f.with_friction.current)
          ratio = std::max(ratio, std::abs(c[i]) / dr.peak_current_A);
  }
  REQUIRE(limited > 0);
  REQUIRE(sum.metrics.scalars.count(d + "peak_current_ratio"));
  CHECK(sum.metrics.scalars.at(d + "peak_current_ratio") == Approx(ratio).epsilon(1e-12));
  CHECK(ratio > 0);
  for (const char* f :
       {"harvest/report.md", "harvest/summary.json", "harvest/final_prototype_9dof_fruits.csv",
        "harvest/final_prototype_9dof_holding.vti"}) {
    CHECK(std::find(sum.files_written.begin(), sum.files_written.end(), f) !=
          sum.files_written.end());
    CHECK(fs::exists(fs::path(sum.output_dir) / f));
  }
  fs::remove_all(dir);
}

TEST_CASE("harvest stage: bad input is an InputError with file, line and key") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_harvest_bad";
  auto expectError = [&](const std::string& harvest, const std::string& key) {
    const std::string path = writeStudy(dir, harvest);
    try {
      (void)loadStudy(path);
      FAIL("no InputError for " << key);
    } catch (const InputError& e) {
      CHECK(e.file() == path);
      CHECK(e.line() > 3);
      CHECK(e.key() == key);
    }
  };
  expectError("[harvest]\n[harvest.approach]\nduration = 0\n", "harvest.approach.duration");
  expectError("[harvest]\nrate = 0\n[harvest.approach]\nduration = 1\n", "harvest.rate");
  expectError("[harvest]\ndesigns = [\"nope\"]\n[harvest.approach]\nduration = 1\n",
              "harvest.designs");
  expectError("[harvest]\nrate = 100\n", "harvest.approach");
  expectError("[harvest]\n[harvest.approach]\nduration = 1\n[harvest.row]\nstems = 0\n",
              "harvest.row.stems");
  expectError(
      "[harvest]\nstart_offset = [\"1 m\", \"2 deg\", 0]\n[harvest.approach]\nduration = 1\n",
      "harvest.start_offset");
  expectError(
      "[harvest]\n[harvest.approach]\nduration = 1\n[harvest.grid]\nx = { from = 1, to = 0, step = "
      "0.1 }\ny = 0\nz = 0\n",
      "harvest.grid.x");
  expectError("[harvest]\nbogus = 1\n[harvest.approach]\nduration = 1\n", "harvest.bogus");
  fs::remove_all(dir);
}
