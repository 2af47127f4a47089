#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <nlopt.hpp>
#include <vector>

#include "common/errors.hpp"
#include "ik/nullspace.hpp"
#include "ik/reach_internal.hpp"

namespace armstudy::ik_detail {

namespace {

// Damped least-squares step dq = Jf^T (Jf Jf^T + lambda I)^-1 e (Jf: J with the held columns
// zeroed). The system is 6 x 6 whatever the number of joints (rows of unselected task components
// are zero and only add lambda on the diagonal), so the loops have compile-time bounds: the
// symmetric product, an in-place Cholesky factorisation and the two triangular solves.
inline void dampedStep(const Jacobian6& Jf, const Vec6& e, double lambda, JointVector& dq) {
  const int n = static_cast<int>(Jf.cols());
  Eigen::Matrix<double, 6, 6> A = lambda * Eigen::Matrix<double, 6, 6>::Identity();
  for (int i = 0; i < n; ++i) {
    const Vec6 col = Jf.col(i);
    A.noalias() += col * col.transpose();  // rank-1 updates: contiguous fixed-size columns
  }
  double a[6][6];
  for (int r = 0; r < 6; ++r)
    for (int s = 0; s <= r; ++s) a[r][s] = A(r, s);
  for (int j = 0; j < 6; ++j) {  // a = L L^T (lower triangle); lambda > 0 keeps it definite
    double d = a[j][j];
    for (int k = 0; k < j; ++k) d -= a[j][k] * a[j][k];
    d = std::sqrt(std::max(d, 1e-300));
    a[j][j] = d;
    const double inv = 1.0 / d;
    for (int i = j + 1; i < 6; ++i) {
      double v = a[i][j];
      for (int k = 0; k < j; ++k) v -= a[i][k] * a[j][k];
      a[i][j] = v * inv;
    }
  }
  Vec6 y;
  for (int i = 0; i < 6; ++i) {
    double v = e[i];
    for (int k = 0; k < i; ++k) v -= a[i][k] * y[k];
    y[i] = v / a[i][i];
  }
  for (int i = 5; i >= 0; --i) {
    double v = y[i];
    for (int k = i + 1; k < 6; ++k) v -= a[k][i] * y[k];
    y[i] = v / a[i][i];
  }
  for (int i = 0; i < n; ++i) dq[i] = Jf.col(i).dot(y);
}

// NLopt SLSQP: analytic gradients, joint limits as bounds.

struct NloptData {
  const Model* model;
  KinematicsWorkspace* kin;
  const PoseTask* target;
  double w_o;
  Eigen::VectorXd q, g;
  int evaluations = 0;
};

double nloptObjective(unsigned n, const double* x, double* grad, void* data) {
  auto* d = static_cast<NloptData*>(data);
  ++d->evaluations;
  d->q = Eigen::Map<const Eigen::VectorXd>(x, n);
  const double f =
      ikObjective(*d->model, *d->kin, *d->target, d->w_o, d->q, grad ? &d->g : nullptr);
  if (grad) Eigen::Map<Eigen::VectorXd>(grad, n) = d->g;
  return f;
}

// |e|^2 with the angular rows weighted by the characteristic length kOrientationLength_m.
double weightedCost(const ik::TaskVec& e) {
  const double l = defaults::kOrientationLength_m;
  double c = e.head<3>().squaredNorm();
  if (e.size() > 3) c += l * l * e.tail(e.size() - 3).squaredNorm();
  return c;
}

void clampToLimits(const Model& model, JointVector& q) {
  for (int i = 0; i < q.size(); ++i)
    q[i] = std::clamp(q[i], model.joints[i].limits.q_min, model.joints[i].limits.q_max);
}

}  // namespace

// Levenberg-Marquardt on |W e|^2 projected onto the joint-limit box (active set). q is updated
// in place to the best configuration of this start; ws.kin holds its forward kinematics on return.
LocalResult runLm(const Context& c, IkWorkspace& ws, const IkOptions& o, JointVector& q,
                  bool limits, double lambda_initial, int& iterations) {
  const Model& model = *c.model;
  KinematicsWorkspace& kin = ws.kin;
  const int n = kin.n;
  LocalResult res;
  Vec6 e, e_new;
  PoseError err_new;
  Jacobian6 J(6, n), Jf(6, n);
  JointVector q_new(n), dq(n);

  forwardKinematics(model, kin, q);
  residual(c, kin, e, res.err);
  res.cost = e.squaredNorm();
  double lambda = lambda_initial;
  int slow = 0;
  bool kin_current = true;  // kin holds the FK of q
  for (int it = 0; it < o.max_iterations; ++it) {
    if (withinTolerance(res.err, o, defaults::kIkConvergenceFraction)) break;
    if (!kin_current) forwardKinematics(model, kin, q);
    tcpJacobian(model, kin);
    kin_current = true;
    if (!taskJacobian(c, kin, J)) {
      res.singular = true;
      break;
    }
    ++iterations;
    bool accepted = false;
    int rejected = 0;
    while (!accepted) {
      // Damped least squares step over the free joints; a joint at a bound that the step pushes
      // outward is held (its column removed) and the step recomputed once.
      Jf = J;
      dampedStep(Jf, e, lambda, dq);
      if (limits) {
        bool changed = false;
        for (int i = 0; i < n; ++i) {
          const JointLimits& L = model.joints[i].limits;
          if ((q[i] <= L.q_min && dq[i] < 0) || (q[i] >= L.q_max && dq[i] > 0)) {
            Jf.col(i).setZero();
            changed = true;
          }
        }
        if (changed) dampedStep(Jf, e, lambda, dq);
      }
      q_new = q + dq;
      if (limits)
        for (int i = 0; i < n; ++i)
          q_new[i] =
              std::clamp(q_new[i], model.joints[i].limits.q_min, model.joints[i].limits.q_max);
      forwardKinematics(model, kin, q_new);
      kin_current = false;
      residual(c, kin, e_new, err_new);
      const double cost_new = e_new.squaredNorm();
      if (cost_new < res.cost) {
        const double ratio = (res.cost - cost_new) / res.cost;
        slow = ratio < o.stagnation_ratio ? slow + 1 : 0;
        q = q_new;
        e = e_new;
        res.err = err_new;
        res.cost = cost_new;
        kin_current = true;
        lambda = std::max(lambda * defaults::kIkLambdaDown, defaults::kIkLambdaMin_m2);
        accepted = true;
      } else {
        lambda *= defaults::kIkLambdaUp;
        if (lambda > defaults::kIkLambdaMax_m2 || ++rejected >= o.max_rejected_steps) break;
      }
    }
    if (!accepted || slow >= defaults::kIkStagnationSteps) break;
  }
  if (!kin_current) forwardKinematics(model, kin, q);
  res.success = withinTolerance(res.err, o, 1.0);
  return res;
}

// Minimises ikObjective from q (in place) with NLopt SLSQP; returns the local result.
LocalResult runSlsqp(const Context& c, IkWorkspace& ws, const IkOptions& o, JointVector& q) {
  const Model& model = *c.model;
  const int n = model.dof();
  NloptData data{&model, &ws.kin, &c.target, c.w_o, Eigen::VectorXd(n), Eigen::VectorXd(n)};
  nlopt::opt opt(nlopt::LD_SLSQP, static_cast<unsigned>(n));
  std::vector<double> lo(n), hi(n), x(n);
  for (int i = 0; i < n; ++i) {
    lo[i] = model.joints[i].limits.q_min;
    hi[i] = model.joints[i].limits.q_max;
    x[i] = std::clamp(q[i], lo[i], hi[i]);
  }
  opt.set_lower_bounds(lo);
  opt.set_upper_bounds(hi);
  opt.set_min_objective(nloptObjective, &data);
  // Stop once the objective corresponds to errors well inside the tolerances.
  const double tp = defaults::kIkConvergenceFraction * o.position_tolerance_m;
  const double to = defaults::kIkConvergenceFraction * o.orientation_tolerance_rad * c.w_o;
  opt.set_stopval(0.5 * (tp * tp + to * to) * 0.25);
  opt.set_xtol_abs(1e-12);
  opt.set_ftol_abs(1e-16);
  opt.set_maxeval(defaults::kIkPolishMaxEvaluations);
  double f = 0;
  try {
    opt.optimize(x, f);
  } catch (const std::exception&) {
    // Round-off or a failed line search: keep the best point NLopt reports in x.
  }
  for (int i = 0; i < n; ++i) q[i] = std::clamp(x[i], lo[i], hi[i]);
  LocalResult res;
  forwardKinematics(model, ws.kin, q);
  Vec6 e;
  residual(c, ws.kin, e, res.err);
  res.cost = e.squaredNorm();
  res.success = withinTolerance(res.err, o, 1.0);
  return res;
}

int runWeightedNewton(const Model& model, KinematicsWorkspace& ws, const PoseTask& target,
                      const IkOptions& o, JointVector& q) {
  const int n = model.dof();
  const double l = defaults::kOrientationLength_m;
  JointVector w_inv = JointVector::Ones(n);
  for (int i = 0; i < static_cast<int>(o.joint_weights.size()) && i < n; ++i)
    w_inv[i] = 1.0 / o.joint_weights[i];
  clampToLimits(model, q);
  ik::TaskJacobian J, Jt;
  ik::TaskVec e, et;
  forwardKinematicsAndJacobian(model, ws, q);
  ik::taskJacobianAndError(ws, target, J, e);
  double cost = weightedCost(e);
  double mu = 1e-6;
  const int m = static_cast<int>(J.rows());
  ik::TaskVec scale = ik::TaskVec::Ones(m);
  if (m > 3) scale.tail(m - 3).setConstant(l);
  int it = 0;
  for (; it < o.max_iterations; ++it) {
    const PoseError pe = poseError(ws, target);
    if (pe.position_m < o.position_tolerance_m && pe.orientation_rad < o.orientation_tolerance_rad)
      break;
    // Levenberg-Marquardt step on the scaled rows: dq = W^-1 Js^T (Js W^-1 Js^T + mu I)^-1 es.
    const ik::TaskJacobian Js = scale.asDiagonal() * J;
    const ik::TaskVec es = scale.cwiseProduct(e);
    JointVector dq(n);
    if (!ik::redundancyResolution(Js, w_inv, es, JointVector(), 0.0, std::sqrt(mu), dq)) {
      mu = std::max(mu * 10, 1e-12);
      continue;
    }
    const double big = dq.cwiseAbs().maxCoeff();
    if (big > o.max_step) dq *= o.max_step / big;
    JointVector q_try = q + dq;
    clampToLimits(model, q_try);
    forwardKinematicsAndJacobian(model, ws, q_try);
    ik::taskJacobianAndError(ws, target, Jt, et);
    const double cost_try = weightedCost(et);
    if (cost_try < cost) {
      q = q_try;
      J = Jt;
      e = et;
      cost = cost_try;
      mu = std::max(mu * 0.1, 1e-12);
    } else {
      mu *= 10;
      forwardKinematicsAndJacobian(model, ws, q);  // restore the workspace at the current iterate
      if (mu > 1e3) break;                         // stalled: no descent even with heavy damping
    }
  }
  return it;
}

}  // namespace armstudy::ik_detail
