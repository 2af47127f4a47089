#pragma once
// Progressive reach maps (private to stages/reach): with RunOptions::preview_stride = k, before
// the grids are computed, each grid's status map of each design on every k-th value along each
// axis, its chained sweep alone (no map search, no audit), drawn to
// reach/preview/<grid>__<design>[_o<k>].svg and .png by the process that owns the design and
// announced through RunOptions::on_preview. Computed apart from the full maps, which do not depend
// on it.
#include <string>
#include <vector>

#include "stages/reach/reach_config.hpp"
#include "study/stage.hpp"

namespace armstudy {

// The grid on samples 0, k, 2k, ... of each axis (its orientations unchanged).
TaskGrid previewGrid(const TaskGrid& g, int k);

// Writes every grid's previews (also when the study's [reach] outputs leave out "images": the run
// asked for them); returns the files written, relative to the output folder.
std::vector<std::string> writeReachPreviews(const StageContext& ctx, const ReachConfig& cfg);

}  // namespace armstudy
