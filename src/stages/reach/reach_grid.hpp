#pragma once
// One task grid of the reach stage (private to stages/reach): every design's sweep of the grid
// (work units, then the search across units), its fields (.vti), boundary surfaces (.vtp), maps,
// audit, comparison of designs; appends the grid's report section to `md` and returns its
// summary.json block.
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "reach/reach_sweep.hpp"
#include "stages/reach/reach_config.hpp"
#include "study/stage.hpp"
#include "study/writer.hpp"

namespace armstudy {

nlohmann::ordered_json reportGrid(const StageContext& ctx, const ReachConfig& cfg,
                                  const TaskGrid& g, Progress& progress, StageResult& sum,
                                  Writer& out, std::string& md);

}  // namespace armstudy
