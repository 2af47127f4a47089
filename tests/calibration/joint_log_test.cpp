// Measured joint logs (docs/calibration.md, "Bring your own robot's logs"): the zero-phase filter's
// gain and delay against the Butterworth closed form, the motor-to-joint conversion against a hand
// computation, a synthetic arm with planted joint friction through the whole path (files, coupling,
// filter, fit), and every kind of bad input named by file, line and column.
#include "calibration/joint_log.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "calibration/arm_calibration.hpp"
#include "calibration/calibration_run.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"
#include "dynamics/dynamics.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::calibration;
namespace fs = std::filesystem;

namespace {

// Amplitude and phase of a sine of frequency f fitted to y over the samples [a, b).
void sineFit(const std::vector<double>& y, double h, double f, int a, int b, double& amp,
             double& phase) {
  Eigen::MatrixXd A(b - a, 2);
  Eigen::VectorXd r(b - a);
  for (int i = a; i < b; ++i) {
    A(i - a, 0) = std::sin(2 * M_PI * f * i * h);
    A(i - a, 1) = std::cos(2 * M_PI * f * i * h);
    r[i - a] = y[i];
  }
  const Eigen::Vector2d c = A.colPivHouseholderQr().solve(r);
  amp = c.norm();
  phase = std::atan2(c[1], c[0]);
}

// |H(f)|^2 of the digital (bilinear, prewarped) Butterworth low-pass of order N, squared again by
// the forward-backward pass: 1 / (1 + (tan(pi f h) / tan(pi fc h))^(2N)).
double forwardBackwardGain(double f, double fc, double h, int N) {
  return 1.0 / (1.0 + std::pow(std::tan(M_PI * f * h) / std::tan(M_PI * fc * h), 2 * N));
}

fs::path tmp(const std::string& name) { return test::emptyTempDir("jointlog_" + name); }

void writeText(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::string csv(const std::vector<std::string>& head, const Eigen::MatrixXd& m) {
  std::ostringstream s;
  s.precision(17);
  for (std::size_t c = 0; c < head.size(); ++c) s << (c ? "," : "") << head[c];
  s << "\n";
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) s << (c ? "," : "") << m(i, c);
    s << "\n";
  }
  return s.str();
}

const Model& design6() {
  static const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  return m;
}

// A coupling like a wrist: diagonal ratios, motor 6 also turned by joint 5.
Eigen::MatrixXd wristCoupling() {
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(6, 6);
  const double r[] = {30, 30, 40, -50, 40, 25};
  for (int i = 0; i < 6; ++i) R(i, i) = r[i];
  R(5, 4) = 25;
  return R;
}

// Log files of a smooth joint motion at rate 1/h: motor-side positions R q and motor torques
// R^-T tau, with tau = RNEA + planted friction (pure sign for Coulomb) + offset.
struct Planted {
  double coulomb[6] = {3.0, 4.0, 2.0, 1.0, 0.8, 0.5};
  double viscous[6] = {6.0, 5.0, 2.0, 1.0, 0.7, 0.4};
  double offset[6] = {0.3, -0.6, 0.2, 0.1, -0.1, 0.05};
};

JointLogSpec writeSyntheticLogs(const fs::path& dir, const Planted& pl, double h, int rows) {
  const Model& m = design6();
  const Eigen::MatrixXd R = wristCoupling();
  RigidBodyModel rbm = makeRigidBodyModel(m);
  DynamicsWorkspace ws(rbm);
  Eigen::MatrixXd pos(rows, 6), eff(rows, 6);
  Eigen::VectorXd q(6), qd(6), qdd(6), Q(6);
  for (int i = 0; i < rows; ++i) {
    const double t = i * h;
    for (int j = 0; j < 6; ++j) {
      const JointLimits& l = m.joints[j].limits;
      const double c = 0.5 * (l.q_min + l.q_max), a = std::min(0.6, 0.3 * (l.q_max - l.q_min));
      const double w1 = 2 * M_PI * (0.3 + 0.07 * j), w2 = 2 * M_PI * (0.71 + 0.05 * j);
      q[j] = c + a * (0.7 * std::sin(w1 * t + j) + 0.3 * std::sin(w2 * t + 2 * j));
      qd[j] = a * (0.7 * w1 * std::cos(w1 * t + j) + 0.3 * w2 * std::cos(w2 * t + 2 * j));
      qdd[j] =
          -a * (0.7 * w1 * w1 * std::sin(w1 * t + j) + 0.3 * w2 * w2 * std::sin(w2 * t + 2 * j));
    }
    inverseDynamics(rbm, ws, q, qd, qdd, Q);
    for (int j = 0; j < 6; ++j)
      Q[j] += pl.coulomb[j] * (qd[j] > 0 ? 1 : -1) + pl.viscous[j] * qd[j] + pl.offset[j];
    pos.row(i) = (R * q).transpose();
    eff.row(i) = R.transpose().fullPivLu().solve(Q).transpose();
  }
  writeText(dir / "pos.csv", csv({"m1", "m2", "m3", "m4", "m5", "m6"}, pos));
  writeText(dir / "eff.csv", csv({"e1", "e2", "e3", "e4", "e5", "e6"}, eff));
  JointLogSpec s;
  s.study_file = (dir / "study.toml").string();
  s.study_line = 7;
  for (const auto& j : m.joints) s.joints.push_back(j.name);
  s.positions = {(dir / "pos.csv").string(), {"m1", "m2", "m3", "m4", "m5", "m6"}, 1.0, {}};
  s.efforts = {(dir / "eff.csv").string(), {"e1", "e2", "e3", "e4", "e5", "e6"}, 1.0, {}};
  s.sample_period_s = h;
  s.motor_side = true;
  s.coupling = R;
  s.offsets = Eigen::VectorXd::Zero(6);
  s.cutoff_Hz = 20;
  s.decimate = 5;
  s.trim_s = 0.2;
  return s;
}

}  // namespace

TEST_CASE("the zero-phase low-pass has the Butterworth gain and no delay") {
  const double h = 1e-3, fc = 50;
  const int n = 4000, order = 2;
  for (double f : {5.0, 20.0, 50.0, 120.0}) {
    std::vector<double> x(n);
    for (int i = 0; i < n; ++i) x[i] = std::sin(2 * M_PI * f * i * h + 0.3);
    const std::vector<double> y = zeroPhaseLowPass(x, h, fc, order);
    double ax, px, ay, py;
    sineFit(x, h, f, 500, 3500, ax, px);
    sineFit(y, h, f, 500, 3500, ay, py);
    INFO("f = " << f << " Hz");
    CHECK(ay / ax == Approx(forwardBackwardGain(f, fc, h, order)).epsilon(1e-3));
    CHECK(std::abs(py - px) < 1e-4);  // rad: no delay
  }
  // At the cut-off the forward-backward gain is exactly 1/2.
  CHECK(forwardBackwardGain(fc, fc, h, order) == Approx(0.5));
}

TEST_CASE("central differences of a filtered sine give its derivatives") {
  const double h = 2e-4, f = 1.5;
  const int n = 20000;
  std::vector<double> x(n);
  for (int i = 0; i < n; ++i) x[i] = std::sin(2 * M_PI * f * i * h);
  const auto v = centralDifference(zeroPhaseLowPass(x, h, 100, 2), h);
  const auto a = centralDifference(v, h);
  const double w = 2 * M_PI * f;
  for (int i : {5000, 10000, 15000}) {
    CHECK(v[i] == Approx(w * std::cos(w * i * h)).margin(1e-4 * w));
    CHECK(a[i] == Approx(-w * w * std::sin(w * i * h)).margin(1e-3 * w * w));
  }
}

TEST_CASE("motor side to joint side: ratios and a coupled wrist by hand") {
  // theta_m = R q with R = diag(32, 32, 45, -48, 45, 32) and R(6,5) = 32; tau = R^T tau_m.
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(6, 6);
  const double r[] = {32, 32, 45, -48, 45, 32};
  for (int i = 0; i < 6; ++i) R(i, i) = r[i];
  R(5, 4) = 32;
  Eigen::VectorXd th(6), tm(6), q, tau;
  th << 3.2, -6.4, 9.0, 4.8, 22.5, 48.0;
  tm << 0.5, 1.0, -0.2, 0.1, 0.3, -0.4;
  motorToJoint(R, th, tm, q, tau);
  // By hand: q_i = theta_i / r_i, except q6 = theta6 / 32 - q5 = 1.5 - 0.5 = 1.0.
  const double q_hand[] = {0.1, -0.2, 0.2, -0.1, 0.5, 1.0};
  // tau_i = r_i tau_m,i, except tau5 = 45 * 0.3 + 32 * (-0.4) = 0.7.
  const double tau_hand[] = {16.0, 32.0, -9.0, -4.8, 0.7, -12.8};
  for (int i = 0; i < 6; ++i) {
    CHECK(q[i] == Approx(q_hand[i]).margin(1e-12));
    CHECK(tau[i] == Approx(tau_hand[i]).margin(1e-12));
  }
}

TEST_CASE("a synthetic arm with planted joint friction through the log path recovers it") {
  const fs::path dir = tmp("planted");
  const Planted pl;
  const JointLogSpec s = writeSyntheticLogs(dir, pl, 1e-3, 12000);
  const TrajectoryData d = readJointLog(s, design6());
  const auto P = makeTrajectoryProblem(design6(), d);
  EffectValues start;
  for (const auto& j : design6().joints)
    for (const char* k : {"coulomb", "viscous", "offset"}) {
      EffectValue v;
      v.effect = P->findEffect(j.name + "." + k);
      REQUIRE(v.effect >= 0);
      v.x = Eigen::VectorXd::Zero(1);
      start.push_back(v);
    }
  const SetFit fit = fitEffects(*P, start);
  for (const EffectValue& v : fit.values) {
    const ArmEffect& e = P->catalogue[v.effect];
    const int j = design6().jointIndex(e.joint);
    const double planted = e.effect == "coulomb"   ? pl.coulomb[j]
                           : e.effect == "viscous" ? pl.viscous[j]
                                                   : pl.offset[j];
    INFO(e.name);
    // The smooth sign (1 % of the peak speed) against the planted pure sign: within 3 %.
    CHECK(v.x[0] == Approx(planted).epsilon(0.03).margin(0.02));
  }
  // The ranking names friction first on a joint whose friction dominates the residual.
  ArmFitOptions o;
  const ArmDiagnosis diag = diagnoseArm(*P, o);
  REQUIRE(!diag.ranking.empty());
  const std::string first = diag.ranking.front().name;
  CHECK(
      (first.find(".coulomb") != std::string::npos || first.find(".viscous") != std::string::npos));
}

namespace {

// A small log of the 6-DoF design (joint side, identity coupling) and the InputError it gives.
struct BadLog {
  fs::path dir;
  JointLogSpec spec;
  explicit BadLog(const std::string& name) : dir(tmp(name)) {
    spec = writeSyntheticLogs(dir, Planted{}, 1e-3, 400);
    spec.cutoff_Hz = 50;
    spec.decimate = 1;
    spec.trim_s = 0;
  }
  // Replaces line `line` (1-based) of a file.
  void setLine(const std::string& file, int line, const std::string& text) {
    std::ifstream in(dir / file);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    lines[line - 1] = text;
    std::ofstream out(dir / file);
    for (const auto& l : lines) out << l << "\n";
  }
  InputError error() {
    try {
      readJointLog(spec, design6());
    } catch (const InputError& e) {
      return e;
    }
    FAIL("no InputError");
    return InputError("", 0, "", "");
  }
};

}  // namespace

TEST_CASE("bad joint logs are named by file line and column") {
  SECTION("files of different lengths") {
    BadLog b("lengths");
    std::ifstream in(b.dir / "eff.csv");
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    lines.pop_back();
    std::ofstream out(b.dir / "eff.csv");
    for (const auto& l : lines) out << l << "\n";
    out.close();
    const InputError e = b.error();
    CHECK(e.file() == (b.dir / "eff.csv").string());
    CHECK(e.line() == 401);  // the first missing row: header + 399 rows
    CHECK(e.key() == "e1");
    CHECK_THAT(e.message(), Catch::Contains("400 rows"));
  }
  SECTION("time going backwards") {
    BadLog b("time");
    std::ifstream in(b.dir / "pos.csv");
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    std::ofstream out(b.dir / "pos.csv");
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const double t =
          i == 0 ? 0 : (i == 100 ? 0.05 : 1e-3 * (i - 1));  // row of line 101 goes back
      out << lines[i] << (i == 0 ? std::string(",t") : "," + std::to_string(t)) << "\n";
    }
    out.close();
    b.spec.time_column = "t";
    const InputError e = b.error();
    CHECK(e.file() == (b.dir / "pos.csv").string());
    CHECK(e.line() == 101);
    CHECK(e.key() == "t");
  }
  SECTION("a gap in the time column") {
    BadLog b("gap");
    std::ifstream in(b.dir / "pos.csv");
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    std::ofstream out(b.dir / "pos.csv");
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const double t = 1e-3 * (static_cast<double>(i) - 1) +
                       (i >= 200 ? 0.01 : 0.0);  // 10 ms missing before line 201
      out << lines[i] << (i == 0 ? std::string(",t") : "," + std::to_string(t)) << "\n";
    }
    out.close();
    b.spec.time_column = "t";
    const InputError e = b.error();
    CHECK(e.file() == (b.dir / "pos.csv").string());
    CHECK(e.line() == 201);
    CHECK(e.key() == "t");
    CHECK_THAT(e.message(), Catch::Contains("samples are missing"));
  }
  SECTION("a NaN cell") {
    BadLog b("nan");
    b.setLine("eff.csv", 50, "1,2,nan,4,5,6");
    const InputError e = b.error();
    CHECK(e.file() == (b.dir / "eff.csv").string());
    CHECK(e.line() == 50);
    CHECK(e.key() == "e3");
  }
  SECTION("an empty row") {
    BadLog b("empty");
    b.setLine("pos.csv", 60, "");
    const InputError e = b.error();
    CHECK(e.file() == (b.dir / "pos.csv").string());
    CHECK(e.line() == 60);
    CHECK(e.key() == "m1");
  }
  SECTION("a row of empty cells") {
    BadLog b("emptycells");
    b.setLine("pos.csv", 70, ",,,,,");
    const InputError e = b.error();
    CHECK(e.file() == (b.dir / "pos.csv").string());
    CHECK(e.line() == 70);
    CHECK(e.key() == "m1");
  }
  SECTION("a singular coupling matrix") {
    BadLog b("singular");
    b.spec.coupling(5, 5) = 0;
    b.spec.coupling(5, 4) = 0;
    const InputError e = b.error();
    CHECK(e.file() == b.spec.study_file);
    CHECK(e.line() == 7);
    CHECK(e.key() == "coupling");
    CHECK_THAT(e.message(), Catch::Contains("singular"));
  }
  SECTION("an unknown joint name") {
    BadLog b("joint");
    b.spec.joints[2] = "elbow";
    const InputError e = b.error();
    CHECK(e.file() == b.spec.study_file);
    CHECK(e.key() == "joints");
    CHECK_THAT(e.message(), Catch::Contains("no joint 'elbow'"));
  }
  SECTION("an unknown column") {
    BadLog b("column");
    b.spec.efforts.columns[1] = "E2";
    const InputError e = b.error();
    CHECK(e.file() == (b.dir / "eff.csv").string());
    CHECK(e.line() == 1);
    CHECK_THAT(e.message(), Catch::Contains("E2"));
  }
}

namespace {

// A study with a [calibration.measured] section on the synthetic logs; `edit` replaces text.
fs::path measuredStudy(const fs::path& dir, const std::string& from, const std::string& to) {
  std::string text =
      "[study]\nname = \"logs\"\n\n[[design]]\nfile = \"" +
      test::sourcePath("designs/first_prototype_6dof.toml") +
      "\"\n\n[[calibration]]\nname = \"logs\"\nkind = \"trajectory\"\ndesign = "
      "\"first_prototype_6dof\"\n\n"
      "[calibration.measured]\njoints = [\"j1\", \"j2\", \"j3\", \"j4\", \"j5\", \"j6\"]\nside = "
      "\"motor\"\n"
      "sample_period = \"1 ms\"\nratios = [30, 30, 40, -50, 40, 25]\n"
      "coupling = [{ motor = \"j6\", joint = \"j5\", ratio = 25 }]\n"
      "positions = { file = \"pos.csv\", columns = [1, 2, 3, 4, 5, 6], unit = \"rad\" }\n"
      "efforts = { file = \"eff.csv\", columns = [\"e1\", \"e2\", \"e3\", \"e4\", \"e5\", \"e6\"], "
      "unit = \"N m\" }\n"
      "filter = { cutoff = \"50 Hz\" }\n";
  if (!from.empty()) {
    REQUIRE(text.find(from) != std::string::npos);
    text.replace(text.find(from), from.size(), to);
  }
  const fs::path p = dir / "study.toml";
  writeText(p, text);
  return p;
}

int lineInFile(const fs::path& p, const std::string& needle) {
  std::ifstream in(p);
  int k = 0;
  for (std::string l; std::getline(in, l);) {
    ++k;
    if (l.find(needle) != std::string::npos) return k;
  }
  return -1;
}

}  // namespace

TEST_CASE("a study measured-log section takes columns by name or number and names bad settings") {
  const fs::path dir = tmp("study");
  writeSyntheticLogs(dir, Planted{}, 1e-3, 400);
  REQUIRE(design6().joints[0].name == "j1");
  REQUIRE_NOTHROW(loadStudy(measuredStudy(dir, "", "").string()));
  struct Case {
    std::string from, to, key, line_of;
  };
  const Case cases[] = {
      {", unit = \"N m\"", "", "calibration[0].measured.efforts.unit", "efforts ="},
      {"ratios = [30, 30, 40, -50, 40, 25]", "ratios = [30, 30, 40, -50, 40, 0]",
       "calibration[0].measured.coupling", "[calibration.measured]"},
      {"\"j3\", \"j4\"", "\"elbow\", \"j4\"", "calibration[0].measured.joints",
       "[calibration.measured]"},
      {"sample_period = \"1 ms\"", "sample_period = \"1\"", "calibration[0].measured.sample_period",
       "sample_period"},
  };
  for (const Case& c : cases) {
    const fs::path p = measuredStudy(dir, c.from, c.to);
    INFO(c.to);
    try {
      (void)loadStudy(p.string());
      FAIL("no InputError");
    } catch (const InputError& e) {
      INFO(e.what());
      CHECK(e.file() == p.string());
      CHECK(e.key() == c.key);
      CHECK(e.line() == lineInFile(p, c.line_of));
    }
  }
  // Through the CLI: exit code 2, the file and key named, no output folder.
  const fs::path p = measuredStudy(dir, ", unit = \"N m\"", "");
  std::string out;
  CHECK(test::runCommand(
            test::binaryPath() + " run " + p.string() + " --output " + (dir / "out").string(),
            out) == 2);
  CHECK_THAT(out, Catch::Contains("unit"));
  CHECK(!fs::exists(dir / "out"));
  // A bad log cell: exit 2 naming the log file and its line, no output folder.
  {
    std::ifstream in(dir / "eff.csv");
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    lines[41] = "1,2,3,nan,5,6";
    std::ofstream o(dir / "eff.csv");
    for (const auto& l : lines) o << l << "\n";
  }
  const fs::path good = measuredStudy(dir, "", "");
  CHECK(test::runCommand(
            test::binaryPath() + " run " + good.string() + " --output " + (dir / "out").string(),
            out) == 2);
  CHECK_THAT(out, Catch::Contains("eff.csv") && Catch::Contains("42") && Catch::Contains("e4"));
  CHECK(!fs::exists(dir / "out"));
}

TEST_CASE("one operating point repeated is not identifiable and gets no calibrated design") {
  const fs::path dir = tmp("onepoint");
  const std::string bed =
      readFileOrThrow(test::sourcePath("studies/data/drive_testbed_module_b2.csv"));
  const std::string header = bed.substr(0, bed.find('\n') + 1);
  const std::size_t second = bed.find('\n', header.size());
  const std::string row = bed.substr(header.size(), second - header.size() + 1);
  std::string text = header;
  for (int i = 0; i < 12; ++i) text += row;
  writeText(dir / "same.csv", text);
  std::string out;
  const int rc = test::runCommand(test::binaryPath() + " fit " +
                                      test::sourcePath("designs/final_prototype_9dof.toml") +
                                      " --drive j6 --auto --data " + (dir / "same.csv").string() +
                                      " --out " + (dir / "out").string(),
                                  out);
  INFO(out);
  CHECK(rc == 0);
  CHECK_THAT(out, Catch::Contains("not identifiable: all 12 rows are the same operating point"));
  CHECK_THAT(out, Catch::Contains("calibrated design: none"));
  CHECK_THAT(out, !Catch::Contains("lower)"));  // no "x inf lower"
  CHECK(fs::exists(dir / "out" / "result.json"));
  CHECK(!fs::exists(dir / "out" / "final_prototype_9dof_calibrated.toml"));
}

TEST_CASE("a joint that never moves in a log is not identifiable and gets no calibrated design") {
  const fs::path dir = tmp("still");
  JointLogSpec s = writeSyntheticLogs(dir, Planted{}, 1e-3, 3000);
  // Joint j4 held at zero: its motor column constant.
  std::ifstream in(dir / "pos.csv");
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::ofstream o(dir / "pos.csv");
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::vector<std::string> cells;
    std::stringstream ss(lines[i]);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (i > 0) cells[3] = "0";
    for (std::size_t c = 0; c < cells.size(); ++c) o << (c ? "," : "") << cells[c];
    o << "\n";
  }
  o.close();
  const TrajectoryData d = readJointLog(s, design6());
  const auto P = makeTrajectoryProblem(design6(), d);
  ArmFitOptions opt;
  opt.auto_add = true;
  const ArmDiagnosis diag = diagnoseArm(*P, opt);
  CHECK_THAT(diag.identifiable, Catch::Contains("joint j4 never moves"));
  CHECK_THAT(diag.verdict, Catch::StartsWith("not identifiable"));
  CHECK(diag.added.empty());
  const ArmFitFiles f = writeArmFit(diag, *P, design6(), (dir / "out").string(), "", true);
  CHECK(f.calibrated_design_path.empty());
  CHECK(!fs::exists(dir / "out" / "first_prototype_6dof_calibrated.toml"));
}

TEST_CASE("a time column with controller jitter is read with the actual times and a warning") {
  const fs::path dir = tmp("jitter");
  JointLogSpec s = writeSyntheticLogs(dir, Planted{}, 1e-3, 4000);
  std::ifstream in(dir / "pos.csv");
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::ofstream out(dir / "pos.csv");
  out.precision(17);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    // Samples taken at their nominal instants, stamped with +-5 % jitter of the 1 ms period.
    const double t = 1e-3 * (static_cast<double>(i) - 1) + (i % 2 ? 5e-5 : -5e-5);
    out << lines[i];
    if (i == 0)
      out << ",t";
    else
      out << "," << t;
    out << "\n";
  }
  out.close();
  s.time_column = "t";
  const TrajectoryData d = readJointLog(s, design6());
  bool warned = false;
  for (const auto& w : d.warnings)
    warned = warned || w.find("time steps vary") != std::string::npos;
  CHECK(warned);
  CHECK(d.rows() > 100);
}

namespace {

// Keeps the header and the first `rows` rows of a log file.
void keepRows(const fs::path& p, int rows) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  in.close();
  std::ofstream out(p);
  for (int i = 0; i <= rows && i < static_cast<int>(lines.size()); ++i) out << lines[i] << "\n";
}

// Adds a time column `t` (the row index times h) to the positions file.
void addTimeColumn(const fs::path& p, double h) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  in.close();
  std::ofstream out(p);
  out.precision(17);
  for (std::size_t i = 0; i < lines.size(); ++i)
    out << lines[i] << "," << (i == 0 ? std::string("t") : formatG(h * double(i - 1), 17)) << "\n";
}

}  // namespace

TEST_CASE("counts a joint log's settings imply are checked before any index is formed") {
  SECTION("one row with a time column") {
    BadLog b("onerow");
    addTimeColumn(b.dir / "pos.csv", 1e-3);
    keepRows(b.dir / "pos.csv", 1);
    keepRows(b.dir / "eff.csv", 1);
    b.spec.time_column = "t";
    const InputError e = b.error();
    CHECK(e.file() == (b.dir / "pos.csv").string());
    CHECK(e.line() == 2);
    CHECK(e.key() == "t");
    CHECK_THAT(e.message(), Catch::Contains("1 row") && Catch::Contains("at least 3"));
  }
  SECTION("two rows without a time column") {
    BadLog b("tworows");
    keepRows(b.dir / "pos.csv", 2);
    keepRows(b.dir / "eff.csv", 2);
    const InputError e = b.error();
    CHECK(e.file() == (b.dir / "pos.csv").string());
    CHECK(e.key() == "m1");
    CHECK_THAT(e.message(), Catch::Contains("2 rows"));
  }
  // 400 rows at 1 ms; trims whose sample count overflows an int (430,000 s at 0.2 ms is 2.15e9
  // samples) or any integer.
  for (const double trim : {0.2, 430000.0, 1e300}) {
    DYNAMIC_SECTION("a trim of " << trim << " s") {
      BadLog b("trim");
      b.spec.trim_s = trim;
      if (trim == 430000.0) {
        b.spec.sample_period_s = 2e-4;
        b.spec.cutoff_Hz = 100;
      }
      const InputError e = b.error();
      CHECK(e.file() == b.spec.study_file);
      CHECK(e.line() == 7);
      CHECK(e.key() == "filter.trim");
      CHECK_THAT(e.message(), Catch::Contains("samples at each end"));
    }
  }
  SECTION("a sample period of 1e-12 s with a trim of 0.1 s (1e11 samples)") {
    BadLog b("period");
    b.spec.sample_period_s = 1e-12;
    b.spec.trim_s = 0.1;
    const InputError e = b.error();
    CHECK(e.file() == b.spec.study_file);
    CHECK(e.key() == "sample_period");
    CHECK_THAT(e.message(), Catch::Contains("not plausible"));
  }
  SECTION("a time column stepping 1e-12 s") {
    BadLog b("timestep");
    addTimeColumn(b.dir / "pos.csv", 1e-12);
    b.spec.time_column = "t";
    b.spec.trim_s = 0.1;
    const InputError e = b.error();
    CHECK(e.file() == (b.dir / "pos.csv").string());
    CHECK(e.key() == "t");
    CHECK_THAT(e.message(), Catch::Contains("not plausible"));
  }
  SECTION("the filter's start-up length for a cut-off far below the sample rate") {
    // 3 x order x 1 / (fc h) = 3e9 samples of padding, more than an int holds: the whole log
    // pads instead.
    const std::vector<double> x = {1, 2, 3, 4, 5};
    const std::vector<double> y = zeroPhaseLowPass(x, 1e-6, 2e-3, 2);
    REQUIRE(y.size() == x.size());
    for (double v : y) CHECK(std::isfinite(v));
  }
}

TEST_CASE("a study's trim that leaves no sample is exit 2 naming the key, nothing written") {
  const fs::path dir = tmp("studytrim");
  writeSyntheticLogs(dir, Planted{}, 1e-3, 400);
  const fs::path p = measuredStudy(dir, "filter = { cutoff = \"50 Hz\" }",
                                   "filter = { cutoff = \"50 Hz\", trim = \"1e300 s\" }");
  std::string out;
  CHECK(test::runCommand(
            test::binaryPath() + " run " + p.string() + " --output " + (dir / "out").string(),
            out) == 2);
  INFO(out);
  CHECK_THAT(
      out, Catch::Contains("study.toml") && Catch::Contains("calibration[0].measured.filter.trim"));
  CHECK(!fs::exists(dir / "out"));
}
