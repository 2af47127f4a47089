#include <cmath>
#include <string>
#include <vector>

#include "common/format.hpp"
#include "stages/dexterity/dexterity_status.hpp"

// The row around the stem (docs/dexterity.md, "The row around the stem"): the approachable share
// of the near and far half of the circle with the neighbouring stems at each spacing of the row
// sweep, what limits each half, compared with the thesis' "only one half of the plant can be
// approached; for the other half the robot has to be turned around in the corridor" (section
// 3.2.1).
namespace armstudy::dexterity {

namespace {

std::string spacingLabel(double spacing_m) {
  if (spacing_m < 0) return "no stems";
  if (spacing_m == 0) return "own stem only";
  return formatFixed(spacing_m, 3) + " m";
}

// The approachable cells of each half of `map` (with neighbouring stems `spacing_m` apart) and
// what limits each.
RowHalves rowHalves(const DexterityMap& map, double spacing_m) {
  const StatusCounts c = statusCounts(map);
  return {spacing_m,
          c.count(Half::Near, ReachStatus::Reachable),
          c.total(Half::Near),
          c.count(Half::Far, ReachStatus::Reachable),
          c.total(Half::Far),
          limitingEffect(map, c, Half::Near),
          limitingEffect(map, c, Half::Far)};
}

// One row of the table and its summary.json entry.
std::vector<std::string> sweepRow(const RowHalves& h, nlohmann::ordered_json& js) {
  js.push_back({{"spacing_m", h.spacing_m < 0 ? nlohmann::ordered_json(nullptr)
                                              : nlohmann::ordered_json(h.spacing_m)},
                {"near_reachable", h.near_reachable},
                {"near_cells", h.near_cells},
                {"far_reachable", h.far_reachable},
                {"far_cells", h.far_cells},
                {"near_limited_by", h.near_limited_by},
                {"far_limited_by", h.far_limited_by}});
  const auto share = [](long a, long n) {
    return std::to_string(a) + " of " + std::to_string(n) + " (" + formatShare(a, n, 1) + ")";
  };
  return {spacingLabel(h.spacing_m), share(h.near_reachable, h.near_cells),
          share(h.far_reachable, h.far_cells), h.near_limited_by, h.far_limited_by};
}

}  // namespace

report::Document rowSweep(const Model& m, const DexterityOptions& options, const DexterityMap& main,
                          int threads, nlohmann::ordered_json& d, std::vector<RowHalves>& halves) {
  const StatusCounts c = statusCounts(main);
  if (options.row_spacing_m < 0 && options.row_sweep.empty()) return {};
  if (c.total(Half::Far) == 0 && options.row_sweep.empty()) return {};
  nlohmann::ordered_json js = nlohmann::ordered_json::array();
  halves = {rowHalves(main, options.row_spacing_m)};
  DexterityOptions o = options;
  o.audit_cells = 0;
  o.row_sweep.clear();
  for (std::size_t k = 0; k < options.row_sweep.size(); ++k) {
    o.collision = options.row_sweep[k];
    const DexterityMap map = computeDexterityMap(m, o, threads);
    halves.push_back(rowHalves(map, options.row_sweep_spacing_m[k]));
  }
  std::vector<std::vector<std::string>> rows;
  for (const RowHalves& h : halves) rows.push_back(sweepRow(h, js));
  d["row_sweep"] = js;
  return report::Document()
      .heading(3, "The row around the stem (thesis section 3.2.1)")
      .paragraph(
          "The thesis: \"only one half of the plant can be approached [...]. For the other half, "
          "the robot has to be turned around in the corridor.\" Approachable (reachable "
          "collision-free) cells of the near half (|gamma| < 90 deg, the robot's side of the row) "
          "and the far half (|gamma| > 90 deg), with the stem and its neighbours along the row as "
          "obstacles at each spacing, and the effect that blocks most of the other cells of each "
          "half:")
      .table({"neighbouring stems", "near half", "far half", "near half limited by",
              "far half limited by"},
             rows, report::TableRule::compact)
      .paragraph("The first line is this map (spacing " + spacingLabel(options.row_spacing_m) +
                 "); the others are the same grid and search with the spacing of the row sweep.");
}

}  // namespace armstudy::dexterity
