// Continuity of dH_c/dq where the closest volume pair of a body pair switches (thesis eq.
// 5.53-5.57 with SSV pairs as the collision pairs). Along a one-joint sweep the closest volume
// pair of a body pair changes (ws.self[i].volume_a / volume_b); at the switch the two volume pairs
// are equally far apart but their distances have different gradients. The sum over SSV pairs
// has a gradient whose jump across the switch vanishes with the step; the body-pair minimum
// (one term per body pair, computed here from ws.self) jumps by a finite amount.
#include <catch2/catch.hpp>
#include <iterator>
#include <random>
#include <vector>

#include "collision/potential.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::collision;

namespace {

// Half-widths of the configuration pairs straddling the switch [rad or m], largest first.
constexpr double kSteps[] = {1e-4, 1e-5, 1e-6, 1e-7};
// Bisection on the joint stops when the bracket is this narrow.
constexpr double kBisectionWidth = 1e-13;
// The body-pair minimum's gradient jumps by at least this much (|dH/dd| ~ 1-10 at these
// distances, lever arms of 0.1-1 m) and keeps most of its jump as the step shrinks.
constexpr double kOldJumpMin = 1e-3;
constexpr double kOldJumpKept = 0.5;
// Sum over SSV pairs: the jump is O(step) (Lipschitz gradient), so it shrinks with the step
// and is negligible against the body-pair minimum's jump at the smallest step.
constexpr double kNewJumpShrink = 1e-2;  // jump(1e-7) / jump(1e-4) below this (ideal: 1e-3)
constexpr double kNewVsOld = 1e-3;       // jump_new / jump_old at the smallest step
// Rounding floor of a gradient difference (gradients are O(1-10)).
constexpr double kJumpRounding = 1e-12;
// H is continuous: |H(+h) - H(-h)| <= kValueSlack * h * (1 + |dH_c/dq|).
constexpr double kValueSlack = 1e2;
// Switches are searched where the body pair is well inside d_a (dH/dd clearly non-zero).
constexpr double kInsideFraction = 0.8;

struct Eval {
  double h_new = 0, h_old = 0;
  Eigen::VectorXd g_new, g_old;
};

// H_c of the body-pair minimum formulation (the superseded one): eq. (5.53) over ws.self, one term
// per body pair at its closest volume pair, gradient eq. (5.55)/(5.56) at its witness points.
double bodyPairPotential(const Model& m, const KinematicsWorkspace& kin,
                         const CollisionWorkspace& ws, const CollisionPotentialOptions& o,
                         Eigen::VectorXd& g) {
  g.setZero(m.dof());
  Jacobian6 J(6, m.dof());
  double h = 0;
  for (int i = 0; i < ws.num_self; ++i) {
    const PairDistance& p = ws.self[i];
    if (!p.exact || p.distance_m >= o.safety_distance_m) continue;
    double dH = 0;
    h += pairPotential(p.distance_m, o, &dH);
    if (p.w.n.isZero()) continue;
    pointJacobian(m, kin, p.link_a, p.w.c_a, J);
    g -= dH * (J.topRows<3>().transpose() * p.w.n);
    pointJacobian(m, kin, p.link_b, p.w.c_b, J);
    g += dH * (J.topRows<3>().transpose() * p.w.n);
  }
  return h;
}

struct Sweep {
  const Model& m;
  KinematicsWorkspace kin;
  CollisionWorkspace ws;
  CollisionPotentialOptions o;
  CollisionQueryOptions qo;
  explicit Sweep(const Model& model, double d_a) : m(model), kin(model), ws(model) {
    o.safety_distance_m = d_a;
    qo.cutoff_m = d_a;
  }
  void query(const Eigen::VectorXd& q) {
    forwardKinematics(m, kin, q);
    collisionDistances(m, kin, {}, ws, qo);
  }
  Eval eval(const Eigen::VectorXd& q) {
    query(q);
    Eval e;
    e.g_new.resize(m.dof());
    e.h_new = collisionPotential(m, kin, ws, o, e.g_new);
    e.h_old = bodyPairPotential(m, kin, ws, o, e.g_old);
    return e;
  }
  // Closest volume pair of body pair i (encoded), or -1 unless the pair is apart and well
  // inside d_a.
  long winner(const Eigen::VectorXd& q, int i) {
    query(q);
    return winner(i);
  }
  long winner(int i) const {
    const PairDistance& p = ws.self[i];
    if (!p.exact || p.distance_m <= 0 || p.distance_m >= kInsideFraction * o.safety_distance_m)
      return -1;
    return static_cast<long>(p.volume_a) * 100000 + p.volume_b;
  }
};

}  // namespace

TEST_CASE("dH_c/dq is continuous where the closest volume pair of a body pair switches") {
  constexpr double kDa = 0.15;
  constexpr int kSweepSteps = 200;
  constexpr double kSweepHalfRange = 0.6;  // [rad or m] around the random configuration
  for (const auto& design : test::shippedDesigns()) {
    const Model m = loadDesign(test::sourcePath(design));
    Sweep sw(m, kDa);
    std::mt19937_64 rng(41);
    bool found = false;
    for (int attempt = 0; attempt < 400 && !found; ++attempt) {
      const Eigen::VectorXd q0 = test::randomConfiguration(m, rng);
      const int j = attempt % m.dof();
      auto at = [&](double t) {
        Eigen::VectorXd q = q0;
        q[j] += t;
        return q;
      };
      // Coarse sweep: a body pair whose closest volume pair differs between two neighbouring
      // steps, with the pair well inside d_a on both sides.
      std::vector<long> prev(sw.ws.num_self), cur(sw.ws.num_self);
      for (int k = 0; k <= kSweepSteps && !found; ++k) {
        const double t1 = -kSweepHalfRange + 2 * kSweepHalfRange * k / kSweepSteps;
        const double t0 = t1 - 2 * kSweepHalfRange / kSweepSteps;
        sw.query(at(t1));
        for (int i = 0; i < sw.ws.num_self; ++i) cur[i] = sw.winner(i);
        std::swap(prev, cur);  // prev: this step, cur: the step before
        if (k == 0) continue;
        for (int i = 0; i < sw.ws.num_self && !found; ++i) {
          const long w0 = cur[i], w1 = prev[i];
          if (w0 < 0 || w1 < 0 || w0 == w1) continue;
          // Bisect to the switch: winner(lo) == w0, winner(hi) != w0.
          double lo = t0, hi = t1;
          bool inside = true;
          while (hi - lo > kBisectionWidth && inside) {
            const double mid = 0.5 * (lo + hi);
            const long wm = sw.winner(at(mid), i);
            inside = wm >= 0;
            (wm == w0 ? lo : hi) = mid;
          }
          if (!inside) continue;
          const double ts = 0.5 * (lo + hi);
          // Both sides of every step must have different closest volume pairs (one switch only).
          bool straddles = true;
          for (double h : kSteps)
            straddles = straddles && sw.winner(at(ts - h), i) != sw.winner(at(ts + h), i);
          if (!straddles) continue;
          found = true;
          sw.query(at(ts));
          INFO(design << ": body pair " << pairName(m, sw.ws.self[i], false) << " at d = "
                      << sw.ws.self[i].distance_m << " m, joint " << j << " offset " << ts);
          double jump_new[std::size(kSteps)], jump_old[std::size(kSteps)];
          for (std::size_t s = 0; s < std::size(kSteps); ++s) {
            const Eval a = sw.eval(at(ts - kSteps[s])), b = sw.eval(at(ts + kSteps[s]));
            jump_new[s] = (a.g_new - b.g_new).norm();
            jump_old[s] = (a.g_old - b.g_old).norm();
            INFO("step " << kSteps[s] << ": jump of dH_c/dq " << jump_new[s] << " (SSV pairs), "
                         << jump_old[s] << " (body-pair minimum); H " << a.h_new << " / "
                         << a.h_old);
            // The values themselves are continuous in both formulations.
            CHECK(std::abs(a.h_new - b.h_new) < kValueSlack * kSteps[s] * (1 + a.g_new.norm()));
            CHECK(std::abs(a.h_old - b.h_old) < kValueSlack * kSteps[s] * (1 + a.g_old.norm()));
            CHECK(jump_old[s] > kOldJumpMin);
          }
          const std::size_t last = std::size(kSteps) - 1;
          INFO("jumps SSV pairs " << jump_new[0] << " -> " << jump_new[last]
                                  << ", body-pair minimum " << jump_old[0] << " -> "
                                  << jump_old[last]);
          CHECK(jump_old[last] > kOldJumpKept * jump_old[0]);  // a true jump
          CHECK(jump_new[last] <=
                kNewJumpShrink * jump_new[0] + kJumpRounding);  // shrinks with the step
          CHECK(jump_new[last] < kNewVsOld * jump_old[last]);   // continuous
        }
      }
    }
    INFO(design);
    CHECK(found);
  }
}
