#include "collision/potential.hpp"

#include <array>
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
  // second-order Taylor polynomial of the cubic at d1: a s0^3 + 3 a s0^2 (d1 - d) + 3 a s0 (d1 -
  // d)^2. H(0) = H_0 fixes a.
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

double collisionPotential(const Model& model, const KinematicsWorkspace& kin,
                          CollisionWorkspace& ws, const CollisionPotentialOptions& o,
                          Eigen::Ref<Eigen::VectorXd> grad) {
  ARMSTUDY_CHECK(grad.size() == model.dof(), "collisionPotential: gradient size must be the DoF");
  ARMSTUDY_CHECK(ws.cutoff_used_m >= o.safety_distance_m &&
                     ws.cutoff_used_m < std::numeric_limits<double>::infinity(),
                 "collisionPotential: query distances with a finite cutoff_m >= safety_distance_m");
  // Eq. (5.55), (5.56): dd/dq = n^T (J_T,B(c_B) - J_T,A(c_A)) at the core witness points. Summed
  // over the pairs as J_T^T f: each pair pushes f = dH/dd n at c_B on body B and -f at c_A on
  // body A; per link the forces F and moments M = sum c x f about the origin of W are added up,
  // and joint j sees everything beyond it: z_j . (M - p_j x F) (revolute) or z_j . F (prismatic),
  // the columns of pointJacobian contracted with the force.
  const int n = model.dof();
  std::array<Eigen::Vector3d, kMaxBodies> F, M;
  for (int l = 0; l < n; ++l) F[l].setZero(), M[l].setZero();
  double H = 0;
  auto push = [&](int link, const Eigen::Vector3d& c, const Eigen::Vector3d& f) {
    if (link < 0) return;  // the base does not move
    F[link] += f;
    M[link] += c.cross(f);
  };
  auto add = [&](const PairDistance& p, bool environment) {
    if (p.distance_m >= o.safety_distance_m) return;
    double dH = 0;
    H += pairPotential(p.distance_m, o, &dH);  // eq. (5.53)
    if (p.w.n.isZero()) return;                // cores touch: direction undefined
    const Eigen::Vector3d f = dH * p.w.n;
    push(p.link_a, p.w.c_a, -f);
    if (!environment) push(p.link_b, p.w.c_b, f);
  };
  // The collision pairs of eq. (5.53) are pairs of SSVs: every volume pair closer than the query
  // cutoff, listed by collisionDistances (pairs beyond d_a add nothing).
  if (o.self)
    for (int i = 0; i < ws.num_near_self; ++i) add(ws.near_self[i], false);
  if (o.environment)
    for (int i = 0; i < ws.num_near_env; ++i) add(ws.near_env[i], true);
  Eigen::Vector3d F_sum = Eigen::Vector3d::Zero(), M_sum = Eigen::Vector3d::Zero();
  for (int j = n - 1; j >= 0; --j) {
    F_sum += F[j];
    M_sum += M[j];
    const Eigen::Vector3d z = kin.R_WF[j].col(2);
    grad[j] = model.joints[j].type == JointType::Revolute ? z.dot(M_sum - kin.p_WF[j].cross(F_sum))
                                                          : z.dot(F_sum);
  }
  return H;
}

}  // namespace armstudy::collision
