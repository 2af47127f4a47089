// A synthetic arm through the study path a user takes for a real one (docs/calibration.md, "Bring
// your own robot's logs"): tests/calibration/urdf/lift_arm.urdf, a gravity-compensated prismatic
// torso lift and five revolute joints, a 1 kg tool fixed beyond the tip and a 1.5 kg head on a
// branch off the torso. Its logs are made here, seeded: joint torques from orocos-kdl's tree
// inverse dynamics on kdl_parser's reading of the URDF (never armstudy's own dynamics or lumping),
// plus planted joint friction, written as motor currents with torque constants of both signs, the
// two wrist channels quantised at 0.02 N m as a logger writes them, positions and velocities in
// their own files. `armstudy run` on a study written as the docs say must recover the friction
// where the data identify it and say "not identifiable" where they do not.
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "report/html_report.hpp"
#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr int kJoints = 6;
const char* const kNames[kJoints] = {"torso_lift_joint", "arm_1_joint", "arm_2_joint",
                                     "arm_3_joint",      "arm_4_joint", "arm_5_joint"};
constexpr double kHeadHeld = 0.2;  // head_joint: q = 0 clamped into its limits [0.2, 1]
constexpr double kGravity = 9.81;
constexpr double kRate_Hz = 200;
constexpr double kDuration_s = 20;
constexpr std::uint64_t kSeed = 46;
// Signed torque constants [N m/A; N/A for the lift] and reduction ratios [rad/rad; rad/m].
constexpr double kLiftArmKt[kJoints] = {0.136, -0.136, 0.102, -0.102, 0.05, -0.05};
constexpr double kLiftArmRatio[kJoints] = {1570, 100, 100, 100, 100, 100};
// Planted joint friction: Coulomb [N m | N] and viscous [N m s/rad | N s/m]. The wrist's (arm_4,
// arm_5) lie below its logging resolution.
constexpr double kCoulomb[kJoints] = {30, 1.5, 2.0, 0.8, 0, 0};
constexpr double kViscous[kJoints] = {200, 2.0, 1.5, 0.6, 0.004, 0.004};
constexpr double kLiftArmNoise[kJoints] = {1.0,  0.03,  0.03,
                                           0.03, 0.003, 0.003};  // N | N m, Gaussian
constexpr double kStep_Nm = 0.02;  // the wrist channels' logging resolution (joint side)
constexpr bool kQuantised[kJoints] = {false, false, false, false, true, true};
// Tolerances of the fitted friction against the planted (issue text: viscous 15 %, Coulomb 20 %).
constexpr double kViscousTolerance = 0.15;
constexpr double kCoulombTolerance = 0.20;

std::string urdfPath() { return test::sourcePath("tests/calibration/urdf/lift_arm.urdf"); }

// The motion: two sines per joint inside the joint's limits, with exact derivatives.
struct LiftArmMotion {
  double q[kJoints], qd[kJoints], qdd[kJoints];
};
LiftArmMotion liftArmMotionAt(double t) {
  const double lo[kJoints] = {0, -2.5, -1.5, -2, -2.5, -1.8},
               hi[kJoints] = {0.4, 2.5, 1.5, 2, 2.5, 1.8};
  LiftArmMotion s{};
  for (int j = 0; j < kJoints; ++j) {
    const double c = 0.5 * (lo[j] + hi[j]), a = std::min(0.8, 0.3 * (hi[j] - lo[j]));
    const double w1 = 2 * M_PI * (0.23 + 0.06 * j), w2 = 2 * M_PI * (0.61 + 0.05 * j);
    s.q[j] = c + a * (0.7 * std::sin(w1 * t + j) + 0.3 * std::sin(w2 * t + 2 * j));
    s.qd[j] = a * (0.7 * w1 * std::cos(w1 * t + j) + 0.3 * w2 * std::cos(w2 * t + 2 * j));
    s.qdd[j] =
        -a * (0.7 * w1 * w1 * std::sin(w1 * t + j) + 0.3 * w2 * w2 * std::sin(w2 * t + 2 * j));
  }
  return s;
}

// Joint torques of the whole tree (tool, head) by KDL, the lift's gravity force left out (its
// controller compensates it), planted friction added.
class TreeTorques {
 public:
  TreeTorques() {
    REQUIRE(kdl_parser::treeFromFile(urdfPath(), tree_));
    for (const auto& [name, e] : tree_.getSegments()) {
      const KDL::Joint& j = GetTreeElementSegment(e).getJoint();
      if (j.getType() != KDL::Joint::None) qnr_[j.getName()] = GetTreeElementQNr(e);
    }
    REQUIRE(qnr_.size() == kJoints + 1);  // the chain and the head
  }
  std::vector<double> at(const LiftArmMotion& s) {
    KDL::TreeIdSolver_RNE id(tree_, KDL::Vector(0, 0, -kGravity));
    const unsigned n = tree_.getNrOfJoints();
    KDL::JntArray q(n), qd(n), qdd(n), tau(n), zero(n), tau_g(n);
    for (int j = 0; j < kJoints; ++j) {
      const unsigned at = qnr_.at(kNames[j]);
      q(at) = s.q[j], qd(at) = s.qd[j], qdd(at) = s.qdd[j];
    }
    q(qnr_.at("head_joint")) = kHeadHeld;
    REQUIRE(id.CartToJnt(q, qd, qdd, KDL::WrenchMap(), tau) >= 0);
    REQUIRE(id.CartToJnt(q, zero, zero, KDL::WrenchMap(), tau_g) >= 0);
    std::vector<double> out(kJoints);
    for (int j = 0; j < kJoints; ++j) {
      const unsigned at = qnr_.at(kNames[j]);
      out[j] = tau(at) - (j == 0 ? tau_g(at) : 0.0) + kViscous[j] * s.qd[j] +
               kCoulomb[j] * (s.qd[j] > 0 ? 1.0 : -1.0);
    }
    return out;
  }

 private:
  KDL::Tree tree_;
  std::map<std::string, unsigned> qnr_;
};

// Writes pos.csv (t, positions), vel.csv (t, velocities) and cur.csv (t, motor currents
// i = tau / (ratio kt), the wrist's on a grid of kStep_Nm / |ratio kt|) into dir.
void writeLogs(const fs::path& dir) {
  TreeTorques torques;
  std::mt19937_64 rng(kSeed);
  std::normal_distribution<double> normal(0, 1);
  std::ofstream pos(dir / "pos.csv"), vel(dir / "vel.csv"), cur(dir / "cur.csv");
  for (std::ofstream* f : {&pos, &vel, &cur}) f->precision(17);
  pos << "t,p1,p2,p3,p4,p5,p6\n";
  vel << "t,v1,v2,v3,v4,v5,v6\n";
  cur << "t,i1,i2,i3,i4,i5,i6\n";
  const int rows = static_cast<int>(kDuration_s * kRate_Hz);
  for (int k = 0; k < rows; ++k) {
    const double t = k / kRate_Hz;
    const LiftArmMotion s = liftArmMotionAt(t);
    const std::vector<double> tau = torques.at(s);
    pos << t, vel << t, cur << t;
    for (int j = 0; j < kJoints; ++j) {
      const double per_amp = kLiftArmRatio[j] * kLiftArmKt[j];
      double i = (tau[j] + kLiftArmNoise[j] * normal(rng)) / per_amp;
      if (kQuantised[j]) {
        const double step = kStep_Nm / std::abs(per_amp);
        i = std::round(i / step) * step;
      }
      pos << "," << s.q[j], vel << "," << s.qd[j], cur << "," << i;
    }
    pos << "\n", vel << "\n", cur << "\n";
  }
}

// The study a user writes from the docs (paths relative to the study file).
std::string studyText() {
  return "[study]\nname = \"lift_arm\"\n\n[[design]]\nfile = \"" + urdfPath() +
         "\"\nname = \"lift_arm\"\nbase_link = \"base_link\"\ntip_link = \"arm_5_link\"\n\n"
         "[[calibration]]\nname = \"lift_arm\"\nkind = \"trajectory\"\ndesign = \"lift_arm\"\n"
         "auto = true\n\n[calibration.measured]\n"
         "joints = [\"torso_lift_joint\", \"arm_1_joint\", \"arm_2_joint\", \"arm_3_joint\", "
         "\"arm_4_joint\", \"arm_5_joint\"]\n"
         "side = \"joint\"\ntime_column = \"t\"\ngravity_compensated = [\"torso_lift_joint\"]\n"
         "positions = { file = \"pos.csv\", columns = [\"p1\", \"p2\", \"p3\", \"p4\", \"p5\", "
         "\"p6\"], unit = \"rad\" }\n"
         "velocities = { file = \"vel.csv\", columns = [\"v1\", \"v2\", \"v3\", \"v4\", \"v5\", "
         "\"v6\"], unit = \"rad/s\" }\n"
         "efforts = { file = \"cur.csv\", columns = [\"i1\", \"i2\", \"i3\", \"i4\", \"i5\", "
         "\"i6\"], unit = \"A\", torque_constants = [0.136, -0.136, 0.102, -0.102, 0.05, -0.05], "
         "ratios = [1570, 100, 100, 100, 100, 100] }\n"
         "filter = { cutoff = \"40 Hz\", decimate = 2, trim = \"0.2 s\" }\n";
}

// One run of the study on freshly written logs, shared by the test cases below: the first writes
// the logs and runs the study; in ctest it is the fixture of the others (tests/
// shipped_fixtures.cmake.in), which read its outputs (`study`: the study's output folder).
struct SyntheticRun {
  fs::path study;
  int rc = -1;      // the run's exit status (run() only)
  std::string log;  // what it printed (run() only)
  json summary;
  std::string report;
  // Writes the logs and the study file into <root>/synthetic_lift_arm_logs/ and runs the study
  // into <root>/lift_arm/; root: $ARMSTUDY_SHIPPED_OUTPUT in ctest, else a temporary folder.
  static SyntheticRun run() {
    const char* shipped = std::getenv("ARMSTUDY_SHIPPED_OUTPUT");
    const fs::path root = shipped ? fs::path(shipped) : test::emptyTempDir("synthetic_lift_arm");
    const fs::path logs = root / "synthetic_lift_arm_logs";
    fs::remove_all(logs);
    fs::create_directories(logs);
    writeLogs(logs);
    std::ofstream(logs / "study.toml") << studyText();
    SyntheticRun r;
    r.rc = test::runCommand(test::binaryPath() + " run " + (logs / "study.toml").string() +
                                " --output " + root.string() + " --overwrite --threads 2",
                            r.log);
    r.read(root / "lift_arm");
    return r;
  }
  // The outputs the first test case wrote (the fixture; tests/shipped_output.hpp).
  static SyntheticRun written() {
    SyntheticRun r;
    r.read(test::shippedOutput("lift_arm", "calibration:synthetic lift arm: the study runs, ..."));
    return r;
  }
  void read(const fs::path& out) {
    study = out;
    const fs::path s = out / "calibration/lift_arm/summary.json";
    if (fs::exists(s)) summary = json::parse(readFileOrThrow(s.string()));
    if (fs::exists(out / "calibration/report.md"))
      report = readFileOrThrow((out / "calibration/report.md").string());
  }
  bool added(const std::string& effect) const {
    for (const auto& a : summary.at("added"))
      if (a.get<std::string>() == effect) return true;
    return false;
  }
  // A fitted parameter of the final model by key ("arm_1_joint.viscous.viscous"); NaN if absent.
  double param(const std::string& key) const {
    for (const auto& p : summary.at("final_params"))
      if (p.at("key").get<std::string>() == key) return p.at("value").get<double>();
    return std::nan("");
  }
  std::string warnings() const {
    std::string w;
    for (const auto& x : summary.at("warnings")) w += x.get<std::string>() + "\n";
    return w;
  }
};

const SyntheticRun& fixtureRun() {
  static const SyntheticRun r = SyntheticRun::written();
  return r;
}

bool containsText(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("synthetic lift arm: the study runs, exit 0, and names its joints and units",
          "[calibration][study]") {
  const SyntheticRun r = SyntheticRun::run();
  INFO(r.log);
  REQUIRE(r.rc == 0);
  REQUIRE(r.summary.is_object());
  CHECK(containsText(r.report, "torso_lift_joint: its controller compensates gravity"));
  CHECK(containsText(r.report, "logged velocities used"));
  CHECK_FALSE(containsText(r.report, "N m|N"));
  CHECK_FALSE(containsText(r.report, "tau1"));
}

TEST_CASE("synthetic lift arm: friction recovered where the data identify it",
          "[calibration][study]") {
  const SyntheticRun& r = fixtureRun();
  INFO(r.summary.at("verdict").get<std::string>());
  for (int j = 0; j < 4; ++j) {  // the lift and arm_1..arm_3, above the floor
    const std::string n = kNames[j];
    INFO(n);
    CHECK(r.added(n + ".viscous"));
    CHECK(r.added(n + ".coulomb"));
    const double v = r.param(n + ".viscous.viscous"), c = r.param(n + ".coulomb.coulomb");
    CHECK(std::abs(v / kViscous[j] - 1) <= kViscousTolerance);
    CHECK(std::abs(c / kCoulomb[j] - 1) <= kCoulombTolerance);
  }
}

TEST_CASE("synthetic lift arm: the quantised wrist channels are not identifiable",
          "[calibration][study]") {
  const SyntheticRun& r = fixtureRun();
  const std::string w = r.warnings();
  INFO(w);
  for (int j = 4; j < kJoints; ++j) {
    const std::string n = kNames[j];
    INFO(n);
    CHECK(containsText(w, "channel " + n +
                              " is at the logging resolution (its values lie on steps of "
                              "0.02 N m"));
    for (const auto& a : r.summary.at("added")) CHECK(a.get<std::string>().rfind(n + ".", 0) != 0);
    // Nor is a pattern there called an effect.
    CHECK_FALSE(
        containsText(r.summary.at("verdict").get<std::string>(), "channel " + n + " against"));
  }
  for (int j = 0; j < 4; ++j)
    CHECK_FALSE(containsText(w, std::string("channel ") + kNames[j] + " is at"));
}

TEST_CASE("synthetic lift arm: no mass refitted: the tool and head are the design's",
          "[calibration][study]") {
  // The logs hold exactly the URDF's tree (KDL), so every body is where the design says: neither
  // the tool beyond the tip as a payload nor a link mass (a negative one least of all) is added.
  const SyntheticRun& r = fixtureRun();
  INFO(r.summary.at("verdict").get<std::string>());
  for (const auto& p : r.summary.at("final_params")) {
    const std::string key = p.at("key").get<std::string>();
    INFO(key);
    CHECK(key.rfind("payload", 0) != 0);
    CHECK(key.rfind("link_mass", 0) != 0);
  }
  CHECK_FALSE(r.added("payload"));
}

TEST_CASE(
    "synthetic lift arm: a URDF design gets a calibrated TOML and URDF holding the fitted friction",
    "[calibration][study]") {
  const SyntheticRun& r = fixtureRun();
  const std::string rel = r.summary.at("calibrated").at("design").get<std::string>();
  REQUIRE_FALSE(rel.empty());
  const fs::path toml = r.study / "calibration/lift_arm" / rel;
  fs::path urdf_path = toml;
  urdf_path.replace_extension(".urdf");
  REQUIRE(fs::exists(toml));
  REQUIRE(fs::exists(urdf_path));
  const Model cal = loadDesign(toml.string());
  // urdfdom reads the calibrated URDF, independent of the project's URDF importer.
  const urdf::ModelInterfaceSharedPtr u = urdf::parseURDFFile(urdf_path.string());
  REQUIRE(u);
  int fitted = 0;
  for (const Joint& j : cal.joints) {
    INFO(j.name);
    const double v = r.param(j.name + ".viscous.viscous");
    const double c = r.param(j.name + ".coulomb.coulomb");
    fitted += !std::isnan(v) + !std::isnan(c);
    CHECK(j.dynamics.viscous == (std::isnan(v) ? 0.0 : v));
    CHECK(j.dynamics.coulomb == (std::isnan(c) ? 0.0 : c));
    const urdf::JointConstSharedPtr uj = u->getJoint(j.name);
    REQUIRE(uj);
    CHECK((uj->dynamics ? uj->dynamics->damping : 0.0) == (std::isnan(v) ? 0.0 : v));
    CHECK((uj->dynamics ? uj->dynamics->friction : 0.0) == (std::isnan(c) ? 0.0 : c));
  }
  CHECK(fitted >= 8);  // the lift and the first three arm joints: viscous and Coulomb each
}

TEST_CASE(
    "synthetic lift arm: the identification report is handed over in memory, report.html is built "
    "from it and not from the file, and a resumed entry hands over the same document",
    "[calibration][study][report]") {
  const fs::path dir = test::emptyTempDir("synthetic_lift_arm_documents");
  writeLogs(dir);
  writeFileAtomic((dir / "study.toml").string(), studyText());
  const Study study = loadStudy((dir / "study.toml").string());
  const fs::path out = dir / "out";
  std::string message;
  const CheckpointStore store(out.string(), studyFingerprint(study), message);
  RunOptions ro;
  ro.threads = 2;
  ro.progress = false;
  const auto document = [](const StageResult& r, const std::string& path) {
    for (const report::ReportFile& f : r.reports)
      if (f.path == path) return &f.doc;
    return static_cast<const report::Document*>(nullptr);
  };
  const std::string rel = "calibration/lift_arm/identification.md";
  const StageResult first = runStage(study, "calibration", out.string(), ro, &store);
  REQUIRE(std::find(first.files.begin(), first.files.end(), rel) != first.files.end());
  const report::Document* doc = document(first, rel);
  REQUIRE(doc);
  const std::string md = readFileOrThrow((out / rel).string());
  CHECK(report::toMarkdown(*doc) == md);
  REQUIRE(md.rfind("# Identification: lift_arm", 0) == 0);
  // The file changed on disk after the stage wrote it: the page shows the document.
  writeFileAtomic((out / rel).string(), "# STALE ON DISK\n");
  const std::string html =
      report::htmlReport(out.string(), "s", {{"calibration", first.files, first.reports}});
  CHECK(html.find("STALE ON DISK") == std::string::npos);
  CHECK(html.find("Identification: lift_arm") != std::string::npos);
  // The file as written again (the unit's files are checked by hash): the entry is resumed from
  // its unit and hands over a document with the same Markdown and HTML.
  writeFileAtomic((out / rel).string(), md);
  const StageResult again = runStage(study, "calibration", out.string(), ro, &store);
  CHECK(again.units_resumed == 1);
  const report::Document* resumed = document(again, rel);
  REQUIRE(resumed);
  CHECK(report::toMarkdown(*resumed) == md);
  const auto image = [](const std::string& f) { return f; };
  CHECK(report::toHtml(*resumed, "p-", image) == report::toHtml(*doc, "p-", image));
}
