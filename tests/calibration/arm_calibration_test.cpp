// Model versus measurement for arms (kinds tcp and trajectory): every hidden effect of both
// catalogues must rank first in synthetic data and bring the held-out RMSE to the injected noise,
// nothing hidden must give "no significant missing effect", identifiability and bad input are
// reported, and the Savitzky-Golay derivative matches a closed form.
#include "calibration/arm_calibration.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "calibration/tcp_calibration.hpp"
#include "calibration/trajectory_calibration.hpp"
#include "common/errors.hpp"
#include "dynamics/dynamics.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "kinematics/kinematics.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::calibration;

namespace {

constexpr double kNoiseRatio = 1.2;       // held-out RMSE after the fix <= 1.2 x noise
constexpr double kTcpNoise_m = 2e-4;      // injected TCP position noise
constexpr double kTauNoise = 0.05;        // injected effort noise [N m | N]
constexpr double kSgTolerance = 2e-3;     // relative error of the SG derivative of a slow sine
constexpr double kSgEndTolerance = 1e-2;  // at the ends, where the window is shifted inside
constexpr int kTcpRows = 50;

const Model& design7() {
  static const Model m = loadDesign(test::sourcePath("designs/final_prototype_7dof.toml"));
  return m;
}

struct Outcome {
  ArmDiagnosis d;     // after adding the effect
  std::string first;  // best candidate of the design as is
  bool significant = false;
};

Outcome fitWith(const ArmProblem& P, const std::string& add_first_ranked) {
  ArmFitOptions o;
  Outcome r;
  r.d = diagnoseArm(P, o);
  r.first = r.d.ranking.empty() ? "" : r.d.ranking.front().name;
  r.significant =
      !r.d.ranking.empty() && r.d.ranking.front().significant && r.d.missing_effect_found;
  if (!add_first_ranked.empty()) {
    o.add = {add_first_ranked};
    r.d = diagnoseArm(P, o);
  }
  return r;
}

std::string tmpDir(const std::string& name) {
  const std::string dir = test::binaryPath() + "_" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace

TEST_CASE("Savitzky-Golay derivative of a sine equals the closed form (interior and ends)") {
  std::vector<double> t, y;
  const double w = 2.0;
  for (int i = 0; i <= 200; ++i) {
    t.push_back(i * 0.01);
    y.push_back(std::sin(w * t.back()));
  }
  const auto d = savitzkyGolayDerivative(t, y, 4, 2);
  for (std::size_t i = 0; i < t.size(); ++i) {
    const bool end = i < 4 || i + 4 >= t.size();
    CHECK(std::abs(d[i] - w * std::cos(w * t[i])) < (end ? kSgEndTolerance : kSgTolerance) * w);
  }
  // A quadratic is differentiated exactly, also with uneven steps.
  std::vector<double> tu, yu;
  for (int i = 0; i < 30; ++i) {
    tu.push_back(i * 0.1 + 0.03 * (i % 3));
    yu.push_back(3 + 2 * tu.back() - 0.5 * tu.back() * tu.back());
  }
  const auto du = savitzkyGolayDerivative(tu, yu, 4, 2);
  for (std::size_t i = 0; i < tu.size(); ++i) CHECK(du[i] == Approx(2 - tu[i]).margin(1e-9));
}

TEST_CASE(
    "tcp: every hidden effect ranks first - its values lie in the intervals - adding it brings the "
    "held-out RMSE to the noise") {
  const Model& m = design7();
  const char* hidden[] = {"joint_offset.j3", "link_length.j4.x", "base_offset",
                          "joint_compliance.j3"};
  for (const char* h : hidden) {
    TcpSynthOptions so;
    so.rows = kTcpRows;
    so.noise_m = kTcpNoise_m;
    so.seed = 11;
    so.hidden = {h};
    const TcpData data = synthesizeTcp(m, so);
    const auto P = makeTcpProblem(m, data);
    const Outcome r = fitWith(*P, h);
    INFO("hidden " << h << ", first " << r.first << ", before " << r.d.rmse_before << ", after "
                   << r.d.rmse_after);
    CHECK(r.first == h);
    CHECK(r.significant);
    CHECK(r.d.added == std::vector<std::string>{h});
    CHECK(r.d.rmse_after <= kNoiseRatio * kTcpNoise_m);
    for (int c = 0; c < P->channels(); ++c)  // at the noise in every channel
      CHECK(r.d.final_fit.channel_heldout[c].rmse <= kNoiseRatio * kTcpNoise_m);
    CHECK(r.d.as_designed_map.flagged() > 0);
    // The hidden (typical) values lie inside the reported 95 % intervals.
    const ArmEffect& info = P->catalogue[P->findEffect(h)];
    REQUIRE(r.d.final_fit.params.size() == info.params.size());
    for (std::size_t k = 0; k < info.params.size(); ++k) {
      const auto& fp = r.d.final_fit.params[k];
      INFO(fp.key << " = " << fp.value << " [" << fp.ci_low << ", " << fp.ci_high << "], hidden "
                  << info.params[k].typical);
      CHECK(fp.ci_low <= info.params[k].typical);
      CHECK(fp.ci_high >= info.params[k].typical);
    }
  }
}

TEST_CASE(
    "tcp with orientation: angles wrap and count in the fit - a hidden base rotation is found") {
  const Model& m = design7();
  TcpSynthOptions so;
  so.rows = kTcpRows;
  so.noise_m = kTcpNoise_m;
  so.orientation = true;
  so.noise_rad = kTcpNoise_m / defaults::kTcpAngleLength_m;  // the same noise in fit units
  so.seed = 4;
  so.hidden = {"base_offset:x=0,y=0,z=0,alpha=0.004,beta=-0.003,gamma=0.002"};
  const auto P = makeTcpProblem(m, synthesizeTcp(m, so));
  REQUIRE(P->channels() == 6);
  const Outcome r = fitWith(*P, "base_offset");
  INFO(r.first << " " << r.d.rmse_before << " -> " << r.d.rmse_after);
  CHECK(r.first == "base_offset");
  CHECK(r.significant);
  CHECK(r.d.rmse_after <= kNoiseRatio * kTcpNoise_m);
  // Angle residuals stay small although measured angles wrap at +-pi.
  for (int c = 3; c < 6; ++c) CHECK(r.d.final_fit.channel_train[c].max_abs < 10 * so.noise_rad);
}

TEST_CASE(
    "tcp: nothing hidden gives no significant missing effect - noise estimate near the injected "
    "noise") {
  TcpSynthOptions so;
  so.rows = kTcpRows;
  so.noise_m = kTcpNoise_m;
  so.seed = 5;
  const auto P = makeTcpProblem(design7(), synthesizeTcp(design7(), so));
  const ArmDiagnosis d = diagnoseArm(*P, {});
  CHECK_FALSE(d.missing_effect_found);
  CHECK(d.verdict == "no significant missing effect");
  CHECK(d.noise_estimate == Approx(kTcpNoise_m).epsilon(0.35));
  CHECK(d.as_designed_map.flagged() == 0);
}

TEST_CASE(
    "tcp: identifiability warnings (lift offset vs base z, compliance of the lift vs its offset)") {
  TcpSynthOptions so;
  so.rows = kTcpRows;
  so.noise_m = kTcpNoise_m;
  const auto P = makeTcpProblem(design7(), synthesizeTcp(design7(), so));
  const ArmDiagnosis d = diagnoseArm(*P, {});
  auto warningsOf = [&](const std::string& name) {
    for (const auto& c : d.ranking)
      if (c.name == name) return c.warnings;
    FAIL("no candidate " << name);
    return std::vector<std::string>{};
  };
  auto mentions = [](const std::vector<std::string>& w, const std::string& s) {
    for (const auto& x : w)
      if (x.find(s) != std::string::npos) return true;
    return false;
  };
  // The prismatic lift j1 moves along the base z axis: its offset is a base z translation and, with
  // a constant gravity force on the lift, its compliance is an offset too.
  CHECK(mentions(warningsOf("joint_offset.j1"), "base_offset"));
  CHECK(mentions(warningsOf("joint_compliance.j1"), "joint_offset.j1"));
  // A joint whose axis is vertical carries no gravity torque: its compliance has no effect.
  bool some_dead = false;
  for (const auto& c : d.ranking)
    if (c.name.rfind("joint_compliance.", 0) == 0 && c.status == "unidentifiable") some_dead = true;
  CHECK(some_dead);
}

TEST_CASE(
    "tcp: a hidden effect that other candidates mimic exactly is named with them (parsimony "
    "first)") {
  const Model& m = design7();
  // j2 turns about the base z axis: its offset is a base rotation gamma. The 1-parameter offset
  // ranks ahead of the 6-parameter base_offset, and the verdict names base_offset.
  {
    TcpSynthOptions so;
    so.rows = kTcpRows;
    so.noise_m = kTcpNoise_m;
    so.seed = 21;
    so.hidden = {"joint_offset.j2"};
    const ArmDiagnosis d = diagnoseArm(*makeTcpProblem(m, synthesizeTcp(m, so)), {});
    INFO(d.verdict);
    CHECK(d.ranking.front().name == "joint_offset.j2");
    CHECK(d.verdict.find("base_offset") != std::string::npos);
  }
  // Link entries along parallel axes are the same displacement: the hidden one is first or named.
  {
    TcpSynthOptions so;
    so.rows = kTcpRows;
    so.noise_m = kTcpNoise_m;
    so.seed = 23;
    so.hidden = {"link_length.j3.y"};
    const ArmDiagnosis d = diagnoseArm(*makeTcpProblem(m, synthesizeTcp(m, so)), {});
    INFO(d.verdict);
    REQUIRE(d.missing_effect_found);
    CHECK(d.verdict.find("link_length.j3.y") != std::string::npos);
    CHECK(d.verdict.find("cannot be told apart") != std::string::npos);
  }
}

TEST_CASE(
    "trajectory: every hidden effect ranks first and adding it brings the held-out RMSE to the "
    "noise") {
  const Model& m = design7();
  const char* hidden[] = {"payload",     "rotor_inertia", "gravity_tilt",    "link_mass.j3",
                          "j3.coulomb",  "j3.viscous",    "j4.load_coulomb", "j4.load_viscous",
                          "j3.stribeck", "j3.asymmetry"};
  for (const char* h : hidden) {
    TrajectorySynthOptions so;
    so.duration_s = 3.0;
    so.rate_Hz = 40;
    so.noise = kTauNoise;
    so.seed = 7;
    so.hidden = {h};
    const TrajectoryData data = synthesizeTrajectory(m, so);
    const auto P = makeTrajectoryProblem(m, data);
    const Outcome r = fitWith(*P, h);
    INFO("hidden " << h << ", first " << r.first << ", before " << r.d.rmse_before << ", after "
                   << r.d.rmse_after);
    CHECK(r.first == h);
    CHECK(r.significant);
    CHECK(r.d.added == std::vector<std::string>{h});
    CHECK(r.d.rmse_after <= kNoiseRatio * kTauNoise);
    for (int c = 0; c < P->channels(); ++c) {  // at the noise in every channel
      INFO("channel " << P->channel_names[c] << " held-out "
                      << r.d.final_fit.channel_heldout[c].rmse);
      CHECK(r.d.final_fit.channel_heldout[c].rmse <= kNoiseRatio * kTauNoise);
    }
    // Single-parameter effects (and the payload mass): the hidden value lies in the 95 % interval
    // (not for the Stribeck torque, whose interval is conditional on the profiled v_S grid value).
    const ArmEffect& info = P->catalogue[P->findEffect(h)];
    if (info.hasProfile()) continue;
    const auto& fp = r.d.final_fit.params.front();
    INFO(fp.key << " = " << fp.value << " [" << fp.ci_low << ", " << fp.ci_high << "], hidden "
                << info.params[0].typical);
    CHECK(fp.ci_low <= info.params[0].typical);
    CHECK(fp.ci_high >= info.params[0].typical);
  }
}

TEST_CASE("trajectory: nothing hidden gives no significant missing effect") {
  TrajectorySynthOptions so;
  so.duration_s = 3.0;
  so.rate_Hz = 40;
  so.noise = kTauNoise;
  so.seed = 3;
  const auto P = makeTrajectoryProblem(design7(), synthesizeTrajectory(design7(), so));
  const ArmDiagnosis d = diagnoseArm(*P, {});
  CHECK_FALSE(d.missing_effect_found);
  CHECK(d.noise_estimate == Approx(kTauNoise).epsilon(0.35));
}

TEST_CASE(
    "bad input: missing column / NaN cell / too few rows / joints the design lacks / unknown "
    "effect") {
  const Model& m = design7();
  const std::string dir = tmpDir("arm_bad");
  TcpSynthOptions so;
  so.rows = 12;
  const std::string good = tcpDataToCsv(synthesizeTcp(m, so));
  auto write = [&](const std::string& name, const std::string& text) {
    writeFileAtomic(dir + "/" + name, text);
    return dir + "/" + name;
  };
  // Missing q3: the column is named.
  {
    std::string text = good;
    text.replace(text.find("q3"), 2, "qq");
    try {
      readTcpData(write("noq3.csv", text), m);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(std::string(e.what()).find("q3") != std::string::npos);
    }
  }
  // NaN in data line 4 (header is line 1).
  {
    std::string text = good;
    std::size_t pos = 0;
    for (int i = 0; i < 3; ++i) pos = text.find('\n', pos) + 1;
    text.replace(pos, text.find(',', pos) - pos, "NaN");
    try {
      readTcpData(write("nan.csv", text), m);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(e.line() == 4);
      CHECK(e.file() == dir + "/nan.csv");
    }
  }
  // A column for a joint the design does not have.
  {
    std::string text = good;
    text.replace(text.find("x,y,z"), 5, "q8,x,y");
    try {
      readTcpData(write("q8.csv", text), m);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(std::string(e.what()).find("q8") != std::string::npos);
    }
    TrajectorySynthOptions ts;
    ts.duration_s = 0.5;
    std::string traj = trajectoryDataToCsv(synthesizeTrajectory(m, ts), true);
    traj.replace(traj.find("tau1"), 4, "tau9");
    CHECK_THROWS_AS(readTrajectoryData(write("tau9.csv", traj), m), InputError);
  }
  // Neither efforts nor currents; too few rows; unknown effect to add.
  {
    TrajectorySynthOptions ts;
    ts.duration_s = 0.5;
    const TrajectoryData td = synthesizeTrajectory(m, ts);
    std::string traj = trajectoryDataToCsv(td, true);
    for (int j = 1; j <= 7; ++j) traj.replace(traj.find("tau" + std::to_string(j)), 3, "xyz");
    try {
      readTrajectoryData(write("notau.csv", traj), m);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(std::string(e.what()).find("tau1") != std::string::npos);
    }
    TcpSynthOptions few;
    few.rows = 6;
    CHECK_THROWS_AS(compareArm(*makeTcpProblem(m, synthesizeTcp(m, few)), {}), InputError);
    ArmFitOptions o;
    o.add = {"joint_offset.j12"};
    CHECK_THROWS_AS(diagnoseArm(*makeTcpProblem(m, synthesizeTcp(m, so)), o), InputError);
  }
  // A design without drives cannot explain motor currents.
  {
    const Model m6 = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
    TrajectorySynthOptions ts;
    ts.duration_s = 0.5;
    TrajectoryData td = synthesizeTrajectory(m6, ts);
    td.currents = true;
    CHECK_THROWS_AS(makeTrajectoryProblem(m6, td), InputError);
  }
}

TEST_CASE(
    "trajectory: a joint that does not move makes its friction effects unidentifiable (warned)") {
  TrajectorySynthOptions so;
  so.duration_s = 2.0;
  so.rate_Hz = 40;
  so.noise = kTauNoise;
  so.still_joints = {"j4"};
  const auto P = makeTrajectoryProblem(design7(), synthesizeTrajectory(design7(), so));
  const ArmDiagnosis d = diagnoseArm(*P, {});
  bool warned = false;
  for (const auto& w : d.warnings)
    warned = warned || w.find("j4 does not move") != std::string::npos;
  CHECK(warned);
  int dead = 0;
  for (const auto& c : d.ranking)
    if (c.name.rfind("j4.", 0) == 0) {
      // coulomb/viscous/stribeck/asymmetry/load terms see no speed: no column at all.
      CHECK(c.status == "unidentifiable");
      ++dead;
    }
  CHECK(dead == 6);
}

TEST_CASE(
    "trajectory: accelerations from the Savitzky-Golay filter still find the hidden payload") {
  TrajectorySynthOptions so;
  so.duration_s = 3.0;
  so.rate_Hz = 100;
  so.noise = kTauNoise;
  so.hidden = {"payload"};
  so.write_qdd = false;
  const std::string dir = tmpDir("arm_sg");
  const Model& m = design7();
  writeFileAtomic(dir + "/run.csv", trajectoryDataToCsv(synthesizeTrajectory(m, so), false));
  const TrajectoryData data = readTrajectoryData(dir + "/run.csv", m);
  CHECK_FALSE(data.qdd_given);
  const ArmDiagnosis d = diagnoseArm(*makeTrajectoryProblem(m, data), {});
  REQUIRE(d.missing_effect_found);
  CHECK(d.ranking.front().name == "payload");
}

TEST_CASE(
    "CLI: synth -> fit --auto -> calibrated design -> compare (tcp and trajectory) - bad input "
    "exits 2") {
  namespace fs = std::filesystem;
  const std::string dir = tmpDir("arm_cli");
  const std::string bin = test::binaryPath();
  const std::string design = test::sourcePath("designs/final_prototype_7dof.toml");
  std::string out;
  // tcp
  REQUIRE(test::runCommand(bin + " synth " + design +
                               " --kind tcp --rows 50 --hide joint_offset.j3:offset=0.01 --noise "
                               "2e-4 --seed 3 --out " +
                               dir + "/tcp.csv",
                           out) == 0);
  REQUIRE(test::runCommand(bin + " fit " + design + " --kind tcp --data " + dir +
                               "/tcp.csv --auto --out " + dir + "/tcp",
                           out) == 0);
  INFO(out);
  auto j = nlohmann::json::parse(readFileOrThrow(dir + "/tcp/result.json"));
  CHECK(j["kind"] == "tcp");
  CHECK(j["ranking"][0]["effect"] == "joint_offset.j3");
  CHECK(j["ranking"][0]["significant"] == true);
  for (const char* k : {"rmse", "noise_estimate", "regions", "rmse_before", "rmse_after"})
    CHECK(j.contains(k));
  CHECK(j["rmse_after"].get<double>() <= kNoiseRatio * 2e-4);
  CHECK(fs::exists(dir + "/tcp/before_workspace_cells.vti"));
  CHECK(fs::exists(dir + "/tcp/after_residual_points.vtp"));
  // The calibrated copy has the offset in its joint table: compared as is, it meets the noise.
  const std::string cal_rel = j["calibrated_design"];
  CHECK_FALSE(fs::path(cal_rel).is_absolute());  // from result.json's folder
  const std::string cal = dir + "/tcp/" + cal_rel;
  REQUIRE(test::runCommand(bin + " compare " + cal + " --kind tcp --data " + dir +
                               "/tcp.csv --out " + dir + "/tcp",
                           out) == 0);
  j = nlohmann::json::parse(readFileOrThrow(dir + "/tcp/result.json"));
  CHECK(j["as_designed"]["rmse"].get<double>() <= kNoiseRatio * 2e-4);
  const std::string hist = readFileOrThrow(dir + "/tcp/history.csv");
  CHECK(std::count(hist.begin(), hist.end(), '\n') ==
        1 + 2 + 1);  // header, fit ladder (2), compare
  // trajectory with currents
  REQUIRE(test::runCommand(bin + " synth " + design +
                               " --kind trajectory --duration 2 --rate 40 --currents --noise 0.01 "
                               "--hide payload --out " +
                               dir + "/run.csv",
                           out) == 0);
  REQUIRE(test::runCommand(bin + " fit " + design + " --kind trajectory --data " + dir +
                               "/run.csv --add payload --out " + dir + "/traj",
                           out) == 0);
  j = nlohmann::json::parse(readFileOrThrow(dir + "/traj/result.json"));
  CHECK(j["kind"] == "trajectory");
  CHECK(j["added"][0] == "payload");
  CHECK(j["rmse_after"].get<double>() <= kNoiseRatio * 0.01);
  const Model cm = loadDesign(dir + "/traj/" + j["calibrated_design"].get<std::string>());
  CHECK(cm.payload_kg == Approx(design7().payload_kg + 0.5).margin(0.01));
  // Bad input: exit code 2 with a message.
  writeFileAtomic(dir + "/bad.csv", "q1,q2,x,y,z\n0,0,0,0,0\n");
  CHECK(test::runCommand(bin + " compare " + design + " --kind tcp --data " + dir +
                             "/bad.csv --out " + dir + "/bad",
                         out) == 2);
  CHECK(out.find("q3") != std::string::npos);
  CHECK(test::runCommand(
            bin + " compare " + design + " --kind tcp --drive j3 --data " + dir + "/tcp.csv",
            out) == 2);
}
