#pragma once
// One task grid of the reach stage (private to stages/reach): its results computed
// (reach_grid_results.hpp: every design's map, search and audit), rendered in pieces
// (reach_grid_pieces.hpp: fields (.vti), boundary surfaces (.vtp), figures, summary entries and
// report blocks), then joined with the grid's tables and the comparison of designs; appends the
// grid's report section to `doc`, fills `facts` (what the answer says of the grid) and returns its
// summary.json block.
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "reach/reach_sweep.hpp"
#include "report/document.hpp"
#include "stages/reach/reach_answer.hpp"
#include "stages/reach/reach_config.hpp"
#include "study/stage.hpp"
#include "study/writer.hpp"

namespace armstudy {

nlohmann::ordered_json reportGrid(const StageContext& ctx, const ReachConfig& cfg,
                                  const TaskGrid& g, Progress& progress, StageResult& sum,
                                  Writer& out, report::Document& doc,
                                  reach_report::CoverageFacts& facts);

}  // namespace armstudy
