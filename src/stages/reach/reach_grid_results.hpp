#pragma once
// A task grid's computed results (private to stages/reach): every design's map of the grid after
// the search across work units, the searches' counts, the audits and the pairs of designs
// compared. solveReachGrid makes them once; they are const afterwards, and the grid's files, report
// lines and summary entries are rendered from them (reach_grid_pieces.hpp, reach_grid.hpp).
#include <array>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "reach/reach_audit.hpp"
#include "reach/reach_sweep.hpp"
#include "stages/reach/reach_config.hpp"
#include "study/stage.hpp"

namespace armstudy {

// Two designs compared on a grid (indices into the study's designs, first < second).
using DesignPair = std::pair<std::size_t, std::size_t>;

struct ReachGridResults {
  const TaskGrid* grid = nullptr;
  std::array<int, 3> dims{};         // grid positions along x, y, z
  long positions = 0;                // grid positions per orientation
  int orientation_count = 0;         // a pose's index is orientation * positions + position
  std::string folder;                // the grid's output folder, "reach/<grid>"
  std::vector<const Model*> models;  // the designs, study order
  // Per design, study order: its map (status, solution and manipulability per pose), the map
  // search's counts and the audit (empty when the study asks for none).
  std::vector<PoseSweep> maps;
  std::vector<SweepSearchSummary> searches;
  std::vector<ReachAudit> audits;
  // The pairs of designs compared on the grid: every pair up to kMaxComparedDesigns designs,
  // beyond, the first design against each other.
  std::vector<DesignPair> pairs;
  std::size_t designCount() const { return maps.size(); }
  const TaskGrid& taskGrid() const { return *grid; }
};

// Designs compared pairwise (tables, dexterity) up to this many; beyond, the first against each
// other.
constexpr std::size_t kMaxComparedDesigns = 12;

// The pairs of `design_count` designs compared on a grid, ordered by first then second design.
std::vector<DesignPair> comparedPairs(std::size_t design_count);

// Every design's sweep of `grid` (work units through ctx.units, one pool for all designs), then
// the map search across units and the audit (docs/reachability.md "The audit"), each interleaved
// over the designs (study/interleave.hpp). Timings and unit metrics go to `sum`.
ReachGridResults solveReachGrid(const StageContext& ctx, const ReachConfig& cfg,
                                const TaskGrid& grid, Progress& progress, StageResult& sum);

}  // namespace armstudy
