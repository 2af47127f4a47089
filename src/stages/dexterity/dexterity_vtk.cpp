#include <cmath>
#include <filesystem>

#include "io/vtk_io.hpp"
#include "metrics/measure_declarations.hpp"
#include "stages/dexterity/dexterity_output.hpp"
#include "study/scene.hpp"

// The dexterity stage's VTK files (docs/dexterity.md, docs/paraview.md): the map over (gamma, z)
// as .vti, the same map on its cylinder around the stem in world metres as .vts, the robot at the
// map's best pose and the ellipsoid glyphs as .vtp.
namespace armstudy::dexterity {

namespace {

// The map's point arrays (the same in the .vti and the .vts): NaN where a quantity does not exist.
// Per declared measure on the maps <name>_{plain,optimised}[_normalised], in the declared order.
std::vector<io::NamedArray> mapArrays(const DexterityMap& map, const MapFields& f) {
  std::vector<io::NamedArray> arrays{{"reachable", io::ArrayType::UInt8, 1, f.reachable}};
  std::vector<std::pair<std::string, const std::vector<double>*>> fields;
  const auto decl = metrics::measureDeclarations();
  for (std::size_t k = 0; k < decl.size(); ++k) {
    if (!decl[k].on_maps) continue;
    const std::string name = decl[k].name;
    const MeasureFields& m = f.measures[k];
    fields.insert(fields.end(), {{name + "_plain", &m.plain}, {name + "_optimised", &m.opt}});
    if (decl[k].normalised)
      fields.insert(fields.end(), {{name + "_plain_normalised", &m.plain_norm},
                                   {name + "_optimised_normalised", &m.opt_norm}});
  }
  fields.insert(fields.end(), {{"objective_plain", &f.H_plain},
                               {"objective_optimised", &f.H_opt},
                               {"nullspace_iterations", &f.nullspace_iterations}});
  for (const auto& [name, v] : fields) arrays.push_back({name, io::ArrayType::Float64, 1, *v});
  std::vector<double> found_by(map.cells.size());
  for (std::size_t i = 0; i < map.cells.size(); ++i)
    found_by[i] = static_cast<double>(map.cells[i].found_by);
  // 0 chained row, 1 seeded multi-start, 2 neighbour
  arrays.push_back({"found_by", io::ArrayType::UInt8, 1, found_by});
  std::vector<double> status(map.cells.size()), pair(map.cells.size()), dist(map.cells.size());
  for (std::size_t i = 0; i < map.cells.size(); ++i) {
    status[i] = static_cast<double>(map.cells[i].status);
    pair[i] = map.cells[i].colliding_pair;
    dist[i] = map.cells[i].min_distance_m;
  }
  arrays.push_back({"status", io::ArrayType::UInt8, 1, status});  // ReachStatus values
  if (map.collision) {
    arrays.push_back({"colliding_pair", io::ArrayType::Float64, 1, pair});
    arrays.push_back({"min_distance", io::ArrayType::Float64, 1, dist});
  }
  return arrays;
}

// Units of the arrays of the map and the glyphs in a measure space (the declared measures' units,
// metrics/measure_declarations.hpp, then the map's other arrays).
std::vector<std::string> measureUnits(metrics::MeasureSpace space) {
  std::vector<std::string> units;
  for (const metrics::MeasureDeclaration& d : metrics::measureDeclarations()) {
    if (!d.on_maps) continue;
    const std::string name = d.name, unit = metrics::unitIn(d, space);
    units.insert(units.end(), {name + "_plain: " + unit, name + "_optimised: " + unit});
    if (d.on_glyphs) units.push_back(name + ": " + unit);
    if (d.normalised)
      units.insert(units.end(), {name + "_plain_normalised: 1", name + "_optimised_normalised: 1"});
  }
  units.insert(units.end(), {"objective_plain: 1", "objective_optimised: 1",
                             "nullspace_iterations: 1", "reachable: 1", "found_by: 1", "status: 1",
                             "colliding_pair: 1", "min_distance: m"});
  return units;
}

const std::vector<std::string> kMapLegend = {
    "reachable 0: no solution at this cell (every other quantity NaN)",
    "reachable 1: reachable",
    "found_by 0: chained row",
    "found_by 1: seeded multi-start",
    "found_by 2: neighbour propagation",
    "status 0: reachable (collision-free where collisions are checked)",
    "status 1: out_of_reach",
    "status 2: joint_limits",
    "status 4: self_collision (reached only in self-collision)",
    "status 6: obstacle_collision (reached only in contact with an obstacle)",
    "colliding_pair: index of the pairs listed below (-1: not in collision)",
    "min_distance: smallest checked distance at the optimised posture (negative: penetration)"};

// The legend with the map's checked pairs ("colliding_pair 3: j2-obstacle:stem").
std::vector<std::string> mapLegend(const DexterityMap& map) {
  std::vector<std::string> l = kMapLegend;
  for (std::size_t k = 0; k < map.pair_names.size(); ++k)
    l.push_back("colliding_pair " + std::to_string(k) + ": " + map.pair_names[k]);
  return l;
}

std::string writeMapVti(const DexterityMap& map, const MapFields& f, const std::string& dir,
                        const std::vector<std::string>& units) {
  const StemGrid& g = map.grid;
  io::ImageGrid grid;
  // Axes: x = gamma [rad], y = z [m]; point index = i_gamma + i_z * n_gamma (VTK order).
  grid.dims = {g.gamma_rad.count, g.z_m.count, 1};
  grid.origin = {g.gamma_rad.min, g.z_m.min, 0.0};
  grid.spacing = {g.gamma_rad.count > 1 ? g.gamma_rad.step() : 1.0,
                  g.z_m.count > 1 ? g.z_m.step() : 1.0, 1.0};
  grid.point_arrays = mapArrays(map, f);
  grid.field_data =
      io::fieldData(units, mapLegend(map),
                    "parameter plane: x = gamma [rad], y = z [m] (world metres: " + map.design +
                        "_cylinder.vts)");
  const std::string name = map.design + ".vti";
  io::writeVti((std::filesystem::path(dir) / name).string(), grid);
  return name;
}

// The same map on its cylinder around the stem: point (i_gamma, i_z) at the TCP position of
// that cell, p_WT = (x_s, y_s, z) - r u(gamma) (dexterity/stem_grid.hpp).
std::string writeMapVts(const DexterityMap& map, const MapFields& f, const std::string& dir,
                        std::vector<std::string> units) {
  const StemGrid& g = map.grid;
  io::StructuredGridSet grid;
  grid.dims = {g.gamma_rad.count, g.z_m.count, 1};
  io::NamedArray gamma{"gamma", io::ArrayType::Float64, 1, {}},
      z{"z", io::ArrayType::Float64, 1, {}};
  for (int j = 0; j < g.z_m.count; ++j)
    for (int i = 0; i < g.gamma_rad.count; ++i) {
      const StemGrid::Cell c = g.cell(i, j);
      grid.points.push_back(c.target.p_WT);
      gamma.values.push_back(c.gamma);
      z.values.push_back(c.z);
    }
  grid.point_arrays = mapArrays(map, f);
  grid.point_arrays.push_back(std::move(gamma));
  grid.point_arrays.push_back(std::move(z));
  units.insert(units.begin(), {"position: m", "gamma: rad", "z: m"});
  grid.field_data = io::fieldData(units, mapLegend(map));
  const std::string name = map.design + "_cylinder.vts";
  io::writeVts((std::filesystem::path(dir) / name).string(), grid);
  return name;
}

std::string writeEllipsoidsVtp(const DexterityMap& map, bool optimised, const std::string& dir,
                               const std::vector<std::string>& units) {
  io::PolyDataSet poly;
  poly.vertices = true;
  // U diag(sigma) U^T: ParaView's Tensor Glyph draws semi-axes sigma_k along u_k.
  io::NamedArray tensor{"ellipsoid_tensor", io::ArrayType::Float64, 9, {}};
  io::NamedArray semi{"semi_axes", io::ArrayType::Float64, 3, {}};
  constexpr io::ArrayType kF64 = io::ArrayType::Float64;
  io::NamedArray a1{"axis_1", kF64, 3, {}}, a2{"axis_2", kF64, 3, {}}, a3{"axis_3", kF64, 3, {}};
  io::NamedArray u{"u", kF64, 3, {}}, gam{"gamma", kF64, 1, {}}, zz{"z", kF64, 1, {}};
  // The declared measures on the glyphs, as <name>.
  std::vector<io::NamedArray> glyph;
  std::vector<const metrics::MeasureDeclaration*> glyph_decl;
  for (const metrics::MeasureDeclaration& d : metrics::measureDeclarations())
    if (d.on_glyphs) {
      glyph.push_back({d.name, kF64, 1, {}});
      glyph_decl.push_back(&d);
    }
  auto push3 = [](io::NamedArray& a, const Eigen::Vector3d& v) {
    a.values.insert(a.values.end(), {v.x(), v.y(), v.z()});
  };
  const int G = map.grid.gamma_rad.count;
  for (std::size_t i = 0; i < map.cells.size(); ++i) {
    const CellResult& c = map.cells[i];
    if (!c.reachable) continue;
    const StemGrid::Cell cell = map.grid.cell(static_cast<int>(i) % G, static_cast<int>(i) / G);
    const metrics::Ellipsoid& e = optimised ? c.ellipsoid_opt : c.ellipsoid_plain;
    poly.points.push_back(cell.target.p_WT);
    const Eigen::Matrix3d T = e.axes_W * e.lengths.asDiagonal() * e.axes_W.transpose();
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) tensor.values.push_back(T(r, k));
    push3(semi, e.lengths);
    push3(a1, e.lengths[0] * e.axes_W.col(0));
    push3(a2, e.lengths[1] * e.axes_W.col(1));
    push3(a3, e.lengths[2] * e.axes_W.col(2));
    push3(u, cell.u_W);
    for (std::size_t k = 0; k < glyph.size(); ++k)
      glyph[k].values.push_back((optimised ? c.opt : c.plain).*glyph_decl[k]->value);
    gam.values.push_back(cell.gamma);
    zz.values.push_back(cell.z);
  }
  for (io::NamedArray* a : {&tensor, &semi, &a1, &a2, &a3, &u})
    poly.point_arrays.push_back(std::move(*a));
  for (io::NamedArray& a : glyph) poly.point_arrays.push_back(std::move(a));
  for (io::NamedArray* a : {&gam, &zz}) poly.point_arrays.push_back(std::move(*a));
  poly.active_tensors = "ellipsoid_tensor";
  std::vector<std::string> u_all{"position: m",
                                 "ellipsoid_tensor: m/rad",
                                 "semi_axes: m/rad",
                                 "axis_1: m/rad",
                                 "axis_2: m/rad",
                                 "axis_3: m/rad",
                                 "u: 1",
                                 "gamma: rad",
                                 "z: m"};
  u_all.insert(u_all.end(), units.begin(), units.end());
  poly.field_data = io::fieldData(u_all);
  const std::string name =
      map.design + (optimised ? "_ellipsoids_optimised.vtp" : "_ellipsoids_plain.vtp");
  io::writeVtp((std::filesystem::path(dir) / name).string(), poly);
  return name;
}

}  // namespace

std::vector<std::string> writeMapVtk(const DexterityMap& map, const MapFields& f,
                                     const Model& model, metrics::MeasureSpace space,
                                     bool ellipsoids, const std::string& dir) {
  const std::vector<std::string> units = measureUnits(space);
  std::vector<std::string> files{writeMapVti(map, f, dir, units), writeMapVts(map, f, dir, units)};
  if (ellipsoids) {
    files.push_back(writeEllipsoidsVtp(map, false, dir, units));
    files.push_back(writeEllipsoidsVtp(map, true, dir, units));
  }
  // The robot at the cell of the best optimised manipulability.
  int best = -1;
  for (std::size_t i = 0; i < map.cells.size(); ++i)
    if (map.cells[i].reachable &&
        (best < 0 || f.manipulability().opt[i] > f.manipulability().opt[best]))
      best = static_cast<int>(i);
  if (best >= 0) {
    const CellResult& c = map.cells[best];
    const StemGrid::Cell cell =
        map.grid.cell(best % map.grid.gamma_rad.count, best / map.grid.gamma_rad.count);
    io::PolyDataSet robot = scene::robotPolyData(model, c.optimised ? c.q_opt : c.q_plain);
    robot.field_data.push_back(
        {"pose",
         {"best optimised manipulability of the map, gamma = " + std::to_string(cell.gamma) +
          " rad, z = " + std::to_string(cell.z) + " m"}});
    const std::string name = map.design + "_robot_best.vtp";
    io::writeVtp((std::filesystem::path(dir) / name).string(), robot);
    files.push_back(name);
  }
  return files;
}

}  // namespace armstudy::dexterity
