// The selection rule on data made to fool it (docs/calibration.md "Selection rule"): a catalogue
// effect overlapping an effect outside the catalogue is still added and the rest is reported as a
// remainder; a torque offset and a link mass that the data cannot tell apart are named, and the
// impossible (negative) mass is refused; a channel quantised at the logging resolution is not
// identifiable. Efforts are the design's prediction plus a closed-form extra plus Gaussian noise.
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

// The 6-DoF prototype has no [[drive]]: with a smooth-sign width (as for measured logs) every
// joint gets the joint-side terms coulomb, viscous, offset, armature.
const Model& design6Dof() {
  static const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  return m;
}

template <class Extra>
TrajectoryData dataWith(const Model& m, double noise, std::uint64_t seed, Extra extra,
                        std::vector<std::string> still = {}) {
  TrajectorySynthOptions so;
  so.duration_s = 4.0;
  so.rate_Hz = 50;
  so.noise = 0;
  so.seed = seed;
  so.still_joints = std::move(still);
  TrajectoryData d = synthesizeTrajectory(m, so);
  d.friction_width_fraction = 0.01;
  rng::SplitMix64 rng{seed + 1000};
  for (int i = 0; i < d.rows(); ++i)
    for (int j = 0; j < m.dof(); ++j) d.measured(i, j) += extra(d, i, j) + noise * rng.normal();
  return d;
}

bool containsPart(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE(
    "selection rule: viscous friction overlapping a cubic speed term outside the catalogue is "
    "added, the rest is a remainder") {
  const Model& m = design6Dof();
  const int j3 = m.jointIndex("j3");
  const double b = 2.0, k3 = 0.5;  // N m s/rad, N m s^3/rad^3
  const TrajectoryData data = dataWith(m, 0.05, 5, [&](const TrajectoryData& d, int i, int j) {
    if (j != j3) return 0.0;
    const double v = d.qd(i, j);
    return b * v + k3 * v * v * v;
  });
  const auto P = makeTrajectoryProblem(m, data);
  ArmFitOptions o;
  o.auto_add = true;
  const ArmDiagnosis d = diagnoseArm(*P, o);
  INFO(d.verdict);
  // The catalogue effect that halves the channel's error is added although a pattern remains.
  bool viscous = false;
  for (const std::string& a : d.added) viscous = viscous || a == "j3.viscous";
  CHECK(viscous);
  CHECK_FALSE(containsPart(d.verdict, "no catalogue effect explains it"));
  // What stands is a remainder of tau3 against the joint's speed, with its size and share, and it
  // is among the warnings.
  const ArmRemainder* r = nullptr;
  for (const ArmRemainder& x : d.remainders)
    if (x.channel == "tau3") r = &x;
  REQUIRE(r != nullptr);
  INFO(r->text());
  CHECK(containsPart(r->variable, "qd3"));
  CHECK(r->explained_by_catalogue);
  CHECK(r->rms > 0);
  CHECK(r->share_final > 0);
  CHECK(r->share_final <= 1);
  CHECK(r->rmse_final <= 0.5 * r->rmse_design);
  bool warned = false;
  for (const std::string& w : d.warnings) warned = warned || containsPart(w, "remainder in tau3");
  CHECK(warned);
}

TEST_CASE(
    "physical consistency: an offset and a link mass the data cannot tell apart are named, the "
    "negative mass is refused") {
  const Model& m = design6Dof();
  const int j1 = m.jointIndex("j1");  // the lift: its link's weight is nearly a constant force
  const double g = 9.81, m1 = m.inertias[j1].mass_kg;
  // The lift force reads (m1 + 1) g low (a controller compensating gravity): a link mass
  // explaining it would be -1 kg.
  const double shift = -(m1 + 1.0) * g;
  const TrajectoryData data = dataWith(
      m, 0.05, 7, [&](const TrajectoryData&, int, int j) { return j == j1 ? shift : 0.0; });
  const auto P = makeTrajectoryProblem(m, data);
  ArmFitOptions o;
  o.auto_add = true;
  const ArmDiagnosis d = diagnoseArm(*P, o);
  INFO(d.verdict);
  const ArmCandidate* mass = nullptr;
  for (const ArmCandidate& c : d.ranking)
    if (c.name == "link_mass.j1") mass = &c;
  // The first ranking (before the offset is added) has both: the pair is named and the mass that
  // would be negative is refused with its value.
  ArmFitOptions once;
  const ArmDiagnosis r0 = diagnoseArm(*P, once);
  const ArmCandidate* mass0 = nullptr;
  for (const ArmCandidate& c : r0.ranking)
    if (c.name == "link_mass.j1") mass0 = &c;
  REQUIRE(mass0 != nullptr);
  std::string why;
  for (const std::string& w : mass0->warnings) why += w + " | ";
  INFO(why);
  CHECK(mass0->status == "impossible");
  CHECK_FALSE(mass0->significant);
  CHECK(containsPart(why, "refused: link_mass.j1.mass would be -"));
  bool named = false;
  for (const std::string& n : mass0->indistinguishable) named = named || n == "j1.offset";
  CHECK(named);
  // The fit adds the offset and never a link mass at or below zero.
  bool offset = false;
  for (const std::string& a : d.added) {
    offset = offset || a == "j1.offset";
    CHECK(a.rfind("link_mass", 0) != 0);
  }
  CHECK(offset);
  for (const FittedParameter& p : d.final_fit.params)
    if (p.key == "j1.offset.offset") CHECK(p.value == Approx(shift).epsilon(0.02));
  if (mass) CHECK_FALSE(mass->significant);
}

TEST_CASE("identifiability at the floor: a channel quantised at 0.02 N m is not identifiable") {
  const Model& m = design6Dof();
  const int j6 = m.jointIndex("j6");
  const double q = 0.02;
  // A small viscous term on the wrist j6 (0.01 N m s/rad) below the logging resolution, then the
  // channel quantised as a logger would write it.
  TrajectoryData data = dataWith(m, 0.003, 11, [&](const TrajectoryData& d, int i, int j) {
    return j == j6 ? 0.01 * d.qd(i, j) : 0.0;
  });
  // A logger writes the whole torque on its grid.
  for (int i = 0; i < data.rows(); ++i)
    data.measured(i, j6) = std::round(data.measured(i, j6) / q) * q;
  const auto P = makeTrajectoryProblem(m, data);
  ArmFitOptions o;
  o.auto_add = true;
  const ArmDiagnosis d = diagnoseArm(*P, o);
  INFO(d.verdict);
  REQUIRE(d.channel_resolution.size() == 6u);
  CHECK(d.channel_resolution[j6] == Approx(q).epsilon(1e-6));
  CHECK(d.channel_at_floor[j6]);
  for (int c = 0; c < 6; ++c)
    if (c != j6) {
      CHECK(d.channel_resolution[c] == 0.0);  // continuous (noise) channels lie on no grid
      CHECK_FALSE(d.channel_at_floor[c]);
    }
  bool warned = false;
  for (const std::string& w : d.warnings)
    warned =
        warned || (containsPart(w, "tau6") && containsPart(w, "not identifiable from these logs"));
  CHECK(warned);
  for (const std::string& a : d.added) CHECK(a.rfind("j6.", 0) != 0);
  for (const ArmCandidate& c : d.ranking)
    if (c.name.rfind("j6.", 0) == 0) CHECK(c.status == "at_floor");
}
