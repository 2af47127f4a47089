#include "collision/potential.hpp"

#include <cmath>
#include <limits>

#include "common/errors.hpp"

namespace armstudy::collision {

std::string CollisionPotentialOptions::validate() const {
  if (!(safety_distance_m > 0) || !std::isfinite(safety_distance_m))
    return "safety distance d_a must be positive and finite";
  if (!(blend_t > 0 && blend_t < 1)) return "blend parameter t must lie in (0, 1)";
  if (!(h0 > 0) || !std::isfinite(h0)) return "H_0 must be positive and finite";
  return "";
}

double pairPotential(double d, const CollisionPotentialOptions& o, double* dH_dd) {
  const double da = o.safety_distance_m;
  if (d >= da) {
    if (dH_dd) *dH_dd = 0;
    return 0;
  }
  // Cubic a s^3 with s = d_a - d; at d1 = t d_a: s0 = (1 - t) d_a. The quadratic below d1 is the
  // second-order Taylor polynomial of the cubic at d1: a s0^3 + 3 a s0^2 (d1 - d) + 3 a s0 (d1 - d)^2.
  // H(0) = H_0 fixes a.
  const double d1 = o.blend_t * da;
  const double s0 = da - d1;
  const double a = o.h0 / (s0 * s0 * s0 + 3 * s0 * s0 * d1 + 3 * s0 * d1 * d1);
  if (d >= d1) {
    const double s = da - d;
    if (dH_dd) *dH_dd = -3 * a * s * s;
    return a * s * s * s;
  }
  const double e = d1 - d;
  if (dH_dd) *dH_dd = -(3 * a * s0 * s0 + 6 * a * s0 * e);
  return a * s0 * s0 * s0 + 3 * a * s0 * s0 * e + 3 * a * s0 * e * e;
}

double collisionPotential(const Model& model, const KinematicsWorkspace& kin, CollisionWorkspace& ws,
                          const CollisionPotentialOptions& o, Eigen::Ref<Eigen::VectorXd> grad) {
  ARMSTUDY_CHECK(grad.size() == model.dof(), "collisionPotential: gradient size must be the DoF");
  ARMSTUDY_CHECK(ws.cutoff_used_m >= o.safety_distance_m &&
                     ws.cutoff_used_m < std::numeric_limits<double>::infinity(),
                 "collisionPotential: query distances with a finite cutoff_m >= safety_distance_m");
  grad.setZero();
  double H = 0;
  auto add = [&](const PairDistance& p, bool environment) {
    if (p.distance_m >= o.safety_distance_m) return;
    double dH = 0;
    H += pairPotential(p.distance_m, o, &dH);  // eq. (5.53)
    if (p.w.n.isZero()) return;                 // cores touch: direction undefined
    // Eq. (5.55), (5.56): dd/dq = n^T (J_T,B - J_T,A) at the witness points.
    pointJacobian(model, kin, p.link_a, p.w.c_a, ws.J_a);
    grad.noalias() -= dH * (ws.J_a.topRows<3>().transpose() * p.w.n);
    if (!environment) {
      pointJacobian(model, kin, p.link_b, p.w.c_b, ws.J_b);
      grad.noalias() += dH * (ws.J_b.topRows<3>().transpose() * p.w.n);
    }
  };
  // The collision pairs of eq. (5.53) are pairs of SSVs: every volume pair closer than the query
  // cutoff, listed by collisionDistances (pairs beyond d_a add nothing).
  if (o.self)
    for (int i = 0; i < ws.num_near_self; ++i) add(ws.near_self[i], false);
  if (o.environment)
    for (int i = 0; i < ws.num_near_env; ++i) add(ws.near_env[i], true);
  return H;
}

}  // namespace armstudy::collision
