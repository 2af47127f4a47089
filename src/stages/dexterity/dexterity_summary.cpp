#include "stages/dexterity/dexterity_summary.hpp"

#include <limits>

#include "common/format.hpp"
#include "stages/dexterity/dexterity_status.hpp"

namespace armstudy::dexterity {

namespace {

// The valley of the optimised map (MapSummary::valley_row).
void findValley(const DexterityMap& map, const MapFields& f, MapSummary& s) {
  const int G = map.grid.gamma_rad.count;
  for (int iz = 0; iz < map.grid.z_m.count; ++iz) {
    double sum_n = 0, sum_a = 0;
    int n = 0;
    for (int ig = 0; ig < G; ++ig) {
      const int i = map.grid.index(ig, iz);
      if (!map.cells[i].reachable) continue;
      sum_n += f.manipulability().opt_norm[i];
      sum_a += f.manipulability().opt[i];
      ++n;
    }
    if (n == 0 || (s.valley_row >= 0 && !(sum_n / n < s.valley_norm))) continue;
    s.valley_row = iz;
    s.valley_norm = sum_n / n;
    s.valley_abs = sum_a / n;
  }
}

}  // namespace

double valleyHeight(const StemGrid& grid, const MapSummary& s) {
  const int n = grid.z_m.count;
  if (s.valley_row < 0 || n < 3 || s.valley_row == 0 || s.valley_row == n - 1)
    return std::numeric_limits<double>::quiet_NaN();
  return grid.z_m.value(s.valley_row);
}

std::string valleyText(const DexterityMap& map, const MapSummary& s, const std::string& unit) {
  if (s.valley_row < 0 || map.grid.z_m.count < 3) return "-";  // a valley needs rows around it
  const bool edge = s.valley_row == 0 || s.valley_row == map.grid.z_m.count - 1;
  return "z " + formatFixedOr(map.grid.z_m.value(s.valley_row), 2, "-") + " m (row mean " +
         formatFixedOr(s.valley_norm, 3, "-") + ", " + formatFixedOr(s.valley_abs, 3, "-") + " " +
         unit + ")" + (edge ? " at the edge of the grid: no valley inside it" : "");
}

MapSummary summarise(const DexterityMap& map, const MapFields& f, const StemGrid& g) {
  MapSummary s;
  const int G = g.gamma_rad.count;
  s.beta_s = fieldStats(map, f.transmission().opt);
  s.mo = fieldStats(map, f.manipulability().opt_norm),
  s.mp = fieldStats(map, f.manipulability().plain_norm);
  s.bp = fieldStats(map, f.transmission().plain);
  for (int i = 0; i < static_cast<int>(map.cells.size()); ++i) {
    const bool neg = g.gamma_rad.value(i % G) < 0;
    (neg ? s.n_neg : s.n_pos)++;
    if (map.cells[i].reachable) {
      (neg ? s.reach_neg : s.reach_pos)++;
      s.mean_p += f.manipulability().plain_norm[i];
      s.mean_o += f.manipulability().opt_norm[i];
      s.iters += map.cells[i].nullspace_iterations;
    }
  }
  s.R = map.reachable();
  if (s.R > 0) s.mean_p /= s.R, s.mean_o /= s.R;
  findValley(map, f, s);
  return s;
}

}  // namespace armstudy::dexterity
