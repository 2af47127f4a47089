#pragma once
// Swept-sphere volumes from a link mesh (docs/collision.md, "Fitting volumes to CAD meshes").
//
// A closed triangle mesh (STL or OFF) of one link, given in that link's frame, is cut into slabs
// along its principal axis; each slab's points (the mesh vertices in it plus the points where
// mesh edges cross the slab planes, so the slab's part of the solid is inside their convex hull)
// are reduced to their convex hull (CGAL convex_hull_3), and three candidates are fitted: a point
// SSV (CGAL Min_sphere_of_spheres_d), a line SSV along the least-squares line (CGAL
// linear_least_squares_fitting_3) with the tightest end points for its radius, and a plate of two
// triangle SSVs on the least-squares plane covering the minimum-area rectangle of the projected
// hull. The smallest candidate wins; the slab count (1..max_volumes) with the smallest total SSV
// volume wins. Guarantee: every radius is finally inflated to the largest distance of any slab
// point from the core (plus defaults::kSsvFitInflation_m), so every mesh vertex lies inside.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "model/model.hpp"

namespace armstudy::defaults {
// The largest collision mesh file read (16 MiB; fit-ssv and URDF meshes): reading and fitting a
// binary STL takes about 43 bytes of memory per byte of it (docs/hardening.md), so one mesh stays
// under about 0.75 GB.
inline constexpr unsigned long long kMaxMeshFileBytes = 16ull << 20;
}  // namespace armstudy::defaults

namespace armstudy::collision {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;  // [m] after scaling, in the link frame
  std::vector<std::array<int, 3>> triangles;
};

// Empty when every point is finite with coordinates of at most `max_abs_m` (callers reading files
// pass io/units.hpp kMaxLength_m), else which point is not and why. fitSsvs needs such points: a
// coordinate of 1e308 overflows its sums.
std::string meshVertexProblem(const std::vector<Eigen::Vector3d>& points, double max_abs_m);

// Reads a closed triangle mesh (.stl ASCII/binary or .off; other extensions are rejected).
// Throws InputError(path, 0, "mesh", ...) for a missing, unreadable, empty or special file, a file
// larger than defaults::kMaxMeshFileBytes, a mesh without faces, a mesh that is not closed (has
// border edges), or a vertex that meshVertexProblem refuses after scaling. `scale` converts file
// units to metres (e.g. 0.001 for millimetres).
TriangleMesh loadTriangleMesh(const std::string& path, double scale, double max_abs_m);

struct SsvFitOptions {
  int max_volumes = 4;           // upper bound on the number of SSVs (a plate counts as two)
  double margin_m = 0;           // extra radius on every volume (clearance)
  std::string validate() const;  // "" when valid
};

struct FittedSsv {
  SsvType type = SsvType::Point;
  std::array<Eigen::Vector3d, 3> p{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                   Eigen::Vector3d::Zero()};
  double radius_m = 0;
};

struct SsvFitSummary {
  std::vector<FittedSsv> volumes;
  int slabs = 0;  // slab count chosen
  int mesh_vertices = 0;
  int hull_vertices = 0;           // summed over the slabs
  double swept_volume_m3 = 0;      // summed SSV volumes (overlaps counted twice)
  double mesh_volume_m3 = 0;       // enclosed volume of the mesh, for comparison
  double max_vertex_excess_m = 0;  // max over vertices of (distance to nearest SSV surface); <= 0
};

SsvFitSummary fitSsvs(const TriangleMesh& mesh, const SsvFitOptions& options);

// Volume of one swept-sphere volume [m^3] (Steiner formula for the flat cores).
double ssvVolume(const FittedSsv& v);

// Signed distance of a point from the surface of an SSV (negative inside).
double ssvSignedDistance(const FittedSsv& v, const Eigen::Vector3d& x);

// Replaces the [[collision]] tables of `link` in a design file's text by `volumes` (appended at the
// end with a comment naming `mesh_label`), leaving every other line untouched.
std::string replaceLinkVolumesInDesignText(const std::string& design_text, const std::string& link,
                                           const std::vector<FittedSsv>& volumes,
                                           const std::string& mesh_label);

}  // namespace armstudy::collision
