#include "ik/nullspace.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "common/defaults.hpp"
#include "common/enum_names.hpp"
#include "common/errors.hpp"
#include "metrics/dexterity_measures.hpp"

namespace armstudy::ik {

namespace {
using SmallMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using Basis = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3>;
}  // namespace

constexpr const char* kTrackingStatusNames[] = {"completed", "joint_limit_reached",
                                                "singular_jacobian"};
const char* toString(TrackingStatus s) { return enumName(s, kTrackingStatusNames); }

constexpr const char* kNullspaceStatusNames[] = {"converged", "iteration_limit", "not_on_pose"};
const char* toString(NullspaceStatus s) { return enumName(s, kNullspaceStatusNames); }

bool withinLimits(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q) {
  for (int i = 0; i < q.size(); ++i)
    if (q[i] < model.joints[i].limits.q_min || q[i] > model.joints[i].limits.q_max) return false;
  return true;
}

void taskJacobianAndError(const KinematicsWorkspace& ws, const PoseTask& target, TaskJacobian& J,
                          TaskVec& e, Basis* S_out, PoseError* pe) {
  ARMSTUDY_CHECK(target.kind != PoseTaskKind::CardanAngles,
                 "taskJacobianAndError: a task of Cardan angles has analytic rows");
  const int n = ws.n;
  const int m = target.rows();
  const int p = target.positionRows();
  J.resize(m, n);
  e.resize(m);
  if (p == 3) {
    J.topRows<3>() = ws.J_W_tcp.topRows<3>();
    e.head<3>() = target.p_WT - ws.p_WT;
  } else {
    for (int k = 0, r = 0; k < 3; ++k)
      if (target.position_selected[k]) {
        J.row(r) = ws.J_W_tcp.row(k);
        e[r++] = target.p_WT[k] - ws.p_WT[k];
      }
  }
  Basis S;
  if (target.kind == PoseTaskKind::PositionAxis) {
    // Constrained angular directions: perpendicular to the current tool axis (rotation about the
    // axis itself leaves it unchanged, so it belongs to the null space).
    const Eigen::Vector3d a = ws.a_WT;
    Eigen::Vector3d b1, b2;
    perpendicularBasis(a, b1, b2);
    S.resize(3, 2);
    S.col(0) = b1;
    S.col(1) = b2;
    const Eigen::Vector3d rv = rotationBetween(a, target.axis_W.normalized());
    J.bottomRows<2>() = S.transpose() * ws.J_W_tcp.bottomRows<3>();
    e.tail<2>() = S.transpose() * rv;
    if (pe) pe->orientation_rad = rv.norm();
  } else if (target.kind == PoseTaskKind::FullPose) {
    S = Eigen::Matrix3d::Identity();
    J.bottomRows<3>() = ws.J_W_tcp.bottomRows<3>();
    const Eigen::AngleAxisd aa(target.R_WT * ws.R_WT.transpose());
    e.tail<3>() = aa.angle() * aa.axis();
    if (pe) pe->orientation_rad = aa.angle();
  } else {
    S.resize(3, 0);
    if (pe) pe->orientation_rad = 0;
  }
  if (pe) pe->position_m = p == 3 ? (target.p_WT - ws.p_WT).norm() : e.head(p).norm();
  if (S_out) *S_out = S;
}

double adaptiveDamping(double manipulability, double lambda0, double m0) {
  if (lambda0 <= 0 || m0 <= 0 || manipulability >= m0) return 0.0;
  const double r = 1.0 - manipulability / m0;
  return lambda0 * r * r;  // eq. (5.67)
}

bool redundancyResolution(const Eigen::Ref<const Eigen::MatrixXd>& J,
                          const Eigen::Ref<const Eigen::VectorXd>& w_inv,
                          const Eigen::Ref<const Eigen::VectorXd>& wdot,
                          const Eigen::Ref<const Eigen::VectorXd>& grad, double alpha,
                          double lambda, Eigen::Ref<Eigen::VectorXd> qdot) {
  const int m = static_cast<int>(J.rows()), n = static_cast<int>(J.cols());
  ARMSTUDY_CHECK(w_inv.size() == n && wdot.size() == m && qdot.size() == n,
                 "redundancyResolution: size mismatch");
  ARMSTUDY_CHECK(grad.size() == 0 || grad.size() == n, "redundancyResolution: gradient size");
  TaskJacobian JWinv = J * w_inv.asDiagonal();
  // Algorithm 5.3, line 1: p = wdot + alpha J W^-1 grad^T.
  TaskVec p = wdot;
  if (grad.size() == n && alpha != 0) p.noalias() += alpha * (JWinv * grad);
  // Line 2 (+ eq. 5.65b): B = J W^-1 J^T + lambda^2 I.
  SmallMat B = JWinv * J.transpose();
  B.diagonal().array() += lambda * lambda;
  // Line 3: solve B gamma = p by Cholesky elimination (no explicit inverse).
  const Eigen::LLT<SmallMat> llt(B);
  if (llt.info() != Eigen::Success) return false;
  const TaskVec gamma = llt.solve(p);
  // Line 4: qdot = W^-1 (J^T gamma - alpha grad^T).
  JointVector r = J.transpose() * gamma;
  if (grad.size() == n && alpha != 0) r -= alpha * grad;
  qdot = w_inv.cwiseProduct(r);
  return true;
}

std::string RedundancyOptions::validate(int dof) const {
  if (!joint_weights.empty()) {
    if (static_cast<int>(joint_weights.size()) != dof)
      return "joint_weights needs one weight per joint (" + std::to_string(dof) + ")";
    for (double w : joint_weights)
      if (!(w >= defaults::kMinWeight && w <= defaults::kMaxWeight))
        return "joint weights must lie in [1e-6, 1e6]";
  }
  if (!std::isfinite(alpha) || alpha < 0) return "null-space gain alpha must be finite and >= 0";
  if (!std::isfinite(drift_gain) || drift_gain < 0) return "drift gain must be finite and >= 0";
  if (!std::isfinite(damping_lambda0) || damping_lambda0 < 0)
    return "damping lambda0 must be finite and >= 0";
  if (!std::isfinite(damping_m0) || damping_m0 < 0) return "damping m0 must be finite and >= 0";
  return "";
}

JointVector RedundancyOptions::weightInverse(int dof) const {
  JointVector w_inv = JointVector::Ones(dof);
  for (int i = 0; i < static_cast<int>(joint_weights.size()) && i < dof; ++i)
    w_inv[i] = 1.0 / joint_weights[i];
  return w_inv;
}

std::string TrackingOptions::validate(int dof) const {
  if (!std::isfinite(dt) || dt <= 0) return "time step must be finite and > 0";
  return redundancy.validate(dof);
}

TrackingSummary trackReference(const Model& model, KinematicsWorkspace& ws,
                               const Reference& reference, const Eigen::VectorXd& q0,
                               double duration, const WeightedObjective* objective,
                               ObjectiveContext* ctx, const TrackingOptions& options) {
  const int n = model.dof();
  const std::string why = options.validate(n);
  ARMSTUDY_CHECK(why.empty(), why);
  ARMSTUDY_CHECK(!objective || ctx, "trackReference: an objective needs a context");
  TrackingSummary sum;
  sum.options_used = options;
  const JointVector w_inv = options.redundancy.weightInverse(n);
  JointVector q = q0, qdot(n), grad(n);
  TaskJacobian J;
  TaskVec e;
  Basis S;
  const int steps = static_cast<int>(std::ceil(duration / options.dt - 1e-9));
  sum.samples.reserve(steps + 1);
  for (int k = 0; k <= steps; ++k) {
    const double t = std::min(k * options.dt, duration);
    const ReferencePoint ref = reference(t);
    forwardKinematicsAndJacobian(model, ws, q);
    taskJacobianAndError(ws, ref.pose, J, e, &S);
    // eq. (5.50): effective task velocity wdot_d + K e.
    TaskVec wdot(J.rows());
    wdot.head<3>() = ref.v_W;
    if (J.rows() > 3) wdot.tail(J.rows() - 3) = S.transpose() * ref.omega_W;
    wdot += options.redundancy.drift_gain * e;
    const double mbar = metrics::computeMeasures(J, TaskVec()).manipulability;
    const double lambda =
        adaptiveDamping(mbar, options.redundancy.damping_lambda0, options.redundancy.damping_m0);
    bool have_grad = false;
    if (objective && !objective->empty()) {
      ctx->prepare(q);
      objective->evaluate(*ctx, &grad);
      have_grad = true;
    }
    const bool ok = redundancyResolution(J, w_inv, wdot, have_grad ? grad : JointVector(),
                                         options.redundancy.alpha, lambda, qdot);
    TrackingSample smp;
    smp.t = t;
    smp.q = q;
    const PoseError pe = poseError(ws, ref.pose);
    smp.position_error_m = pe.position_m;
    smp.orientation_error_rad = pe.orientation_rad;
    smp.lambda = lambda;
    smp.manipulability = mbar;
    if (!ok) {
      sum.status = TrackingStatus::SingularJacobian;
      smp.qdot.setZero(n);
      sum.samples.push_back(smp);
      break;
    }
    smp.qdot = qdot;
    sum.samples.push_back(smp);
    sum.max_joint_speed = std::max(sum.max_joint_speed, qdot.cwiseAbs().maxCoeff());
    sum.steps = k;
    if (k == steps) break;
    q += qdot * options.dt;  // eq. (5.49), explicit Euler
    for (int i = 0; i < n && sum.limit_joint < 0; ++i)
      if (q[i] < model.joints[i].limits.q_min || q[i] > model.joints[i].limits.q_max) {
        sum.limit_joint = i;
        sum.limit_q = q[i] < model.joints[i].limits.q_min ? model.joints[i].limits.q_min
                                                          : model.joints[i].limits.q_max;
        sum.status = TrackingStatus::JointLimitReached;
      }
    if (sum.limit_joint >= 0 && options.stop_at_joint_limit) break;
  }
  return sum;
}

std::string NullspaceOptions::validate() const {
  if (max_iterations < 0) return "max_iterations must be >= 0";
  if (!std::isfinite(relative_improvement) || relative_improvement < 0)
    return "relative_improvement must be finite and >= 0";
  if (!std::isfinite(max_step) || max_step <= 0) return "max_step must be finite and > 0";
  if (correction_iterations < 0) return "correction_iterations must be >= 0";
  if (!std::isfinite(pose_tolerance) || pose_tolerance <= 0) return "pose tolerance must be > 0";
  if (!std::isfinite(damping_lambda0) || damping_lambda0 < 0)
    return "damping lambda0 must be finite and >= 0";
  if (!std::isfinite(damping_m0) || damping_m0 < 0) return "damping m0 must be finite and >= 0";
  return "";
}

NullspaceResult optimiseAtPose(const Model& model, KinematicsWorkspace& ws, ObjectiveContext& ctx,
                               const PoseTask& target, const Eigen::VectorXd& q_start,
                               const WeightedObjective& objective, const Eigen::VectorXd& w_inv,
                               const NullspaceOptions& options) {
  const int n = model.dof();
  NullspaceResult res;
  res.q = q_start;
  forwardKinematicsAndJacobian(model, ws, res.q);
  ctx.prepare(res.q);
  res.error = poseError(ws, target);
  JointVector grad(n);
  res.H_start = res.H_final = objective.evaluate(ctx, &grad);
  res.evaluations = 1;
  res.kernel_evaluations = 1;
  // The tool may not drift further from the pose than where it started (or the tolerance).
  const double tol_p = std::max(options.pose_tolerance, res.error.position_m);
  const double tol_o = std::max(options.pose_tolerance, res.error.orientation_rad);
  if (res.error.position_m > 1e-3 || res.error.orientation_rad > 1e-2 ||
      !withinLimits(model, res.q)) {
    res.status = NullspaceStatus::NotOnPose;
    return res;
  }
  TaskJacobian J;
  TaskVec e;
  taskJacobianAndError(ws, target, J, e);
  JointVector q = res.q, d(n), q_try(n), dq(n);
  double H = res.H_start;
  double step = options.max_step;
  res.status = NullspaceStatus::IterationLimit;
  for (int it = 0; it < options.max_iterations; ++it) {
    // Descent direction in the null space: Algorithm 5.3 with wdot = 0 and alpha = 1,
    // d = -N W^-1 grad^T (eq. 5.46).
    // (The manipulability is only needed when the damping is on.)
    const bool damped = options.damping_lambda0 > 0 && options.damping_m0 > 0;
    const double lambda =
        damped ? adaptiveDamping(metrics::computeMeasures(J, TaskVec()).manipulability,
                                 options.damping_lambda0, options.damping_m0)
               : 0.0;
    if (!redundancyResolution(J, w_inv, TaskVec::Zero(J.rows()), grad, 1.0, lambda, d)) {
      res.status = NullspaceStatus::Converged;
      break;
    }
    const double slope = grad.dot(d);  // <= 0
    const double dmax = d.cwiseAbs().maxCoeff();
    if (!(dmax > 1e-14) || !(slope < 0)) {
      res.status = NullspaceStatus::Converged;
      break;
    }
    double s = std::min(2.0 * step, options.max_step / dmax);
    bool accepted = false;
    double H_try = H;
    for (int ls = 0; ls < 30 && s * dmax > 1e-12; ++ls, s *= 0.5) {
      q_try = q + s * d;
      if (!withinLimits(model, q_try)) continue;
      // Drift compensation (eq. 5.50 as Newton iteration): back onto the pose.
      bool on_pose = false;
      TaskJacobian Jc;
      TaskVec ec;
      for (int c = 0; c <= options.correction_iterations; ++c) {
        forwardKinematicsAndJacobian(model, ws, q_try);
        ++res.kernel_evaluations;
        PoseError pe;
        taskJacobianAndError(ws, target, Jc, ec, nullptr, &pe);
        if (pe.position_m <= tol_p && pe.orientation_rad <= tol_o) {
          on_pose = true;
          break;
        }
        if (c == options.correction_iterations) break;
        if (!redundancyResolution(Jc, w_inv, ec, JointVector(), 0.0, 0.0, dq)) break;
        q_try += dq;
      }
      if (!on_pose || !withinLimits(model, q_try)) continue;
      ctx.prepare(q_try);
      H_try = objective.evaluate(ctx, nullptr);
      ++res.evaluations;
      if (H_try < H + 1e-4 * s * slope) {  // Armijo condition
        accepted = true;
        J = Jc;
        break;
      }
    }
    if (!accepted) {
      res.status = NullspaceStatus::Converged;
      break;
    }
    step = s;
    res.last_step = s * dmax;
    res.step_sum += res.last_step;
    const double improvement = H - H_try;
    q = q_try;
    H = H_try;
    ++res.iterations;
    ctx.prepare(q);  // ws holds FK and J at q_try from the last correction
    objective.evaluate(ctx, &grad);
    ++res.evaluations;
    if (improvement <= options.relative_improvement * std::max(std::abs(H), 1e-12)) {
      res.status = NullspaceStatus::Converged;
      break;
    }
  }
  res.q = q;
  res.H_final = H;
  forwardKinematicsAndJacobian(model, ws, q);
  ++res.kernel_evaluations;
  res.error = poseError(ws, target);
  return res;
}

void DescentTally::add(const NullspaceResult& r) {
  ++descents;
  iterations += r.iterations;
  objective_evaluations += r.evaluations;
  kernel_evaluations += r.kernel_evaluations;
  step_sum += r.step_sum;
  last_step_sum += r.last_step;
  ++stopped[static_cast<int>(r.status)];
}

void DescentTally::add(const DescentTally& o) {
  descents += o.descents;
  changed += o.changed;
  iterations += o.iterations;
  objective_evaluations += o.objective_evaluations;
  kernel_evaluations += o.kernel_evaluations;
  step_sum += o.step_sum;
  last_step_sum += o.last_step_sum;
  for (int k = 0; k < 3; ++k) stopped[k] += o.stopped[k];
}

}  // namespace armstudy::ik
