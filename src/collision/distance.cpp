#include "collision/distance.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/defaults.hpp"
#include "common/errors.hpp"

namespace armstudy::collision {
namespace {

using Eigen::Vector3d;

inline double clamp01(double x) { return std::min(1.0, std::max(0.0, x)); }

// Keeps the best (smallest) of a set of feasible candidate pairs.
struct Best {
  double sq = std::numeric_limits<double>::infinity();
  Vector3d a = Vector3d::Zero(), b = Vector3d::Zero();
  void offer(const Vector3d& ca, const Vector3d& cb) {
    const double s = (ca - cb).squaredNorm();
    if (s < sq) {
      sq = s;
      a = ca;
      b = cb;
    }
  }
  void offer(double s, const Vector3d& ca, const Vector3d& cb) {
    if (s < sq) {
      sq = s;
      a = ca;
      b = cb;
    }
  }
};

// Point of triangle (a, e0 = b - a, e1 = c - a) closest to p when that point is interior to the
// triangle's plane projection; false when the projection falls outside or the triangle is
// degenerate. The returned point is a convex combination of the corners, so it is feasible even
// when rounding perturbs the barycentric coordinates.
inline bool projectIntoTriangle(const Vector3d& p, const Vector3d& a, const Vector3d& e0,
                                const Vector3d& e1, Vector3d& q) {
  const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
  const double det = d00 * d11 - d01 * d01;
  if (!(det > defaults::kCollisionDegenerateRelative * d00 * d11)) return false;
  const Vector3d w = p - a;
  const double w0 = e0.dot(w), w1 = e1.dot(w);
  const double u = (d11 * w0 - d01 * w1) / det;
  const double v = (d00 * w1 - d01 * w0) / det;
  if (u < 0 || v < 0 || u + v > 1) return false;
  q = a + u * e0 + v * e1;
  return true;
}

// Point where segment [p0, p1] crosses the plane of triangle (a, b, c) inside the triangle.
inline bool pierce(const Vector3d& p0, const Vector3d& p1, const Vector3d& a, const Vector3d& e0,
                   const Vector3d& e1, Vector3d& x_seg, Vector3d& x_tri) {
  const Vector3d n = e0.cross(e1);
  const double s0 = n.dot(p0 - a), s1 = n.dot(p1 - a);
  if (!((s0 > 0 && s1 < 0) || (s0 < 0 && s1 > 0))) return false;
  const double t = s0 / (s0 - s1);
  x_seg = p0 + t * (p1 - p0);
  return projectIntoTriangle(x_seg, a, e0, e1, x_tri);
}

}  // namespace

double squaredDistancePointSegment(const Vector3d& p, const Vector3d& a, const Vector3d& b,
                                   Vector3d& c_seg) {
  const Vector3d d = b - a;
  const double dd = d.squaredNorm();
  const double t = dd > 0 ? clamp01(d.dot(p - a) / dd) : 0.0;
  c_seg = a + t * d;
  return (p - c_seg).squaredNorm();
}

double squaredDistanceSegmentSegment(const Vector3d& p0, const Vector3d& p1, const Vector3d& q0,
                                     const Vector3d& q1, Vector3d& c_p, Vector3d& c_q) {
  const Vector3d d1 = p1 - p0, d2 = q1 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm();
  if (a > 0 && e > 0) {
    double s = 0, t = 0;
    const double sq =
        squaredDistanceSegmentSegmentFast(p0, d1, a, 1.0 / a, q0, d2, e, 1.0 / e, s, t);
    c_p = p0 + s * d1;
    c_q = q0 + t * d2;
    return sq;
  }
  // A zero-length segment is a point.
  if (a > 0) {
    c_q = q0;
    return squaredDistancePointSegment(q0, p0, p1, c_p);
  }
  c_p = p0;
  return squaredDistancePointSegment(p0, q0, q1, c_q);
}

double squaredDistancePointTriangle(const Vector3d& p, const Vector3d& a, const Vector3d& b,
                                    const Vector3d& c, Vector3d& c_tri) {
  Vector3d q;
  if (projectIntoTriangle(p, a, b - a, c - a, q)) {
    c_tri = q;
    return (p - q).squaredNorm();
  }
  // Outside the prism over the triangle (or degenerate): the closest point is on an edge.
  Best best;
  best.offer(squaredDistancePointSegment(p, a, b, q), p, q);
  best.offer(squaredDistancePointSegment(p, b, c, q), p, q);
  best.offer(squaredDistancePointSegment(p, c, a, q), p, q);
  c_tri = best.b;
  return best.sq;
}

double squaredDistanceSegmentTriangle(const Vector3d& p0, const Vector3d& p1, const Vector3d& a,
                                      const Vector3d& b, const Vector3d& c, Vector3d& c_seg,
                                      Vector3d& c_tri) {
  Vector3d x, y;
  const Vector3d e0 = b - a, e1 = c - a;
  const Vector3d n = e0.cross(e1);
  const double s0 = n.dot(p0 - a), s1 = n.dot(p1 - a);
  if ((s0 > 0 && s1 < 0) || (s0 < 0 && s1 > 0)) {
    // Crossing the plane: inside the triangle the distance is 0.
    x = p0 + (s0 / (s0 - s1)) * (p1 - p0);
    if (projectIntoTriangle(x, a, e0, e1, y)) {
      c_seg = x;
      c_tri = y;
      return (x - y).squaredNorm();
    }
  } else {
    // One side: when both endpoints project into the triangle, so does the whole segment, and
    // its distance to the plane is linear along it: the nearer endpoint is the minimiser.
    Vector3d y1;
    if (projectIntoTriangle(p0, a, e0, e1, y) && projectIntoTriangle(p1, a, e0, e1, y1)) {
      const double q0 = (p0 - y).squaredNorm(), q1 = (p1 - y1).squaredNorm();
      c_seg = q0 <= q1 ? p0 : p1;
      c_tri = q0 <= q1 ? y : y1;
      return std::min(q0, q1);
    }
  }
  // Otherwise a minimiser has a segment endpoint or lies on a triangle edge.
  Best best;
  best.offer(squaredDistancePointTriangle(p0, a, b, c, y), p0, y);
  best.offer(squaredDistancePointTriangle(p1, a, b, c, y), p1, y);
  best.offer(squaredDistanceSegmentSegment(p0, p1, a, b, x, y), x, y);
  best.offer(squaredDistanceSegmentSegment(p0, p1, b, c, x, y), x, y);
  best.offer(squaredDistanceSegmentSegment(p0, p1, c, a, x, y), x, y);
  c_seg = best.a;
  c_tri = best.b;
  return best.sq;
}

double squaredDistanceTriangleTriangle(const Vector3d& a0, const Vector3d& a1, const Vector3d& a2,
                                       const Vector3d& b0, const Vector3d& b1, const Vector3d& b2,
                                       Vector3d& c_a, Vector3d& c_b) {
  const Vector3d* A[3] = {&a0, &a1, &a2};
  const Vector3d* B[3] = {&b0, &b1, &b2};
  const Vector3d ea0 = a1 - a0, ea1 = a2 - a0, eb0 = b1 - b0, eb1 = b2 - b0;
  Vector3d x, y;
  // Intersecting triangles: an edge of one pierces the other (transversal case); coplanar
  // overlaps are found below as edge crossings (distance 0) or a corner inside the other.
  for (int i = 0; i < 3; ++i) {
    if (pierce(*A[i], *A[(i + 1) % 3], b0, eb0, eb1, x, y)) {
      c_a = x;
      c_b = y;
      return (x - y).squaredNorm();
    }
    if (pierce(*B[i], *B[(i + 1) % 3], a0, ea0, ea1, y, x)) {
      c_a = x;
      c_b = y;
      return (x - y).squaredNorm();
    }
  }
  // Disjoint: a minimiser is an edge-edge pair or a corner against the other triangle.
  Best best;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      best.offer(
          squaredDistanceSegmentSegment(*A[i], *A[(i + 1) % 3], *B[j], *B[(j + 1) % 3], x, y), x,
          y);
  for (int i = 0; i < 3; ++i) {
    best.offer(squaredDistancePointTriangle(*A[i], b0, b1, b2, y), *A[i], y);
    best.offer(squaredDistancePointTriangle(*B[i], a0, a1, a2, x), x, *B[i]);
  }
  c_a = best.a;
  c_b = best.b;
  return best.sq;
}

double squaredDistanceCores(const Core& a, const Core& b, Vector3d& c_a, Vector3d& c_b) {
  // Order so that the first argument has fewer points; swap the witnesses back.
  if (a.n > b.n) return squaredDistanceCores(b, a, c_b, c_a);
  switch (a.n * 3 + b.n) {
    case 4:  // point-point
      c_a = a.p[0];
      c_b = b.p[0];
      return (c_a - c_b).squaredNorm();
    case 5:  // point-segment
      c_a = a.p[0];
      return squaredDistancePointSegment(a.p[0], b.p[0], b.p[1], c_b);
    case 6:  // point-triangle
      c_a = a.p[0];
      return squaredDistancePointTriangle(a.p[0], b.p[0], b.p[1], b.p[2], c_b);
    case 8:  // segment-segment
      return squaredDistanceSegmentSegment(a.p[0], a.p[1], b.p[0], b.p[1], c_a, c_b);
    case 9:  // segment-triangle
      return squaredDistanceSegmentTriangle(a.p[0], a.p[1], b.p[0], b.p[1], b.p[2], c_a, c_b);
    case 12:  // triangle-triangle
      return squaredDistanceTriangleTriangle(a.p[0], a.p[1], a.p[2], b.p[0], b.p[1], b.p[2], c_a,
                                             c_b);
    default:
      break;
  }
  ARMSTUDY_CHECK(false, "squaredDistanceCores: a core has 1, 2 or 3 points");
  return 0;
}

void ssvDistance(const Core& a, double r_a, const Core& b, double r_b, SsvDistance& out) {
  Vector3d c_a, c_b;
  squaredDistanceCores(a, b, c_a, c_b);
  ssvDistanceFromWitnesses(c_a, r_a, c_b, r_b, out);
}

}  // namespace armstudy::collision
