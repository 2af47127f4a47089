// Secondary objectives (thesis eq. 5.52, 5.59, 5.61) against central finite differences of their
// own values, and H_m1 / H_m2 values against the SVD-based metrics (a second algorithm).
#include "ik/objectives.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "io/design_io.hpp"
#include "metrics/dexterity_measures.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::ik;
using namespace armstudy::test;

namespace {

constexpr double kGradRelTolerance = 1e-6;  // central differences of H with step kFdStep

double valueAt(const Model& m, KinematicsWorkspace& ws, ObjectiveContext& ctx,
               const ObjectiveTerm& term, const Eigen::VectorXd& q) {
  forwardKinematicsAndJacobian(m, ws, q);
  ctx.prepare(q);
  return term.evaluate(ctx, nullptr);
}

void checkGradient(const Model& m, const ObjectiveTerm& term, const Eigen::VectorXd& q,
                   const Eigen::Vector3d& u) {
  KinematicsWorkspace ws(m);
  ObjectiveContext ctx(m, ws);
  ctx.u_W = u;
  forwardKinematicsAndJacobian(m, ws, q);
  ctx.prepare(q);
  JointVector g(m.dof());
  const double h = term.evaluate(ctx, &g);
  REQUIRE(std::isfinite(h));
  for (int i = 0; i < m.dof(); ++i) {
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += kFdStep;
    qm[i] -= kFdStep;
    const double fd =
        (valueAt(m, ws, ctx, term, qp) - valueAt(m, ws, ctx, term, qm)) / (2 * kFdStep);
    INFO(term.name() << " joint " << i << " analytic " << g[i] << " fd " << fd);
    CHECK(std::abs(g[i] - fd) <=
          kGradRelTolerance * std::max(1.0, std::abs(h)) + kFdTolerance * 10);
  }
}

}  // namespace

TEST_CASE("H_m1 and H_m2 gradients (eq. 5.62, 5.64) match central differences",
          "[ik][objectives][fd]") {
  std::mt19937_64 rng(7);
  for (const auto& rel : shippedDesigns()) {
    const Model m = loadDesign(sourcePath(rel));
    for (auto space : {metrics::MeasureSpace::Translational, metrics::MeasureSpace::Full}) {
      if (metrics::measureRows(space) > m.dof()) continue;
      const ManipulabilityTerm hm1(space);
      const TransmissionTerm hm2(space);
      for (int trial = 0; trial < 20; ++trial) {
        const Eigen::VectorXd q = randomConfiguration(m, rng);
        const Eigen::Vector3d u = Eigen::Vector3d::Random().normalized();
        KinematicsWorkspace ws(m);
        forwardKinematicsAndJacobian(m, ws, q);
        // The 6-DoF spraying arm is structurally rank-deficient in the full space: no gradient.
        if (metrics::tcpMeasures(ws, space, u, false).inverse_condition < 1e-6) continue;
        INFO(rel << " space " << metrics::toString(space) << " trial " << trial);
        checkGradient(m, hm1, q, u);
        checkGradient(m, hm2, q, u);
      }
    }
  }
}

TEST_CASE("H_j gradient (eq. 5.52) matches central differences beyond the thresholds",
          "[ik][objectives][fd]") {
  std::mt19937_64 rng(11);
  const Model m = loadDesign(sourcePath("designs/final_prototype_7dof.toml"));
  const JointLimitTerm hj(m, 0.1);
  for (int trial = 0; trial < 50; ++trial) {
    // Uniform configurations (about 20 % of the joints beyond a threshold), and every other trial
    // all joints pushed to 1 % of their range from the nearer limit.
    Eigen::VectorXd q = randomConfiguration(m, rng);
    if (trial % 2)
      for (int i = 0; i < m.dof(); ++i) {
        const auto& l = m.joints[i].limits;
        const double mid = 0.5 * (l.q_min + l.q_max), range = l.q_max - l.q_min;
        q[i] = q[i] > mid ? l.q_max - 0.01 * range : l.q_min + 0.01 * range;
      }
    checkGradient(m, hj, q, Eigen::Vector3d::UnitX());
  }
  // Closed form: one summand reaches 1 exactly at the limit, 0 at the threshold.
  KinematicsWorkspace ws(m);
  ObjectiveContext ctx(m, ws);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(m.dof());
  q[0] = m.joints[0].limits.q_max;
  CHECK(std::abs(valueAt(m, ws, ctx, hj, q) - 1.0) < kHandCheckTolerance);
  q[0] = hj.qBarMax(0);
  CHECK(std::abs(valueAt(m, ws, ctx, hj, q)) < kHandCheckTolerance);
}

TEST_CASE("H_m1 and H_m2 values agree with the SVD-based measures", "[ik][objectives][oracle]") {
  std::mt19937_64 rng(3);
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  KinematicsWorkspace ws(m);
  ObjectiveContext ctx(m, ws);
  const ManipulabilityTerm hm1(metrics::MeasureSpace::Translational);
  const TransmissionTerm hm2(metrics::MeasureSpace::Translational);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::VectorXd q = randomConfiguration(m, rng);
    const Eigen::Vector3d u = Eigen::Vector3d::Random().normalized();
    forwardKinematicsAndJacobian(m, ws, q);
    ctx.prepare(q);
    ctx.u_W = u;
    const auto d = metrics::tcpMeasures(ws, metrics::MeasureSpace::Translational, u, true);
    CHECK(std::abs(-hm1.evaluate(ctx, nullptr) - d.manipulability) <
          1e-12 * std::max(1.0, d.manipulability));
    const double beta = 1.0 / std::sqrt(hm2.evaluate(ctx, nullptr));  // eq. (5.60) from (5.61)
    CHECK(std::abs(beta - d.transmission) < 1e-10 * std::max(1.0, beta));
  }
}

TEST_CASE("weighted objective is the weighted sum of its terms (eq. 5.51)", "[ik][objectives]") {
  std::mt19937_64 rng(5);
  const Model m = loadDesign(sourcePath("designs/final_prototype_9dof.toml"));
  KinematicsWorkspace ws(m);
  ObjectiveContext ctx(m, ws);
  auto hj = std::make_shared<JointLimitTerm>(m, 0.2);
  auto hm1 = std::make_shared<ManipulabilityTerm>(metrics::MeasureSpace::Translational);
  auto hm2 = std::make_shared<TransmissionTerm>(metrics::MeasureSpace::Translational);
  WeightedObjective obj;
  obj.add(2.0, hj);
  obj.add(0.5, hm1);
  obj.add(0.25, hm2);
  obj.add(0.0, hm2);  // zero weight: dropped
  CHECK(obj.size() == 3);
  const Eigen::VectorXd q = randomConfiguration(m, rng);
  forwardKinematicsAndJacobian(m, ws, q);
  ctx.prepare(q);
  JointVector g(m.dof()), g1(m.dof()), g2(m.dof()), g3(m.dof());
  const double h = obj.evaluate(ctx, &g);
  const double expect =
      2.0 * hj->evaluate(ctx, &g1) + 0.5 * hm1->evaluate(ctx, &g2) + 0.25 * hm2->evaluate(ctx, &g3);
  CHECK(std::abs(h - expect) < kHandCheckTolerance * std::max(1.0, std::abs(h)));
  CHECK((g - (2.0 * g1 + 0.5 * g2 + 0.25 * g3)).norm() < 1e-12 * std::max(1.0, g.norm()));
}
