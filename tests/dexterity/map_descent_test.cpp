// The map descent's rules against independent oracles: the projected gradient that stops a descent
// against central finite differences of H along a null-space basis from an SVD; the quasi-Newton
// descent against a long steepest descent to the same optimum; the proof that skips a start against
// a planted cell whose stored optimum is not one; the quasi-Newton candidate of a cell whose
// minimum of H lies in self-collision against the steepest one, with the collision model as the
// oracle of where each descent ends.
#include <Eigen/SVD>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "collision/collision.hpp"
#include "common/angles.hpp"
#include "dexterity/dexterity_map.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::dexterity;
using namespace armstudy::test;

namespace {

constexpr double kFiniteStep = 1e-6;      // [rad or m] central differences of H
constexpr double kFiniteError = 1e-8;     // their error on a gradient entry [H per rad]
constexpr double kSameOptimum = 1e-6;     // relative H difference of one optimum reached twice
constexpr double kRequiredSame = 0.9;     // share of starts both descents take to one optimum
constexpr double kBetterOptimum = 0.001;  // the planted cell's true optimum is this much lower
constexpr double kMapTolerance = 0.01;    // the audit's: a candidate this much worse is wrong

// Studies/stem_heatmap.toml's objective on a few cells of its valley region.
DexterityOptions valley() {
  DexterityOptions o;
  o.grid.stem_x_m = 0.225;
  o.grid.stem_y_m = 0.7;
  o.grid.radius_m = 0.15;
  o.grid.gamma_rad = {-M_PI / 2, M_PI / 2, 7};
  o.grid.z_m = {0.40, 0.80, 3};
  o.w_joint_limits = 0.1;
  return o;
}

// The chained rows' plain postures of the reachable cells (starts not yet descended).
struct Start {
  StemGrid::Cell cell;
  JointVector q;
};
std::vector<Start> plainStarts(const Model& m, const DexterityOptions& o) {
  DexterityOptions plain = o;
  plain.seed_starts = plain.propagation_rounds = 0;
  const DexterityMap map = computeDexterityMap(m, plain, 1);
  std::vector<Start> out;
  for (int idx = 0; idx < o.grid.size(); ++idx)
    if (map.cells[idx].reachable)
      out.push_back({o.grid.cell(idx % o.grid.gamma_rad.count, idx / o.grid.gamma_rad.count),
                     map.cells[idx].q_plain});
  return out;
}

// |N grad H|_2 at q from central differences of H along an orthonormal basis of the null space of
// the task rows (from an SVD of the geometric Jacobian's constrained rows, not the solver's
// projection): the directional derivatives of H along the pose's tangent directions.
double finiteDifferenceGradient(const Model& m, KinematicsWorkspace& ws, ik::ObjectiveContext& ctx,
                                const ik::WeightedObjective& obj, const PoseTask& target,
                                const JointVector& q) {
  forwardKinematicsAndJacobian(m, ws, q);
  ik::TaskJacobian J;
  ik::TaskVec e;
  ik::taskJacobianAndError(ws, target, J, e);
  const Eigen::MatrixXd Jd = J;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Jd, Eigen::ComputeFullV);
  const int rows = static_cast<int>(Jd.rows()), n = static_cast<int>(Jd.cols());
  const auto H = [&](const JointVector& x) {
    forwardKinematicsAndJacobian(m, ws, x);
    ctx.prepare(x);
    return obj.evaluate(ctx, nullptr);
  };
  double sum = 0;
  for (int k = rows; k < n; ++k) {
    const JointVector v = svd.matrixV().col(k);
    const double d = (H(q + kFiniteStep * v) - H(q - kFiniteStep * v)) / (2 * kFiniteStep);
    sum += d * d;
  }
  return std::sqrt(sum);
}

// Studies/stem_heatmap.toml's objective and self-collision check on the patch of Fig. 3.6 where the
// minimum of H on the pose lies in self-collision (gamma 11-27 deg, z 0.17-0.20 m).
DexterityOptions contactPatch() {
  DexterityOptions o = valley();
  o.grid.gamma_rad = {11 * kDegToRad, 27 * kDegToRad, 9};
  o.grid.z_m = {0.17, 0.20, 4};
  o.collision.self = true;
  return o;
}

// Smallest self-collision distance at q, from the collision model alone.
double selfClearance(const Model& m, KinematicsWorkspace& ws, collision::CollisionWorkspace& cws,
                     const JointVector& q) {
  forwardKinematics(m, ws, q);
  collision::collisionDistances(m, ws, {}, cws);
  return collision::minSelfDistance(cws);
}

}  // namespace

TEST_CASE(
    "a map descent stops at once where the projected gradient is within its tolerance, and moves "
    "where finite differences say it is not",
    "[dexterity][descent]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  const DexterityOptions o = valley();
  const std::vector<Start> starts = plainStarts(m, o);
  REQUIRE(starts.size() >= 10);
  KinematicsWorkspace ws(m);
  ik::ObjectiveContext ctx(m, ws);
  const ik::WeightedObjective obj = o.buildObjective(m);
  const Eigen::VectorXd w_inv = Eigen::VectorXd::Ones(m.dof());
  // A tolerance between the starts' gradients: some starts are within it, some are not.
  std::vector<double> fd;
  for (const Start& s : starts) {
    ctx.u_W = s.cell.u_W;
    fd.push_back(finiteDifferenceGradient(m, ws, ctx, obj, s.cell.target, s.q));
  }
  std::vector<double> sorted = fd;
  std::sort(sorted.begin(), sorted.end());
  ik::NullspaceOptions no = o.nullspace;
  no.gradient_tolerance = 0.5 * (sorted[sorted.size() / 2] + sorted[sorted.size() / 2 + 1]);
  int stopped = 0, moved = 0;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    ctx.u_W = starts[k].cell.u_W;
    const ik::NullspaceResult r =
        ik::optimiseAtPose(m, ws, ctx, starts[k].cell.target, starts[k].q, obj, w_inv, no);
    // The rule reads max_i |(N grad)_i| <= tolerance; |.|_inf <= |.|_2 <= sqrt(n - m) |.|_inf.
    const double free_dims = m.dof() - starts[k].cell.target.rows();
    if (fd[k] + kFiniteError < no.gradient_tolerance) {
      CHECK(r.iterations == 0);
      CHECK(r.status == ik::NullspaceStatus::Converged);
      ++stopped;
    } else if (fd[k] - kFiniteError > std::sqrt(free_dims) * no.gradient_tolerance) {
      CHECK(r.iterations > 0);
      ++moved;
    }
  }
  CHECK(stopped > 0);  // the scenario: both kinds of start happened
  CHECK(moved > 0);
}

TEST_CASE(
    "a quasi-Newton map descent reaches the optimum of a long steepest descent with fewer kernel "
    "evaluations than a steepest one, and stops where finite differences find the projected "
    "gradient small",
    "[dexterity][descent]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  DexterityOptions o = valley();
  o.nullspace.quasi_newton = true;  // [dexterity.solver] quasi_newton = true
  REQUIRE(o.nullspace.gradient_tolerance > 0);
  const std::vector<Start> starts = plainStarts(m, o);
  REQUIRE(starts.size() >= 10);
  KinematicsWorkspace ws(m);
  ik::ObjectiveContext ctx(m, ws);
  const ik::WeightedObjective obj = o.buildObjective(m);
  const Eigen::VectorXd w_inv = Eigen::VectorXd::Ones(m.dof());
  // The reference: steepest descent until no step is accepted or the gradient is within tolerance.
  ik::NullspaceOptions steep = o.nullspace;
  steep.quasi_newton = false;
  steep.relative_improvement = 0;
  steep.max_iterations = 20000;
  // The same stopping rules without the quasi-Newton directions.
  ik::NullspaceOptions plain = o.nullspace;
  plain.quasi_newton = false;
  long kernel_quasi = 0, kernel_plain = 0;
  int same = 0, by_gradient = 0;
  for (const Start& s : starts) {
    ctx.u_W = s.cell.u_W;
    const ik::NullspaceResult a =
        ik::optimiseAtPose(m, ws, ctx, s.cell.target, s.q, obj, w_inv, o.nullspace);
    const ik::NullspaceResult b =
        ik::optimiseAtPose(m, ws, ctx, s.cell.target, s.q, obj, w_inv, steep);
    kernel_quasi += a.kernel_evaluations;
    kernel_plain +=
        ik::optimiseAtPose(m, ws, ctx, s.cell.target, s.q, obj, w_inv, plain).kernel_evaluations;
    same += std::abs(a.H_final - b.H_final) <= kSameOptimum * std::abs(b.H_final);
    if (a.status == ik::NullspaceStatus::Converged &&
        a.projected_gradient <= o.nullspace.gradient_tolerance) {
      ++by_gradient;
      const double free_dims = m.dof() - s.cell.target.rows();
      CHECK(finiteDifferenceGradient(m, ws, ctx, obj, s.cell.target, a.q) <=
            std::sqrt(free_dims) * o.nullspace.gradient_tolerance + kFiniteError);
    }
  }
  CHECK(same >= kRequiredSame * starts.size());
  CHECK(by_gradient > 0);
  INFO("kernel evaluations: quasi-Newton " << kernel_quasi << ", steepest " << kernel_plain);
  CHECK(kernel_quasi < kernel_plain);
}

TEST_CASE(
    "a start on a cell's proven optimum is not descended, and a start next to a stored optimum "
    "that is no optimum is, finding the better one",
    "[dexterity][descent][proof]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  const DexterityOptions o = valley();
  KinematicsWorkspace ws(m);
  IkWorkspace ik_ws(m);
  ik::ObjectiveContext ctx(m, ws);
  const ik::WeightedObjective obj = o.buildObjective(m);
  const DexterityMap map = computeDexterityMap(m, o, 1);
  int skipped = 0, planted = 0;
  for (int idx = 0; idx < o.grid.size(); ++idx) {
    const CellResult& c = map.cells[idx];
    if (!c.reachable) continue;
    const StemGrid::Cell cell =
        o.grid.cell(idx % o.grid.gamma_rad.count, idx / o.grid.gamma_rad.count);
    // A start next to the stored optimum (well within the proof radius).
    const JointVector near = c.q_opt.array() + 0.25 * kMapProofRadius;
    if (provenOptimum(m, ws, ctx, obj, o, cell, c)) {
      CellResult cand;
      CHECK_FALSE(
          cellFromSeed(m, ws, ik_ws, ctx, obj, o, cell, near, cand, nullptr, false, &c.q_opt));
      skipped += cand.descent.skipped == 1 && cand.descent.descents == 0;
    }
    // Planted: the cell's stored "optimum" is its plain posture, far from its optimum.
    if (!(c.H_opt < c.H_plain - kBetterOptimum * std::abs(c.H_plain))) continue;
    CellResult fake = c;
    fake.q_opt = c.q_plain;
    fake.H_opt = c.H_plain;
    const JointVector beside = fake.q_opt.array() + 0.25 * kMapProofRadius;
    const bool proven = provenOptimum(m, ws, ctx, obj, o, cell, fake);
    CHECK_FALSE(proven);
    CellResult cand;
    const bool landed = cellFromSeed(m, ws, ik_ws, ctx, obj, o, cell, beside, cand, nullptr, false,
                                     proven ? &fake.q_opt : nullptr);
    if (!landed) continue;
    CHECK(cand.descent.skipped == 0);
    CHECK(cand.H_opt < fake.H_opt - kBetterOptimum * std::abs(fake.H_opt));
    ++planted;
  }
  CHECK(skipped > 0);  // the scenarios happened
  CHECK(planted > 0);
}

TEST_CASE(
    "where the minimum of H lies in self-collision, a quasi-Newton candidate is within the audit's "
    "tolerance of the steepest one although its own descent jumps into contact",
    "[dexterity][descent][collision]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  DexterityOptions steep = contactPatch();
  steep.nullspace.quasi_newton = false;  // [dexterity.solver] quasi_newton = false
  DexterityOptions quasi = steep;
  quasi.nullspace.quasi_newton = true;
  const std::vector<Start> starts = plainStarts(m, steep);
  REQUIRE(starts.size() >= 20);
  KinematicsWorkspace ws(m);
  IkWorkspace ik_ws(m);
  ik::ObjectiveContext ctx(m, ws);
  collision::CollisionWorkspace cws(m);
  const ik::WeightedObjective obj = steep.buildObjective(m);
  const Eigen::VectorXd w_inv = Eigen::VectorXd::Ones(m.dof());
  int compared = 0, jumped = 0, within = 0;
  for (const Start& s : starts) {
    if (selfClearance(m, ws, cws, s.q) <= steep.collision.clearance_m) continue;
    CellResult a, b;
    if (!cellFromSeed(m, ws, ik_ws, ctx, obj, steep, s.cell, s.q, a, &cws, false) ||
        !cellFromSeed(m, ws, ik_ws, ctx, obj, quasi, s.cell, s.q, b, &cws, false) || !a.reachable ||
        !b.reachable)
      continue;
    ++compared;
    CHECK(selfClearance(m, ws, cws, b.q_opt) > steep.collision.clearance_m);
    within += b.H_opt <= a.H_opt + kMapTolerance * std::abs(a.H_opt);
    // The scenario: the quasi-Newton descent from this start ends in contact while the steepest
    // one stops clear of it, after lowering H by more than the tolerance. The candidate must then
    // be as good as the steepest one, not the start it fell back to.
    ctx.u_W = s.cell.u_W;
    const ik::NullspaceResult r =
        ik::optimiseAtPose(m, ws, ctx, s.cell.target, a.q_plain, obj, w_inv, quasi.nullspace);
    if (selfClearance(m, ws, cws, r.q) <= steep.collision.clearance_m &&
        a.H_opt < a.H_plain - kMapTolerance * std::abs(a.H_plain)) {
      ++jumped;
      INFO("gamma " << s.cell.gamma << " z " << s.cell.z << ": H plain " << a.H_plain
                    << ", steepest " << a.H_opt << ", quasi-Newton " << b.H_opt);
      CHECK(b.H_opt <= a.H_opt + kMapTolerance * std::abs(a.H_opt));
    }
  }
  INFO("starts compared " << compared << ", within tolerance " << within
                          << ", quasi-Newton descents into contact " << jumped);
  CHECK(compared >= 20);
  CHECK(within >= kRequiredSame * compared);
  CHECK(jumped > 0);
}
