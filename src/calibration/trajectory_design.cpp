// The trajectory kind's calibrated design copy: the fitted values written into the design TOML
// text (docs/calibration.md, "Outputs").
#include <Eigen/Eigenvalues>
#include <cmath>
#include <set>

#include "calibration/trajectory_calibration.hpp"
#include "calibration/trajectory_terms.hpp"
#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"

namespace armstudy::calibration {

namespace {

using namespace trajectory_detail;

// A number as the calibrated design text writes it.
std::string num(double v) {
  char b[48];
  std::snprintf(b, sizeof b, "%.10g", v);
  return std::string(b);
}

// The fitted extra payload (mass, centre, inertia about the centre: v.x) stored in the design text:
// [payload] mass and com, and the inertia the point mass cannot carry added to the last link's
// [[inertia]] where that stays physical. Returns the payload mass written.
double storePayload(const Model& model, const Eigen::VectorXd& x, std::string& text,
                    std::vector<std::string>& notes) {
  const Eigen::Vector3d h = model.payload_kg * model.p_payload_com_T + x.segment<3>(1);
  const double m = std::max(0.0, model.payload_kg + x[0]);
  const Eigen::Vector3d c = m > 1e-9 ? Eigen::Vector3d(h / m) : Eigen::Vector3d::Zero();
  text = setDesignEntry(text, "[payload]", "", "", "mass", num(m));
  text = setDesignEntry(text, "[payload]", "", "", "com",
                        "[" + num(c.x()) + ", " + num(c.y()) + ", " + num(c.z()) + "]");
  // The fitted body (the design's payload plus the extra one) has mass m and centre c, which
  // the [payload] point mass carries, and an inertia about c, which it cannot: that part goes
  // into the last link's [[inertia]] (rigid-body parameters of one link add), so the
  // calibrated copy predicts what the fit predicted. All in frame N about its origin.
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
  const Eigen::Matrix3d dI = pointI(m0, model.T_NT * model.p_payload_com_T) + delta.I_O[L] -
                             (m > 0 ? pointI(m, model.T_NT * c) : Eigen::Matrix3d::Zero().eval());
  const bool has_link = L < static_cast<int>(model.inertias.size()) && model.inertias[L].given;
  if (dI.norm() > 1e-15) {
    const Eigen::Matrix3d I =
        has_link ? Eigen::Matrix3d(model.inertias[L].I_com_kgm2 + 0.5 * (dI + dI.transpose()))
                 : Eigen::Matrix3d::Zero();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(I);
    const Eigen::Vector3d ev = es.eigenvalues();  // ascending
    const std::string link = model.joints[L].name;
    if (has_link && ev[0] > 0 && ev[2] <= ev[0] + ev[1]) {
      text = setDesignEntry(text, "[[inertia]]", "link", link, "inertia",
                            "[" + num(I(0, 0)) + ", " + num(I(1, 1)) + ", " + num(I(2, 2)) + ", " +
                                num(I(0, 1)) + ", " + num(I(0, 2)) + ", " + num(I(1, 2)) + "]");
      notes.push_back(
          "the fitted payload's inertia about its centre of mass, which the [payload] point "
          "mass cannot "
          "carry, is added to the [[inertia]] of link " +
          link);
    } else {
      notes.push_back(
          "the fitted payload's inertia about its centre of mass is not stored (the "
          "[payload] is a point "
          "mass and link " +
          link + (has_link ? " would get a non-physical inertia)" : " has no [[inertia]])"));
    }
  }
  return m;
}

// A fitted friction term of joint j stored in its [drive.friction] (and, when the design's law
// lacks the term, in [model] effects).
void storeFriction(const Model& model, int j, drive::Effect effect, const std::string& key,
                   double value, double profile, drive::FrictionParams& p,
                   std::vector<std::string>& effects, std::string& text) {
  if (effect == drive::Effect::Stribeck) {
    if (!p.has(effect)) p.stribeck_torque = p.coulomb;
    p.stribeck_velocity = profile;
    text = setDesignEntry(text, "[drive.friction]", "joint", model.joints[j].name,
                          "stribeck_velocity", num(profile));
  }
  if (!p.has(effect)) {
    bool in_law = false;
    for (auto e : drive::lawEffects(p.law)) in_law = in_law || e == effect;
    if (!in_law) effects.push_back(model.joints[j].name + "." + drive::toString(effect));
  }
  p.on[static_cast<int>(effect)] = true;
  addFriction(p, key, value);
  text = setDesignEntry(text, "[drive.friction]", "joint", model.joints[j].name, key,
                        num(frictionValue(p, key)));
}

}  // namespace

std::string calibratedTrajectoryToml(const Model& model, const ArmProblem& problem,
                                     const EffectValues& values, std::vector<std::string>& notes) {
  const TrajectoryTerms P = trajectoryTerms(problem);
  std::string text = readFileOrThrow(model.file);
  std::vector<std::string> effects = model.effects;
  std::vector<drive::FrictionParams> fp = P.friction;
  std::set<int> friction_joints;
  Model expect = model;
  for (const auto& v : values) {
    const Tag& t = P.tags[v.effect];
    switch (t.type) {
      case TrajEffect::Payload:
        expect.payload_kg = storePayload(model, v.x, text, notes);
        break;
      case TrajEffect::RotorInertia:
        for (int j = 0; j < model.dof(); ++j) {
          if (v.x[j] == 0) continue;
          if (!P.drives[j]) {
            notes.push_back("armature of " + model.joints[j].name + " (" + num(v.x[j]) +
                            ") is not stored: the joint has no [[drive]]");
            continue;
          }
          const double N = P.drives[j]->gear_ratio;
          text = setDesignEntry(text, "[[drive]]", "joint", model.joints[j].name, "rotor_inertia",
                                num(P.drives[j]->rotor_inertia_kgm2 + v.x[j] / (N * N)));
        }
        break;
      case TrajEffect::GravityTilt:
        text = setDesignEntry(text, "[base]", "", "", "alpha", num(model.base.alpha + v.x[0]));
        text = setDesignEntry(text, "[base]", "", "", "beta", num(model.base.beta + v.x[1]));
        notes.push_back(
            "gravity_tilt is stored as the base orientation (alpha, beta): a tilted base is a "
            "tilted gravity vector");
        break;
      case TrajEffect::LinkMass:
        text = setDesignEntry(text, "[[inertia]]", "link", model.joints[t.joint].name, "mass",
                              num(std::max(0.0, model.inertias[t.joint].mass_kg + v.x[0])));
        break;
      case TrajEffect::JointSide:
      case TrajEffect::Motor:
        notes.push_back(problem.catalogue[v.effect].name + " = " + num(v.x[0]) + " " +
                        problem.catalogue[v.effect].params[0].unit +
                        " is not stored: the design format has no joint-side friction, offset or "
                        "coupled-motor terms");
        break;
      case TrajEffect::Friction:
        storeFriction(model, t.joint, t.friction, problem.catalogue[v.effect].params[0].key, v.x[0],
                      v.profile, fp[t.joint], effects, text);
        break;
    }
  }
  if (effects != model.effects) {
    std::string list;
    for (const auto& e : effects) list += (list.empty() ? "\"" : ", \"") + e + "\"";
    text = setDesignEntry(text, "[model]", "", "", "effects", "[" + list + "]");
  }
  const Model back = parseDesign(text, model.file + " (calibrated)");  // must stay a valid design
  ARMSTUDY_CHECK(std::abs(back.payload_kg - expect.payload_kg) < 1e-9,
                 "calibrated design round trip (payload)");
  return text;
}

}  // namespace armstudy::calibration
