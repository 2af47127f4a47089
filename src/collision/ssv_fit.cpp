#include "collision/ssv_fit.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Min_sphere_of_spheres_d.h>
#include <CGAL/Min_sphere_of_spheres_d_traits_3.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/linear_least_squares_fitting_3.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <sstream>

#include "collision/collision_model.hpp"
#include "collision/distance.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"

namespace armstudy::collision {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;
using Eigen::Vector3d;

K::Point_3 toCgal(const Vector3d& v) { return K::Point_3(v.x(), v.y(), v.z()); }
Vector3d toEigen(const K::Point_3& p) { return Vector3d(p.x(), p.y(), p.z()); }
Vector3d toEigen(const K::Vector_3& v) { return Vector3d(v.x(), v.y(), v.z()); }

Core coreOf(const FittedSsv& v) {
  Core c;
  c.n = static_cast<int>(v.type);
  for (int i = 0; i < 3; ++i) c.p[i] = v.p[i];
  return c;
}

double coreDistance(const FittedSsv& v, const Vector3d& x) {
  Core p;
  p.n = 1;
  p.p[0] = x;
  Vector3d a, b;
  return std::sqrt(squaredDistanceCores(p, coreOf(v), a, b));
}

// A candidate: one or two volumes sharing a radius, and its swept volume for comparison.
struct Candidate {
  std::vector<FittedSsv> volumes;
  double volume_m3 = std::numeric_limits<double>::infinity();
};

// Radius so that every point is inside at least one of the candidate's volumes.
void inflate(Candidate& c, const std::vector<Vector3d>& pts, double margin) {
  double r = 0;
  for (const auto& x : pts) {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& v : c.volumes) d = std::min(d, coreDistance(v, x));
    r = std::max(r, d);
  }
  r += defaults::kSsvFitInflation_m + margin;
  for (auto& v : c.volumes) v.radius_m = r;
}

// The candidate made of the one volume `v`, inflated over the points.
Candidate singleVolume(const FittedSsv& v, const std::vector<Vector3d>& pts, double margin) {
  Candidate out;
  out.volumes.push_back(v);
  inflate(out, pts, margin);
  out.volume_m3 = ssvVolume(out.volumes[0]);
  return out;
}

// CGAL's least-squares line or plane `fit` through the points; returns their centroid.
template <class LineOrPlane>
Vector3d leastSquaresFit(const std::vector<Vector3d>& pts, LineOrPlane& fit) {
  std::vector<K::Point_3> cp;
  for (const auto& p : pts) cp.push_back(toCgal(p));
  K::Point_3 centroid;
  CGAL::linear_least_squares_fitting_3(cp.begin(), cp.end(), fit, centroid,
                                       CGAL::Dimension_tag<0>());
  return toEigen(centroid);
}

Candidate sphereCandidate(const std::vector<Vector3d>& pts, double margin) {
  using Traits = CGAL::Min_sphere_of_spheres_d_traits_3<K, double>;
  using MinSphere = CGAL::Min_sphere_of_spheres_d<Traits>;
  std::vector<Traits::Sphere> spheres;
  for (const auto& p : pts) spheres.emplace_back(toCgal(p), 0.0);
  MinSphere ms(spheres.begin(), spheres.end());
  Vector3d c;
  auto it = ms.center_cartesian_begin();
  for (int i = 0; i < 3; ++i, ++it) c[i] = *it;
  FittedSsv v;
  v.type = SsvType::Point;
  v.p[0] = c;
  return singleVolume(v, pts, margin);
}

Candidate capsuleCandidate(const std::vector<Vector3d>& pts, double margin) {
  if (pts.size() < 2) return {};
  K::Line_3 line;
  const Vector3d c = leastSquaresFit(pts, line);
  const Vector3d u = toEigen(line.to_vector()).normalized();
  // Radius: the largest distance from the axis; end points as far in as that radius allows
  // (a point at axial t, radial rho needs an end within sqrt(r^2 - rho^2) of t).
  double r = 0;
  for (const auto& p : pts) r = std::max(r, ((p - c) - (p - c).dot(u) * u).norm());
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& p : pts) {
    const double t = (p - c).dot(u);
    const double rho = ((p - c) - t * u).norm();
    const double slack = std::sqrt(std::max(0.0, r * r - rho * rho));
    lo = std::min(lo, t + slack);
    hi = std::max(hi, t - slack);
  }
  if (!(hi - lo > defaults::kCollisionCoincident_m * 10)) return {};  // a sphere is better
  FittedSsv v;
  v.type = SsvType::Line;
  v.p[0] = c + lo * u;
  v.p[1] = c + hi * u;
  return singleVolume(v, pts, margin);
}

Candidate plateCandidate(const std::vector<Vector3d>& pts, double margin) {
  Candidate out;
  if (pts.size() < 3) return out;
  K::Plane_3 plane;
  const Vector3d c = leastSquaresFit(pts, plane);
  const Vector3d e1 = toEigen(plane.base1()).normalized();
  const Vector3d e2 = toEigen(plane.base2()).normalized();
  std::vector<K::Point_2> p2, hull;
  for (const auto& p : pts) p2.emplace_back((p - c).dot(e1), (p - c).dot(e2));
  CGAL::convex_hull_2(p2.begin(), p2.end(), std::back_inserter(hull));
  if (hull.size() < 3) return out;
  // Minimum-area enclosing rectangle: one side is flush with a hull edge.
  double best_area = std::numeric_limits<double>::infinity();
  Eigen::Vector2d bu = Eigen::Vector2d::UnitX(), bv = Eigen::Vector2d::UnitY(),
                  lo = Eigen::Vector2d::Zero(), hi = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const K::Point_2& a = hull[i];
    const K::Point_2& b = hull[(i + 1) % hull.size()];
    Eigen::Vector2d u(b.x() - a.x(), b.y() - a.y());
    if (u.norm() == 0) continue;
    u.normalize();
    const Eigen::Vector2d v(-u.y(), u.x());
    Eigen::Vector2d mn(1e300, 1e300), mx(-1e300, -1e300);
    for (const auto& q : hull) {
      const Eigen::Vector2d x(q.x(), q.y());
      mn = mn.cwiseMin(Eigen::Vector2d(x.dot(u), x.dot(v)));
      mx = mx.cwiseMax(Eigen::Vector2d(x.dot(u), x.dot(v)));
    }
    const double area = (mx - mn).prod();
    if (area < best_area) {
      best_area = area;
      bu = u;
      bv = v;
      lo = mn;
      hi = mx;
    }
  }
  auto corner = [&](double su, double sv) {
    const Eigen::Vector2d x = su * bu + sv * bv;
    return Vector3d(c + x.x() * e1 + x.y() * e2);
  };
  const Vector3d A = corner(lo.x(), lo.y()), B = corner(hi.x(), lo.y()), C = corner(hi.x(), hi.y()),
                 D = corner(lo.x(), hi.y());
  FittedSsv t1, t2;
  t1.type = t2.type = SsvType::Triangle;
  t1.p = {A, B, C};
  t2.p = {A, C, D};
  if (!volumeGeometryProblem(SsvType::Triangle, t1.p, 0).empty() ||
      !volumeGeometryProblem(SsvType::Triangle, t2.p, 0).empty())
    return out;
  out.volumes = {t1, t2};
  inflate(out, pts, margin);
  const double r = out.volumes[0].radius_m;
  const double w = hi.x() - lo.x(), h = hi.y() - lo.y();
  // Steiner formula of the rectangle swept by a sphere.
  out.volume_m3 =
      2 * w * h * r + std::numbers::pi * (w + h) * r * r + 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return out;
}

// Points whose convex hull contains the part of the solid between the planes t0 <= (x - c).u <= t1.
std::vector<Vector3d> slabPoints(const TriangleMesh& m, const Vector3d& c, const Vector3d& u,
                                 double t0, double t1) {
  std::vector<Vector3d> pts;
  std::vector<double> t(m.vertices.size());
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    t[i] = (m.vertices[i] - c).dot(u);
    if (t[i] >= t0 && t[i] <= t1) pts.push_back(m.vertices[i]);
  }
  for (const auto& tri : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const int i = tri[k], j = tri[(k + 1) % 3];
      if (i > j) continue;  // each edge once per orientation pair
      for (double tau : {t0, t1}) {
        if ((t[i] - tau) * (t[j] - tau) < 0) {
          const double s = (tau - t[i]) / (t[j] - t[i]);
          pts.push_back(m.vertices[i] + s * (m.vertices[j] - m.vertices[i]));
        }
      }
    }
  return pts;
}

std::vector<Vector3d> hullVertices(const std::vector<Vector3d>& pts) {
  if (pts.size() < 4) return pts;
  std::vector<K::Point_3> cp;
  for (const auto& p : pts) cp.push_back(toCgal(p));
  SurfaceMesh hull;
  CGAL::convex_hull_3(cp.begin(), cp.end(), hull);
  std::vector<Vector3d> out;
  for (auto v : hull.vertices()) out.push_back(toEigen(hull.point(v)));
  if (out.empty()) out = pts;
  // A fixed (lexicographic) order: the hull's internal vertex order may vary from run to run,
  // and the least-squares sums would then differ in the last bits.
  std::sort(out.begin(), out.end(), [](const Vector3d& a, const Vector3d& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  return out;
}

}  // namespace

double ssvVolume(const FittedSsv& v) {
  const double r = v.radius_m;
  const double ball = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  if (v.type == SsvType::Point) return ball;
  if (v.type == SsvType::Line) return std::numbers::pi * r * r * (v.p[1] - v.p[0]).norm() + ball;
  const double area = 0.5 * (v.p[1] - v.p[0]).cross(v.p[2] - v.p[0]).norm();
  const double perim =
      (v.p[1] - v.p[0]).norm() + (v.p[2] - v.p[1]).norm() + (v.p[0] - v.p[2]).norm();
  return 2 * area * r + 0.5 * std::numbers::pi * perim * r * r + ball;
}

double ssvSignedDistance(const FittedSsv& v, const Vector3d& x) {
  return coreDistance(v, x) - v.radius_m;
}

std::string SsvFitOptions::validate() const {
  if (max_volumes < 1 || max_volumes > 32) return "max_volumes must lie in 1..32";
  if (!(margin_m >= 0) || !std::isfinite(margin_m)) return "margin must be a finite length >= 0";
  return "";
}

std::string meshVertexProblem(const std::vector<Vector3d>& points, double max_abs_m) {
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Vector3d& p = points[k];
    const bool finite = p.allFinite();
    if (finite && p.cwiseAbs().maxCoeff() <= max_abs_m) continue;
    return "point " + std::to_string(k + 1) + " of " + std::to_string(points.size()) + " at (" +
           formatG(p.x(), 6) + ", " + formatG(p.y(), 6) + ", " + formatG(p.z(), 6) + ") m " +
           (finite ? "is not plausible: each coordinate must be at most"
                   : "is not finite (NaN or Inf); each coordinate must be at most") +
           " " + formatScientific(max_abs_m, 0) + " m";
  }
  return "";
}

TriangleMesh loadTriangleMesh(const std::string& path, double scale, double max_abs_m) {
  namespace fs = std::filesystem;
  auto fail = [&](const std::string& msg) { throw InputError(path, 0, "mesh", msg); };
  if (!(scale > 0) || !std::isfinite(scale)) fail("mesh scale must be positive");
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) fail("cannot open mesh file (missing or not a file)");
  const auto size = fs::file_size(path, ec);
  if (size == 0) fail("mesh file is empty");
  if (size > defaults::kMaxMeshFileBytes)
    fail("mesh file of " + std::to_string(size) + " bytes exceeds the limit for a mesh of " +
         std::to_string(defaults::kMaxMeshFileBytes) + " bytes");
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return std::tolower(ch); });
  if (ext != ".stl" && ext != ".off")
    fail("unsupported mesh format '" + ext + "' (expected .stl or .off)");
  SurfaceMesh sm;
  bool ok = false;
  try {
    ok = PMP::IO::read_polygon_mesh(path, sm, CGAL::parameters::verbose(false));
  } catch (const std::exception& e) {
    fail(std::string("cannot read mesh: ") + e.what());
  }
  if (!ok) fail("cannot read mesh (not a valid, orientable " + ext.substr(1) + " surface)");
  if (sm.number_of_faces() == 0 || sm.number_of_vertices() == 0) fail("mesh has no faces (empty)");
  std::vector<Vector3d> points;
  for (auto v : sm.vertices()) points.push_back(toEigen(sm.point(v)) * scale);
  if (const std::string p = meshVertexProblem(points, max_abs_m); !p.empty())
    fail("mesh vertex (scaled): " + p);
  if (!CGAL::is_closed(sm))
    fail("mesh is not closed (it has border edges): export the link as a watertight solid");
  if (!CGAL::is_triangle_mesh(sm)) PMP::triangulate_faces(sm);
  TriangleMesh out;
  std::map<SurfaceMesh::Vertex_index, int> index;
  for (auto v : sm.vertices()) {
    index[v] = static_cast<int>(out.vertices.size());
    out.vertices.push_back(toEigen(sm.point(v)) * scale);
  }
  for (auto f : sm.faces()) {
    std::array<int, 3> tri{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      if (k < 3) tri[k] = index[v];
      ++k;
    }
    if (k == 3) out.triangles.push_back(tri);
  }
  return out;
}

SsvFitSummary fitSsvs(const TriangleMesh& mesh, const SsvFitOptions& o) {
  ARMSTUDY_CHECK(o.validate().empty(), "fitSsvs: invalid options: " + o.validate());
  ARMSTUDY_CHECK(!mesh.vertices.empty(), "fitSsvs: empty mesh");
  // CGAL's randomised steps (hull insertion order, sphere pivoting) draw from its default
  // generator, seeded from the clock: reseed it so a refit gives identical bits.
  CGAL::get_default_random() = CGAL::Random(defaults::kSsvFitSeed);
  // Principal axis of the whole mesh (least-squares line through the vertices).
  std::vector<K::Point_3> cp;
  for (const auto& p : mesh.vertices) cp.push_back(toCgal(p));
  Vector3d c = Vector3d::Zero(), u = Vector3d::UnitX();
  if (cp.size() >= 2) {
    K::Line_3 line;
    K::Point_3 centroid;
    CGAL::linear_least_squares_fitting_3(cp.begin(), cp.end(), line, centroid,
                                         CGAL::Dimension_tag<0>());
    c = toEigen(centroid);
    u = toEigen(line.to_vector()).normalized();
  }
  double tmin = std::numeric_limits<double>::infinity(), tmax = -tmin;
  for (const auto& p : mesh.vertices) {
    tmin = std::min(tmin, (p - c).dot(u));
    tmax = std::max(tmax, (p - c).dot(u));
  }

  SsvFitSummary best;
  best.swept_volume_m3 = std::numeric_limits<double>::infinity();
  for (int slabs = 1; slabs <= o.max_volumes; ++slabs) {
    std::vector<Candidate> chosen;
    std::vector<std::vector<Vector3d>> slab_pts;
    int hull_count = 0;
    for (int k = 0; k < slabs; ++k) {
      const double t0 = k == 0 ? tmin : tmin + (tmax - tmin) * k / slabs;
      const double t1 = k + 1 == slabs ? tmax : tmin + (tmax - tmin) * (k + 1) / slabs;
      std::vector<Vector3d> pts = hullVertices(slabPoints(mesh, c, u, t0, t1));
      if (pts.empty()) continue;
      hull_count += static_cast<int>(pts.size());
      Candidate cands[3] = {sphereCandidate(pts, o.margin_m), capsuleCandidate(pts, o.margin_m),
                            plateCandidate(pts, o.margin_m)};
      Candidate* pick = &cands[0];
      for (auto& cd : cands)
        if (!cd.volumes.empty() && cd.volume_m3 < pick->volume_m3) pick = &cd;
      chosen.push_back(*pick);
      slab_pts.push_back(std::move(pts));
    }
    // Respect the volume budget: replace plates (two volumes) by the best single volume.
    auto count = [&] {
      int n = 0;
      for (const auto& cd : chosen) n += static_cast<int>(cd.volumes.size());
      return n;
    };
    for (std::size_t k = 0; k < chosen.size() && count() > o.max_volumes; ++k)
      if (chosen[k].volumes.size() > 1) {
        Candidate s = sphereCandidate(slab_pts[k], o.margin_m),
                  l = capsuleCandidate(slab_pts[k], o.margin_m);
        chosen[k] = (!l.volumes.empty() && l.volume_m3 < s.volume_m3) ? l : s;
      }
    if (count() > o.max_volumes) continue;
    SsvFitSummary s;
    s.slabs = slabs;
    s.hull_vertices = hull_count;
    s.swept_volume_m3 = 0;
    for (const auto& cd : chosen)
      for (const auto& v : cd.volumes) {
        s.volumes.push_back(v);
        s.swept_volume_m3 += ssvVolume(v);
      }
    if (s.swept_volume_m3 < best.swept_volume_m3 * (1 - 1e-9)) best = s;
  }
  best.mesh_vertices = static_cast<int>(mesh.vertices.size());
  // Enclosed volume (divergence theorem; orientation-independent magnitude).
  double vol = 0;
  for (const auto& t : mesh.triangles)
    vol += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]])) / 6.0;
  best.mesh_volume_m3 = std::abs(vol);
  best.max_vertex_excess_m = -std::numeric_limits<double>::infinity();
  for (const auto& x : mesh.vertices) {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& v : best.volumes) d = std::min(d, ssvSignedDistance(v, x));
    best.max_vertex_excess_m = std::max(best.max_vertex_excess_m, d);
  }
  ARMSTUDY_CHECK(best.max_vertex_excess_m <= 0,
                 "fitSsvs: a mesh vertex is outside the fitted volumes");
  return best;
}

std::string replaceLinkVolumesInDesignText(const std::string& text, const std::string& link,
                                           const std::vector<FittedSsv>& volumes,
                                           const std::string& mesh_label) {
  // Split into lines; drop every [[collision]] table whose link is `link` (the table runs to the
  // next table header).
  std::vector<std::string> lines;
  {
    std::stringstream ss(text);
    for (std::string l; std::getline(ss, l);) lines.push_back(l);
  }
  auto trimmed = [](const std::string& l) {
    const auto a = l.find_first_not_of(" \t");
    return a == std::string::npos ? std::string() : l.substr(a);
  };
  auto isHeader = [&](const std::string& l) { return trimmed(l).rfind("[", 0) == 0; };
  const std::string ours_comment = "# [[collision]] volumes of link \"" + link + "\" fitted";
  std::vector<std::string> out;
  for (std::size_t i = 0; i < lines.size();) {
    if (lines[i].rfind(ours_comment, 0) == 0) {  // the comment of an earlier fit of this link
      i += (i + 1 < lines.size() && lines[i + 1].rfind("# (every mesh vertex inside", 0) == 0) ? 2
                                                                                               : 1;
      continue;
    }
    if (trimmed(lines[i]).rfind("[[collision]]", 0) == 0) {
      std::size_t j = i + 1;
      bool ours = false;
      while (j < lines.size() && !isHeader(lines[j])) {
        std::string t = trimmed(lines[j]);
        t.erase(std::remove_if(t.begin(), t.end(), [](char ch) { return ch == ' ' || ch == '\t'; }),
                t.end());
        if (t.rfind("link=\"" + link + "\"", 0) == 0 || t.rfind("link='" + link + "'", 0) == 0)
          ours = true;
        ++j;
      }
      if (ours) {
        i = j;
        continue;
      }
    }
    out.push_back(lines[i++]);
  }
  while (!out.empty() && trimmed(out.back()).empty()) out.pop_back();
  std::ostringstream os;
  for (const auto& l : out) os << l << "\n";
  os << "\n# [[collision]] volumes of link \"" << link << "\" fitted by `armstudy fit-ssv` to "
     << mesh_label << "\n# (every mesh vertex inside; docs/collision.md).\n";
  int idx = 0;
  for (const auto& v : volumes) {
    os << "\n[[collision]]\nlink = \"" << link << "\"\nname = \"fitted_" << idx++ << "\"\ntype = \""
       << toString(v.type) << "\"\npoints = [";
    for (int i = 0; i < static_cast<int>(v.type); ++i)
      os << (i ? ", " : "") << "[" << formatRoundTrip(v.p[i].x()) << ", "
         << formatRoundTrip(v.p[i].y()) << ", " << formatRoundTrip(v.p[i].z()) << "]";
    os << "]\nradius = " << formatRoundTrip(v.radius_m) << "\n";
  }
  return os.str();
}

}  // namespace armstudy::collision
