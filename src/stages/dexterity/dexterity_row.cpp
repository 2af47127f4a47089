#include <cmath>
#include <sstream>

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

// One row of the table and its summary.json entry.
std::string sweepRow(const DexterityMap& map, double spacing_m, nlohmann::ordered_json& js) {
  const StatusCounts c = statusCounts(map);
  const int near = c.count(Half::Near, ReachStatus::Reachable);
  const int far = c.count(Half::Far, ReachStatus::Reachable);
  const std::string lim_near = limitingEffect(map, c, Half::Near);
  const std::string lim_far = limitingEffect(map, c, Half::Far);
  js.push_back({{"spacing_m", spacing_m < 0 ? nlohmann::ordered_json(nullptr)
                                            : nlohmann::ordered_json(spacing_m)},
                {"near_reachable", near},
                {"near_cells", c.total(Half::Near)},
                {"far_reachable", far},
                {"far_cells", c.total(Half::Far)},
                {"near_limited_by", lim_near},
                {"far_limited_by", lim_far}});
  std::ostringstream md;
  md << "| " << spacingLabel(spacing_m) << " | " << near << " of " << c.total(Half::Near) << " ("
     << formatShare(near, c.total(Half::Near), 1) << ") | " << far << " of " << c.total(Half::Far)
     << " (" << formatShare(far, c.total(Half::Far), 1) << ") | " << lim_near << " | " << lim_far
     << " |\n";
  return md.str();
}

}  // namespace

std::string rowSweep(const Model& m, const DexterityOptions& options, const DexterityMap& main,
                     int threads, nlohmann::ordered_json& d) {
  const StatusCounts c = statusCounts(main);
  if (options.row_spacing_m < 0 && options.row_sweep.empty()) return "";
  if (c.total(Half::Far) == 0 && options.row_sweep.empty()) return "";
  nlohmann::ordered_json js = nlohmann::ordered_json::array();
  std::ostringstream md;
  md << "### The row around the stem (thesis section 3.2.1)\n\n"
     << "The thesis: \"only one half of the plant can be approached [...]. For the other half, "
        "the robot has to be turned around in the corridor.\" Approachable (reachable "
        "collision-free) cells of the near half (|gamma| < 90 deg, the robot's side of the row) "
        "and the far half (|gamma| > 90 deg), with the stem and its neighbours along the row as "
        "obstacles at each spacing, and the effect that blocks most of the other cells of each "
        "half:\n\n"
     << "| neighbouring stems | near half | far half | near half limited by | far half limited "
        "by |\n|---|---|---|---|---|\n"
     << sweepRow(main, options.row_spacing_m, js);
  DexterityOptions o = options;
  o.audit_cells = 0;
  o.row_sweep.clear();
  for (std::size_t k = 0; k < options.row_sweep.size(); ++k) {
    o.collision = options.row_sweep[k];
    const DexterityMap map = computeDexterityMap(m, o, threads);
    md << sweepRow(map, options.row_sweep_spacing_m[k], js);
  }
  md << "\nThe first line is this map (spacing " << spacingLabel(options.row_spacing_m)
     << "); the others are the same grid and search with the spacing of the row sweep.\n\n";
  d["row_sweep"] = js;
  return md.str();
}

}  // namespace armstudy::dexterity
