#include "ik/nullspace.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

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

namespace {

// Algorithm 5.3 in two parts: lines 2-3 (B = J W^-1 J^T + lambda^2 I and its Cholesky factor) at
// one J, then lines 1 and 4 for any (wdot, grad, alpha): a descent resolves several vectors at the
// same configuration with one factorisation.
class TaskFactor {
 public:
  // False when B is not positive definite (singular J and lambda = 0).
  bool factor(const Eigen::Ref<const Eigen::MatrixXd>& J,
              const Eigen::Ref<const Eigen::VectorXd>& w_inv, double lambda) {
    JWinv_ = J * w_inv.asDiagonal();
    SmallMat B = JWinv_ * J.transpose();
    B.diagonal().array() += lambda * lambda;
    llt_.compute(B);
    ok_ = llt_.info() == Eigen::Success;
    return ok_;
  }
  // qdot for the J and w_inv of the last factor() (false, qdot untouched, when it failed).
  bool resolve(const Eigen::Ref<const Eigen::MatrixXd>& J,
               const Eigen::Ref<const Eigen::VectorXd>& w_inv,
               const Eigen::Ref<const Eigen::VectorXd>& wdot,
               const Eigen::Ref<const Eigen::VectorXd>& grad, double alpha,
               Eigen::Ref<Eigen::VectorXd> qdot) const {
    if (!ok_) return false;
    const long n = J.cols();
    // Line 1: p = wdot + alpha J W^-1 grad^T.
    TaskVec p = wdot;
    if (grad.size() == n && alpha != 0) p.noalias() += alpha * (JWinv_ * grad);
    // Line 3: solve B gamma = p by Cholesky elimination (no explicit inverse).
    const TaskVec gamma = llt_.solve(p);
    // Line 4: qdot = W^-1 (J^T gamma - alpha grad^T).
    JointVector r = J.transpose() * gamma;
    if (grad.size() == n && alpha != 0) r -= alpha * grad;
    qdot = w_inv.cwiseProduct(r);
    return true;
  }

 private:
  TaskJacobian JWinv_;
  Eigen::LLT<SmallMat> llt_;
  bool ok_ = false;
};

}  // namespace

bool redundancyResolution(const Eigen::Ref<const Eigen::MatrixXd>& J,
                          const Eigen::Ref<const Eigen::VectorXd>& w_inv,
                          const Eigen::Ref<const Eigen::VectorXd>& wdot,
                          const Eigen::Ref<const Eigen::VectorXd>& grad, double alpha,
                          double lambda, Eigen::Ref<Eigen::VectorXd> qdot) {
  const int m = static_cast<int>(J.rows()), n = static_cast<int>(J.cols());
  ARMSTUDY_CHECK(w_inv.size() == n && wdot.size() == m && qdot.size() == n,
                 "redundancyResolution: size mismatch");
  ARMSTUDY_CHECK(grad.size() == 0 || grad.size() == n, "redundancyResolution: gradient size");
  TaskFactor f;
  return f.factor(J, w_inv, lambda) && f.resolve(J, w_inv, wdot, grad, alpha, qdot);
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
  if (!std::isfinite(gradient_tolerance) || gradient_tolerance < 0)
    return "gradient_tolerance must be finite and >= 0";
  if (!std::isfinite(damping_lambda0) || damping_lambda0 < 0)
    return "damping lambda0 must be finite and >= 0";
  if (!std::isfinite(damping_m0) || damping_m0 < 0) return "damping m0 must be finite and >= 0";
  return "";
}

namespace {

// Drift compensation (eq. 5.50) as a Newton iteration with the generalised inverse: moves q back
// onto the pose. True when it ends within (tol_p, tol_o); ws then holds FK and the TCP Jacobian at
// q, and Jc the task rows there.
bool backOntoPose(const Model& model, KinematicsWorkspace& ws, const PoseTask& target,
                  const Eigen::VectorXd& w_inv, int corrections, double tol_p, double tol_o,
                  JointVector& q, TaskJacobian& Jc, int& kernel_evaluations) {
  TaskVec ec;
  JointVector dq(q.size());
  for (int c = 0; c <= corrections; ++c) {
    forwardKinematicsAndJacobian(model, ws, q);
    ++kernel_evaluations;
    PoseError pe;
    taskJacobianAndError(ws, target, Jc, ec, nullptr, &pe);
    if (pe.position_m <= tol_p && pe.orientation_rad <= tol_o) return true;
    if (c == corrections) return false;
    if (!redundancyResolution(Jc, w_inv, ec, JointVector(), 0.0, 0.0, dq)) return false;
    q += dq;
  }
  return false;
}

// N_W v = v - W^-1 J^T (J W^-1 J^T)^-1 J v, the part of v that leaves the task still (Algorithm
// 5.3 with wdot = 0 and the "gradient" W v). False when J is singular.
// `f`: the factor of B at J with lambda = 0.
bool nullspacePart(const TaskFactor& f, const TaskJacobian& J, const Eigen::VectorXd& w_inv,
                   const JointVector& v, JointVector& out) {
  const JointVector wv = v.cwiseQuotient(w_inv);
  if (!f.resolve(J, w_inv, TaskVec::Zero(J.rows()), wv, 1.0, out)) return false;
  out = -out;
  return true;
}

// The last few (step, change of projected gradient) pairs of a descent, and the two-loop
// recursion that applies their limited-memory BFGS inverse Hessian (Nocedal & Wright, Numerical
// Optimization, Algorithm 7.4, initial scaling eq. 7.20).
struct QuasiNewtonMemory {
  static constexpr int kPairs = kQuasiNewtonPairs;
  std::array<JointVector, kPairs> s, y;
  std::array<double, kPairs> rho{};
  int count = 0, next = 0;
  void clear() { count = next = 0; }
  // Keeps the pair when its curvature s^T y is positive (the update stays positive definite).
  void push(const JointVector& si, const JointVector& yi) {
    const double sy = si.dot(yi);
    if (!(sy > kQuasiNewtonCurvatureFloor * si.norm() * yi.norm())) return;
    s[next] = si;
    y[next] = yi;
    rho[next] = 1.0 / sy;
    next = (next + 1) % kPairs;
    count = std::min(count + 1, kPairs);
  }
  int at(int k) const { return (next - 1 - k + 2 * kPairs) % kPairs; }  // k-th newest
  JointVector apply(const JointVector& g) const {
    JointVector r = g;
    std::array<double, kPairs> a{};
    for (int k = 0; k < count; ++k) {
      const int i = at(k);
      a[i] = rho[i] * s[i].dot(r);
      r -= a[i] * y[i];
    }
    const int n0 = at(0);
    r *= s[n0].dot(y[n0]) / y[n0].squaredNorm();
    for (int k = count - 1; k >= 0; --k) {
      const int i = at(k);
      r += s[i] * (a[i] - rho[i] * y[i].dot(r));
    }
    return r;
  }
};

// One descent's state: the iterate on the pose, its objective, gradient and task rows, and the
// projected (steepest) descent direction -N W^-1 grad there.
struct DescentState {
  JointVector q, grad, d_sd;
  double H = 0;
  TaskJacobian J;
  TaskFactor factor;  // of B at J, with the damping of the steepest direction
};

// The damped or undamped steepest null-space direction at the state (Algorithm 5.3 with wdot = 0
// and alpha = 1, d = -N W^-1 grad^T, eq. 5.46). False when B is not positive definite.
bool steepest(const NullspaceOptions& o, const Eigen::VectorXd& w_inv, DescentState& st,
              double& lambda) {
  const bool damped = o.damping_lambda0 > 0 && o.damping_m0 > 0;
  lambda = damped ? adaptiveDamping(metrics::computeMeasures(st.J, TaskVec()).manipulability,
                                    o.damping_lambda0, o.damping_m0)
                  : 0.0;
  return st.factor.factor(st.J, w_inv, lambda) &&
         st.factor.resolve(st.J, w_inv, TaskVec::Zero(st.J.rows()), st.grad, 1.0, st.d_sd);
}

// Whether H at q (FK and J in ws) satisfies the Armijo condition H < H0 + 1e-4 * decrease, with
// decrease = s * grad^T d < 0; H is in H_out.
bool armijo(const WeightedObjective& objective, ObjectiveContext& ctx, const JointVector& q,
            double H0, double decrease, double& H_out, int& evaluations) {
  ctx.prepare(q);
  H_out = objective.evaluate(ctx, nullptr);
  ++evaluations;
  return H_out < H0 + 1e-4 * decrease;
}

// The step direction into d: the quasi-Newton direction from `memory`, kept in the null space, or
// the steepest one (when the option is off, the descent is damped, there are no pairs, or the
// quasi-Newton direction does not descend; the pairs are then dropped). True for a quasi-Newton
// direction (tried with a unit step first).
bool direction(const NullspaceOptions& o, const Eigen::VectorXd& w_inv, const DescentState& st,
               double lambda, QuasiNewtonMemory& memory, JointVector& d) {
  d = st.d_sd;
  if (!o.quasi_newton || lambda != 0 || memory.count == 0) return false;
  JointVector t(d.size());
  if (nullspacePart(st.factor, st.J, w_inv, memory.apply(-st.d_sd), t) && st.grad.dot(-t) < 0) {
    d = -t;
    return true;
  }
  memory.clear();
  return false;
}

}  // namespace

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
  DescentState st;
  st.grad.resize(n);
  st.d_sd.resize(n);
  res.H_start = res.H_final = objective.evaluate(ctx, &st.grad);
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
  TaskVec e;
  taskJacobianAndError(ws, target, st.J, e);
  st.q = res.q;
  st.H = res.H_start;
  JointVector d(n), q_try(n);
  TaskJacobian Jc;
  QuasiNewtonMemory memory;
  double step = options.max_step, lambda = 0;
  bool have_direction = steepest(options, w_inv, st, lambda);
  res.status = NullspaceStatus::IterationLimit;
  for (int it = 0; it < options.max_iterations; ++it) {
    if (!have_direction) {
      res.status = NullspaceStatus::Converged;
      break;
    }
    res.projected_gradient = st.d_sd.cwiseAbs().maxCoeff();
    // First-order condition: the projected gradient vanishes (docs/dexterity.md, "Descent").
    if (res.projected_gradient <= options.gradient_tolerance) {
      res.status = NullspaceStatus::Converged;
      break;
    }
    const bool unit = direction(options, w_inv, st, lambda, memory, d);
    const double slope = st.grad.dot(d);  // < 0
    const double dmax = d.cwiseAbs().maxCoeff();
    if (!(dmax > 1e-14) || !(slope < 0)) {
      res.status = NullspaceStatus::Converged;
      break;
    }
    double s = std::min(unit ? 1.0 : 2.0 * step, options.max_step / dmax);
    double H_try = st.H;
    bool accepted = false;
    for (int ls = 0; ls < 30 && s * dmax > 1e-12 && !accepted; ++ls) {
      q_try = st.q + s * d;
      accepted = withinLimits(model, q_try) &&
                 backOntoPose(model, ws, target, w_inv, options.correction_iterations, tol_p, tol_o,
                              q_try, Jc, res.kernel_evaluations) &&
                 withinLimits(model, q_try) &&
                 armijo(objective, ctx, q_try, st.H, s * slope, H_try, res.evaluations);
      if (!accepted) s *= 0.5;
    }
    if (!accepted) {
      res.status = NullspaceStatus::Converged;
      break;
    }
    if (!unit) step = s;
    res.last_step = s * dmax;
    res.step_sum += res.last_step;
    const double improvement = st.H - H_try;
    const JointVector q_old = st.q, g_old = -st.d_sd;
    st.q = q_try;
    st.H = H_try;
    st.J = Jc;
    ++res.iterations;
    ctx.prepare(st.q);  // ws holds FK and J at q_try from the last correction
    objective.evaluate(ctx, &st.grad);
    ++res.evaluations;
    have_direction = steepest(options, w_inv, st, lambda);
    if (options.quasi_newton && have_direction && lambda == 0) {
      // The pair in the new point's null space: its step and the change of the projected gradient.
      JointVector sk(n), gk(n);
      if (nullspacePart(st.factor, st.J, w_inv, st.q - q_old, sk) &&
          nullspacePart(st.factor, st.J, w_inv, g_old, gk))
        memory.push(sk, -st.d_sd - gk);
    }
    if (improvement <= options.relative_improvement * std::max(std::abs(st.H), 1e-12)) {
      // A small improvement stops a steepest step; after a quasi-Newton step it says the pairs no
      // longer model H here: steepest descent decides.
      if (unit) {
        memory.clear();
        continue;
      }
      res.status = NullspaceStatus::Converged;
      break;
    }
  }
  res.q = st.q;
  res.H_final = st.H;
  forwardKinematicsAndJacobian(model, ws, st.q);
  ++res.kernel_evaluations;
  res.error = poseError(ws, target);
  return res;
}

double projectedGradient(const Model& model, KinematicsWorkspace& ws, ObjectiveContext& ctx,
                         const PoseTask& target, const Eigen::VectorXd& q,
                         const WeightedObjective& objective, const Eigen::VectorXd& w_inv) {
  DescentState st;
  st.grad.resize(model.dof());
  st.d_sd.resize(model.dof());
  forwardKinematicsAndJacobian(model, ws, q);
  ctx.prepare(q);
  objective.evaluate(ctx, &st.grad);
  TaskVec e;
  taskJacobianAndError(ws, target, st.J, e);
  double lambda = 0;
  if (!steepest(NullspaceOptions{}, w_inv, st, lambda))
    return std::numeric_limits<double>::infinity();
  return st.d_sd.cwiseAbs().maxCoeff();
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
  skipped += o.skipped;
}

}  // namespace armstudy::ik
