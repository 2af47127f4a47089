#pragma once
// The harvest stage's work units (private to stages/harvest): one design's result assembled from
// units of fruits and holding-grid points, run through ctx.units (see harvest_stage.hpp).
#include "stages/harvest/harvest_stage.hpp"

namespace armstudy::harvest {

DesignResult unitDesign(const StageContext& ctx, const Model& model, const HarvestOptions& options,
                        const GreenhouseRow& row, long& units_resumed);

}  // namespace armstudy::harvest
