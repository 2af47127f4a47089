#pragma once
// Exact minimum distance between the cores of swept-sphere volumes (thesis section 3.4.4,
// Fig. 3.24): a point, a segment (line SSV) or a triangle, swept by a sphere of radius r.
//
// All functions return the SQUARED distance between the two cores and write one pair of witness
// points (c_a on the first core, c_b on the second, |c_a - c_b|^2 = returned value). They are
// robust for parallel, touching, intersecting and degenerate inputs (zero-length segments,
// collinear or coincident triangle corners): every candidate is a feasible point pair on both
// cores, and the set of candidates always contains a true minimiser, so the result is the exact
// minimum up to floating-point rounding. No heap allocation; all are pure functions.
#include <Eigen/Core>
#include <algorithm>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <array>
#include <cmath>

#include "common/defaults.hpp"

namespace armstudy::collision {

// Closest point on segment [a, b] to p. A zero-length segment is a point.
double squaredDistancePointSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                   const Eigen::Vector3d& b, Eigen::Vector3d& c_seg);

// Segments [p0, p1] and [q0, q1]; parallel and overlapping segments included.
double squaredDistanceSegmentSegment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                     const Eigen::Vector3d& q0, const Eigen::Vector3d& q1,
                                     Eigen::Vector3d& c_p, Eigen::Vector3d& c_q);

// Point p and triangle (a, b, c) (a degenerate triangle acts as its edges).
double squaredDistancePointTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                    Eigen::Vector3d& c_tri);

// Segment [p0, p1] and triangle (a, b, c); a segment piercing the triangle gives 0.
double squaredDistanceSegmentTriangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                      const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                      const Eigen::Vector3d& c, Eigen::Vector3d& c_seg,
                                      Eigen::Vector3d& c_tri);

// Triangles (a0, a1, a2) and (b0, b1, b2); intersecting triangles give 0.
double squaredDistanceTriangleTriangle(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                       const Eigen::Vector3d& a2, const Eigen::Vector3d& b0,
                                       const Eigen::Vector3d& b1, const Eigen::Vector3d& b2,
                                       Eigen::Vector3d& c_a, Eigen::Vector3d& c_b);

// The core of an SSV: 1 (point), 2 (segment) or 3 (triangle) points.
struct Core {
  std::array<Eigen::Vector3d, 3> p;
  int n = 1;
};

// Dispatch on the two core types (any order); witness c_a lies on `a`, c_b on `b`.
double squaredDistanceCores(const Core& a, const Core& b, Eigen::Vector3d& c_a,
                            Eigen::Vector3d& c_b);

// Distance between two swept-sphere volumes with radii r_a, r_b: core distance minus the radii,
// negative when the volumes overlap (the penetration depth along the core witness direction).
struct SsvDistance {
  double distance_m = 0;     // |c_b - c_a| - r_a - r_b
  Eigen::Vector3d c_a, c_b;  // witness points on the cores
  Eigen::Vector3d p_a, p_b;  // witness points on the SSV surfaces: c_a + r_a n, c_b - r_b n
  Eigen::Vector3d n;         // unit vector from c_a to c_b; zero when the cores touch
};
void ssvDistance(const Core& a, double r_a, const Core& b, double r_b, SsvDistance& out);
// The same from known core witness points (c_a on a, c_b on b closest to each other).
inline void ssvDistanceFromWitnesses(const Eigen::Vector3d& c_a, double r_a,
                                     const Eigen::Vector3d& c_b, double r_b, SsvDistance& out) {
  out.c_a = c_a;
  out.c_b = c_b;
  const Eigen::Vector3d diff = c_b - c_a;
  const double dc = diff.norm();
  out.distance_m = dc - r_a - r_b;
  if (dc > defaults::kCollisionTouching_m) {
    out.n = diff * (1.0 / dc);
    out.p_a = c_a + r_a * out.n;
    out.p_b = c_b - r_b * out.n;
  } else {
    // Cores touch or intersect (a distance at rounding level has no meaningful direction):
    // report the contact point on both and a zero normal.
    out.n.setZero();
    out.p_a = c_a;
    out.p_b = c_b;
  }
}

// Clamp to [0, 1] without a branch (minsd/maxsd on x86-64; a data-dependent branch here
// mispredicts often and serialises the otherwise independent pair evaluations).
inline double clampUnit(double x) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_min_sd(_mm_max_sd(_mm_set_sd(x), _mm_setzero_pd()), _mm_set_sd(1.0)));
#else
  return std::min(1.0, std::max(0.0, x));
#endif
}

// Square root of a non-negative value without libm's error-handling branch.
inline double sqrtNonNegative(double x) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_sqrt_sd(_mm_setzero_pd(), _mm_set_sd(x)));
#else
  return std::sqrt(x);
#endif
}

// Maximum without a branch.
inline double maxNoBranch(double x, double y) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(x), _mm_set_sd(y)));
#else
  return std::max(x, y);
#endif
}

// Hot-path kernel for two segments p0 + s d1 and q0 + t d2 (s, t in [0, 1]) with non-zero squared
// lengths a = |d1|^2, e = |d2|^2 and their inverses precomputed (per configuration, per volume).
// Returns the squared distance and the parameters of the witness points. Same algorithm as
// squaredDistanceSegmentSegment: the clamped line solution (Ericson, Real-Time Collision
// Detection, 5.1.9; at the box-constrained optimum each parameter minimises for the other, so s
// is recomputed from the clamped t), and for near-parallel pairs (sin^2 of the angle <=
// kCollisionParallelSin2, e.g. housings on parallel joint axes) also the four endpoint-to-segment
// candidates, one of which is a minimiser of parallel segments. One division, no heap.
inline double squaredDistanceSegmentSegmentFast(const Eigen::Vector3d& p0,
                                                const Eigen::Vector3d& d1, double a, double inv_a,
                                                const Eigen::Vector3d& q0,
                                                const Eigen::Vector3d& d2, double e, double inv_e,
                                                double& s, double& t) {
  auto clamp01 = clampUnit;
  const Eigen::Vector3d r = p0 - q0;
  const double b = d1.dot(d2), c = d1.dot(r), f = d2.dot(r);
  const double denom = a * e - b * b;
  // Clamped line solution; feasible (and NaN-free) even when denom is 0.
  const double s0 = denom > 0 ? clamp01((b * f - c * e) / denom) : 0.0;
  t = clamp01((b * s0 + f) * inv_e);
  s = clamp01((b * t - c) * inv_a);
  double best = (r + s * d1 - t * d2).squaredNorm();
  if (denom > defaults::kCollisionParallelSin2 * a * e) return best;
  auto offer = [&](double si, double ti) {
    const double q = (r + si * d1 - ti * d2).squaredNorm();
    if (q < best) {
      best = q;
      s = si;
      t = ti;
    }
  };
  offer(0.0, clamp01(f * inv_e));        // p0 against segment q
  offer(1.0, clamp01((f + b) * inv_e));  // p1
  offer(clamp01(-c * inv_a), 0.0);       // q0 against segment p
  offer(clamp01((b - c) * inv_a), 1.0);  // q1
  return best;
}

}  // namespace armstudy::collision
