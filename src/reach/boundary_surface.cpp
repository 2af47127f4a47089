#include "reach/boundary_surface.hpp"

#include <CGAL/Alpha_shape_3.h>
#include <CGAL/Alpha_shape_cell_base_3.h>
#include <CGAL/Alpha_shape_vertex_base_3.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

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

  // CGAL iterates cells and facets in memory order, which differs from run to run; every output
  // below is put into a canonical order so result files are byte-identical across runs.
  // Volume: the solid (interior) tetrahedra, summed in sorted order.
  std::vector<double> cell_volumes;
  for (auto c = as.finite_cells_begin(); c != as.finite_cells_end(); ++c) {
    if (as.classify(c) != AlphaShape::INTERIOR) continue;
    cell_volumes.push_back(
        std::abs(CGAL::to_double(CGAL::volume(c->vertex(0)->point(), c->vertex(1)->point(),
                                              c->vertex(2)->point(), c->vertex(3)->point()))));
  }
  std::sort(cell_volumes.begin(), cell_volumes.end());
  for (double v : cell_volumes) out.volume_m3 += v;
  out.components = static_cast<int>(cell_volumes.size());
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
    // Vertices of the facet opposite vertex i, ordered so the normal points away from the interior
    // cell (away from its vertex i).
    int a = (i + 1) % 4, b = (i + 2) % 4, c = (i + 3) % 4;
    const K::Point_3 &pa = f.first->vertex(a)->point(), &pb = f.first->vertex(b)->point(),
                     &pc = f.first->vertex(c)->point(), &pi = f.first->vertex(i)->point();
    if (CGAL::orientation(pa, pb, pc, pi) == CGAL::POSITIVE) std::swap(b, c);
    out.triangles.push_back(
        {vid(f.first->vertex(a)), vid(f.first->vertex(b)), vid(f.first->vertex(c))});
  }
  // Canonical order: vertices lexicographically by coordinates, each triangle rotated to start at
  // its smallest index (orientation kept), triangles sorted.
  std::vector<int> order(out.vertices.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int i, int j) {
    const Eigen::Vector3d &a = out.vertices[i], &b = out.vertices[j];
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  std::vector<int> new_index(order.size());
  std::vector<Eigen::Vector3d> sorted(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    new_index[order[k]] = static_cast<int>(k);
    sorted[k] = out.vertices[order[k]];
  }
  out.vertices = std::move(sorted);
  for (auto& t : out.triangles) {
    for (auto& v : t) v = new_index[v];
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  }
  std::sort(out.triangles.begin(), out.triangles.end());
  return out;
}

}  // namespace armstudy
