// The trajectory kind's calibrated design: the fitted values applied to a copy of the design's
// Model (docs/calibration.md, "Outputs"); calibrated_design.cpp writes it.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "calibration/trajectory_calibration.hpp"
#include "calibration/trajectory_terms.hpp"
#include "common/format.hpp"

namespace armstudy::calibration {

namespace {

using namespace trajectory_detail;

constexpr double kMassFloor_kg = 1e-9;         // a payload lighter than this has no centre
constexpr double kInertiaChangeFloor = 1e-15;  // kg m^2: no inertia to store below this

// The fitted extra payload (mass, centre, inertia about the TCP: x) applied to `cal`: [payload]
// mass and com, and the inertia the point mass cannot carry added to the last link's inertia
// where that stays physical.
void applyPayload(const Model& model, const Eigen::VectorXd& x, Model& cal,
                  std::vector<std::string>& notes) {
  const Eigen::Vector3d h = model.payload_kg * model.p_payload_com_T + x.segment<3>(1);
  const double m = std::max(0.0, model.payload_kg + x[0]);
  cal.payload_kg = m;
  cal.p_payload_com_T = m > kMassFloor_kg ? Eigen::Vector3d(h / m) : Eigen::Vector3d::Zero();
  // The fitted body (the design's payload plus the extra one) has mass m and centre c, which
  // the [payload] point mass carries, and an inertia about c, which it cannot: that part goes
  // into the last link's [[inertia]] (rigid-body parameters of one link add), so the
  // calibrated design predicts what the fit predicted. All in frame N about its origin.
  const int L = model.dof() - 1;
  const Eigen::Matrix3d one = Eigen::Matrix3d::Identity();
  auto pointI = [&](double mm, const Eigen::Vector3d& cc) {
    return Eigen::Matrix3d(mm * (cc.squaredNorm() * one - cc * cc.transpose()));
  };
  RigidBodyModel delta{};
  delta.mass[L] = 0;
  delta.h[L].setZero();
  delta.I_O[L].setZero();
  addPayloadParameters(model, x, delta);
  const double m0 = model.payload_kg > 0 ? model.payload_kg : 0.0;
  const Eigen::Matrix3d dI =
      pointI(m0, model.T_NT * model.p_payload_com_T) + delta.I_O[L] -
      (m > 0 ? pointI(m, model.T_NT * cal.p_payload_com_T) : Eigen::Matrix3d::Zero().eval());
  if (dI.norm() <= kInertiaChangeFloor) return;
  const bool has_link = L < static_cast<int>(model.inertias.size()) && model.inertias[L].given;
  const Eigen::Matrix3d I =
      has_link ? Eigen::Matrix3d(model.inertias[L].I_com_kgm2 + 0.5 * (dI + dI.transpose()))
               : Eigen::Matrix3d::Zero();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(I);
  const Eigen::Vector3d ev = es.eigenvalues();  // ascending
  const std::string link = model.joints[L].name;
  if (has_link && ev[0] > 0 && ev[2] <= ev[0] + ev[1]) {
    cal.inertias[L].I_com_kgm2 = I;
    notes.push_back(
        "the fitted payload's inertia about its centre of mass, which the [payload] point mass "
        "cannot carry, is added to the [[inertia]] of link " +
        link);
  } else {
    notes.push_back(
        "the fitted payload's inertia about its centre of mass is not stored (the "
        "[payload] is a point mass and link " +
        link + (has_link ? " would get a non-physical inertia)" : " has no [[inertia]])"));
  }
}

// A fitted friction term of joint j stored in its drive's [drive.friction] (and, when the
// design's law lacks the term, in [model] effects). `p`: the joint's friction so far.
void applyFriction(int j, drive::Effect effect, const std::string& key, double value,
                   double profile, drive::FrictionParams& p, Model& cal) {
  Drive* d = nullptr;
  for (Drive& x : cal.drives)
    if (x.joint == cal.joints[j].name) d = &x;
  if (d->friction_law.empty()) d->friction_law = "none";
  const drive::EffectDeclaration& decl = drive::declaration(effect);
  if (decl.starts_at_coulomb && !p.has(effect)) p.*decl.params[0].field = p.coulomb;
  for (const drive::EffectParameter& x : decl.params)
    if (x.profiled) {
      p.*x.field = profile;
      d->friction[x.key] = profile;
    }
  if (!p.has(effect)) {
    const auto law = drive::lawEffects(p.law);
    const std::string entry = cal.joints[j].name + "." + drive::toString(effect);
    if (std::find(law.begin(), law.end(), effect) == law.end() &&
        std::find(cal.effects.begin(), cal.effects.end(), entry) == cal.effects.end())
      cal.effects.push_back(entry);
  }
  p.on[static_cast<int>(effect)] = true;
  addFriction(p, key, value);
  d->friction[key] = frictionValue(p, key);
}

}  // namespace

Model calibratedTrajectoryModel(const Model& model, const ArmProblem& problem,
                                const EffectValues& values, std::vector<std::string>& notes) {
  const TrajectoryTerms P = trajectoryTerms(problem);
  Model cal = model;
  std::vector<drive::FrictionParams> fp = P.friction;
  for (const auto& v : values) {
    const Tag& t = P.tags[v.effect];
    const ArmEffect& e = problem.catalogue[v.effect];
    switch (t.type) {
      case TrajEffect::Payload:
        applyPayload(model, v.x, cal, notes);
        break;
      case TrajEffect::RotorInertia:
        for (int j = 0; j < model.dof(); ++j) {
          if (v.x[j] == 0) continue;
          if (!P.drives[j]) {  // the joint's own armature (joint side)
            cal.joints[j].dynamics.armature += v.x[j];
            continue;
          }
          const double N = P.drives[j]->gear_ratio;
          for (Drive& d : cal.drives)
            if (d.joint == model.joints[j].name) d.rotor_inertia_kgm2 += v.x[j] / (N * N);
        }
        break;
      case TrajEffect::GravityTilt:
        cal.base.alpha += v.x[0];
        cal.base.beta += v.x[1];
        notes.push_back(
            "gravity_tilt is stored as the base orientation (alpha, beta): a tilted base is a "
            "tilted gravity vector");
        break;
      case TrajEffect::LinkMass:
        cal.inertias[t.joint].mass_kg = std::max(0.0, model.inertias[t.joint].mass_kg + v.x[0]);
        break;
      case TrajEffect::JointSide:
        cal.joints[t.joint].dynamics.*sideField(t.term) += v.x[0];
        break;
      case TrajEffect::Motor:
        notes.push_back(e.name + " = " + formatG(v.x[0], 10) + " " + e.params[0].unit +
                        " is not stored: the design format has no coupled-motor terms (the "
                        "fitted value is in result.json)");
        break;
      case TrajEffect::Friction:
        applyFriction(t.joint, t.friction, e.params[0].key, v.x[0], v.profile, fp[t.joint], cal);
        break;
    }
  }
  cal.finalize();
  return cal;
}

}  // namespace armstudy::calibration
