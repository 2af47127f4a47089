// Friction laws and drive chain: closed forms from the thesis tables, sign conventions, finite
// differences of the exposed derivatives, design-file validation.
#include "drive/friction.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "common/errors.hpp"
#include "drive/drive_chain.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::drive;

namespace {

constexpr double kClosedForm = 1e-12;  // relative agreement with a hand-evaluated formula

Drive csd20Catalog() {  // Table A.2 module B.2 with the Table C.1 CSD-20-100 catalog fit
  Drive d;
  d.joint = "j6";
  d.gear_ratio = 100;
  d.torque_constant_NmpA = 0.075;
  d.friction_law = "harmonic_drive";
  d.friction = {
      {"coulomb", 8.02e-2}, {"load_coulomb", 0.0}, {"viscous", 1.51e-4}, {"load_viscous", 7.23e-6}};
  return d;
}

Drive b2Measured() {  // Table 4.4 module B.2, eq. (3.33)
  Drive d = csd20Catalog();
  d.friction_law = "stribeck";
  d.friction = {{"coulomb", 1.36e-1},
                {"load_coulomb", 4.4e-3},
                {"viscous", 1.95e-5},
                {"stribeck_torque", 4.77e-2},
                {"stribeck_velocity", 65.2}};
  return d;
}

std::string designWithDrive(const std::string& drive_extra, const std::string& model_section = "") {
  return R"([design]
name = "t"
[[joint]]
name = "j1"
type = "revolute"
x = 0
y = 0
z = 0
alpha = 0
beta = 0
gamma = 0
min = -3
max = 3
[tcp]
z = 0.1
[[drive]]
joint = "j1"
gear_ratio = 100
torque_constant = 0.075
)" + drive_extra +
         "\n" + model_section;
}

}  // namespace

TEST_CASE("eq. 3.30 with the Table C.1 CSD-20-100 fit: closed form / odd in speed / even in load") {
  const Drive d = csd20Catalog();
  const double phi = 104.7, Tl = 9.0;
  const double expect = 8.02e-2 + 0.0 * Tl + 1.51e-4 * phi + 7.23e-6 * Tl * phi;
  CHECK(frictionTorque(d, phi, Tl, 30) == Approx(expect).epsilon(kClosedForm));
  CHECK(frictionTorque(d, -phi, -Tl, 30) == Approx(-expect).epsilon(kClosedForm));
  CHECK(frictionTorque(d, -phi, Tl, 30) ==
        Approx(-expect).epsilon(kClosedForm));   // assisting load: |T_l|
  CHECK(frictionTorque(d, 0.0, Tl, 30) == 0.0);  // standstill
}

TEST_CASE("eq. 3.33 with Table 4.4 B.2: limits at standstill / at v_S and at high speed") {
  const FrictionParams p = frictionParams(b2Measured(), {});
  const double Tl = 10, mu = 4.4e-3, T0 = 1.36e-1, TS = 4.77e-2, b = 1.95e-5, vS = 65.2;
  // Just above standstill the loss approaches T_S + mu |T_l| (the Stribeck level).
  CHECK(frictionTorque(p, 1e-9, Tl, 30) == Approx(TS + mu * Tl).epsilon(1e-9));
  // At v = v_S the Stribeck fraction is one half.
  CHECK(frictionTorque(p, vS, Tl, 30) ==
        Approx(T0 + mu * Tl + b * vS + 0.5 * (TS - T0)).epsilon(kClosedForm));
  // Far above v_S it is the Coulomb + viscous line.
  const double v = 1e5;
  CHECK(frictionTorque(p, v, Tl, 30) ==
        Approx(T0 + mu * Tl + b * v + (TS - T0) / (1 + (v / vS) * (v / vS))).epsilon(kClosedForm));
  CHECK(frictionTorque(p, -vS, -Tl, 30) ==
        Approx(-frictionTorque(p, vS, Tl, 30)).epsilon(kClosedForm));
}

TEST_CASE("eq. 3.35 prismatic law (Table 3.9) acts on the joint side and is reflected through N") {
  Drive d;
  d.joint = "j1";
  d.gear_ratio = 2.0 / 0.07385;  // cog wheel d = 73.85 mm
  d.torque_constant_NmpA = 0.56;
  d.friction_law = "prismatic";
  d.friction = {{"coulomb", 67.41}, {"viscous", 22.97}};
  const double qd = 0.2;  // m/s
  const double F = 67.41 + 22.97 * qd;
  CHECK(frictionTorque(d, d.gear_ratio * qd, 100.0, 20) ==
        Approx(F / d.gear_ratio).epsilon(kClosedForm));
  // Drive chain: T_a = (Q + F_f) / N (thesis eq. 3.27a, prismatic).
  const MotorState s = motorState(d, frictionParams(d, {}), qd, 0.0, 150.0, 20);
  CHECK(s.motor_torque_Nm == Approx((150.0 + F) / d.gear_ratio).epsilon(kClosedForm));
  CHECK(s.current_A == Approx(s.motor_torque_Nm / 0.56).epsilon(kClosedForm));
}

TEST_CASE("effect terms: asymmetry and temperature - effectTorque sums to frictionTorque") {
  Drive d = csd20Catalog();
  d.friction["asymmetry"] = 0.01;
  d.friction["temperature_coefficient"] = -2e-3;
  d.friction["reference_temperature"] = 20;
  d.friction["stribeck_torque"] = 0.03;
  d.friction["stribeck_velocity"] = 50;
  const FrictionParams p =
      frictionParams(d, {Effect::Asymmetry, Effect::Temperature, Effect::Stribeck});
  const double plus = frictionTorque(p, 200, 5, 40), minus = frictionTorque(p, -200, -5, 40);
  // Asymmetry: the + direction loses 2 d more than the - direction loses in magnitude.
  CHECK(plus + minus == Approx(2 * 0.01).epsilon(kClosedForm));
  const FrictionParams p2 =
      frictionParams(d, {Effect::Asymmetry, Effect::Temperature, Effect::Stribeck});
  CHECK(frictionTorque(p2, 200, 5, 30) - frictionTorque(p2, 200, 5, 40) ==
        Approx(-2e-3 * (30 - 40)).epsilon(1e-10));
  double sum = 0;
  for (Effect e : kAllEffects) sum += effectTorque(p, e, 123.0, 7.0, 33.0);
  CHECK(sum == Approx(frictionTorque(p, 123.0, 7.0, 33.0)).epsilon(kClosedForm));
}

TEST_CASE("friction derivatives agree with central differences (all terms on / both directions)") {
  Drive d = b2Measured();
  d.friction["load_viscous"] = 7e-6;
  d.friction["asymmetry"] = 0.01;
  const FrictionParams p = frictionParams(d, {Effect::LoadViscous, Effect::Asymmetry});
  const double h = 1e-4;
  for (double phi : {-300.0, -40.0, -3.0, 2.0, 65.0, 250.0})
    for (double Tl : {-12.0, -1.0, 0.5, 9.0}) {
      const FrictionDerivatives g = frictionDerivatives(p, phi, Tl, 30);
      const double ds =
          (frictionTorque(p, phi + h, Tl, 30) - frictionTorque(p, phi - h, Tl, 30)) / (2 * h);
      const double dl =
          (frictionTorque(p, phi, Tl + h, 30) - frictionTorque(p, phi, Tl - h, 30)) / (2 * h);
      CHECK(g.d_speed == Approx(ds).margin(test::kFdTolerance));
      CHECK(g.d_load == Approx(dl).margin(test::kFdTolerance));
    }
}

TEST_CASE(
    "drive chain: motor speed / torque with rotor inertia / current (eq. 4.5) / voltage (eq. 3.29) "
    "/ limits") {
  Drive d = csd20Catalog();
  d.rotor_inertia_kgm2 = 1.5e-5;
  d.resistance_ohm = 0.9;
  d.inductance_H = 1e-3;
  d.max_voltage_V = 48;
  d.peak_current_A = 5;
  d.max_motor_speed_radps = 366.52;
  const FrictionParams p = frictionParams(d, {});
  const double qd = 2.0, qdd = 10.0, Q = 12.0;
  const MotorState s = motorState(d, p, qd, qdd, Q, 25, 50.0);
  const double phi = 100 * qd;
  const double Ta = Q / 100 + frictionTorque(d, phi, Q, 25) + 1.5e-5 * 100 * qdd;
  CHECK(s.motor_speed_radps == Approx(phi).epsilon(kClosedForm));
  CHECK(s.motor_torque_Nm == Approx(Ta).epsilon(kClosedForm));
  CHECK(s.current_A == Approx(Ta / 0.075).epsilon(kClosedForm));
  REQUIRE(s.voltage_known);
  CHECK(s.voltage_V == Approx(1e-3 * 50.0 + 0.9 * Ta / 0.075 + 0.075 * phi).epsilon(kClosedForm));
  CHECK_FALSE(s.over.any());
  DriveChainOptions no_rotor;
  no_rotor.include_rotor_inertia = false;
  CHECK(motorState(d, p, qd, qdd, Q, 25, 0, no_rotor).motor_torque_Nm ==
        Approx(Q / 100 + frictionTorque(d, phi, Q, 25)).epsilon(kClosedForm));
  const MotorState fast = motorState(d, p, 4.0, 0, 40.0, 25);  // 400 rad/s, 40 N m
  CHECK(fast.over.motor_speed);
  CHECK(fast.over.peak_current);
  // Test bed balance (eq. 4.3): k_m I = T_l / N + T_loss.
  CHECK(0.075 * testBedCurrent(d, p, -150, -8, 25) ==
        Approx(-8.0 / 100 + frictionTorque(d, -150, -8, 25)));
}

TEST_CASE("shipped final prototypes carry Table A.2 / C.1 / 3.9 drive data") {
  for (const char* f : {"designs/final_prototype_9dof.toml", "designs/final_prototype_7dof.toml"}) {
    const Model m = loadDesign(test::sourcePath(f));
    CHECK(m.drives.size() == static_cast<std::size_t>(m.dof()));
    for (const Drive& d : m.drives) {
      std::string key;
      CHECK(validateFriction(d, extraEffects(m, d.joint), key).empty());
      if (d.joint == "j2") {
        CHECK(d.gear_ratio == 50);
        CHECK(d.friction.at("coulomb") == 0.251);  // CPL-32-50
      }
      if (d.joint == "j1") CHECK(d.friction_law == "prismatic");
    }
  }
}

TEST_CASE("design validation of friction sections and model effects names file / line and key") {
  auto fails = [](const std::string& text, const std::string& key_part) {
    try {
      parseDesign(text, "bad.toml");
    } catch (const InputError& e) {
      INFO(e.what());
      CHECK(e.file() == "bad.toml");
      CHECK(e.line() > 0);
      CHECK(e.key().find(key_part) != std::string::npos);
      return true;
    }
    return false;
  };
  CHECK(fails(designWithDrive("[drive.friction]\nlaw = \"magic\"\n"), "friction.law"));
  CHECK(fails(designWithDrive("[drive.friction]\nlaw = \"harmonic_drive\"\ncoulomb = 0.1\n"),
              "friction."));
  CHECK(fails(designWithDrive("[drive.friction]\nlaw = \"prismatic\"\ncoulomb = -1\nviscous = 1\n"),
              "friction.coulomb"));
  CHECK(fails(designWithDrive("[drive.friction]\nlaw = \"none\"\nasymmetry = 0.1\n"),
              "friction.asymmetry"));
  CHECK(fails(designWithDrive("[drive.friction]\nlaw = \"none\"\n",
                              "[model]\neffects = [\"j1.stribek\"]\n"),
              "model.effects"));
  CHECK(fails(designWithDrive("[drive.friction]\nlaw = \"none\"\n",
                              "[model]\neffects = [\"j1.stribeck\"]\n"),
              "friction.stribeck"));
  CHECK(fails(designWithDrive("[drive.friction]\nlaw = \"none\"\n",
                              "[model]\neffects = [\"j9.coulomb\"]\n"),
              "model.effects"));
  // A valid composite: law none plus effects with their parameters.
  const Model m = parseDesign(
      designWithDrive("[drive.friction]\nlaw = \"none\"\ncoulomb = 0.1\nasymmetry = 0.01\n",
                      "[model]\neffects = [\"j1.coulomb\", \"j1.asymmetry\"]\n"),
      "ok.toml");
  const FrictionParams p = frictionParams(m, m.drives[0]);
  CHECK(p.has(Effect::Coulomb));
  CHECK(p.has(Effect::Asymmetry));
  CHECK(frictionTorque(p, 10, 0, 20) == Approx(0.11).epsilon(kClosedForm));
}
