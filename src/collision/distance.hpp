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
#include <array>

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
double squaredDistanceCores(const Core& a, const Core& b, Eigen::Vector3d& c_a, Eigen::Vector3d& c_b);

// Distance between two swept-sphere volumes with radii r_a, r_b: core distance minus the radii,
// negative when the volumes overlap (the penetration depth along the core witness direction).
struct SsvDistance {
  double distance_m = 0;       // |c_b - c_a| - r_a - r_b
  Eigen::Vector3d c_a, c_b;    // witness points on the cores
  Eigen::Vector3d p_a, p_b;    // witness points on the SSV surfaces: c_a + r_a n, c_b - r_b n
  Eigen::Vector3d n;           // unit vector from c_a to c_b; zero when the cores touch
};
void ssvDistance(const Core& a, double r_a, const Core& b, double r_b, SsvDistance& out);

}  // namespace armstudy::collision
