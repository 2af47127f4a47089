#include <algorithm>

#include "stages/dexterity/dexterity_output.hpp"

namespace armstudy::dexterity {

namespace {

constexpr char kUnitMagic[] = "armstudy-dexterity-unit-v2";

}  // namespace

std::string serializeRows(const DexterityMap& map, const ItemRange& rows) {
  const int G = map.grid.gamma_rad.count;
  UnitWriter w(kUnitMagic);
  for (long v : {long(map.dof), long(G), long(map.grid.z_m.count), rows.begin, rows.end})
    w.put<std::int64_t>(v);
  for (long i = rows.begin * G; i < rows.end * G; ++i) putCell(w, map.cells[i]);
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
  for (CellResult& c : cells) getCell(r, c);
  if (!r.finished()) return false;
  std::move(cells.begin(), cells.end(), map.cells.begin() + b * G);
  rows = {b, e};
  return true;
}

}  // namespace armstudy::dexterity
