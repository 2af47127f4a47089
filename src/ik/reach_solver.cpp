#include "ik/reach_solver.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <nlopt.hpp>
#include <numbers>
#include <vector>

#include "common/enum_names.hpp"
#include "common/errors.hpp"
#include "common/rng.hpp"
#include "ik/nullspace.hpp"
#include "ik/reach_internal.hpp"
#include "metrics/dexterity_measures.hpp"

namespace armstudy {

constexpr const char* kReachStatusNames[] = {
    "reachable",      "out_of_reach", "joint_limits",      "representation_singularity",
    "self_collision", "torque",       "obstacle_collision"};
static_assert(std::size(kReachStatusNames) == kReachStatusCount);
const char* toString(ReachStatus s) { return enumName(s, kReachStatusNames); }
constexpr const char* kReachStatusTexts[] = {"reachable",
                                             "out of reach",
                                             "blocked by joint limits",
                                             "representation singularity",
                                             "only in self-collision",
                                             "torque",
                                             "only in contact with an obstacle"};
const char* describe(ReachStatus s) { return enumName(s, kReachStatusTexts); }

std::vector<std::string> statusNamesShownOnMaps() {
  std::vector<std::string> names;
  for (int k = 0; k < kReachStatusCount; ++k) {
    const auto st = static_cast<ReachStatus>(k);
    const bool shown = st == ReachStatus::Reachable || st == ReachStatus::SelfCollision ||
                       st == ReachStatus::ObstacleCollision;
    names.push_back(shown ? describe(st) : "");
  }
  return names;
}

constexpr const char* kIkAlgorithmNames[] = {"lm+slsqp", "lm", "slsqp", "weighted_newton"};
const char* toString(IkAlgorithm a) { return enumName(a, kIkAlgorithmNames); }

IkOptions IkOptions::exactPose() {
  IkOptions o;
  o.algorithm = IkAlgorithm::WeightedNewton;
  o.position_tolerance_m = defaults::kPoseSolveTolerance_m;
  o.orientation_tolerance_rad = defaults::kPoseSolveTolerance_rad;
  o.max_iterations = defaults::kPoseSolveMaxIterations;
  o.max_starts = 1;
  o.classify_failures = false;
  return o;
}

std::string IkOptions::validate() const {
  if (!(position_tolerance_m > 0) || !std::isfinite(position_tolerance_m))
    return "position tolerance must be positive";
  if (!(orientation_tolerance_rad > 0) || !std::isfinite(orientation_tolerance_rad))
    return "orientation tolerance must be positive";
  if (max_starts < 1) return "at least one start is needed";
  if (max_iterations < 1) return "at least one iteration is needed";
  if (classify_starts < 0) return "classification starts must not be negative";
  if (!(orientation_weight_m > 0)) return "orientation weight must be positive";
  if (!(lambda_initial_m2 > 0) || !std::isfinite(lambda_initial_m2) || !(lambda_warm_m2 > 0) ||
      !std::isfinite(lambda_warm_m2))
    return "initial damping must be positive";
  if (!(stagnation_ratio >= 0 && stagnation_ratio < 1))
    return "stagnation ratio must lie in [0, 1)";
  if (max_rejected_steps < 1) return "at least one rejected step must be allowed";
  if (seed_candidates < 1) return "at least one seed candidate is needed";
  for (double w : joint_weights)
    if (!(w >= defaults::kMinWeight && w <= defaults::kMaxWeight))
      return "joint weights must lie in [1e-6, 1e6]";
  if (!(max_step > 0) || !std::isfinite(max_step)) return "max_step must be finite and > 0";
  return "";
}

using namespace ik_detail;

namespace {

inline double wrapAngle(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

Context makeContext(const Model* model, const PoseTask& t, double w_o) {
  const bool full = t.kind == PoseTaskKind::FullPose;
  const bool cardan = t.kind == PoseTaskKind::CardanAngles;
  const bool axis = t.kind == PoseTaskKind::PositionAxis;
  Context c{model, t, w_o, full, full || cardan, axis, 0};
  c.m = t.positionRows() + (axis ? 3 : t.orientationRows());
  return c;
}

}  // namespace

// Weighted residual e = W (w_d - f(q)) of the pose in kin (the m selected rows first, the rest
// zero), and the unweighted errors.
void ik_detail::residual(const Context& c, const KinematicsWorkspace& kin, Vec6& e,
                         PoseError& err) {
  const PoseTask& t = c.target;
  e.setZero();
  int r = 0;
  double pp = 0;
  for (int k = 0; k < 3; ++k)
    if (t.position_selected[k]) {
      const double d = t.p_WT[k] - kin.p_WT[k];
      e[r++] = d;
      pp += d * d;
    }
  err.position_m = std::sqrt(pp);
  err.singular = false;
  err.orientation_rad = 0;
  if (c.full_orientation) {
    const Eigen::AngleAxisd aa(Eigen::Matrix3d(t.R_WT * kin.R_WT.transpose()));
    e.segment<3>(r) = (c.w_o * aa.angle()) * aa.axis();
    err.orientation_rad = std::abs(aa.angle());
  } else if (c.tool_axis) {
    double angle = 0;
    e.segment<3>(r) = c.w_o * rotationBetween(kin.a_WT, t.axis_W, &angle);
    err.orientation_rad = angle;
  } else if (c.any_orientation) {
    const CardanAngles a = cardanFromRotation(kin.R_WT);
    err.singular = a.singular;
    const double cur[3] = {a.alpha, a.beta, a.gamma};
    double oo = 0;
    for (int k = 0; k < 3; ++k)
      if (t.angle_selected[k]) {
        const double d = wrapAngle(t.angles[k] - cur[k]);
        e[r++] = c.w_o * d;
        oo += d * d;
      }
    err.orientation_rad = std::sqrt(oo);
  }
}

// Weighted task Jacobian rows matching residual() (unselected rows zero). False at the
// representation singularity.
bool ik_detail::taskJacobian(const Context& c, const KinematicsWorkspace& kin, Jacobian6& J) {
  const auto& sel = c.target.position_selected;
  const int n = kin.n;
  if (c.m == 6 && c.full_orientation) {
    J.resize(6, n);
    J.topRows<3>() = kin.J_W_tcp.topRows<3>();
    J.bottomRows<3>() = c.w_o * kin.J_W_tcp.bottomRows<3>();
    return true;
  }
  J.setZero(6, n);
  int r = 0;
  for (int k = 0; k < 3; ++k)
    if (sel[k]) J.row(r++) = kin.J_W_tcp.row(k);
  if (c.full_orientation) {
    J.middleRows(r, 3) = c.w_o * kin.J_W_tcp.bottomRows<3>();
  } else if (c.tool_axis) {
    // Rotations about the tool axis do not change it: omega projected perpendicular to z.
    const Eigen::Vector3d z = kin.a_WT;
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - z * z.transpose();
    J.middleRows(r, 3) = c.w_o * (P * kin.J_W_tcp.bottomRows<3>());
  } else if (c.any_orientation) {
    const CardanAngles a = cardanFromRotation(kin.R_WT);
    Eigen::Matrix3d T_A_inv;
    if (a.singular || !cardanRateMatrix(a.alpha, a.beta, T_A_inv)) return false;
    for (int k = 0; k < 3; ++k)
      if (c.target.angle_selected[k])
        J.row(r++) = c.w_o * (T_A_inv.row(k) * kin.J_W_tcp.bottomRows<3>());  // eq. (5.9)
  }
  return true;
}

namespace {

// The manipulability (metrics::computeMeasures, thesis eq. 5.59) of rows of a task Jacobian; 1
// for no rows.
double manipulabilityOf(const Eigen::Ref<const Eigen::MatrixXd>& J) {
  if (J.rows() == 0) return 1.0;
  return metrics::computeMeasures(J, Eigen::VectorXd()).manipulability;
}

bool cardanSelection(const Context& c) {
  return c.any_orientation && !c.full_orientation && !c.tool_axis;
}

double cardanValue(const Context& c, const KinematicsWorkspace& kin) {
  Jacobian6 J(6, kin.n);
  if (!taskJacobian(c, kin, J)) return 0.0;
  return manipulabilityOf(J.topRows(c.m));  // eq. (5.59) of the analytic rows (eq. 5.11)
}

// Errors, manipulability and joint-limit margin of configuration q into r (r.q = q).
void fillSolution(const Model& model, IkWorkspace& ws, const Context& c, const JointVector& q,
                  IkResult& r) {
  r.q = q;
  forwardKinematicsAndJacobian(model, ws.kin, q);
  Vec6 e;
  PoseError err;
  residual(c, ws.kin, e, err);
  r.position_error_m = err.position_m;
  r.orientation_error_rad = err.orientation_rad;
  r.manipulability = taskManipulability(ws.kin, c.target);
  r.joint_limit_margin = jointLimitMargin(model, q);
}

}  // namespace

bool ik_detail::withinTolerance(const PoseError& e, const IkOptions& o, double fraction) {
  return e.position_m <= fraction * o.position_tolerance_m &&
         e.orientation_rad <= fraction * o.orientation_tolerance_rad;
}

double uniformDraw(std::uint64_t seed, std::uint64_t id, std::uint64_t k) {
  // Counter-based (splitmix64): the k-th draw of `id` is the same on any thread.
  const std::uint64_t s =
      rng::splitmix64(rng::splitmix64(seed ^ rng::splitmix64(id * 0x100000001B3ull + k)));
  return rng::unitDouble(s);
}

std::vector<long> drawIndices(long n, long count, std::uint64_t seed) {
  std::vector<long> all(std::max(0L, n));
  for (long i = 0; i < n; ++i) all[i] = i;
  if (count >= n) return all;
  for (long i = 0; i < count; ++i) {
    const double u = uniformDraw(seed, 0xD1CEull, static_cast<std::uint64_t>(i));
    const long j = i + std::min(n - i - 1, static_cast<long>(u * static_cast<double>(n - i)));
    std::swap(all[i], all[j]);
  }
  all.resize(std::max(0L, count));
  std::sort(all.begin(), all.end());
  return all;
}

void randomConfiguration(const Model& model, std::uint64_t seed, std::uint64_t pose_id, int k,
                         JointVector& q) {
  q.resize(model.dof());
  std::uint64_t s = rng::splitmix64(
      seed ^ rng::splitmix64(pose_id * 0x100000001B3ull + static_cast<std::uint64_t>(k)));
  for (int i = 0; i < model.dof(); ++i) {
    s = rng::splitmix64(s);
    const double u = rng::unitDouble(s);
    const JointLimits& L = model.joints[i].limits;
    q[i] = L.q_min + u * (L.q_max - L.q_min);
  }
}

namespace {

void midStart(const Model& model, JointVector& q) {
  for (int i = 0; i < model.dof(); ++i)
    q[i] = 0.5 * (model.joints[i].limits.q_min + model.joints[i].limits.q_max);
}

// Random start: the best (lowest weighted cost) of K seeded random configurations.
void seededStart(const Context& c, IkWorkspace& ws, const IkOptions& o, std::uint64_t pose_id,
                 int k, JointVector& q) {
  const Model& model = *c.model;
  const int K = o.seed_candidates;
  if (K <= 1) {
    randomConfiguration(model, o.seed, pose_id, k, q);
    return;
  }
  JointVector cand(model.dof());
  double best = std::numeric_limits<double>::infinity();
  Vec6 e;
  PoseError err;
  for (int j = 0; j < K; ++j) {
    randomConfiguration(model, o.seed, pose_id, k * K + j, cand);
    forwardKinematics(model, ws.kin, cand);
    residual(c, ws.kin, e, err);
    const double cost = e.squaredNorm();
    if (cost < best) {
      best = cost;
      q = cand;
    }
  }
}

// Distance of the target position to the set the first revolute joint's origin can reach.
// True when no configuration comes within `tolerance_m` of the target's position: the bound
// rejects a pose only when even the tolerance ball around it lies beyond the reach radius, so a
// pose reached within the tolerance is never rejected.
bool beyondReachBound(const IkWorkspace& ws, const PoseTask& t, bool limits, double tolerance_m) {
  if (!ws.has_bound || !t.allPositionSelected()) return false;
  const Eigen::Vector3d d = t.p_WT - ws.bound_p0;
  double tt = d.dot(ws.bound_axis);
  if (limits) tt = std::clamp(tt, ws.bound_t_min, ws.bound_t_max);
  const double dist = (d - tt * ws.bound_axis).norm();
  return dist > ws.reach_radius + tolerance_m + defaults::kIkReachBoundSlack_m;
}

}  // namespace

IkWorkspace::IkWorkspace(const Model& model) : kin(model) {
  // First revolute joint r; the joints before it must be at most one prismatic joint.
  int r = 0;
  while (r < model.dof() && model.joints[r].type == JointType::Prismatic) ++r;
  if (r == model.dof() || r > 1) return;
  Eigen::Isometry3d T = model.T_WB;
  for (int i = 0; i <= r; ++i) {
    T = T * model.joints[i].T_PJ0;
    if (i < r) {
      bound_axis = T.linear().col(2);
      bound_t_min = model.joints[i].limits.q_min;
      bound_t_max = model.joints[i].limits.q_max;
    }
  }
  bound_p0 = T.translation();
  double radius = model.T_NT.translation().norm();
  for (int i = r + 1; i < model.dof(); ++i) {
    radius += model.joints[i].T_PJ0.translation().norm();
    if (model.joints[i].type == JointType::Prismatic)
      radius +=
          std::max(std::abs(model.joints[i].limits.q_min), std::abs(model.joints[i].limits.q_max));
  }
  reach_radius = radius;
  has_bound = true;
}

PoseError poseError(const KinematicsWorkspace& kin, const PoseTask& target) {
  // The weight only scales e, not the reported errors.
  const Context c = makeContext(nullptr, target, 1.0);
  Vec6 e;
  PoseError err;
  residual(c, kin, e, err);
  return err;
}

double ikObjective(const Model& model, KinematicsWorkspace& kin, const PoseTask& target, double w_o,
                   const Eigen::VectorXd& q, Eigen::VectorXd* grad) {
  const Context c = makeContext(&model, target, w_o);
  const auto& sel = target.position_selected;
  const int n = model.dof();
  forwardKinematics(model, kin, q);
  if (grad) {
    tcpJacobian(model, kin);
    grad->setZero(n);
  }
  double f = 0;
  for (int k = 0; k < 3; ++k)
    if (sel[k]) {
      const double d = target.p_WT[k] - kin.p_WT[k];
      f += 0.5 * d * d;
      if (grad) *grad -= d * kin.J_W_tcp.row(k).transpose();
    }
  if (c.full_orientation) {
    // w^2 (1 - cos(angle)), cos(angle) = (tr(A) - 1) / 2 with A = R R_d^T; d tr(A)/dq_i = -omega_i
    // . v.
    const Eigen::Matrix3d A = kin.R_WT * target.R_WT.transpose();
    f += w_o * w_o * (1.0 - 0.5 * (A.trace() - 1.0));
    if (grad) {
      const Eigen::Vector3d v(A(2, 1) - A(1, 2), A(0, 2) - A(2, 0), A(1, 0) - A(0, 1));
      *grad += 0.5 * w_o * w_o * (kin.J_W_tcp.bottomRows<3>().transpose() * v);
    }
  } else if (c.tool_axis) {
    // w^2 (1 - a . a_d); d(a . a_d)/dq_i = omega_i . (a x a_d), a the tool axis in W.
    const Eigen::Vector3d& a = kin.a_WT;
    f += w_o * w_o * (1.0 - a.dot(target.axis_W));
    if (grad)
      *grad -= w_o * w_o * (kin.J_W_tcp.bottomRows<3>().transpose() * a.cross(target.axis_W));
  } else if (c.any_orientation) {
    const CardanAngles a = cardanFromRotation(kin.R_WT);
    const double cur[3] = {a.alpha, a.beta, a.gamma};
    Eigen::Matrix3d T_A_inv;
    const bool ok = !a.singular && cardanRateMatrix(a.alpha, a.beta, T_A_inv);
    for (int k = 0; k < 3; ++k)
      if (target.angle_selected[k]) {
        const double d = wrapAngle(target.angles[k] - cur[k]);
        f += 0.5 * w_o * w_o * d * d;
        if (grad && ok)
          *grad -= w_o * w_o * d * (T_A_inv.row(k) * kin.J_W_tcp.bottomRows<3>()).transpose();
      }
  }
  return f;
}

double taskManipulability(const KinematicsWorkspace& kin, const PoseTask& target) {
  const Context c = makeContext(nullptr, target, 1.0);
  if (cardanSelection(c)) return cardanValue(c, kin);
  ik::TaskJacobian J;
  ik::TaskVec e;
  ik::taskJacobianAndError(kin, target, J, e);
  return manipulabilityOf(J);
}

int taskJacobianRows(const KinematicsWorkspace& kin, const PoseTask& target, Jacobian6& J_out) {
  const Context c = makeContext(nullptr, target, 1.0);
  J_out.setZero(6, kin.n);
  if (cardanSelection(c)) return taskJacobian(c, kin, J_out) ? c.m : 0;
  ik::TaskJacobian J;
  ik::TaskVec e;
  ik::taskJacobianAndError(kin, target, J, e);
  J_out.topRows(J.rows()) = J;
  return static_cast<int>(J.rows());
}

double cardanManipulability(const KinematicsWorkspace& kin, const TaskSpace& task_space) {
  PoseTask t = taskTarget(task_space, TaskVector6::Zero());
  t.kind = PoseTaskKind::CardanAngles;
  t.angle_selected = {task_space.selected[3], task_space.selected[4], task_space.selected[5]};
  return cardanValue(makeContext(nullptr, t, 1.0), kin);
}

ManipulabilityParts taskManipulabilityParts(const KinematicsWorkspace& kin,
                                            const PoseTask& target) {
  // The rows of selected Cardan angles are analytic (eq. 5.11): only their position part counts.
  PoseTask geometric = target;
  if (target.kind == PoseTaskKind::CardanAngles) geometric.kind = PoseTaskKind::Position;
  ik::TaskJacobian J;
  ik::TaskVec e;
  ik::taskJacobianAndError(kin, geometric, J, e);
  ManipulabilityParts p;
  const int position = geometric.positionRows(), angular = geometric.orientationRows();
  if (position > 0) p.translation = manipulabilityOf(J.topRows(position));
  if (angular > 0) p.rotation = manipulabilityOf(J.bottomRows(angular));
  return p;
}

IkResult evaluateSolution(const Model& model, IkWorkspace& ws, const PoseTask& target,
                          const IkOptions& options, const JointVector& q, ReachStatus otherwise) {
  const Context c = makeContext(&model, target, options.orientation_weight_m);
  IkResult r;
  fillSolution(model, ws, c, q, r);
  bool within_limits = true;
  for (int i = 0; i < model.dof(); ++i)
    within_limits &= q[i] >= model.joints[i].limits.q_min && q[i] <= model.joints[i].limits.q_max;
  PoseError err;
  err.position_m = r.position_error_m;
  err.orientation_rad = r.orientation_error_rad;
  r.status =
      within_limits && withinTolerance(err, options, 1.0) ? ReachStatus::Reachable : otherwise;
  return r;
}

double jointLimitMargin(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q) {
  double margin = 0.5;
  for (int i = 0; i < model.dof(); ++i) {
    const JointLimits& L = model.joints[i].limits;
    const double range = L.q_max - L.q_min;
    if (!(range > 0)) return 0.0;
    margin = std::min(margin, std::min(q[i] - L.q_min, L.q_max - q[i]) / range);
  }
  return std::max(margin, 0.0);
}

namespace {

// IkAlgorithm::WeightedNewton: one start, the last iterate judged against o's tolerances.
IkResult solveWeightedNewton(const Model& model, IkWorkspace& ws, const Context& c,
                             const IkOptions& o, const JointVector* warm_start) {
  const int n = model.dof();
  ARMSTUDY_CHECK(o.joint_weights.empty() || static_cast<int>(o.joint_weights.size()) == n,
                 "solvePose: joint_weights needs one weight per joint");
  JointVector q(n);
  if (warm_start)
    q = *warm_start;
  else
    midStart(model, q);
  IkResult r;
  r.starts = 1;
  r.iterations = runWeightedNewton(model, ws.kin, c.target, o, q);
  fillSolution(model, ws, c, q, r);
  r.status = withinTolerance({r.position_error_m, r.orientation_error_rad}, o, 1.0)
                 ? ReachStatus::Reachable
                 : ReachStatus::OutOfReach;
  return r;
}

}  // namespace

IkResult solvePose(const Model& model, IkWorkspace& ws, const PoseTask& target, const IkOptions& o,
                   std::uint64_t pose_id, const JointVector* warm_start) {
  const int n = model.dof();
  ARMSTUDY_CHECK(ws.kin.n == n, "IkWorkspace was built for another model");
  const Context c = makeContext(&model, target, o.orientation_weight_m);
  if (o.algorithm == IkAlgorithm::WeightedNewton)
    return solveWeightedNewton(model, ws, c, o, warm_start);
  IkResult r;
  r.q.resize(n);
  JointVector q(n), best_q(n);
  LocalResult best;
  best.cost = std::numeric_limits<double>::infinity();
  bool have_best = false;
  bool solved = false;

  const bool bound_out =
      o.use_reach_bound && beyondReachBound(ws, target, true, o.position_tolerance_m);
  if (bound_out) {
    // Certainly unreachable; one local solve from the middle of the limits gives the closest
    // configuration found for the reported errors.
    r.bound_rejected = true;
    midStart(model, best_q);
    best = runLm(c, ws, o, best_q, true, o.lambda_initial_m2, r.iterations);
    best.success = false;
    have_best = true;
  } else {
    for (int k = 0; k < o.max_starts && !solved; ++k) {
      if (k == 0 && warm_start) {
        q = *warm_start;
      } else if (k == (warm_start ? 1 : 0)) {
        midStart(model, q);
      } else {
        seededStart(c, ws, o, pose_id, k, q);
      }
      ++r.starts;
      const LocalResult lr =
          o.algorithm == IkAlgorithm::SlsqpOnly
              ? runSlsqp(c, ws, o, q)
              : runLm(c, ws, o, q, true,
                      k == 0 && warm_start ? o.lambda_warm_m2 : o.lambda_initial_m2, r.iterations);
      if (lr.success || lr.cost < best.cost) {
        best = lr;
        best_q = q;
        have_best = true;
      }
      solved = lr.success;
    }
    // Constrained fallback: polish a near miss with SLSQP.
    if (!solved && o.algorithm == IkAlgorithm::LmThenSlsqp && have_best && !best.singular &&
        best.err.position_m < defaults::kIkPolishBand * o.position_tolerance_m &&
        best.err.orientation_rad < defaults::kIkPolishBand * o.orientation_tolerance_rad) {
      q = best_q;
      const LocalResult lr = runSlsqp(c, ws, o, q);
      if (lr.success || lr.cost < best.cost) {
        best = lr;
        best_q = q;
      }
      solved = lr.success;
      r.polished = solved;
    }
  }

  fillSolution(model, ws, c, best_q, r);
  // The verdict agrees with the posture stored beside it: a best posture within the limits and
  // the tolerances is a solution, however it was found.
  solved = solved || (have_best && ik::withinLimits(model, best_q) &&
                      withinTolerance({r.position_error_m, r.orientation_error_rad}, o, 1.0));
  if (solved) {
    r.status = ReachStatus::Reachable;
    return r;
  }

  // Why not: re-solve without joint limits.
  bool free_success = false;
  if (o.classify_failures && !beyondReachBound(ws, target, false, o.position_tolerance_m)) {
    for (int k = 0; k < o.classify_starts + 1 && !free_success; ++k) {
      if (k == 0)
        q = best_q;
      else
        randomConfiguration(model, o.seed ^ 0x5A5A5A5A5A5A5A5Aull, pose_id, k, q);
      const double lambda0 = k == 0 ? o.lambda_warm_m2 : o.lambda_initial_m2;
      free_success = runLm(c, ws, o, q, false, lambda0, r.iterations).success;
    }
  }
  if (free_success)
    r.status = ReachStatus::JointLimits;
  else if (best.singular)
    r.status = ReachStatus::RepresentationSingularity;
  else
    r.status = ReachStatus::OutOfReach;
  return r;
}

}  // namespace armstudy
