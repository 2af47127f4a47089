#pragma once
// The reachability stage of a study run (docs/reachability.md): sweeps every design (and
// variant) over every task grid and pose list of the study's [reach] section, then writes
//   reach/<grid>/<design>.vti, reach/<grid>/comparison.vti, reach/<grid>/<design>_surface_o<k>.vtp,
//   reach/<list>/<design>.vtp, reach/images/*.png, summary.json and report.md
// into the study's output folder.
//
// Work units: one design x a chunk of a grid's lines or a pose list's chunks (about
// ctx.options.unit_items poses, default defaults::kReachUnitPoses, rounded to whole sweep units),
// ids reach/<grid>/<design>/units_<b>-<e>. Metrics: reach/<grid>/<design>/... (regression
// checks). Results do not depend on the unit size, the thread count or the traversal order.
#include "stages/reach/reach_config.hpp"
#include "study/stage.hpp"

namespace armstudy {

StageResult runReachStage(const StageContext& ctx, const ReachConfig& cfg);

}  // namespace armstudy
