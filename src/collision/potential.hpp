#pragma once
// Collision-avoidance potential H_c and its gradient (thesis section 5.4.3, eq. 5.53-5.57), a
// secondary objective of the null-space inverse kinematics.
#include <Eigen/Core>
#include <string>

#include "collision/collision.hpp"
#include "common/defaults.hpp"

namespace armstudy::collision {

struct CollisionPotentialOptions {
  double safety_distance_m = defaults::kCollisionSafetyDistance_m;  // d_a: H_c,i = 0 beyond
  double blend_t = defaults::kCollisionBlendT;                      // t in (0, 1)
  double h0 = defaults::kCollisionPotentialAtContact;               // H_0 = H_c,i(0)
  bool self = true;                                                 // volume-volume pairs
  bool environment = true;                                          // volume-obstacle pairs
  // "" when valid, else the problem (d_a > 0, 0 < t < 1, H_0 > 0).
  std::string validate() const;
};

// Thesis eq. (5.57) for one pair: 0 for d >= d_a; a cubic a (d_a - d)^3 for t d_a <= d < d_a
// (zero value, slope and curvature at d_a); below t d_a the quadratic continuing the cubic with
// equal value, slope and curvature at t d_a, scaled so that H(0) = H_0. Penetration (d < 0)
// continues the quadratic, so H keeps growing. Writes dH/dd when dH_dd is given.
double pairPotential(double d, const CollisionPotentialOptions& options, double* dH_dd = nullptr);

// Thesis eq. (5.53): H_c = sum over the collision pairs of H_c,i(d_i), where a collision pair is
// a pair of swept-sphere volumes (thesis section 5.4.3 after Schwienbacher 2013): every volume
// pair of every self body pair and every volume against every obstacle, each with its own
// distance and witnesses (CollisionWorkspace::near_self / near_env of the last query; pairs at
// or beyond d_a contribute nothing). Summing over SSV pairs rather than taking one minimum per
// body pair keeps dH_c/dq continuous where the closest volume pair of a body pair switches.
// Eq. (5.55), (5.56): dH_c/dq = sum dH/dd * n^T (J_T,B - J_T,A) with J_T the translational point
// Jacobians at the core witness points (n: unit vector from A to B; equal to eq. 5.56 for
// d > 0 and still defined for overlapping volumes as long as the cores are apart).
// Requires that the last collisionDistances query used a finite cutoff_m >= d_a (it lists the
// volume pairs below the cutoff). grad_out has size n.
double collisionPotential(const Model& model, const KinematicsWorkspace& kin,
                          CollisionWorkspace& ws, const CollisionPotentialOptions& options,
                          Eigen::Ref<Eigen::VectorXd> grad_out);

}  // namespace armstudy::collision
