// The [[calibration]] study stage (docs/calibration.md, "As a study stage"): the shipped thesis
// study reproduces thesis Tables 4.4/4.5 and the documented ladder; the shipped arm study finds the
// effects its data were synthesized with (the synth hidden values are the oracle, and the data
// files are checked to be what `armstudy synth` writes); result files are byte-identical for 1 and
// 2 threads; a checkpointed entry is reused only while its files are intact; `armstudy check`
// passes against the committed baselines; bad input is an InputError with file, line and key.
#include "stages/calibration/calibration_stage.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "common/errors.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::calibration;
namespace fs = std::filesystem;

namespace {

constexpr double kTableTolerance = 0.10;  // relative agreement with thesis Tables 4.4/4.5
constexpr double kRoundTripTolerance =
    1e-9;  // calibrated copy read from disk vs the fit (relative)
constexpr double kProfileTolerance =
    0.05;  // profiled Stribeck velocity vs the hidden one (relative)
// Thesis section 4.6.1: adding the missing effect lowers the RMSE by a factor of two to five.
constexpr double kThesisFactorMin = 2.0, kThesisFactorMax = 5.0;

const char* kThesisStudy = "studies/thesis_drive_friction.toml";
const char* kArmStudy = "studies/arm_calibration.toml";

RunOptions runOptions(const fs::path& root, int threads) {
  RunOptions ro;
  ro.output_root = root.string();
  ro.threads = threads;
  ro.overwrite = true;
  ro.progress = false;
  return ro;
}

fs::path freshDir(const std::string& name) { return test::emptyTempDir("calstage_" + name); }

// Every file of a run but the manifest (timings, date) and the checkpoint store, by relative path.
std::map<std::string, std::string> resultFiles(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string rel = fs::relative(e.path(), dir).string();
    if (e.is_regular_file() && rel != "manifest.json" && rel.rfind(".partial", 0) != 0)
      out[rel] = readFileOrThrow(e.path().string());
  }
  return out;
}

// What runStage returns: the stage's result and the entries' summaries.
struct StageRun {
  StageResult result;
  std::vector<EntrySummary> entries;
};

const EntrySummary& entry(const StageRun& s, const std::string& name) {
  for (const auto& e : s.entries)
    if (e.name == name) return e;
  FAIL("no calibration entry " << name);
  throw 0;
}

std::map<std::string, FittedParameter> params(const EntrySummary& s) {
  std::map<std::string, FittedParameter> p;
  for (const auto& f : s.final_params) p[f.key] = f;
  return p;
}

const Model& studyModel(const Study& s, const std::string& name) {
  for (const auto& d : s.designs)
    if (d.model.name == name) return d.model;
  FAIL("no design " << name);
  throw 0;
}

// Runs the calibration stage of a study alone, with a checkpoint store in `root`/<study>.
StageRun runStage(const Study& s, const fs::path& root, RunSummary& rs, int threads) {
  const RunOptions ro = runOptions(root, threads);
  const std::string out = (root / s.name).string();
  std::string msg;
  CheckpointStore store(out, studyFingerprint(s), msg);
  const UnitRunner units(store);
  StageRun r;
  r.result = runCalibrationStage(StageContext{s, ro, out, units, threads, {}, {}},
                                 *stageSettings<std::vector<CalibrationEntry>>(s, "calibration"),
                                 &r.entries);
  rs.metrics = r.result.metrics;
  return r;
}

}  // namespace

TEST_CASE(
    "thesis study: catalog law vs the B.2 sample reproduces Tables 4.4/4.5 and the documented "
    "ladder",
    "[calibration][study][thesis]") {
  const Study s = loadStudy(test::sourcePath(kThesisStudy));
  // The data file is an input of the run, with its content hash.
  const std::string data = test::sourcePath("studies/data/drive_testbed_module_b2.csv");
  bool hashed = false;
  for (const auto& in : s.inputs)
    hashed = hashed || (fs::equivalent(in.path, data) && in.hash == fileHash(data));
  CHECK(hashed);

  const fs::path root = freshDir("thesis");
  const RunSummary rs = runStudy(s, runOptions(root, 1));
  const EntrySummary e = entrySummaryFromJson(
      readFileOrThrow((root / s.name / "calibration/b2_friction/summary.json").string()));
  REQUIRE(e.ladder.size() == 3);  // as designed, refit eq. 3.30, + stribeck
  CHECK(e.added == std::vector<std::string>{"stribeck"});
  CHECK(e.verdict == "missing effect: stribeck");

  // docs/calibration.md "The thesis story" quotes the held-out ladder to three significant digits.
  const double doc[] = {0.533, 0.211, 0.0437};
  for (int k = 0; k < 3; ++k) {
    const double half_digit = 0.5 * std::pow(10.0, std::floor(std::log10(doc[k])) - 2);
    CHECK(std::abs(e.ladder[k].heldout_rmse - doc[k]) <= half_digit);
  }
  // Friction-torque RMSE (current RMSE x k_m, thesis eq. 4.6) against Table 4.5 (refit eq. 3.30,
  // B.2: 1.59e-2 N m) and Table 4.4 (eq. 3.33, B.2: 3.2e-3 N m).
  double km = 0;
  for (const Drive& d : studyModel(s, "final_prototype_9dof").drives)
    if (d.joint == "j6") km = d.torque_constant_NmpA;
  REQUIRE(km > 0);
  CHECK(e.ladder[1].heldout_rmse * km == Approx(1.59e-2).epsilon(kTableTolerance));
  CHECK(e.ladder[2].heldout_rmse * km == Approx(3.2e-3).epsilon(kTableTolerance));
  const double factor = e.rmse_before / e.rmse_after;
  CHECK(factor > kThesisFactorMin);
  CHECK(factor < kThesisFactorMax);
  // Fitted eq. (3.33) parameters against Table 4.4, B.2.
  auto p = params(e);
  CHECK(p["refit.coulomb"].value == Approx(1.36e-1).epsilon(kTableTolerance));
  CHECK(p["refit.load_coulomb"].value == Approx(4.4e-3).epsilon(kTableTolerance));
  CHECK(p["stribeck.stribeck_torque"].value == Approx(4.77e-2).epsilon(kTableTolerance));
  CHECK(p["stribeck.stribeck_velocity"].value == Approx(65.2).epsilon(kTableTolerance));

  // The calibrated copy, read back from disk and compared with the data (a second computation),
  // predicts what the fit predicted; the bins the noise cannot explain are gone.
  CHECK(e.calibrated_rmse == Approx(e.ladder[2].train_rmse).epsilon(kRoundTripTolerance));
  CHECK(e.as_designed_flagged > 0);
  CHECK(e.calibrated_flagged == 0);
  const Model cal =
      loadDesign((root / s.name / "calibration/b2_friction" / e.calibrated_design).string());
  for (const Drive& d : cal.drives)
    if (d.joint == "j6")
      CHECK(d.friction.at("stribeck_velocity") == Approx(p["stribeck.stribeck_velocity"].value));
  // Metrics for baselines, and the manifest lists the stage's files.
  CHECK(rs.metrics.scalars.at("calibration/b2_friction/rmse_after") == e.rmse_after);
  CHECK(rs.metrics.scalars.at("calibration/b2_friction/added/stribeck") == 1.0);
  CHECK(rs.metrics.flags.at("calibration/b2_friction/added") ==
        std::vector<std::uint8_t>{0, 0, 0, 0, 1, 0, 0, 0});
  const auto man =
      nlohmann::json::parse(readFileOrThrow((root / s.name / "manifest.json").string()));
  const auto files = man["files"].get<std::vector<std::string>>();
  CHECK(std::find(files.begin(), files.end(), "calibration/b2_friction/calibrated/result.json") !=
        files.end());
  // The study's output folder is locked as a whole: its fits leave no `<folder>.lock` among the
  // results.
  for (const auto& f : fs::recursive_directory_iterator(root / s.name))
    if (f.path().extension() == ".lock") CHECK(f.path().filename() == ".armstudy.lock");
  for (const std::string& f : files) CHECK(fs::path(f).extension() != ".lock");
  fs::remove_all(root);
}

TEST_CASE(
    "arm study: the effects the data were synthesized with are found - 1 and 2 threads write the "
    "same bytes",
    "[calibration][study]") {
  const Study s = loadStudy(test::sourcePath(kArmStudy));
  const Model& m = studyModel(s, "final_prototype_7dof");
  // The committed data are what the `armstudy synth` commands in the study's header write.
  TcpSynthOptions to;
  to.rows = 60;
  to.noise_m = 2e-4;
  to.seed = 1;
  to.hidden = {"joint_offset.j3:offset=0.01", "link_length.j4.x:dx=0.005"};
  const TcpData tcp = synthesizeTcp(m, to);
  CHECK(tcpDataToCsv(tcp) == readFileOrThrow(test::sourcePath("studies/data/arm_tcp_synth.csv")));
  TrajectorySynthOptions yo;
  yo.duration_s = 4;
  yo.rate_Hz = 100;
  yo.currents = true;
  yo.noise = 0.01;
  yo.seed = 1;
  yo.hidden = {"payload", "j3.stribeck"};
  const TrajectoryData traj = synthesizeTrajectory(m, yo);
  CHECK(trajectoryDataToCsv(traj, true) ==
        readFileOrThrow(test::sourcePath("studies/data/arm_trajectory_synth.csv")));

  const fs::path root = freshDir("arm");
  RunSummary rs1;
  const StageRun c = runStage(s, root, rs1, 1);
  const auto one = resultFiles(root / s.name);

  // tcp: both hidden effects added, their values inside the 95 % intervals.
  const EntrySummary& t = entry(c, "tcp");
  CHECK(std::set<std::string>(t.added.begin(), t.added.end()) ==
        std::set<std::string>{"joint_offset.j3", "link_length.j4.x"});
  auto tp = params(t);
  for (const auto& [key, hidden] : std::map<std::string, double>{{"joint_offset.j3.offset", 0.01},
                                                                 {"link_length.j4.x.dx", 0.005}}) {
    INFO(key);
    CHECK(tp[key].ci_low <= hidden);
    CHECK(hidden <= tp[key].ci_high);
  }
  CHECK(t.calibrated_rmse == Approx(t.ladder.back().train_rmse).epsilon(kRoundTripTolerance));
  CHECK(t.calibrated_flagged == 0);

  // The variant already carries the j4 error: only the j3 offset is left, and its calibrated copy
  // keeps the variant's j4 entry.
  const EntrySummary& v = entry(c, "tcp_variant");
  CHECK(v.added == std::vector<std::string>{"joint_offset.j3"});
  auto vp = params(v);
  CHECK(vp["joint_offset.j3.offset"].ci_low <= 0.01);
  CHECK(0.01 <= vp["joint_offset.j3.offset"].ci_high);
  const Model vcal =
      loadDesign((root / s.name / "calibration/tcp_variant" / v.calibrated_design).string());
  const Model& variant = studyModel(s, "final_prototype_7dof+j4.x=0.355");
  CHECK(vcal.joints[vcal.jointIndex("j4")].offset.x ==
        variant.joints[variant.jointIndex("j4")].offset.x);
  CHECK(vcal.joints[vcal.jointIndex("j3")].offset.gamma ==
        Approx(variant.joints[variant.jointIndex("j3")].offset.gamma +
               vp["joint_offset.j3.offset"].value));
  CHECK(v.calibrated_rmse == Approx(v.ladder.back().train_rmse).epsilon(kRoundTripTolerance));

  // trajectory: payload and the j3 Stribeck term, against the hidden values `synth` used.
  const EntrySummary& y = entry(c, "trajectory");
  CHECK(std::set<std::string>(y.added.begin(), y.added.end()) ==
        std::set<std::string>{"payload", "j3.stribeck"});
  const auto P = makeTrajectoryProblem(m, traj);
  auto yp = params(y);
  for (const std::string name : {"payload", "j3.stribeck"}) {
    const EffectValue hidden = parseHiddenEffect(*P, name);
    const ArmEffect& info = P->catalogue[hidden.effect];
    for (std::size_t k = 0; k < info.params.size(); ++k) {
      const FittedParameter& f = yp[name + "." + info.params[k].key];
      INFO(name << "." << info.params[k].key << " hidden " << hidden.x[k] << " fitted " << f.value);
      CHECK(f.ci_low <= hidden.x[k]);
      CHECK(hidden.x[k] <= f.ci_high);
    }
    if (info.hasProfile())
      CHECK(yp[name + "." + info.profile.key].value ==
            Approx(hidden.profile).epsilon(kProfileTolerance));
  }
  CHECK(y.calibrated_flagged == 0);

  // Two threads: the fixture "shipped: arm_calibration" (tests/CMakeLists.txt) runs the study on 2
  // threads through `armstudy check`. Its calibration folder holds the same files with the same
  // bytes, the output folder's own path aside (the calibrated designs' headers name the file they
  // were made from), and its metrics (the comparison's current values) are the same numbers.
  const fs::path shipped = test::shippedOutput("arm_calibration");
  const auto two = resultFiles(shipped / "calibration");
  REQUIRE(one.size() == two.size());
  for (const auto& [path, bytes] : one) {
    INFO(path);
    REQUIRE(path.rfind("calibration/", 0) == 0);
    const std::string rel = path.substr(std::string("calibration/").size());
    REQUIRE(two.count(rel));
    std::string other = two.at(rel);
    const std::string from = shipped.string(), to = (root / s.name).string();
    for (std::size_t at = other.find(from); at != std::string::npos;
         at = other.find(from, at + to.size()))
      other.replace(at, from.size(), to);
    CHECK(other == bytes);
  }
  std::map<std::string, double> scalars;
  const nlohmann::json check = test::shippedCheck("arm_calibration");
  for (const auto& row : check.at("rows"))
    if (row.at("kind") == "scalar" && row.at("verdict") != "MISSING")
      scalars[row.at("metric")] =
          row.at("now").is_null() ? std::nan("") : row.at("now").get<double>();
  REQUIRE(scalars.size() == rs1.metrics.scalars.size());
  for (const auto& [name, value] : rs1.metrics.scalars) {
    INFO(name << " = " << value << " on 1 thread");
    REQUIRE(scalars.count(name));
    CHECK(((std::isnan(value) && std::isnan(scalars.at(name))) || scalars.at(name) == value));
  }
  fs::remove_all(root);
}

TEST_CASE(
    "checkpoint: a saved entry is reused while its files are intact, run again when one changed",
    "[calibration][study][checkpoint]") {
  const Study s = loadStudy(test::sourcePath(kThesisStudy));
  const fs::path root = freshDir("resume");
  RunSummary r1, r2, r3;
  const StageRun a = runStage(s, root, r1, 1);
  CHECK(a.result.units_resumed == 0);
  const auto first = resultFiles(root / s.name / "calibration");
  const StageRun b = runStage(s, root, r2, 1);
  CHECK(b.result.units_resumed == 1);
  CHECK(resultFiles(root / s.name / "calibration") == first);
  CHECK(r2.metrics.scalars == r1.metrics.scalars);
  CHECK(r2.metrics.flags == r1.metrics.flags);
  // A damaged result file: the entry runs again and restores it.
  const fs::path damaged = root / s.name / "calibration/b2_friction/residuals.csv";
  std::ofstream(damaged) << "not the residuals\n";
  const StageRun c = runStage(s, root, r3, 1);
  CHECK(c.result.units_resumed == 0);
  CHECK(resultFiles(root / s.name / "calibration") == first);
  fs::remove_all(root);
}

TEST_CASE("the shipped calibration studies pass `armstudy check` against their committed baselines",
          "[calibration][study][regression]") {
  // The fixtures "shipped: <study>" run the checks once per suite (tests/CMakeLists.txt).
  for (const char* study : {"thesis_drive_friction", "arm_calibration"}) {
    const nlohmann::json check = test::shippedCheck(study);
    INFO(study << "\n" << check.dump(1));
    CHECK(check.at("passed").get<bool>());
    CHECK_FALSE(check.at("rows").empty());
  }
}

namespace {

int lineOf(const std::string& text, const std::string& needle) {
  const auto pos = text.find(needle);
  REQUIRE(pos != std::string::npos);
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + pos, '\n'));
}

}  // namespace

TEST_CASE(
    "bad [[calibration]] input is an InputError with file, line and key, and nothing is written",
    "[calibration][study][input]") {
  const fs::path dir = freshDir("bad");
  const std::string head = "[study]\nname = \"bad\"\n[[design]]\nfile = \"" +
                           test::sourcePath("designs/final_prototype_9dof.toml") +
                           "\"\n[[design]]\nfile = \"" +
                           test::sourcePath("designs/final_prototype_7dof.toml") + "\"\n";
  const std::string good = R"(
[[calibration]]
name = "drive"
kind = "drive"
design = "final_prototype_9dof"
data = "DRIVE"
drive = "j6"
add = ["stribeck"]
speed_bins = 8

[[calibration]]
name = "arm"
kind = "tcp"
design = "final_prototype_7dof"
data = "TCP"
add = ["joint_offset.j3"]
variable_bins = 4
)";
  auto withData = [](std::string body) {
    if (body.find("DRIVE") != std::string::npos)
      body.replace(body.find("DRIVE"), 5,
                   test::sourcePath("studies/data/drive_testbed_module_b2.csv"));
    body.replace(body.find("TCP"), 3, test::sourcePath("studies/data/arm_tcp_synth.csv"));
    return body;
  };
  const fs::path path = dir / "study.toml";
  std::ofstream(path) << head << withData(good);
  REQUIRE_NOTHROW(loadStudy(path.string()));
  struct Case {
    std::string from, to, key, line_of;  // the error's line is the line holding `line_of`
  };
  const Case cases[] = {
      {"design = \"final_prototype_9dof\"", "design = \"nope\"", "calibration[0].design",
       "\"nope\""},
      {"data = \"DRIVE\"", "data = \"missing.csv\"", "calibration[0].data", "missing.csv"},
      {"kind = \"drive\"", "kind = \"motor\"", "calibration[0].kind", "\"motor\""},
      {"add = [\"stribeck\"]", "add = [\"striback\"]", "calibration[0].add", "striback"},
      {"add = [\"joint_offset.j3\"]", "add = [\"joint_offset.j99\"]", "calibration[1].add", "j99"},
      {"drive = \"j6\"", "drive = \"j99\"", "calibration[0].drive", "j99"},
      {"drive = \"j6\"", "drive = \"j6\"\ndrvie = 1", "calibration[0].drvie", "drvie"},
      {"variable_bins = 4", "variable_bins = 4\ndrive = \"j3\"", "calibration[1].drive", "\"j3\""},
      {"variable_bins = 4", "variable_bins = 4\nspeed_bins = 3", "calibration[1].speed_bins",
       "speed_bins = 3"},
      {"speed_bins = 8", "speed_bins = 0", "calibration[0].speed_bins", "speed_bins = 0"},
      {"speed_bins = 8", "speed_bins = 8\nfolds = 1", "calibration[0].folds", "folds = 1"},
      {"speed_bins = 8", "speed_bins = 8\nmode = \"compare\"", "calibration[0].add", "add = "},
      {"speed_bins = 8", "speed_bins = 8\nmode = \"refit\"", "calibration[0].mode", "refit"},
      {"name = \"arm\"", "name = \"drive\"", "calibration[1].name",
       "name = \"drive\"\nkind = \"tcp\""},
      {"name = \"arm\"", "name = \"an arm\"", "calibration[1].name", "an arm"},
  };
  for (const Case& c : cases) {
    std::string body = good;
    REQUIRE(body.find(c.from) != std::string::npos);
    body.replace(body.find(c.from), c.from.size(), c.to);
    const std::string text = head + withData(body);
    std::ofstream(path) << text;
    INFO(c.to);
    try {
      (void)loadStudy(path.string());
      FAIL("no InputError");
    } catch (const InputError& e) {
      INFO(e.what());
      CHECK(e.file() == path.string());
      CHECK(e.key() == c.key);
      CHECK(e.line() == lineOf(text, c.line_of));
    }
  }
  // Through the CLI: exit code 2 and no output folder.
  std::string body = good;
  body.replace(body.find("drive = \"j6\""), 12, "drive = \"j99\"");
  std::ofstream(path) << head << withData(body);
  std::string out;
  CHECK(test::runCommand(
            test::binaryPath() + " run " + path.string() + " --output " + (dir / "out").string(),
            out) == 2);
  CHECK(!fs::exists(dir / "out"));
  // A malformed data file names the data file and its line.
  const fs::path csv = dir / "bed.csv";
  std::ofstream(csv) << "speed,load_torque,current\n10,1,0.5\n0,1,0.5\n";
  body = good;
  body.replace(body.find("data = \"DRIVE\""), 14, "data = \"bed.csv\"");
  std::ofstream(path) << head << withData(body);
  try {
    (void)loadStudy(path.string());
    FAIL("no InputError");
  } catch (const InputError& e) {
    CHECK(fs::equivalent(e.file(), csv));
    CHECK(e.line() == 3);
  }
  fs::remove_all(dir);
}
