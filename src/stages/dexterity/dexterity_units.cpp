#include <algorithm>

#include "stages/dexterity/dexterity_output.hpp"

namespace armstudy::dexterity {

namespace {

constexpr char kUnitMagic[] = "armstudy-dexterity-unit-v2";

void putMeasures(UnitWriter& w, const metrics::DexterityMeasures& m) {
  for (double v : {m.manipulability, m.transmission, m.condition, m.inverse_condition, m.sigma_min,
                   m.sigma_max})
    w.put(v);
}
void getMeasures(UnitReader& r, metrics::DexterityMeasures& m) {
  for (double* v : {&m.manipulability, &m.transmission, &m.condition, &m.inverse_condition,
                    &m.sigma_min, &m.sigma_max})
    *v = r.get<double>();
}

}  // namespace

std::string serializeRows(const DexterityMap& map, const ItemRange& rows) {
  const int G = map.grid.gamma_rad.count;
  UnitWriter w(kUnitMagic);
  for (long v : {long(map.dof), long(G), long(map.grid.z_m.count), rows.begin, rows.end})
    w.put<std::int64_t>(v);
  for (long i = rows.begin * G; i < rows.end * G; ++i) {
    const CellResult& c = map.cells[i];
    w.put<std::uint8_t>(c.reachable);
    w.put<std::uint8_t>(c.optimised);
    w.put<std::uint8_t>(static_cast<std::uint8_t>(c.status));
    w.put<std::int32_t>(c.colliding_pair);
    w.put(c.min_distance_m);
    w.putMatrix(c.q_plain);
    w.putMatrix(c.q_opt);
    putMeasures(w, c.plain);
    putMeasures(w, c.opt);
    for (const metrics::Ellipsoid* e : {&c.ellipsoid_plain, &c.ellipsoid_opt}) {
      w.putMatrix(e->axes_W);
      w.putMatrix(e->lengths);
    }
    for (double v : {c.H_plain, c.H_opt, c.position_error_m, c.orientation_error_rad}) w.put(v);
    w.put<std::int32_t>(c.starts);
    w.put<std::int32_t>(c.nullspace_iterations);
    w.put<std::int32_t>(static_cast<std::int32_t>(c.nullspace_status));
  }
  return w.bytes();
}

bool deserializeRows(const std::string& bytes, DexterityMap& map, ItemRange& rows) {
  const int G = map.grid.gamma_rad.count;
  UnitReader r(bytes, kUnitMagic);
  const auto dof = r.get<std::int64_t>(), g = r.get<std::int64_t>(), z = r.get<std::int64_t>();
  const auto b = r.get<std::int64_t>(), e = r.get<std::int64_t>();
  if (!r.ok() || dof != map.dof || g != G || z != map.grid.z_m.count ||
      !(0 <= b && b < e && e <= z) || map.cells.size() != static_cast<std::size_t>(g * z))
    return false;
  std::vector<CellResult> cells(static_cast<std::size_t>((e - b) * G));
  for (CellResult& c : cells) {
    c.reachable = r.get<std::uint8_t>() != 0;
    c.optimised = r.get<std::uint8_t>() != 0;
    const auto status = r.get<std::uint8_t>();
    if (status >= kReachStatusCount) r.fail();
    c.status = static_cast<ReachStatus>(status);
    c.colliding_pair = r.get<std::int32_t>();
    c.min_distance_m = r.get<double>();
    r.getMatrix(c.q_plain);
    r.getMatrix(c.q_opt);
    getMeasures(r, c.plain);
    getMeasures(r, c.opt);
    for (metrics::Ellipsoid* el : {&c.ellipsoid_plain, &c.ellipsoid_opt}) {
      r.getMatrix(el->axes_W);
      r.getMatrix(el->lengths);
    }
    for (double* v : {&c.H_plain, &c.H_opt, &c.position_error_m, &c.orientation_error_rad})
      *v = r.get<double>();
    c.starts = r.get<std::int32_t>();
    c.nullspace_iterations = r.get<std::int32_t>();
    const auto st = r.get<std::int32_t>();
    if (st < 0 || st > static_cast<int>(ik::NullspaceStatus::NotOnPose)) r.fail();
    c.nullspace_status = static_cast<ik::NullspaceStatus>(st);
  }
  if (!r.finished()) return false;
  std::move(cells.begin(), cells.end(), map.cells.begin() + b * G);
  rows = {b, e};
  return true;
}

}  // namespace armstudy::dexterity
