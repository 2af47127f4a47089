#pragma once
// The reach stage's work units (private to stages/reach): one design x a range of a grid's lines
// or a pose list's chunks, as bytes for the unit runner, and the sweep assembled from them.
#include <string>
#include <vector>

#include "reach/reach_sweep.hpp"
#include "stages/reach/reach_config.hpp"
#include "study/stage.hpp"

namespace armstudy::reach_units {

// A chunk's result as bytes (its place in the sweep, every per-pose column and the chains' solve
// counts, no timings), and back: false when the bytes are not such a unit.
std::string serializeSweep(const PoseSweep& s);
bool deserializeSweep(const std::string& bytes, const std::string& design, PoseSweep& s);

// Every design's sweep of a grid through ctx.units as one pool of units (runUnitBatches: one
// hand-out pool and one exchange in a distributed run instead of one per design); unit ids
// <prefix>/<design>/units_<b>-<e>, results in `models` order. Per-unit timings go to sum.timings,
// resumed units to sum.units_resumed.
std::vector<PoseSweep> solveGridDesigns(const StageContext& ctx, StageResult& sum,
                                        const std::string& prefix,
                                        const std::vector<const Model*>& models, const TaskGrid& g,
                                        const ReachConfig& cfg, Progress& progress);
// A design's sweep of a pose list through ctx.units (unit ids <prefix>/units_<b>-<e>).
PoseSweep solvePoseList(const StageContext& ctx, StageResult& sum, const std::string& prefix,
                        const Model& model, const PoseList& l, const ReachConfig& cfg,
                        Progress& progress);

// Summary metrics of one design's sweep for baselines and checks (<prefix>/reachable_fraction,
// ...).
void addUnitMetrics(StudyMetrics& m, const std::string& prefix, const PoseSweep& s);

}  // namespace armstudy::reach_units
