// Logs as robots write them (docs/calibration.md, "Bring your own robot's logs"): efforts logged as
// motor current with per-joint torque constants (both signs) and ratios, logged velocities used
// instead of differentiated positions, a gravity-compensated lift, time columns checked file
// against file, channels named by joint with their own units, and the bad inputs of each through
// a study (exit 2, nothing written).
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "calibration/arm_calibration.hpp"
#include "calibration/joint_log.hpp"
#include "common/errors.hpp"
#include "dynamics/dynamics.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::calibration;
namespace fs = std::filesystem;

namespace {

const Model& lift6() {  // j1 a vertical prismatic lift, j2..j6 revolute, no [[drive]]
  static const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  return m;
}

// The planted motion: sums of two sines per joint, with exact velocity and acceleration.
struct Motion {
  Eigen::VectorXd q, qd, qdd;
};
Motion motionAt(const Model& m, double t) {
  Motion s{Eigen::VectorXd(6), Eigen::VectorXd(6), Eigen::VectorXd(6)};
  for (int j = 0; j < 6; ++j) {
    const JointLimits& l = m.joints[j].limits;
    const double c = 0.5 * (l.q_min + l.q_max), a = std::min(0.6, 0.3 * (l.q_max - l.q_min));
    const double w1 = 2 * M_PI * (0.3 + 0.07 * j), w2 = 2 * M_PI * (0.71 + 0.05 * j);
    s.q[j] = c + a * (0.7 * std::sin(w1 * t + j) + 0.3 * std::sin(w2 * t + 2 * j));
    s.qd[j] = a * (0.7 * w1 * std::cos(w1 * t + j) + 0.3 * w2 * std::cos(w2 * t + 2 * j));
    s.qdd[j] =
        -a * (0.7 * w1 * w1 * std::sin(w1 * t + j) + 0.3 * w2 * w2 * std::sin(w2 * t + 2 * j));
  }
  return s;
}

Eigen::VectorXd rnea(const Model& m, const Motion& s) {
  static RigidBodyModel rbm = makeRigidBodyModel(m);
  static DynamicsWorkspace ws(rbm);
  Eigen::VectorXd Q(6);
  inverseDynamics(rbm, ws, s.q, s.qd, s.qdd, Q);
  return Q;
}

void writeCsv(const fs::path& p, const std::string& prefix, const Eigen::MatrixXd& m,
              const std::vector<double>* time = nullptr) {
  std::ofstream o(p);
  o.precision(17);
  if (time) o << "t,";
  for (int c = 0; c < m.cols(); ++c) o << (c ? "," : "") << prefix << c + 1;
  o << "\n";
  for (int i = 0; i < m.rows(); ++i) {
    if (time) o << (*time)[static_cast<std::size_t>(i)] << ",";
    for (int c = 0; c < m.cols(); ++c) o << (c ? "," : "") << m(i, c);
    o << "\n";
  }
}

const double kKt[6] = {0.12, -0.08, 0.11, -0.05, 0.09, -0.04};  // N m/A (N/A for the lift)
const double kRatio[6] = {20, 100, 120, -100, 80, 50};

// A joint-side log of the planted motion at 1 kHz: pos.csv (+ t), cur.csv the motor currents
// i = tau / (ratio kt), with the lift's gravity force left out when `compensated`, vel.csv the
// exact velocities plus `vel_bias` on joint 3.
struct RobotLog {
  fs::path dir;
  JointLogSpec spec;
  RobotLog(const std::string& name, bool compensated, double vel_bias = 0, int rows = 4000,
           double h = 1e-3)
      : dir(test::emptyTempDir("robotlogs_" + name)) {
    const Model& m = lift6();
    Eigen::MatrixXd pos(rows, 6), cur(rows, 6), vel(rows, 6);
    std::vector<double> t;
    for (int i = 0; i < rows; ++i) {
      t.push_back(i * h);
      const Motion s = motionAt(m, i * h);
      Eigen::VectorXd Q = rnea(m, s);
      if (compensated) Q[0] -= liftGravity();
      pos.row(i) = s.q.transpose();
      vel.row(i) = s.qd.transpose();
      vel(i, 2) += vel_bias;
      for (int j = 0; j < 6; ++j) cur(i, j) = Q[j] / (kRatio[j] * kKt[j]);
    }
    writeCsv(dir / "pos.csv", "p", pos, &t);
    writeCsv(dir / "cur.csv", "i", cur, &t);
    writeCsv(dir / "vel.csv", "v", vel, &t);
    spec.study_file = (dir / "study.toml").string();
    spec.study_line = 3;
    for (const auto& j : m.joints) spec.joints.push_back(j.name);
    spec.positions = {(dir / "pos.csv").string(), {"p1", "p2", "p3", "p4", "p5", "p6"}, 1.0, ""};
    spec.efforts = {(dir / "cur.csv").string(), {"i1", "i2", "i3", "i4", "i5", "i6"}, 1.0, ""};
    spec.time_column = "t";
    spec.coupling = Eigen::MatrixXd::Identity(6, 6);
    spec.offsets = Eigen::VectorXd::Zero(6);
    spec.torque_constants.assign(kKt, kKt + 6);
    spec.effort_ratios.assign(kRatio, kRatio + 6);
    spec.cutoff_Hz = 20;
    spec.decimate = 10;
    spec.trim_s = 0.2;
  }
  // Closed form: a vertical lift carries every link and the payload, g = 9.81 m/s^2.
  static double liftGravity() {
    double mass = lift6().payload_kg;
    for (const auto& in : lift6().inertias) mass += in.mass_kg;
    return 9.81 * mass;
  }
};

}  // namespace

TEST_CASE("current logs with signed torque constants and ratios give the joint torques") {
  RobotLog log("current", false);
  const TrajectoryData d = readJointLog(log.spec, lift6());
  REQUIRE(d.rows() > 300);
  double worst = 0;
  for (int k = 0; k < d.rows(); ++k) {
    const Eigen::VectorXd Q = rnea(lift6(), motionAt(lift6(), d.t[k]));
    for (int j = 0; j < 6; ++j)
      worst = std::max(worst, std::abs(d.measured(k, j) - Q[j]) / (1 + std::abs(Q[j])));
  }
  CHECK(worst < 1e-3);  // the 20 Hz low-pass on sines below 1 Hz: a gain within 1e-6 of 1
}

TEST_CASE("logged velocities replace the differentiated ones and their difference is reported") {
  const double bias = 0.01;  // rad/s on joint 3 only
  RobotLog log("velocities", false, bias);
  log.spec.velocities = {
      (log.dir / "vel.csv").string(), {"v1", "v2", "v3", "v4", "v5", "v6"}, 1.0, ""};
  const TrajectoryData d = readJointLog(log.spec, lift6());
  REQUIRE(d.velocity_difference_rms.size() == 6);
  for (int j = 0; j < 6; ++j) {
    INFO("joint " << j + 1);
    CHECK(d.velocity_difference_rms[j] == Approx(j == 2 ? bias : 0.0).margin(2e-4));
  }
  for (int k = 0; k < d.rows(); k += 37) {  // the logged (biased) velocity is the one used
    const Motion s = motionAt(lift6(), d.t[k]);
    CHECK(d.qd(k, 2) == Approx(s.qd[2] + bias).margin(1e-4));
    CHECK(d.qd(k, 1) == Approx(s.qd[1]).margin(1e-4));
  }
  bool reported = false;
  for (const auto& w : d.warnings)
    reported = reported || (w.find("logged velocities used") != std::string::npos &&
                            w.find("j3 0.01 rad/s") != std::string::npos);
  CHECK(reported);
}

TEST_CASE("a gravity-compensated lift's model force excludes gravity (closed form)") {
  RobotLog log("gravity", true);
  SECTION("declared: the model matches the log") {
    log.spec.gravity_compensated = {"j1"};
    const TrajectoryData d = readJointLog(log.spec, lift6());
    const auto P = makeTrajectoryProblem(lift6(), d);
    const Eigen::MatrixXd r = P->measured - P->predict({});
    CHECK(r.col(0).cwiseAbs().maxCoeff() < 1e-3 * RobotLog::liftGravity());
    CHECK(r.col(1).cwiseAbs().maxCoeff() < 1e-2);  // other joints keep their gravity
  }
  SECTION("not declared: the residual is the lift's gravity force m g") {
    const TrajectoryData d = readJointLog(log.spec, lift6());
    const auto P = makeTrajectoryProblem(lift6(), d);
    const Eigen::MatrixXd r = P->measured - P->predict({});
    CHECK(r.col(0).mean() == Approx(-RobotLog::liftGravity()).epsilon(1e-3));
  }
}

TEST_CASE("measured-log channels are named by joint with N for the lift and N m elsewhere") {
  RobotLog log("channels", false, 0, 1000);
  const TrajectoryData d = readJointLog(log.spec, lift6());
  const auto P = makeTrajectoryProblem(lift6(), d);
  REQUIRE(P->channel_names.size() == 6);
  CHECK(P->channel_names[0] == "j1");
  CHECK(P->channel_names[3] == "j4");
  CHECK(P->channel_units[0] == "N");
  CHECK(P->channel_units[1] == "N m");
  CHECK(P->fit_unit.find('|') == std::string::npos);
}

TEST_CASE("time columns are checked file against file, or resampled when asked") {
  SECTION("efforts offset by 5 ms") {
    RobotLog log("offset", false, 0, 600);
    std::ifstream in(log.dir / "cur.csv");
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    in.close();
    std::ofstream out(log.dir / "cur.csv");
    out.precision(17);
    for (std::size_t i = 0; i < lines.size(); ++i)
      out << (i == 0 ? lines[i]
                     : std::to_string(1e-3 * double(i - 1) + 5e-3) +
                           lines[i].substr(lines[i].find(',')))
          << "\n";
    out.close();
    try {
      readJointLog(log.spec, lift6());
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK(e.file() == (log.dir / "cur.csv").string());
      CHECK(e.line() == 2);
      CHECK(e.key() == "t");
      CHECK_THAT(e.message(), Catch::Contains("offset by 0.005 s"));
    }
    log.spec.resample = true;  // interpolated onto the positions' times instead
    const TrajectoryData d = readJointLog(log.spec, lift6());
    CHECK(d.rows() >= 19);  // 0.2 s trimmed at each end of 0.6 s, every 10th row
  }
  SECTION("efforts at half the rate") {
    RobotLog log("rate", false, 0, 600);
    RobotLog slow("rate_slow", false, 0, 300, 2e-3);
    fs::copy_file(slow.dir / "cur.csv", log.dir / "cur.csv", fs::copy_options::overwrite_existing);
    try {
      readJointLog(log.spec, lift6());
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK(e.file() == (log.dir / "cur.csv").string());
      CHECK(e.key() == "t");
      CHECK_THAT(e.message(), Catch::Contains("rates differ"));
    }
    log.spec.resample = true;
    const TrajectoryData d = readJointLog(log.spec, lift6());
    double worst = 0;
    for (int k = 0; k < d.rows(); ++k) {
      const Eigen::VectorXd Q = rnea(lift6(), motionAt(lift6(), d.t[k]));
      worst = std::max(worst, std::abs(d.measured(k, 1) - Q[1]));
    }
    CHECK(worst < 0.05);  // linear interpolation at 2 ms of a < 1 Hz motion
  }
}

namespace {

// A study of the lift design on a RobotLog, with one text replacement; the run's exit code and
// output, and whether anything was written.
fs::path robotStudy(const RobotLog& log, const std::string& from, const std::string& to) {
  std::string text =
      "[study]\nname = \"robot\"\n\n[[design]]\nfile = \"" +
      test::sourcePath("designs/first_prototype_6dof.toml") +
      "\"\n\n[[calibration]]\nname = \"robot\"\nkind = \"trajectory\"\ndesign = "
      "\"first_prototype_6dof\"\n\n[calibration.measured]\n"
      "joints = [\"j1\", \"j2\", \"j3\", \"j4\", \"j5\", \"j6\"]\nside = \"joint\"\n"
      "time_column = \"t\"\n"
      "gravity_compensated = [\"j1\"]\n"
      "positions = { file = \"pos.csv\", columns = [\"p1\", \"p2\", \"p3\", \"p4\", \"p5\", "
      "\"p6\"], unit = \"rad\" }\n"
      "velocities = { file = \"vel.csv\", columns = [\"v1\", \"v2\", \"v3\", \"v4\", \"v5\", "
      "\"v6\"], unit = \"rad/s\" }\n"
      "efforts = { file = \"cur.csv\", columns = [\"i1\", \"i2\", \"i3\", \"i4\", \"i5\", \"i6\"], "
      "unit = \"A\", torque_constants = [0.12, -0.08, 0.11, -0.05, 0.09, -0.04], "
      "ratios = [20, 100, 120, -100, 80, 50] }\n"
      "filter = { cutoff = \"20 Hz\", decimate = 10, trim = \"0.2 s\" }\n";
  if (!from.empty()) {
    REQUIRE(text.find(from) != std::string::npos);
    text.replace(text.find(from), from.size(), to);
  }
  const fs::path p = log.dir / "study.toml";
  std::ofstream(p) << text;
  return p;
}

}  // namespace

TEST_CASE("a study reads current logs, logged velocities and a compensated lift") {
  RobotLog log("study_ok", true, 0, 1500);
  const fs::path p = robotStudy(log, "", "");
  std::string out;
  const int rc = test::runCommand(
      test::binaryPath() + " run " + p.string() + " --output " + (log.dir / "out").string(), out);
  INFO(out);
  REQUIRE(rc == 0);
  std::ifstream in(log.dir / "out" / "robot" / "calibration" / "report.md");
  std::stringstream report;
  report << in.rdbuf();
  // The report names the logged velocities' difference and the compensated lift; one unit per
  // channel kind, never "N m|N".
  CHECK_THAT(report.str(), Catch::Contains("logged velocities used") &&
                               Catch::Contains("j1: its controller compensates gravity"));
  CHECK(report.str().find("N m|N") == std::string::npos);
}

TEST_CASE("bad robot logs in a study exit 2 naming file, line and key and write nothing") {
  struct Case {
    std::string name, from, to, file, key;
    std::string line_of;  // the study line it names (empty: not checked)
  };
  const Case cases[] = {
      {"torque constant 0", "-0.05, 0.09", "0, 0.09", "study.toml",
       "calibration[0].measured.efforts.torque_constants", "efforts ="},
      {"unknown velocity column", "\"v3\", \"v4\"", "\"v3\", \"speed4\"", "vel.csv:1", "speed4",
       ""},
      {"joint listed twice", "gravity_compensated = [\"j1\"]",
       "gravity_compensated = [\"j1\", \"j1\"]", "study.toml",
       "calibration[0].measured.gravity_compensated", "gravity_compensated ="},
      {"joint named twice in joints", "\"j3\", \"j4\"", "\"j3\", \"j3\"", "study.toml",
       "calibration[0].measured.joints", ""},
      {"unknown velocity unit", "unit = \"rad/s\"", "unit = \"rpm\"", "study.toml",
       "calibration[0].measured.velocities.unit", "velocities ="},
  };
  for (const Case& c : cases) {
    DYNAMIC_SECTION(c.name) {
      RobotLog log("bad", true, 0, 600);
      const fs::path p = robotStudy(log, c.from, c.to);
      std::string out;
      CHECK(test::runCommand(test::binaryPath() + " run " + p.string() + " --output " +
                                 (log.dir / "out").string(),
                             out) == 2);
      INFO(out);
      CHECK_THAT(out, Catch::Contains(c.file) && Catch::Contains(c.key));
      if (!c.line_of.empty()) {
        std::ifstream in(p);
        int k = 0, line = 0;
        for (std::string l; std::getline(in, l) && !line;)
          if (++k, l.find(c.line_of) == 0) line = k;
        CHECK_THAT(out, Catch::Contains(c.file + ":" + std::to_string(line)));
      }
      CHECK(!fs::exists(log.dir / "out"));
    }
  }
  SECTION("an effort file whose time column is offset by 5 ms, or at half the rate") {
    for (const bool offset : {true, false}) {
      RobotLog log(offset ? "time_offset" : "time_rate", true, 0, 600);
      if (offset) {  // every row's time 5 ms late
        std::ifstream in(log.dir / "cur.csv");
        std::vector<std::string> lines;
        for (std::string l; std::getline(in, l);) lines.push_back(l);
        in.close();
        std::ofstream o(log.dir / "cur.csv");
        for (std::size_t i = 0; i < lines.size(); ++i)
          o << (i == 0 ? lines[i]
                       : std::to_string(1e-3 * double(i - 1) + 5e-3) +
                             lines[i].substr(lines[i].find(',')))
            << "\n";
      } else {
        RobotLog slow("time_rate_slow", true, 0, 600, 2e-3);
        fs::copy_file(slow.dir / "cur.csv", log.dir / "cur.csv",
                      fs::copy_options::overwrite_existing);
      }
      const fs::path p = robotStudy(log, "", "");
      std::string out;
      CHECK(test::runCommand(test::binaryPath() + " run " + p.string() + " --output " +
                                 (log.dir / "out").string(),
                             out) == 2);
      INFO(out);
      CHECK_THAT(out, Catch::Contains((log.dir / "cur.csv").string() + (offset ? ":2" : ":3")) &&
                          Catch::Contains(offset ? "offset by 0.005 s" : "rates differ") &&
                          Catch::Contains("key 't'"));
      CHECK(!fs::exists(log.dir / "out"));
    }
  }
  SECTION("an effort file whose time column has a 1 s gap, padded back to the same length") {
    RobotLog log("gap", false, 0, 3000);
    std::ifstream in(log.dir / "cur.csv");
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    in.close();
    std::ofstream o(log.dir / "cur.csv");
    o.precision(17);
    for (std::size_t i = 0; i < lines.size(); ++i)
      o << (i == 0
                ? lines[i]
                : std::to_string(1e-3 * double(i - 1) + (i > 1000 ? 1.0 : 0.0)) +  // from line 1002
                      lines[i].substr(lines[i].find(',')))
        << "\n";
    o.close();
    const fs::path p = robotStudy(log, "", "");
    std::string out;
    CHECK(test::runCommand(
              test::binaryPath() + " run " + p.string() + " --output " + (log.dir / "out").string(),
              out) == 2);
    INFO(out);
    CHECK_THAT(out, Catch::Contains("cur.csv:1002") && Catch::Contains("samples are missing"));
    CHECK(!fs::exists(log.dir / "out"));
  }
}
