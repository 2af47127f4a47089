#include "calibration/trajectory_calibration.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <regex>
#include <set>

#include "calibration/drive_calibration.hpp"
#include "calibration/trajectory_terms.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "common/rng.hpp"
#include "drive/drive_chain.hpp"
#include "dynamics/dynamics.hpp"
#include "io/csv_io.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "kinematics/kinematics.hpp"

namespace armstudy::calibration {

namespace {

using namespace trajectory_detail;

constexpr double kInfD = std::numeric_limits<double>::infinity();

struct SideInfo {
  SideTerm term;
  const char* name;
  const char* key;
  const char* unit_rev;
  const char* unit_pri;
  double typical;
  const char* pattern;
};
constexpr SideInfo kJointTerms[] = {
    {SideTerm::Coulomb, "coulomb", "coulomb", "N m", "N", 2.0,
     "a step with the sign of the joint's speed (smooth over the width w = fraction x peak speed)"},
    {SideTerm::Viscous, "viscous", "viscous", "N m s/rad", "N s/m", 1.0,
     "a residual proportional to the joint's speed"},
    {SideTerm::Offset, "offset", "offset", "N m", "N", 0.5,
     "a constant residual of the joint's effort"},
    {SideTerm::Inertia, "armature", "armature", "kg m^2", "kg", 0.05,
     "a residual proportional to the joint's own acceleration (rotor inertia reflected through the "
     "ratio)"}};

// The physically possible lower bound of a joint-side or motor term (friction and inertia are not
// negative; an offset has none) and why.
double physicalLower(SideTerm t) {
  return t == SideTerm::Offset ? -std::numeric_limits<double>::infinity() : 0.0;
}
const char* physicalReason(SideTerm t) {
  return t == SideTerm::Offset    ? ""
         : t == SideTerm::Inertia ? "an armature is not negative"
                                  : "friction is not negative";
}

// Smooth sign of the Coulomb terms: tanh(v / w) (w = 0: the joint never moves, no force).
double smoothSign(double v, double w) { return w > 0 ? std::tanh(v / w) : 0.0; }

// One joint-side or motor term at one row: the force law times its coefficient 1.
double sideTerm(SideTerm t, double v, double a, double w) {
  switch (t) {
    case SideTerm::Coulomb:
      return smoothSign(v, w);
    case SideTerm::Viscous:
      return v;
    case SideTerm::Offset:
      return 1.0;
    case SideTerm::Inertia:
      return a;
  }
  return 0.0;
}

class TrajectoryProblem : public ArmProblem {
 public:
  TrajectoryProblem(const Model& model, const TrajectoryData& data) : model_(model), data_(data) {
    setSource("trajectory", model.name, data);
    measured = data.measured;
    const int n = model.dof();
    int revolute = 0;
    for (const auto& jt : model.joints) revolute += jt.type == JointType::Revolute;
    fit_unit = data.currents   ? "A"
               : revolute == n ? "N m"
               : revolute == 0 ? "N"
                               : "N m and N";  // revolute and prismatic channels together
    drive_.assign(n, nullptr);
    for (const Drive& d : model.drives) {
      const int j = model.jointIndex(d.joint);
      if (j >= 0 && d.gear_ratio > 0 && d.torque_constant_NmpA > 0) drive_[j] = &d;
    }
    for (int j = 0; j < n; ++j) {
      const bool rev = model.joints[j].type == JointType::Revolute;
      channel_names.push_back(data.joint_named_channels
                                  ? model.joints[j].name
                                  : (data.currents ? "current" : "tau") + std::to_string(j + 1));
      channel_units.push_back(data.currents ? "A" : (rev ? "N m" : "N"));
      if (data.currents && !drive_[j])
        throw InputError(model.file, model.joints[j].source_line, "drive",
                         "the data has motor currents but joint '" + model.joints[j].name +
                             "' has no [[drive]] with gear ratio and torque constant");
      if (drive_[j])
        fp_.push_back(drive::frictionParams(model, *drive_[j]));
      else
        fp_.emplace_back();
    }
    weight = Eigen::VectorXd::Ones(n);
    logged_resolution = data.effort_resolution;
    makeRigidBodyModel(model);  // throws InputError (design file) without [[inertia]] data
    addBodyEffects(model, data.friction_width_fraction > 0);
    addFrictionEffects(model, data);
    if (data.friction_width_fraction > 0) {
      addJointSideEffects(model, data);
      addMotorEffects(model, data);
    }
    addOperatingData(model, data);
    addDesignJointTerms(model, data);
    if (data.friction_width_fraction > 0) linearBodyBasis(model);
  }

 private:
  // The catalogue's body effects: payload, rotor inertia, gravity tilt, extra link masses.
  // `per_joint_armature`: the rotor inertia is a per-joint term of the joint-side catalogue
  // instead.
  void addBodyEffects(const Model& model, bool per_joint_armature) {
    const int n = model.dof();
    {
      ArmEffect e;
      e.name = e.effect = "payload";
      e.pattern =
          "gravity and inertia torques of an extra body at the TCP: largest at the proximal joints "
          "with the "
          "arm stretched out, grows with the TCP acceleration";
      // The standard linear inertial parameters of the extra body, in the TCP frame about the TCP
      // origin: mass m, first moment m c, inertia I: the efforts are linear in all ten,
      // so each is identifiable from a design without payload (m = 0). Typical values: 0.5 kg at
      // c = (0.02, -0.02, 0.06) m as a point mass, I = m (|c|^2 1 - c c^T).
      e.params = {{"mass", "kg", -model.payload_kg, kInfD, 0.5, 1e-4, 0, "a mass is above zero"},
                  {"first_moment_x", "kg m", -kInfD, kInfD, 0.01, 1e-5},
                  {"first_moment_y", "kg m", -kInfD, kInfD, -0.01, 1e-5},
                  {"first_moment_z", "kg m", -kInfD, kInfD, 0.03, 1e-5},
                  {"inertia_xx", "kg m^2", -kInfD, kInfD, 0.002, 1e-6},
                  {"inertia_yy", "kg m^2", -kInfD, kInfD, 0.002, 1e-6},
                  {"inertia_zz", "kg m^2", -kInfD, kInfD, 0.0004, 1e-6},
                  {"inertia_xy", "kg m^2", -kInfD, kInfD, 0.0002, 1e-6},
                  {"inertia_xz", "kg m^2", -kInfD, kInfD, -0.0006, 1e-6},
                  {"inertia_yz", "kg m^2", -kInfD, kInfD, 0.0006, 1e-6}};
      // The design's payload (a point mass m0 at c0) in the same parameters: the fitted body is
      // the sum, and its pseudo-inertia must be positive semidefinite.
      e.rigid_body = true;
      const double m0 = std::max(0.0, model.payload_kg);
      const Eigen::Vector3d c0 = model.p_payload_com_T;
      const Eigen::Matrix3d I0 =
          m0 * (c0.squaredNorm() * Eigen::Matrix3d::Identity() - c0 * c0.transpose());
      e.body_design = {m0,       m0 * c0.x(), m0 * c0.y(), m0 * c0.z(), I0(0, 0),
                       I0(1, 1), I0(2, 2),    I0(0, 1),    I0(0, 2),    I0(1, 2)};
      add(e, {TrajEffect::Payload});
    }
    if (!per_joint_armature) {
      ArmEffect e;
      e.name = e.effect = "rotor_inertia";
      e.pattern = "residual of joint j proportional to its own acceleration qdd_j";
      for (int j = 0; j < n; ++j) {
        const bool rev = model.joints[j].type == JointType::Revolute;
        const double a0 = drive_[j] ? drive_[j]->gear_ratio * drive_[j]->gear_ratio *
                                          drive_[j]->rotor_inertia_kgm2
                                    : 0.0;
        e.params.push_back({"armature_" + model.joints[j].name, rev ? "kg m^2" : "kg", -a0, kInfD,
                            rev ? 0.05 : 0.5, 1e-4, 0, "a rotor inertia is not negative"});
      }
      add(e, {TrajEffect::RotorInertia});
    }
    {
      ArmEffect e;
      e.name = e.effect = "gravity_tilt";
      e.pattern =
          "gravity torques turned about a horizontal axis: a residual like the gravity torque of a "
          "90 deg "
          "rotated arm, scaled by the tilt";
      e.params = {{"alpha", "rad", -kInfD, kInfD, 0.02, 1e-6},
                  {"beta", "rad", -kInfD, kInfD, -0.015, 1e-6}};
      add(e, {TrajEffect::GravityTilt});
    }
    for (int j = 0; j < n; ++j) {
      if (j >= static_cast<int>(model.inertias.size())) break;
      ArmEffect e = jointEffect("link_mass", model.joints[j].name,
                                "gravity and inertia torques of extra mass at the link's centre of "
                                "mass (joints up to this one)");
      e.params = {{"mass", "kg", -model.inertias[j].mass_kg, kInfD, 0.5, 1e-4, 0,
                   "a link's mass is above zero"}};
      add(e, {TrajEffect::LinkMass, j});
    }
  }

  // The catalogue's friction effects of every driven joint (no temperature effects: trajectories
  // carry no temperature column), Stribeck with its velocity profile grid.
  void addFrictionEffects(const Model& model, const TrajectoryData& data) {
    const int n = model.dof();
    for (int j = 0; j < n; ++j) {
      if (!drive_[j]) continue;
      const double N = drive_[j]->gear_ratio;
      const bool js = fp_[j].joint_side;
      double vmax = 0;
      for (int i = 0; i < data.rows(); ++i)
        vmax = std::max(vmax, std::abs(data.qd(i, j)) * (js ? 1.0 : N));
      for (const drive::EffectDeclaration& info : drive::effectDeclarations()) {
        const drive::Effect fe = info.effect;
        if (info.needs_temperature) continue;  // trajectories carry no temperature column
        ArmEffect e;
        e.name = model.joints[j].name + "." + info.name;
        e.effect = info.name;
        e.joint = model.joints[j].name;
        e.pattern =
            std::string(info.pattern) + " (joint " + model.joints[j].name + ", over its speed)";
        const drive::EffectParameter& ep = info.params[0];
        const double scale = js ? drive::jointSideScale(ep, N) : 1.0;
        // An absent Stribeck term starts at the Coulomb level (T_S = T_f0: no change at zero).
        const double cur = info.starts_at_coulomb && !fp_[j].has(fe)
                               ? fp_[j].coulomb
                               : frictionValue(fp_[j], ep.key);
        ArmParam ap{ep.key,
                    js ? ep.unit_joint : ep.unit_motor,
                    ep.lower - cur,
                    ep.upper - cur,
                    ep.typical * scale,
                    std::max(1e-9, std::abs(ep.typical * scale) * 1e-3)};
        e.params = {ap};
        if (info.params.size() > 1 && info.params[1].profiled) {
          const drive::EffectParameter& pv = info.params[1];
          e.profile = {pv.key, js ? pv.unit_joint : pv.unit_motor, 0, kInfD, 0.3 * vmax, 0};
          const double lo = std::max(vmax * 0.01, 1e-6), hi = std::max(vmax, 2e-6);
          for (int g = 0; g < defaults::kArmProfileGridPoints; ++g)
            e.profile_grid.push_back(
                lo * std::pow(hi / lo, g / double(defaults::kArmProfileGridPoints - 1)));
        }
        Tag t{TrajEffect::Friction, j, fe};
        add(e, t);
      }
    }
  }

  // The design's own joint-side terms (Joint::dynamics) at every row, rows x joints (empty when no
  // joint has any): the joint-side catalogue's changes add to them. The Coulomb width is that
  // rule's (friction_width, default defaults::kFrictionWidthFraction, times the joint's peak
  // speed).
  void addDesignJointTerms(const Model& model, const TrajectoryData& data) {
    const double fraction = data.friction_width_fraction > 0 ? data.friction_width_fraction
                                                             : defaults::kFrictionWidthFraction;
    for (int j = 0; j < model.dof(); ++j) {
      const JointDynamics& d = model.joints[j].dynamics;
      if (!d.any()) continue;
      if (design_side_.size() == 0) design_side_ = Eigen::MatrixXd::Zero(data.rows(), model.dof());
      const double w = fraction * data.qd.col(j).cwiseAbs().maxCoeff();
      for (int i = 0; i < data.rows(); ++i)
        design_side_(i, j) = d.coulomb * smoothSign(data.qd(i, j), w) + d.viscous * data.qd(i, j) +
                             d.armature * data.qdd(i, j) + d.effort_offset;
    }
  }

  // Joint-side friction, effort offset and armature of every joint without a [[drive]] (measured
  // logs hold joint-side efforts): <joint>.coulomb|viscous|offset|armature.
  void addJointSideEffects(const Model& model, const TrajectoryData& data) {
    const int n = model.dof();
    joint_width_.assign(n, 0.0);
    for (int j = 0; j < n; ++j) {
      if (drive_[j]) continue;
      joint_width_[j] = data.friction_width_fraction * data.qd.col(j).cwiseAbs().maxCoeff();
      const bool rev = model.joints[j].type == JointType::Revolute;
      for (const SideInfo& si : kJointTerms) {
        ArmEffect e;
        e.name = model.joints[j].name + "." + si.name;
        e.effect = si.name;
        e.joint = model.joints[j].name;
        e.pattern = std::string(si.pattern) + " (joint " + model.joints[j].name + ")";
        e.params = {{si.key, rev ? si.unit_rev : si.unit_pri,
                     physicalLower(si.term) - model.joints[j].dynamics.*sideField(si.term), kInfD,
                     si.typical, 1e-4, 0, physicalReason(si.term)}};
        add(e, {TrajEffect::JointSide, j, drive::Effect::Coulomb, si.term});
      }
    }
  }

  // A motor that turns with several joints (a row k of the coupling matrix R with more than one
  // entry, such as a coupled wrist): its own friction and inertia act at the motor speed
  // theta_m_k = R_k qd and reach every joint j it drives as R_kj times the motor torque (tau = R^T
  // tau_m): motor_<joint>.coulomb|viscous|inertia. Reflected through the motor's own ratio R_kk
  // (speed R_k qd / R_kk, torque R_kj / R_kk times the term) they are in joint-side units.
  void addMotorEffects(const Model& model, const TrajectoryData& data) {
    const int n = model.dof();
    if (data.coupling.rows() != n) return;
    motor_ratio_ = data.coupling;
    for (int k = 0; k < n; ++k)
      if (data.coupling(k, k) != 0) motor_ratio_.row(k) /= data.coupling(k, k);
    motor_v_ = data.qd * motor_ratio_.transpose();
    motor_a_ = data.qdd * motor_ratio_.transpose();
    motor_width_.assign(n, 0.0);
    for (int k = 0; k < n; ++k) {
      if ((data.coupling.row(k).array() != 0).count() < 2 || data.coupling(k, k) == 0) continue;
      motor_width_[k] = data.friction_width_fraction * motor_v_.col(k).cwiseAbs().maxCoeff();
      for (const SideInfo& si : kJointTerms) {
        if (si.term == SideTerm::Offset)
          continue;  // a motor torque offset is a joint offset per joint
        ArmEffect e;
        e.name = "motor_" + model.joints[k].name + "." +
                 (si.term == SideTerm::Inertia ? "inertia" : si.name);
        e.effect = std::string("motor_") + (si.term == SideTerm::Inertia ? "inertia" : si.name);
        e.joint = model.joints[k].name;
        e.pattern = std::string("coupled motor of ") + model.joints[k].name + ": " + si.pattern +
                    " at the motor's speed, in every joint the motor drives";
        const char* unit = si.term == SideTerm::Coulomb   ? "N m"
                           : si.term == SideTerm::Viscous ? "N m s/rad"
                                                          : "kg m^2";
        e.params = {{si.key, unit, physicalLower(si.term), kInfD, si.typical, 1e-4, 0,
                     physicalReason(si.term)}};
        add(e, {TrajEffect::Motor, k, drive::Effect::Coulomb, si.term});
      }
    }
  }

  // The rigid-body efforts are linear in the standard inertial parameters of every body
  // (Q = Y(q, qd, qdd) pi), hence in the payload's ten parameters and in each link's mass (its
  // centre and inertia about it fixed): the nominal efforts and one difference column per
  // parameter, computed once, give every prediction without a gravity tilt (to rounding). Used for
  // measured logs (thousands of rows); trajectory CSV files keep one inverse-dynamics pass per
  // prediction, so their results stay those of the committed baselines to the last digit.
  void linearBodyBasis(const Model& model) {
    Q0_ = rigidBodyEfforts(model, nullptr);
    for (int k = 0; k < 10; ++k) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(10);
      x[k] = 1;
      payload_basis_.push_back(rigidBodyEfforts(model, &x) - Q0_);
    }
    for (std::size_t j = 0; j < model.inertias.size() && static_cast<int>(j) < model.dof(); ++j) {
      Model m = model;
      m.inertias[j].mass_kg += 1.0;
      mass_basis_.push_back(rigidBodyEfforts(m, nullptr) - Q0_);
    }
  }

  // Inverse dynamics (RNEA) of every row for a design, optionally with the payload parameters.
  Eigen::MatrixXd rigidBodyEfforts(const Model& m, const Eigen::VectorXd* payload) const {
    RigidBodyModel rbm = makeRigidBodyModel(m);
    if (payload) addPayloadParameters(m, *payload, rbm);
    DynamicsWorkspace ws(rbm);
    Eigen::MatrixXd out(data_.rows(), m.dof());
    Eigen::VectorXd Q(m.dof()), g(m.dof());
    bool compensated = false;
    for (bool c : data_.gravity_compensated) compensated = compensated || c;
    for (int i = 0; i < data_.rows(); ++i) {
      inverseDynamics(rbm, ws, data_.q.row(i).transpose(), data_.qd.row(i).transpose(),
                      data_.qdd.row(i).transpose(), Q);
      if (compensated) {  // the controller supplies these joints' gravity terms
        gravityForces(rbm, ws, data_.q.row(i).transpose(), g);
        for (int j = 0; j < m.dof(); ++j)
          if (data_.gravity_compensated[static_cast<std::size_t>(j)]) Q[j] -= g[j];
      }
      out.row(i) = Q.transpose();
    }
    return out;
  }

  // Operating variables, workspace positions (design FK), held-out regions (time blocks).
  void addOperatingData(const Model& model, const TrajectoryData& data) {
    const int n = model.dof();
    for (int j = 0; j < n; ++j) {
      const bool rev = model.joints[j].type == JointType::Revolute;
      BinVariable v{"q" + std::to_string(j + 1), rev ? "rad" : "m", {}, true};
      BinVariable w{"qd" + std::to_string(j + 1), rev ? "rad/s" : "m/s", {}};
      for (int i = 0; i < data.rows(); ++i) {
        v.values.push_back(data.q(i, j));
        w.values.push_back(data.qd(i, j));
      }
      variables.push_back(v);
      variables.push_back(w);
      bool moves = false;
      for (int i = 0; i < data.rows(); ++i) moves = moves || data.qd(i, j) != 0;
      if (!moves) {
        warnings.push_back("joint " + model.joints[j].name +
                           " does not move in the data: its friction effects cannot "
                           "be identified");
        unidentifiable.push_back("joint " + model.joints[j].name +
                                 " never moves (its speed is 0 in every row)");
      }
    }
    KinematicsWorkspace ks(model);
    for (int i = 0; i < data.rows(); ++i) {
      forwardKinematics(model, ks, data.q.row(i).transpose());
      workspace.push_back(ks.p_WT);
    }
    region_count = 4;
    for (int i = 0; i < data.rows(); ++i)
      regions.push_back(std::min(3, i * 4 / std::max(1, data.rows())));
    time = data.t;
    load_name = "load";  // the predicted joint effort (or current) of the channel
  }

 public:
  Model calibratedModel(const Model& model, const EffectValues& values,
                        std::vector<std::string>& notes) const override {
    return calibratedTrajectoryModel(model, *this, values, notes);
  }

  Eigen::MatrixXd predict(const EffectValues& values) const override {
    const int n = model_.dof();
    std::vector<drive::FrictionParams> fp = fp_;
    Eigen::VectorXd arm = Eigen::VectorXd::Zero(n);
    bool tilt = false;
    const Eigen::VectorXd* payload = nullptr;
    // The design's joint-side terms plus the fitted joint-side and motor terms.
    Eigen::MatrixXd side =
        design_side_.size() ? design_side_ : Eigen::MatrixXd::Zero(data_.rows(), n).eval();
    Eigen::VectorXd dmass =
        Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model_.inertias.size()));
    for (const auto& v : values) {
      const Tag& t = tags_[v.effect];
      switch (t.type) {
        case TrajEffect::Payload:
          payload = &v.x;
          break;
        case TrajEffect::RotorInertia:
          arm += v.x;
          break;
        case TrajEffect::GravityTilt:
          tilt = true;
          break;
        case TrajEffect::LinkMass:
          dmass[t.joint] = std::max(0.0, model_.inertias[t.joint].mass_kg + v.x[0]) -
                           model_.inertias[t.joint].mass_kg;
          break;
        case TrajEffect::Friction: {
          drive::FrictionParams& p = fp[t.joint];
          const ArmEffect& info = catalogue[v.effect];
          const drive::EffectDeclaration& d = drive::declaration(t.friction);
          if (d.starts_at_coulomb && !p.has(t.friction))
            *drive::parameter(p, info.params[0].key) = p.coulomb;  // no change at zero delta
          if (info.hasProfile()) *drive::parameter(p, info.profile.key) = v.profile;
          p.on[static_cast<int>(t.friction)] = true;
          addFriction(p, info.params[0].key, v.x[0]);
          break;
        }
        case TrajEffect::JointSide:
          for (int i = 0; i < data_.rows(); ++i)
            side(i, t.joint) += v.x[0] * sideTerm(t.term, data_.qd(i, t.joint),
                                                  data_.qdd(i, t.joint), joint_width_[t.joint]);
          break;
        case TrajEffect::Motor:
          for (int i = 0; i < data_.rows(); ++i) {
            const double f = v.x[0] * sideTerm(t.term, motor_v_(i, t.joint), motor_a_(i, t.joint),
                                               motor_width_[t.joint]);
            for (int j = 0; j < n; ++j) side(i, j) += motor_ratio_(t.joint, j) * f;
          }
          break;
      }
    }
    Eigen::MatrixXd Q;
    if (tilt || Q0_.size() == 0) {
      Model m = model_;
      for (const auto& v : values) {
        const Tag& t = tags_[v.effect];
        if (t.type == TrajEffect::GravityTilt) {
          m.base.alpha += v.x[0];
          m.base.beta += v.x[1];
        }
        if (t.type == TrajEffect::LinkMass)
          m.inertias[t.joint].mass_kg = std::max(0.0, m.inertias[t.joint].mass_kg + v.x[0]);
      }
      m.finalize();
      Q = rigidBodyEfforts(m, payload);
    } else {
      Q = Q0_;
      if (payload)
        for (int k = 0; k < 10; ++k) Q += (*payload)[k] * payload_basis_[k];
      for (std::size_t j = 0; j < mass_basis_.size(); ++j)
        if (dmass[static_cast<Eigen::Index>(j)] != 0)
          Q += dmass[static_cast<Eigen::Index>(j)] * mass_basis_[j];
    }
    Eigen::MatrixXd out(data_.rows(), n);
    for (int i = 0; i < data_.rows(); ++i) {
      for (int j = 0; j < n; ++j) {
        const double Qj = Q(i, j) + arm[j] * data_.qdd(i, j) + side(i, j);
        if (!drive_[j]) {
          out(i, j) = Qj;
          continue;
        }
        const drive::MotorState s = drive::motorState(
            *drive_[j], fp[j], data_.qd(i, j), data_.qdd(i, j), Qj, fp[j].reference_temperature_C);
        out(i, j) = data_.currents ? s.current_A : s.motor_torque_Nm * drive_[j]->gear_ratio;
      }
    }
    return out;
  }

  std::vector<Tag> tags_;
  std::vector<const Drive*> drive_;
  std::vector<drive::FrictionParams> fp_;
  std::vector<double> joint_width_, motor_width_;  // smooth-sign widths of the Coulomb terms
  Eigen::MatrixXd motor_ratio_;                    // R with each row divided by its diagonal
  Eigen::MatrixXd motor_v_, motor_a_;  // rows x motors: reflected motor speed, acceleration
  Eigen::MatrixXd Q0_;                 // nominal rigid-body efforts, rows x joints
  Eigen::MatrixXd design_side_;        // the design's joint-side terms, rows x joints (or empty)
  std::vector<Eigen::MatrixXd> payload_basis_, mass_basis_;

 private:
  void add(const ArmEffect& e, Tag t) {
    catalogue.push_back(e);
    tags_.push_back(t);
  }
  Model model_;
  TrajectoryData data_;
};

}  // namespace

namespace trajectory_detail {

double JointDynamics::*sideField(SideTerm term) {
  switch (term) {
    case SideTerm::Coulomb:
      return &JointDynamics::coulomb;
    case SideTerm::Viscous:
      return &JointDynamics::viscous;
    case SideTerm::Offset:
      return &JointDynamics::effort_offset;
    case SideTerm::Inertia:
      break;
  }
  return &JointDynamics::armature;
}

// Adds d to the friction parameter named by its [drive.friction] key (src/drive maps keys to
// fields).
void addFriction(drive::FrictionParams& p, const std::string& key, double d) {
  double* x = drive::parameter(p, key);
  ARMSTUDY_CHECK(x != nullptr, "known friction key " + key);
  *x += d;
}

double frictionValue(const drive::FrictionParams& p, const std::string& key) {
  return drive::parameter(p, key);
}

// Adds an extra body at the TCP, given by its linear inertial parameters x = (m, h_T = m c_T,
// I_T: xx yy zz xy xz yz about the TCP origin in TCP axes), to the last link (frame N) of the
// rigid-body model: with p = p_NT, R = R_NT, h = R h_T,
//   mass += m,  h_N += h + m p,  I_N += R I_T R^T + m (|p|^2 1 - p p^T) + 2 (p.h) 1 - p h^T - h p^T
// (parallel-axis theorem for a body known about the TCP origin), linear in x.
void addPayloadParameters(const Model& m, const Eigen::VectorXd& x, RigidBodyModel& rbm) {
  const int L = m.dof() - 1;
  const Eigen::Matrix3d R = m.T_NT.linear();
  const Eigen::Vector3d p = m.T_NT.translation();
  const Eigen::Vector3d h = R * x.segment<3>(1);
  Eigen::Matrix3d I_T;
  I_T << x[4], x[7], x[8], x[7], x[5], x[9], x[8], x[9], x[6];
  const Eigen::Matrix3d one = Eigen::Matrix3d::Identity();
  rbm.mass[L] += x[0];
  rbm.h[L] += h + x[0] * p;
  rbm.I_O[L] += R * I_T * R.transpose() + x[0] * (p.squaredNorm() * one - p * p.transpose()) +
                2 * p.dot(h) * one - p * h.transpose() - h * p.transpose();
}

TrajectoryTerms trajectoryTerms(const ArmProblem& problem) {
  const auto& P = dynamic_cast<const TrajectoryProblem&>(problem);
  return {P.tags_, P.fp_, P.drive_};
}

}  // namespace trajectory_detail

std::unique_ptr<ArmProblem> makeTrajectoryProblem(const Model& model, const TrajectoryData& data) {
  ARMSTUDY_CHECK(data.q.cols() == model.dof(), "data columns match the design");
  return std::make_unique<TrajectoryProblem>(model, data);
}

}  // namespace armstudy::calibration
