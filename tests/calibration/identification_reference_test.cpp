// The identification report's comparison with a reference on the joint side (docs/calibration.md,
// "The TX40 on its logs"): a joint turned by a coupled motor compares its viscous and armature
// terms as the coefficient of its own speed or acceleration in its own channel (its own term plus
// the motor's, times the squared ratio); the motor's own terms compare as they are. Efforts are the
// design's prediction plus the planted terms written out by hand plus Gaussian noise.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "calibration/arm_calibration.hpp"
#include "calibration/identification_report.hpp"
#include "calibration/trajectory_calibration.hpp"
#include "common/rng.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::calibration;

namespace {

constexpr double kNoise = 0.02;                   // N m, Gaussian
constexpr double kRecoveredRelative = 0.03;       // fitted against planted, relative
constexpr double kReferenceWidthFraction = 0.01;  // smooth sign, as for measured logs

double metric(const IdentificationReport& r, const std::string& name) {
  for (const auto& [k, v] : r.metrics)
    if (k == name) return v;
  FAIL("no metric " << name);
  return NAN;
}

}  // namespace

TEST_CASE(
    "identification report: a joint turned by a coupled motor compares its viscous and armature "
    "terms on the joint side") {
  const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  const int j5 = 4, j6 = 5;
  TrajectorySynthOptions so;
  so.duration_s = 6.0;
  so.rate_Hz = 100;
  so.noise = 0;
  so.seed = 21;
  TrajectoryData data = synthesizeTrajectory(m, so);
  data.friction_width_fraction = kReferenceWidthFraction;
  // Motor 6 turns with joint 6 (ratio 40) and joint 5 (ratio 20): r = R_65 / R_66 = 0.5.
  data.coupling = Eigen::MatrixXd::Identity(6, 6);
  data.coupling(j6, j6) = 40;
  data.coupling(j6, j5) = 20;
  const double r = 0.5;
  // Planted (motor physics): the joints' own viscous and armature terms and the motor's, at the
  // motor speed r qd5 + qd6, reaching joint 5 as r times its torque and joint 6 as once.
  const double own_b5 = 0.7, own_b6 = 0.4, motor_b = 0.6;
  const double own_a5 = 0.05, own_a6 = 0.02, motor_a = 0.03;
  rng::SplitMix64 rng{2021};
  for (int i = 0; i < data.rows(); ++i) {
    const double vm = r * data.qd(i, j5) + data.qd(i, j6),
                 am = r * data.qdd(i, j5) + data.qdd(i, j6);
    const double tm = motor_b * vm + motor_a * am;
    data.measured(i, j5) += own_b5 * data.qd(i, j5) + own_a5 * data.qdd(i, j5) + r * tm;
    data.measured(i, j6) += own_b6 * data.qd(i, j6) + own_a6 * data.qdd(i, j6) + tm;
    for (int j = 0; j < m.dof(); ++j) data.measured(i, j) += kNoise * rng.normal();
  }
  const auto P = makeTrajectoryProblem(m, data);
  const std::string n5 = m.joints[j5].name, n6 = m.joints[j6].name;
  ArmFitOptions o;
  o.add = {n5 + ".viscous",  n6 + ".viscous",  "motor_" + n6 + ".viscous",
           n5 + ".armature", n6 + ".armature", "motor_" + n6 + ".inertia"};
  const ArmDiagnosis d = diagnoseArm(*P, o);
  // The fit separates the three terms (their columns differ): the planted motor physics back.
  for (const FittedParameter& p : d.final_fit.params) {
    INFO(p.key << " = " << p.value);
    if (p.key == n5 + ".viscous.viscous")
      CHECK(p.value == Approx(own_b5).epsilon(kRecoveredRelative));
    if (p.key == "motor_" + n6 + ".viscous.viscous")
      CHECK(p.value == Approx(motor_b).epsilon(kRecoveredRelative));
  }
  // A reference on the joint side (the coefficient of qd_j in tau_j, and the motor's own term).
  IdentificationInput in;
  in.reference_source = "planted, joint side";
  in.reference = {
      {n5 + ".viscous", own_b5 + r * r * motor_b}, {n6 + ".viscous", own_b6 + motor_b},
      {"motor_" + n6 + ".viscous", motor_b},       {n5 + ".armature", own_a5 + r * r * motor_a},
      {n6 + ".armature", own_a6 + motor_a},        {"motor_" + n6 + ".inertia", motor_a}};
  const IdentificationReport rep = identificationReport(d, *P, m, data, in);
  INFO(rep.markdown);
  for (const auto& [name, ref] : in.reference) {
    INFO(name << ": reference " << ref << ", compared " << metric(rep, "fit/" + name));
    CHECK(std::abs(metric(rep, "reference_difference/" + name)) <= kRecoveredRelative);
  }
  // The table says what each joint-side value is made of.
  CHECK(rep.markdown.find(" = " + n5 + ".viscous") != std::string::npos);
  CHECK(rep.markdown.find("0.25 x motor_" + n6 + ".viscous") != std::string::npos);
}

TEST_CASE(
    "identification report: an armature its link's inertia about the joint axis explains is named "
    "beside its value") {
  // Efforts of the design with joint j2's link 0.05 kg m^2 heavier about its axis (the first
  // revolute joint after the lift: nothing before it turns, so that inertia acts as I qdd2 in the
  // j2 channel only, like an armature), fitted with the design as is plus j2.armature.
  const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  const int j2 = m.jointIndex("j2");
  REQUIRE(j2 >= 0);
  const double extra = 0.05;  // kg m^2
  Model heavier = m;
  heavier.inertias[j2].I_com_kgm2(2, 2) += extra;
  TrajectorySynthOptions so;
  so.duration_s = 4.0;
  so.rate_Hz = 50;
  so.noise = kNoise;
  so.seed = 23;
  TrajectoryData data = synthesizeTrajectory(heavier, so);
  data.friction_width_fraction = kReferenceWidthFraction;
  const auto P = makeTrajectoryProblem(m, data);
  ArmFitOptions o;
  o.add = {"j2.armature"};
  const ArmDiagnosis d = diagnoseArm(*P, o);
  // The scenario: the armature takes the whole link inertia (the two columns are one).
  REQUIRE(d.final_fit.params.size() == 1);
  CHECK(d.final_fit.params.front().value == Approx(extra).epsilon(kRecoveredRelative));
  IdentificationInput in;
  in.reference_source = "planted";
  in.reference = {{"j2.armature", 0.0}, {"j2.viscous", 0.0}};
  const IdentificationReport rep = identificationReport(d, *P, m, data, in);
  INFO(rep.markdown);
  CHECK(metric(rep, "indistinguishable/j2.armature") == 1.0);
  CHECK(metric(rep, "indistinguishable/j2.viscous") == 0.0);
  CHECK(rep.markdown.find("the inertia of j2's link about its axis") != std::string::npos);
  bool answered = false;
  for (const std::string& a : rep.answer)
    answered =
        answered ||
        a.find("j2.armature 0.0501 / 0 (cannot be told apart from the inertia of j2's link") !=
            std::string::npos;
  CHECK(answered);
}
