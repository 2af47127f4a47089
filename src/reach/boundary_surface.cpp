#include "reach/boundary_surface.hpp"

#include <CGAL/Alpha_shape_3.h>
#include <CGAL/Alpha_shape_cell_base_3.h>
#include <CGAL/Alpha_shape_vertex_base_3.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <map>

namespace armstudy {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Alpha_shape_vertex_base_3<K>;
using Fb = CGAL::Alpha_shape_cell_base_3<K>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Fb>;
using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds, CGAL::Fast_location>;
using AlphaShape = CGAL::Alpha_shape_3<Delaunay>;
}  // namespace

double gridAlphaRadius(const std::array<double, 3>& h) {
  return 1.05 * 0.5 * std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
}

BoundarySurface alphaShapeSurface(const std::vector<Eigen::Vector3d>& points, double alpha_radius) {
  BoundarySurface out;
  if (points.size() < 4) return out;
  std::vector<K::Point_3> pts;
  pts.reserve(points.size());
  for (const auto& p : points) pts.emplace_back(p.x(), p.y(), p.z());
  AlphaShape as(pts.begin(), pts.end(), alpha_radius * alpha_radius, AlphaShape::REGULARIZED);

  // Volume: the solid (interior) tetrahedra.
  for (auto c = as.finite_cells_begin(); c != as.finite_cells_end(); ++c) {
    if (as.classify(c) != AlphaShape::INTERIOR) continue;
    out.volume_m3 += std::abs(CGAL::to_double(CGAL::volume(c->vertex(0)->point(), c->vertex(1)->point(),
                                                          c->vertex(2)->point(), c->vertex(3)->point())));
    ++out.components;
  }
  // Boundary facets, oriented with the interior cell behind them.
  std::map<AlphaShape::Vertex_handle, int> index;
  auto vid = [&](AlphaShape::Vertex_handle v) {
    auto it = index.find(v);
    if (it != index.end()) return it->second;
    const int i = static_cast<int>(out.vertices.size());
    out.vertices.emplace_back(v->point().x(), v->point().y(), v->point().z());
    index.emplace(v, i);
    return i;
  };
  std::vector<AlphaShape::Facet> facets;
  as.get_alpha_shape_facets(std::back_inserter(facets), AlphaShape::REGULAR);
  for (auto f : facets) {
    if (as.classify(f.first) != AlphaShape::INTERIOR) f = as.mirror_facet(f);
    const int i = f.second;
    // Vertices of the facet opposite vertex i, ordered so the normal points away from the cell.
    int a = (i + 1) % 4, b = (i + 2) % 4, c = (i + 3) % 4;
    if (i % 2 == 0) std::swap(b, c);
    out.triangles.push_back({vid(f.first->vertex(a)), vid(f.first->vertex(b)), vid(f.first->vertex(c))});
  }
  return out;
}

}  // namespace armstudy
