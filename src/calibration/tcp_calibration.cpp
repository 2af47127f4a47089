#include "calibration/tcp_calibration.hpp"

#include <cmath>

#include "common/angles.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"
#include "common/rng.hpp"
#include "dynamics/dynamics.hpp"
#include "io/csv_io.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "kinematics/kinematics.hpp"

namespace armstudy::calibration {

namespace {

enum class TcpEffect { JointOffset, LinkLength, BaseOffset, Compliance };

double wrapAngle(double a) { return std::remainder(a, kFullTurn_rad); }

// The base-offset effect: x = (dx, dy, dz, dalpha, dbeta, dgamma) added to the base pose.
void addBaseOffset(PoseXYZABG& base, const Eigen::VectorXd& x) {
  base.x += x[0];
  base.y += x[1];
  base.z += x[2];
  base.alpha += x[3];
  base.beta += x[4];
  base.gamma += x[5];
}

class TcpProblem : public ArmProblem {
 public:
  TcpProblem(const Model& model, const TcpData& data) : model_(model), q_(data.q) {
    setSource("tcp", model.name, data);
    position_channels = true;
    measured = data.pose;
    fit_unit = "m";
    const int n = model.dof();
    channel_names = {"x", "y", "z"};
    channel_units = {"m", "m", "m"};
    if (data.hasOrientation()) {
      for (const char* a : {"alpha", "beta", "gamma"}) {
        channel_names.push_back(a);
        channel_units.push_back("rad");
      }
    }
    weight = Eigen::VectorXd::Ones(channel_names.size());
    for (int c = 3; c < weight.size(); ++c) weight[c] = defaults::kTcpAngleLength_m;
    const bool has_inertia = !model.inertias.empty();
    if (has_inertia) rbm_ = std::make_unique<RigidBodyModel>(makeRigidBodyModel(model));
    for (int j = 0; j < n; ++j) {
      const Joint& jt = model.joints[j];
      const bool rev = jt.type == JointType::Revolute;
      ArmEffect e = jointEffect("joint_offset", jt.name,
                                "residual grows with the distance of the TCP from the joint axis, "
                                "direction perpendicular to it");
      e.params = {{"offset", rev ? "rad" : "m", -kInfD, kInfD, rev ? 0.01 : 0.005, 1e-6}};
      add(e, TcpEffect::JointOffset, j, 0);
    }
    for (int j = 0; j < n; ++j)
      for (int a = 0; a < 3; ++a) {
        const char* ax = a == 0 ? "x" : a == 1 ? "y" : "z";
        ArmEffect e = jointEffect(
            "link_length", model.joints[j].name,
            "a constant vector in the frame before the joint, rotating with the links before it",
            ax);
        e.params = {{std::string("d") + ax, "m", -kInfD, kInfD, 0.005, 1e-6}};
        add(e, TcpEffect::LinkLength, j, a);
      }
    {
      ArmEffect e;
      e.name = "base_offset";
      e.effect = "base_offset";
      e.pattern =
          "a rigid displacement of every measured TCP position (translation plus a small rotation)";
      for (const char* k : {"x", "y", "z"})
        e.params.push_back({k, "m", -kInfD, kInfD, 0.004, 1e-6});
      for (const char* k : {"alpha", "beta", "gamma"})
        e.params.push_back({k, "rad", -kInfD, kInfD, 0.004, 1e-6});
      add(e, TcpEffect::BaseOffset, -1, 0);
    }
    if (has_inertia) {
      for (int j = 0; j < n; ++j) {
        const bool rev = model.joints[j].type == JointType::Revolute;
        ArmEffect e = jointEffect(
            "joint_compliance", model.joints[j].name,
            "the arm sags with gravity: like a joint offset against the holding torque, "
            "proportional to the "
            "gravity torque at the joint (largest with the arm stretched out horizontally)");
        const double typ = rev ? 2e-4 : 1e-6;
        e.params = {{"compliance", rev ? "rad/(N m)" : "m/N", 0.0, kInfD, typ, typ * 1e-3}};
        add(e, TcpEffect::Compliance, j, 0);
      }
    } else {
      warnings.push_back(
          "the design has no [[inertia]] data: joint_compliance candidates need gravity torques "
          "and are "
          "left out");
    }
    // Gravity torques at the measured configurations (for compliance) and operating variables.
    if (rbm_) {
      DynamicsWorkspace ws(*rbm_);
      gravity_.resize(q_.rows(), n);
      Eigen::VectorXd g(n);
      for (int i = 0; i < q_.rows(); ++i) {
        gravityForces(*rbm_, ws, q_.row(i).transpose(), g);
        gravity_.row(i) = g.transpose();
      }
    }
    for (int j = 0; j < n; ++j) {
      BinVariable v{"q" + std::to_string(j + 1),
                    model.joints[j].type == JointType::Revolute ? "rad" : "m",
                    {},
                    true};
      for (int i = 0; i < q_.rows(); ++i) v.values.push_back(q_(i, j));
      variables.push_back(v);
    }
    for (int i = 0; i < measured.rows(); ++i)
      workspace.push_back(measured.row(i).head<3>().transpose());
    // Held-out by region: quadrants of the workspace split at the median x and y.
    auto median = [&](int c) {
      std::vector<double> v(measured.rows());
      for (int i = 0; i < measured.rows(); ++i) v[i] = measured(i, c);
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v.empty() ? 0.0 : v[v.size() / 2];
    };
    const double mx = median(0), my = median(1);
    region_count = 4;
    for (int i = 0; i < measured.rows(); ++i)
      regions.push_back((measured(i, 0) > mx ? 2 : 0) + (measured(i, 1) > my ? 1 : 0));
  }

  Model calibratedModel(const Model& model, const EffectValues& values,
                        std::vector<std::string>& notes) const override {
    return calibratedTcpModel(model, *this, values, notes);
  }

  Eigen::MatrixXd predict(const EffectValues& values) const override {
    Model m = model_;
    const int n = m.dof();
    Eigen::VectorXd dq = Eigen::VectorXd::Zero(n), comp = Eigen::VectorXd::Zero(n);
    bool geometry = false, any_comp = false;
    for (const auto& v : values) {
      const Tag& t = tags_[v.effect];
      switch (t.type) {
        case TcpEffect::JointOffset:
          dq[t.joint] += v.x[0];
          break;
        case TcpEffect::LinkLength: {
          PoseXYZABG& o = m.joints[t.joint].offset;
          (t.axis == 0 ? o.x : t.axis == 1 ? o.y : o.z) += v.x[0];
          geometry = true;
          break;
        }
        case TcpEffect::BaseOffset:
          addBaseOffset(m.base, v.x);
          geometry = true;
          break;
        case TcpEffect::Compliance:
          comp[t.joint] += v.x[0];
          any_comp = true;
          break;
      }
    }
    if (geometry) m.finalize();
    KinematicsWorkspace ws(m);
    std::unique_ptr<DynamicsWorkspace> dws;
    if (any_comp) dws = std::make_unique<DynamicsWorkspace>(*rbm_);
    Eigen::VectorXd g(n);
    Eigen::MatrixXd out(q_.rows(), measured.cols());
    for (int i = 0; i < q_.rows(); ++i) {
      Eigen::VectorXd q = q_.row(i).transpose() + dq;
      if (any_comp) {
        // A compliant joint sags with gravity. Thesis eq. (4.1b), (4.2a) at rest: 0 = -T_l - T_s,
        // T_s = (q - phi/N) c_fs, so the link sits at q = phi/N - T_l / c_fs; the load torque T_l
        // the drive holds is the static holding force g(q) of src/dynamics (eq. 3.28 with qd = qdd
        // = 0). The measured joint position is the motor side phi/N (encoder before the gear), so
        // q_link = q_m - C g(q_link), solved by a contraction (C dg/dq << 1) started at q_m.
        const Eigen::VectorXd q_m = q;
        g = gravity_.row(i).transpose();
        for (int it = 0; it < defaults::kComplianceFixedPointIterations; ++it) {
          q = q_m - comp.cwiseProduct(g);
          gravityForces(*rbm_, *dws, q, g);
        }
        q = q_m - comp.cwiseProduct(g);
      }
      forwardKinematics(m, ws, q);
      out.block<1, 3>(i, 0) = ws.p_WT.transpose();
      if (measured.cols() == 6) {
        const CardanAngles a = cardanFromRotation(ws.R_WT);
        const double ang[3] = {a.alpha, a.beta, a.gamma};
        for (int k = 0; k < 3; ++k)  // nearest to the measured value, so residuals are wrapped
          out(i, 3 + k) = measured(i, 3 + k) + wrapAngle(ang[k] - measured(i, 3 + k));
      }
    }
    return out;
  }

  struct Tag {
    TcpEffect type;
    int joint, axis;
  };
  std::vector<Tag> tags_;

 private:
  static constexpr double kInfD = std::numeric_limits<double>::infinity();
  void add(const ArmEffect& e, TcpEffect t, int joint, int axis) {
    catalogue.push_back(e);
    tags_.push_back({t, joint, axis});
  }
  Model model_;
  Eigen::MatrixXd q_;
  Eigen::MatrixXd gravity_;
  std::unique_ptr<RigidBodyModel> rbm_;
};

}  // namespace

TcpData readTcpData(const std::string& path, const Model& model) {
  const int n = model.dof();
  io::CsvSchema schema;
  for (int j = 1; j <= n; ++j) schema.required.push_back("q" + std::to_string(j));
  for (const char* c : {"x", "y", "z"}) schema.required.push_back(c);
  schema.optional = {"alpha", "beta", "gamma"};
  const io::CsvTable t = io::readCsv(path, schema);
  TcpData d;
  d.file = path;
  d.hash = fileHash(path);
  d.warnings = t.extraColumnWarnings("q([0-9]+)", model.name, n);
  const int nori = t.has("alpha") + t.has("beta") + t.has("gamma");
  if (nori != 0 && nori != 3)
    throw InputError(path, 1, t.has("alpha") ? (t.has("beta") ? "gamma" : "beta") : "alpha",
                     "orientation needs all three columns alpha, beta, gamma");
  d.q.resize(t.rows(), n);
  for (int j = 0; j < n; ++j) {
    const auto& c = t.column("q" + std::to_string(j + 1));
    for (int i = 0; i < t.rows(); ++i) d.q(i, j) = c[i];
  }
  d.pose.resize(t.rows(), nori == 3 ? 6 : 3);
  int c = 0;
  for (const char* name : {"x", "y", "z", "alpha", "beta", "gamma"}) {
    if (!t.has(name)) continue;
    const auto& col = t.column(name);
    for (int i = 0; i < t.rows(); ++i) d.pose(i, c) = col[i];
    ++c;
  }
  d.lines = t.row_lines;
  for (int i = 0; i < t.rows(); ++i)
    for (int j = 0; j < n; ++j) {
      const JointLimits& l = model.joints[j].limits;
      if (d.q(i, j) < l.q_min - 1e-9 || d.q(i, j) > l.q_max + 1e-9)
        d.warnings.push_back(path + ":" + std::to_string(d.lines[i]) + ": q" +
                             std::to_string(j + 1) + " outside the design's joint limits");
    }
  return d;
}

std::string tcpDataToCsv(const TcpData& d) {
  std::vector<std::string> h;
  std::vector<std::vector<double>> cols;
  for (int j = 0; j < d.q.cols(); ++j) {
    h.push_back("q" + std::to_string(j + 1));
    cols.emplace_back(d.q.col(j).data(), d.q.col(j).data() + d.rows());
  }
  const char* names[6] = {"x", "y", "z", "alpha", "beta", "gamma"};
  for (int c = 0; c < d.pose.cols(); ++c) {
    h.push_back(names[c]);
    const Eigen::VectorXd col = d.pose.col(c);
    cols.emplace_back(col.data(), col.data() + col.size());
  }
  return io::formatCsv(h, cols);
}

std::unique_ptr<ArmProblem> makeTcpProblem(const Model& model, const TcpData& data) {
  ARMSTUDY_CHECK(data.q.cols() == model.dof(), "data columns match the design");
  return std::make_unique<TcpProblem>(model, data);
}

TcpData synthesizeTcp(const Model& model, const TcpSynthOptions& o) {
  if (o.rows < 1 || o.rows > defaults::kMaxSynthRows)
    throw InputError("", 0, "rows", "1 to " + std::to_string(defaults::kMaxSynthRows) + " rows");
  if (!(o.noise_m >= 0) || !(o.noise_rad >= 0))
    throw InputError("", 0, "noise", "noise must not be negative");
  if (!(o.range_fraction > 0 && o.range_fraction <= 1))
    throw InputError("", 0, "range", "range fraction in (0, 1]");
  rng::SplitMix64 rng{o.seed};
  TcpData d;
  const int n = model.dof();
  d.q.resize(o.rows, n);
  for (int i = 0; i < o.rows; ++i)
    for (int j = 0; j < n; ++j) {
      const JointLimits& l = model.joints[j].limits;
      const double c = 0.5 * (l.q_min + l.q_max), h = 0.5 * (l.q_max - l.q_min) * o.range_fraction;
      d.q(i, j) = c + h * (2 * rng.uniform() - 1);
    }
  d.pose = Eigen::MatrixXd::Zero(o.rows, o.orientation ? 6 : 3);
  for (int i = 0; i < o.rows; ++i) d.lines.push_back(i + 2);
  const auto P = makeTcpProblem(model, d);
  EffectValues hidden;
  for (const auto& h : o.hidden) hidden.push_back(parseHiddenEffect(*P, h));
  // Orientation: predict() wraps angles near the "measured" zeros; unwrap with the plain FK value.
  d.pose = P->predict(hidden);
  for (int i = 0; i < o.rows; ++i) {
    for (int c = 0; c < 3; ++c) d.pose(i, c) += o.noise_m * rng.normal();
    for (int c = 3; c < d.pose.cols(); ++c)
      d.pose(i, c) = wrapAngle(d.pose(i, c) + o.noise_rad * rng.normal());
  }
  return d;
}

Model calibratedTcpModel(const Model& model, const ArmProblem& problem, const EffectValues& values,
                         std::vector<std::string>& notes) {
  const auto& P = dynamic_cast<const TcpProblem&>(problem);
  Model m = model;
  for (const auto& v : values) {
    const auto& t = P.tags_[v.effect];
    switch (t.type) {
      case TcpEffect::JointOffset: {
        Joint& j = m.joints[t.joint];
        if (j.type == JointType::Revolute) {
          j.offset.gamma += v.x[0];  // revolute: q adds to gamma, so an offset of q is one of gamma
        } else {
          const Eigen::Vector3d d = j.offset.toIsometry().linear() * Eigen::Vector3d(0, 0, v.x[0]);
          j.offset.x += d.x();
          j.offset.y += d.y();
          j.offset.z += d.z();
        }
        break;
      }
      case TcpEffect::LinkLength: {
        PoseXYZABG& o = m.joints[t.joint].offset;
        (t.axis == 0 ? o.x : t.axis == 1 ? o.y : o.z) += v.x[0];
        break;
      }
      case TcpEffect::BaseOffset:
        addBaseOffset(m.base, v.x);
        break;
      case TcpEffect::Compliance: {
        notes.push_back("joint_compliance of " + m.joints[t.joint].name + " = " +
                        formatG(v.x[0], 6) + " " + problem.catalogue[v.effect].params[0].unit +
                        " is not stored in the design file (no design key yet)");
        break;
      }
    }
  }
  m.finalize();
  return m;
}

}  // namespace armstudy::calibration
