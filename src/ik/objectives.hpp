#pragma once
// Secondary objective functions for null-space optimisation (thesis section 5.4.3), each with its
// analytic gradient, combined as the weighted sum H = sum_k w_k H_k (eq. 5.51). The objective is a
// list of terms, so further terms (self-collision H_c, eq. 5.53) plug in without touching the
// solver.
//
// Terms are immutable and shared between threads; everything that changes per evaluation lives in
// the per-thread ObjectiveContext.
#include <Eigen/Core>
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "kinematics/kinematics.hpp"
#include "metrics/dexterity_measures.hpp"

namespace armstudy::ik {

// Per-thread evaluation state. Valid after `prepare` at the current q (forward kinematics and the
// TCP Jacobian must already be in ws). dJ/dq_i are computed on first use and cached until the
// next `prepare`.
class ObjectiveContext {
 public:
  ObjectiveContext(const Model& model, KinematicsWorkspace& ws);
  // Call after forwardKinematicsAndJacobian(model, ws, q) at a new q.
  void prepare(const Eigen::Ref<const Eigen::VectorXd>& q_now);
  const Model& model() const { return *model_; }
  const KinematicsWorkspace& ws() const { return *ws_; }
  int dof() const { return ws_->n; }
  // dJ_W_tcp / dq_i (6 x n), thesis eq. (5.62), (5.64); uses tcpJacobianDerivative.
  const Jacobian6& jacobianDerivative(int i);

  JointVector q;  // the prepared configuration

  // Task data a term may use: the direction u for the transmission objective (unit, in W).
  Eigen::Vector3d u_W = Eigen::Vector3d::UnitX();

  // Per-thread scratch of terms that need more than the kinematics workspace (e.g. the collision
  // workspace of collision::CollisionTerm), keyed by the term and created by it on first use.
  std::map<const void*, std::shared_ptr<void>> term_scratch;

 private:
  const Model* model_;
  KinematicsWorkspace* ws_;
  std::array<Jacobian6, kMaxDof> dJ_;
  std::array<bool, kMaxDof> dJ_valid_{};
};

class ObjectiveTerm {
 public:
  virtual ~ObjectiveTerm() = default;
  virtual std::string name() const = 0;
  // H(q) at the prepared configuration. When grad is non-null, writes dH/dq (size n) into it.
  virtual double evaluate(ObjectiveContext& ctx, JointVector* grad) const = 0;
};

// Thesis eq. (5.52): quadratic penalty once joint i passes the threshold q_bar inside its limits,
// normalised to 1 at the limit. Thresholds sit `activation` x range inside each limit.
class JointLimitTerm final : public ObjectiveTerm {
 public:
  JointLimitTerm(const Model& model, double activation);
  std::string name() const override { return "joint_limits"; }
  double evaluate(ObjectiveContext& ctx, JointVector* grad) const override;
  double qBarMin(int i) const { return q_bar_min_[i]; }
  double qBarMax(int i) const { return q_bar_max_[i]; }

 private:
  std::vector<double> q_min_, q_max_, q_bar_min_, q_bar_max_;
};

// A term of J J^T, J = the rows `space` of J_W_tcp (the dexterity measures).
class MeasureTerm : public ObjectiveTerm {
 public:
  explicit MeasureTerm(metrics::MeasureSpace space) : space_(space) {}

 protected:
  metrics::MeasureSpace space_;
};

// Thesis eq. (5.59): H_m1 = -sqrt(det(J J^T)), gradient eq. (5.62).
class ManipulabilityTerm final : public MeasureTerm {
 public:
  using MeasureTerm::MeasureTerm;
  std::string name() const override { return "manipulability"; }
  double evaluate(ObjectiveContext& ctx, JointVector* grad) const override;
};

// Thesis eq. (5.61): H_m2 = u^T (J J^T)^-1 u (minimising it maximises beta along u, eq. 5.60),
// gradient eq. (5.64). u = ctx.u_W (translational; zero angular part in the full space).
class TransmissionTerm final : public MeasureTerm {
 public:
  using MeasureTerm::MeasureTerm;
  std::string name() const override { return "transmission"; }
  double evaluate(ObjectiveContext& ctx, JointVector* grad) const override;
};

// Thesis eq. (5.51): H = sum_k w_k H_k. Weights must be finite and >= 0 (checked when built from
// input; see DexterityOptions::validate).
class WeightedObjective {
 public:
  void add(double weight, std::shared_ptr<const ObjectiveTerm> term);
  bool empty() const { return terms_.empty(); }
  std::size_t size() const { return terms_.size(); }
  // H(q) and, when grad is non-null, dH/dq, at the prepared configuration.
  double evaluate(ObjectiveContext& ctx, JointVector* grad) const;
  const std::vector<std::pair<double, std::shared_ptr<const ObjectiveTerm>>>& terms() const {
    return terms_;
  }

 private:
  std::vector<std::pair<double, std::shared_ptr<const ObjectiveTerm>>> terms_;
};

}  // namespace armstudy::ik
