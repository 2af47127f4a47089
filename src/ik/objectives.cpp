#include "ik/objectives.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

#include "common/errors.hpp"

namespace armstudy::ik {

ObjectiveContext::ObjectiveContext(const Model& model, KinematicsWorkspace& ws)
    : model_(&model), ws_(&ws) {
  for (auto& d : dJ_) d.setZero(6, ws.n);
}

void ObjectiveContext::prepare(const Eigen::Ref<const Eigen::VectorXd>& q_now) {
  ARMSTUDY_CHECK(q_now.size() == ws_->n, "ObjectiveContext::prepare: q has the wrong size");
  q = q_now;
  dJ_valid_.fill(false);
}

const Jacobian6& ObjectiveContext::jacobianDerivative(int i) {
  if (!dJ_valid_[i]) {
    dJ_[i].resize(6, ws_->n);
    tcpJacobianDerivative(*model_, *ws_, i, dJ_[i]);
    dJ_valid_[i] = true;
  }
  return dJ_[i];
}

JointLimitTerm::JointLimitTerm(const Model& model, double activation) {
  ARMSTUDY_CHECK(activation > 0 && activation < 0.5,
                 "JointLimitTerm: activation must be in (0, 0.5)");
  for (const Joint& j : model.joints) {
    const double range = j.limits.q_max - j.limits.q_min;
    q_min_.push_back(j.limits.q_min);
    q_max_.push_back(j.limits.q_max);
    q_bar_min_.push_back(j.limits.q_min + activation * range);
    q_bar_max_.push_back(j.limits.q_max - activation * range);
  }
}

double JointLimitTerm::evaluate(ObjectiveContext& ctx, JointVector* grad) const {
  // Thesis eq. (5.52), per joint: ((q - q_bar) / (q_limit - q_bar))^2 beyond the threshold.
  const int n = ctx.dof();
  double h = 0;
  if (grad) grad->setZero(n);
  for (int i = 0; i < n; ++i) {
    const double q = ctx.q[i];
    double bar = 0, lim = 0;
    if (q > q_bar_max_[i]) {
      bar = q_bar_max_[i];
      lim = q_max_[i];
    } else if (q < q_bar_min_[i]) {
      bar = q_bar_min_[i];
      lim = q_min_[i];
    } else {
      continue;
    }
    const double d2 = (lim - bar) * (lim - bar);
    h += (q - bar) * (q - bar) / d2;
    if (grad) (*grad)[i] = 2.0 * (q - bar) / d2;
  }
  return h;
}

namespace {
using SmallMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
using RowsMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, kMaxDof>;

// The rows J of J_W_tcp that the measure space uses and the Cholesky factor of A = J J^T: what the
// manipulability (eq. 5.59) and the transmission ratio (eq. 5.61) are computed from.
struct MeasureGram {
  MeasureGram(const ObjectiveContext& ctx, metrics::MeasureSpace space)
      : m(metrics::measureRows(space)),
        J(ctx.ws().J_W_tcp.topRows(m)),
        llt(SmallMat(J * J.transpose())) {}
  int m;
  Jacobian6::ConstRowsBlockXpr J;
  Eigen::LLT<SmallMat> llt;
};
}  // namespace

double ManipulabilityTerm::evaluate(ObjectiveContext& ctx, JointVector* grad) const {
  const MeasureGram G(ctx, space_);
  const int m = G.m, n = ctx.dof();
  if (grad) grad->setZero(n);
  if (G.llt.info() != Eigen::Success) return 0.0;  // singular: H_m1 = 0, gradient undefined -> 0
  const auto L = G.llt.matrixL();
  double det = 1;
  for (int k = 0; k < m; ++k) det *= L(k, k) * L(k, k);
  const double h = -std::sqrt(det);  // eq. (5.59)
  if (grad) {
    // eq. (5.62): dH/dq_i = H trace(A^-1 dJ_i J^T) = H sum(A^-1 J .* dJ_i) (Frobenius product).
    const RowsMat AinvJ = G.llt.solve(RowsMat(G.J));
    for (int i = 0; i < n; ++i)
      (*grad)[i] = h * AinvJ.cwiseProduct(ctx.jacobianDerivative(i).topRows(m)).sum();
  }
  return h;
}

double TransmissionTerm::evaluate(ObjectiveContext& ctx, JointVector* grad) const {
  const MeasureGram G(ctx, space_);
  const int m = G.m, n = ctx.dof();
  if (grad) grad->setZero(n);
  SmallVec u = SmallVec::Zero(m);
  u.head<3>() = ctx.u_W;
  if (G.llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  const SmallVec v = G.llt.solve(u);  // v = A^-1 u
  const double h = u.dot(v);          // eq. (5.61)
  if (grad) {
    // eq. (5.64): dH/dq_i = -v^T (dJ_i J^T + J dJ_i^T) v = -2 (dJ_i^T v) . (J^T v).
    const JointVector Jtv = G.J.transpose() * v;
    for (int i = 0; i < n; ++i)
      (*grad)[i] = -2.0 * (ctx.jacobianDerivative(i).topRows(m).transpose() * v).dot(Jtv);
  }
  return h;
}

void WeightedObjective::add(double weight, std::shared_ptr<const ObjectiveTerm> term) {
  ARMSTUDY_CHECK(std::isfinite(weight) && weight >= 0, "objective weights must be finite and >= 0");
  ARMSTUDY_CHECK(term != nullptr, "objective term is null");
  if (weight > 0) terms_.emplace_back(weight, std::move(term));
}

double WeightedObjective::evaluate(ObjectiveContext& ctx, JointVector* grad) const {
  const int n = ctx.dof();
  double h = 0;
  if (grad) grad->setZero(n);
  JointVector g(n);
  for (const auto& [w, term] : terms_) {
    h += w * term->evaluate(ctx, grad ? &g : nullptr);  // eq. (5.51)
    if (grad) *grad += w * g;
  }
  return h;
}

}  // namespace armstudy::ik
