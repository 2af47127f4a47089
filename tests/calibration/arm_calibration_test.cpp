// Model versus measurement for arms (kinds tcp and trajectory): every hidden effect of both
// catalogues must rank first in synthetic data and bring the held-out RMSE to the injected noise,
// nothing hidden must give "no significant missing effect", identifiability and bad input are
// reported, and the Savitzky-Golay derivative matches a closed form.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "calibration/arm_calibration.hpp"
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

constexpr double kNoiseRatio = 1.2;        // issue 7: held-out RMSE after the fix <= 1.2 x noise
constexpr double kTcpNoise_m = 2e-4;       // injected TCP position noise
constexpr double kTauNoise = 0.05;         // injected effort noise [N m | N]
constexpr double kSgTolerance = 2e-3;      // relative error of the SG derivative of a slow sine
constexpr double kSgEndTolerance = 1e-2;   // at the ends, where the window is shifted inside
constexpr int kTcpRows = 50;

const Model& design7() {
  static const Model m = loadDesign(test::sourcePath("designs/final_prototype_7dof.toml"));
  return m;
}

struct Outcome {
  ArmDiagnosis d;       // after adding the effect
  std::string first;    // best candidate of the design as is
  bool significant = false;
};

Outcome fitWith(const ArmProblem& P, const std::string& add_first_ranked) {
  ArmFitOptions o;
  Outcome r;
  r.d = diagnoseArm(P, o);
  r.first = r.d.ranking.empty() ? "" : r.d.ranking.front().name;
  r.significant = !r.d.ranking.empty() && r.d.ranking.front().significant && r.d.missing_effect_found;
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

TEST_CASE("tcp: every hidden effect ranks first and adding it brings the held-out RMSE to the noise") {
  const Model& m = design7();
  const char* hidden[] = {"joint_offset.j3", "link_length.j4.x", "base_offset", "joint_compliance.j3"};
  for (const char* h : hidden) {
    TcpSynthOptions so;
    so.rows = kTcpRows;
    so.noise_m = kTcpNoise_m;
    so.seed = 11;
    so.hidden = {h};
    const TcpData data = synthesizeTcp(m, so);
    const auto P = makeTcpProblem(m, data);
    const Outcome r = fitWith(*P, h);
    INFO("hidden " << h << ", first " << r.first << ", before " << r.d.rmse_before << ", after " << r.d.rmse_after);
    CHECK(r.first == h);
    CHECK(r.significant);
    CHECK(r.d.added == std::vector<std::string>{h});
    CHECK(r.d.rmse_after <= kNoiseRatio * kTcpNoise_m);
    CHECK(r.d.as_designed_map.flagged() > 0);
  }
}

TEST_CASE("tcp: nothing hidden gives no significant missing effect; noise estimate near the injected noise") {
  TcpSynthOptions so;
  so.rows = kTcpRows;
  so.noise_m = kTcpNoise_m;
  so.seed = 5;
  const auto P = makeTcpProblem(design7(), synthesizeTcp(design7(), so));
  const ArmDiagnosis d = diagnoseArm(*P, {});
  CHECK_FALSE(d.missing_effect_found);
  CHECK(d.noise_estimate == Approx(kTcpNoise_m).epsilon(0.35));
  CHECK(d.as_designed_map.flagged() == 0);
}

TEST_CASE("tcp: identifiability warnings (lift offset vs base z, compliance of the lift vs its offset)") {
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

TEST_CASE("trajectory: every hidden effect ranks first and adding it brings the held-out RMSE to the noise") {
  const Model& m = design7();
  const char* hidden[] = {"payload",      "rotor_inertia", "gravity_tilt", "link_mass.j3",    "j3.coulomb",
                          "j3.viscous",   "j4.load_coulomb", "j4.load_viscous", "j3.stribeck", "j3.asymmetry"};
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
    INFO("hidden " << h << ", first " << r.first << ", before " << r.d.rmse_before << ", after " << r.d.rmse_after);
    CHECK(r.first == h);
    CHECK(r.significant);
    CHECK(r.d.added == std::vector<std::string>{h});
    CHECK(r.d.rmse_after <= kNoiseRatio * kTauNoise);
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
