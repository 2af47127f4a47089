// The pattern guard of the selection rule (docs/calibration.md "Selection rule"): a residual
// pattern no catalogue effect explains holds back only the candidates whose gain is that pattern
// (rotor_inertia soaking up a slow ripple: model_vs_measurement_test.cpp), not a separate effect of
// the same channel. Efforts are the design's prediction plus closed-form extras plus Gaussian
// noise.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "calibration/arm_calibration.hpp"
#include "calibration/trajectory_calibration.hpp"
#include "common/rng.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::calibration;

namespace {

constexpr double kGuardNoise = 0.05;                // N m, Gaussian
constexpr double kCoulombRecoveredRelative = 0.10;  // the planted Coulomb level, relative
constexpr double kGuardWidthFraction = 0.01;        // smooth sign, as for measured logs

}  // namespace

TEST_CASE(
    "pattern guard: Coulomb friction beside a stronger ripple outside the catalogue in the same "
    "channel is added, the ripple stays a remainder") {
  // The 6-DoF prototype has no [[drive]]: every joint gets coulomb, viscous, offset, armature.
  const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  const int j3 = m.jointIndex("j3");
  // Joint 3: a Coulomb step of 0.3 N m and a position ripple of 0.5 N m amplitude, 12 periods per
  // radian (cogging; no catalogue effect has it). The ripple is the channel's strongest pattern and
  // Coulomb friction alone does not halve the channel's error (RMS 0.3 against 0.35 of ripple).
  const double coulomb = 0.3, ripple = 0.5, per_rad = 12;
  TrajectorySynthOptions so;
  so.duration_s = 4.0;
  so.rate_Hz = 50;
  so.noise = 0;
  so.seed = 11;
  TrajectoryData data = synthesizeTrajectory(m, so);
  data.friction_width_fraction = kGuardWidthFraction;
  double peak = 0;
  for (int i = 0; i < data.rows(); ++i) peak = std::max(peak, std::abs(data.qd(i, j3)));
  const double w = kGuardWidthFraction * peak;
  rng::SplitMix64 rng{1011};
  for (int i = 0; i < data.rows(); ++i)
    for (int j = 0; j < m.dof(); ++j) {
      double extra = 0;
      if (j == j3)
        extra = coulomb * std::tanh(data.qd(i, j) / w) + ripple * std::sin(per_rad * data.q(i, j));
      data.measured(i, j) += extra + kGuardNoise * rng.normal();
    }
  const auto P = makeTrajectoryProblem(m, data);
  ArmFitOptions o;
  o.auto_add = true;
  const ArmDiagnosis d = diagnoseArm(*P, o);
  INFO(d.verdict);
  // The scenario: the ripple is the strongest pattern and the Coulomb term does not halve tau3.
  const ArmCandidate* first = nullptr;
  for (const ArmCandidate& c : d.ranking)
    if (c.name == "j3.coulomb") first = &c;
  REQUIRE(first != nullptr);
  std::string why;
  for (const std::string& x : first->warnings) why += x + " | ";
  INFO(why);
  const double before = d.as_designed.heldout_residual.col(j3).squaredNorm(),
               after = first->fit.heldout_residual.col(j3).squaredNorm();
  CHECK(after > 0.25 * before);
  CHECK(why.find("periodic in q3") != std::string::npos);
  // The Coulomb term is significant, added and recovered; nothing else of joint 3 is added.
  CHECK(first->significant);
  bool added = false;
  for (const std::string& a : d.added) {
    added = added || a == "j3.coulomb";
    CHECK((a == "j3.coulomb" || a.rfind("j3.", 0) != 0));
  }
  CHECK(added);
  for (const FittedParameter& p : d.final_fit.params)
    if (p.key == "j3.coulomb.coulomb")
      CHECK(p.value == Approx(coulomb).epsilon(kCoulombRecoveredRelative));
  // The ripple stands as what the catalogue leaves in tau3, following q3.
  const ArmRemainder* r = nullptr;
  for (const ArmRemainder& x : d.remainders)
    if (x.channel == "tau3") r = &x;
  REQUIRE(r != nullptr);
  INFO(r->text());
  CHECK(r->variable == "q3");
}
