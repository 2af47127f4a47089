// The calibrated design of every kind (docs/calibration.md, "Outputs"): the written design TOML,
// read back by the design reader, holds each fitted value at full precision (compared with the
// fit's reported parameters, not with the writer's Model), and its model predicts what the fit
// predicted.
#include "calibration/calibrated_design.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <string>

#include "calibration/arm_calibration.hpp"
#include "calibration/drive_calibration.hpp"
#include "calibration/tcp_calibration.hpp"
#include "calibration/trajectory_calibration.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::calibration;

namespace {

constexpr double kPredictionRelative = 1e-9;     // the calibrated model's prediction vs the fit's
constexpr double kFrictionWidthFraction = 0.01;  // smooth sign, as for measured logs

std::map<std::string, double> fitted(const ArmDiagnosis& d) {
  std::map<std::string, double> p;
  for (const FittedParameter& x : d.final_fit.params) p[x.key] = x.value;
  return p;
}

double param(const std::map<std::string, double>& p, const std::string& key) {
  const auto it = p.find(key);
  if (it == p.end()) FAIL("no fitted parameter " << key);
  return it->second;
}

}  // namespace

TEST_CASE("calibrated design, drive: the refitted law and an added Stribeck term at full precision",
          "[calibration][design]") {
  const Model m = loadDesign(test::sourcePath("designs/final_prototype_9dof.toml"));
  SynthOptions so;
  so.seed = 2;
  so.hidden = {{drive::Effect::Stribeck, {}}};
  const DriveData data = synthesizeDrive(m, "j6", so);
  const auto P = makeDriveProblem(m, "j6", data);
  ArmFitOptions o;
  o.add = {"stribeck"};
  const ArmDiagnosis d = diagnoseArm(*P, o);
  REQUIRE(d.added.size() == 2);  // refit, then stribeck
  std::vector<std::string> notes;
  const Model back = parseDesign(calibratedDesign(m, *P, d.final_fit.values, notes).toml, "c.toml");
  const auto p = fitted(d);
  const Drive* dr = nullptr;
  for (const Drive& x : back.drives)
    if (x.joint == "j6") dr = &x;
  REQUIRE(dr != nullptr);
  for (const char* key : {"coulomb", "viscous", "load_coulomb", "load_viscous"})
    CHECK(dr->friction.at(key) == param(p, std::string("refit.") + key));
  CHECK(dr->friction.at("stribeck_torque") == param(p, "stribeck.stribeck_torque"));
  CHECK(dr->friction.at("stribeck_velocity") == param(p, "stribeck.stribeck_velocity"));
  CHECK(back.effects == std::vector<std::string>{"j6.stribeck"});
  const Eigen::MatrixXd y = makeDriveProblem(back, "j6", data)->predict({});
  CHECK((y - d.final_fit.predicted).cwiseAbs().maxCoeff() <=
        kPredictionRelative * d.final_fit.predicted.cwiseAbs().maxCoeff());
}

TEST_CASE("calibrated design, tcp: joint offsets, link lengths and the base pose at full precision",
          "[calibration][design]") {
  const Model m = loadDesign(test::sourcePath("designs/final_prototype_7dof.toml"));
  TcpSynthOptions so;
  so.rows = 50;
  so.noise_m = 2e-4;
  so.seed = 3;
  so.hidden = {"joint_offset.j3:offset=0.01", "link_length.j4.x:dx=0.005",
               "base_offset:x=0.002,y=-0.001,z=0.003,alpha=0,beta=0,gamma=0.001"};
  const TcpData data = synthesizeTcp(m, so);
  const auto P = makeTcpProblem(m, data);
  ArmFitOptions o;
  o.add = {"joint_offset.j3", "link_length.j4.x", "base_offset"};
  const ArmDiagnosis d = diagnoseArm(*P, o);
  REQUIRE(d.added.size() == 3);
  std::vector<std::string> notes;
  const CalibratedDesign c = calibratedDesign(m, *P, d.final_fit.values, notes);
  CHECK(c.urdf.empty());  // a design TOML gets no URDF
  CHECK(shownDesign(c.toml) == ShownDesign::calibrated_copy);
  const Model back = parseDesign(c.toml, "cal.toml");
  CHECK(back.name == m.name + "_calibrated");
  const auto p = fitted(d);
  const int j3 = m.jointIndex("j3"), j4 = m.jointIndex("j4");
  REQUIRE(m.joints[j3].type == JointType::Revolute);  // q adds to gamma
  CHECK(back.joints[j3].offset.gamma ==
        m.joints[j3].offset.gamma + param(p, "joint_offset.j3.offset"));
  CHECK(back.joints[j4].offset.x == m.joints[j4].offset.x + param(p, "link_length.j4.x.dx"));
  CHECK(back.base.x == m.base.x + param(p, "base_offset.x"));
  CHECK(back.base.y == m.base.y + param(p, "base_offset.y"));
  CHECK(back.base.z == m.base.z + param(p, "base_offset.z"));
  CHECK(back.base.gamma == m.base.gamma + param(p, "base_offset.gamma"));
  // Everything the fit did not touch is the design's.
  for (int j = 0; j < m.dof(); ++j)
    if (j != j3 && j != j4) CHECK(back.joints[j].T_PJ0.matrix() == m.joints[j].T_PJ0.matrix());
  // The calibrated design as designed predicts what the fit predicted.
  const auto Pc = makeTcpProblem(back, data);
  const Eigen::MatrixXd y = Pc->predict({});
  CHECK((y - d.final_fit.predicted).cwiseAbs().maxCoeff() <=
        kPredictionRelative * d.final_fit.predicted.cwiseAbs().maxCoeff());
}

TEST_CASE("calibrated design, trajectory: payload, link mass and drive friction at full precision",
          "[calibration][design]") {
  const Model m = loadDesign(test::sourcePath("designs/final_prototype_7dof.toml"));
  TrajectorySynthOptions so;
  so.duration_s = 3;
  so.rate_Hz = 40;
  so.seed = 5;
  so.hidden = {"payload", "link_mass.j3", "j3.stribeck", "rotor_inertia"};
  const TrajectoryData data = synthesizeTrajectory(m, so);
  const auto P = makeTrajectoryProblem(m, data);
  ArmFitOptions o;
  o.add = {"payload", "link_mass.j3", "j3.stribeck"};
  const ArmDiagnosis d = diagnoseArm(*P, o);
  REQUIRE(d.added.size() == 3);
  std::vector<std::string> notes;
  const CalibratedDesign c = calibratedDesign(m, *P, d.final_fit.values, notes);
  const Model back = parseDesign(c.toml, "cal.toml");
  const auto p = fitted(d);
  // Payload: mass m0 + dm, centre (m0 c0 + dh) / (m0 + dm) (docs/calibration.md).
  const double m0 = m.payload_kg, dm = param(p, "payload.mass");
  CHECK(back.payload_kg == m0 + dm);
  const Eigen::Vector3d dh(param(p, "payload.first_moment_x"), param(p, "payload.first_moment_y"),
                           param(p, "payload.first_moment_z"));
  const Eigen::Vector3d com = (m0 * m.p_payload_com_T + dh) / (m0 + dm);
  CHECK(back.p_payload_com_T == com);
  const int j3 = m.jointIndex("j3");
  CHECK(back.inertias[j3].mass_kg == m.inertias[j3].mass_kg + param(p, "link_mass.j3.mass"));
  const Drive* dr = nullptr;
  for (const Drive& x : back.drives)
    if (x.joint == "j3") dr = &x;
  REQUIRE(dr != nullptr);
  CHECK(dr->friction.at("stribeck_velocity") == param(p, "j3.stribeck.stribeck_velocity"));
  // The design's law lacks Stribeck: the added term is listed in [model] effects.
  CHECK(std::find(back.effects.begin(), back.effects.end(), "j3.stribeck") != back.effects.end());
  // The payload's own inertia goes into the last link's [[inertia]] (or is said not to); the
  // calibrated file's header says which.
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].find("the fitted payload's inertia about its centre of mass") !=
        std::string::npos);
  CHECK(c.toml.find("# " + notes[0]) != std::string::npos);

  // Rotor inertia is stored per drive as J_m + armature / N^2. Link mass and friction: the
  // calibrated design as designed predicts what the fit predicted. (The rotor_inertia candidate
  // adds its torque to the joint-side load, which the harmonic drives' load-dependent friction
  // sees; a drive's rotor inertia acts on the motor side, so the prediction is not compared here.)
  o.add = {"link_mass.j3", "j3.stribeck", "rotor_inertia"};
  const ArmDiagnosis d2 = diagnoseArm(*P, o);
  REQUIRE(d2.added.size() == 3);
  notes.clear();
  const Model back2 =
      parseDesign(calibratedDesign(m, *P, d2.final_fit.values, notes).toml, "c.toml");
  CHECK(notes.empty());
  const auto p2 = fitted(d2);
  for (std::size_t k = 0; k < m.drives.size(); ++k) {
    const Drive& dm = m.drives[k];
    const double N = dm.gear_ratio;
    CHECK(back2.drives[k].rotor_inertia_kgm2 ==
          dm.rotor_inertia_kgm2 + param(p2, "rotor_inertia.armature_" + dm.joint) / (N * N));
  }
  o.add = {"link_mass.j3", "j3.stribeck"};
  const ArmDiagnosis d3 = diagnoseArm(*P, o);
  const Model back3 =
      parseDesign(calibratedDesign(m, *P, d3.final_fit.values, notes).toml, "c.toml");
  const Eigen::MatrixXd y = makeTrajectoryProblem(back3, data)->predict({});
  CHECK((y - d3.final_fit.predicted).cwiseAbs().maxCoeff() <=
        kPredictionRelative * d3.final_fit.predicted.cwiseAbs().maxCoeff());
}

TEST_CASE(
    "calibrated design, joint-side terms of measured logs: [[joint]] coulomb, viscous, armature "
    "and effort offset at full precision",
    "[calibration][design]") {
  const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  const int j = 1;
  const std::string n = m.joints[j].name;
  TrajectorySynthOptions so;
  so.duration_s = 4.0;
  so.rate_Hz = 100;
  so.noise = 0.01;
  so.seed = 8;
  TrajectoryData data = synthesizeTrajectory(m, so);
  data.friction_width_fraction = kFrictionWidthFraction;
  const double w = kFrictionWidthFraction * data.qd.col(j).cwiseAbs().maxCoeff();
  for (int i = 0; i < data.rows(); ++i)
    data.measured(i, j) +=
        1.5 * std::tanh(data.qd(i, j) / w) + 0.8 * data.qd(i, j) + 0.04 * data.qdd(i, j) + 0.3;
  const auto P = makeTrajectoryProblem(m, data);
  ArmFitOptions o;
  o.add = {n + ".coulomb", n + ".viscous", n + ".armature", n + ".offset"};
  const ArmDiagnosis d = diagnoseArm(*P, o);
  REQUIRE(d.added.size() == 4);
  std::vector<std::string> notes;
  const CalibratedDesign c = calibratedDesign(m, *P, d.final_fit.values, notes);
  const Model back = parseDesign(c.toml, "cal.toml");
  const auto p = fitted(d);
  const JointDynamics& jd = back.joints[j].dynamics;
  CHECK(jd.coulomb == param(p, n + ".coulomb.coulomb"));
  CHECK(jd.viscous == param(p, n + ".viscous.viscous"));
  CHECK(jd.armature == param(p, n + ".armature.armature"));
  CHECK(jd.effort_offset == param(p, n + ".offset.offset"));
  for (int k = 0; k < m.dof(); ++k)
    if (k != j) CHECK_FALSE(back.joints[k].dynamics.any());
  // The calibrated design as designed predicts what the fit predicted, and its own catalogue
  // starts from the written values: nothing left to add for that joint.
  const auto Pc = makeTrajectoryProblem(back, data);
  const Eigen::MatrixXd y = Pc->predict({});
  CHECK((y - d.final_fit.predicted).cwiseAbs().maxCoeff() <=
        kPredictionRelative * d.final_fit.predicted.cwiseAbs().maxCoeff());
}
