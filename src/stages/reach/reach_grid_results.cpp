#include "stages/reach/reach_grid_results.hpp"

#include <chrono>

#include "common/defaults.hpp"
#include "stages/reach/reach_counts.hpp"
#include "stages/reach/reach_units.hpp"
#include "study/interleave.hpp"

namespace armstudy {

using namespace reach_units;

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The grid's shape and designs, and the pairs compared; the maps, searches and audits still
// empty.
ReachGridResults gridLayout(const Study& study, const TaskGrid& grid) {
  ReachGridResults res;
  res.grid = &grid;
  res.dims = grid.dims();
  res.positions = grid.points();
  res.orientation_count = static_cast<int>(grid.orientations.size());
  res.folder = "reach/" + grid.name;
  for (const StudyDesign& sd : study.designs) res.models.push_back(&sd.model);
  res.pairs = comparedPairs(res.models.size());
  return res;
}

// Across units, once every unit is in, the map search: statuses that do not depend on the
// traversal. The designs' searches advance together, one step each per shared loop.
void searchMaps(const StageContext& ctx, const ReachConfig& cfg, ReachGridResults& res,
                StageResult& sum) {
  const std::size_t design_count = res.designCount();
  res.searches.assign(design_count, {});
  std::vector<InterleavedProgram> programs;
  for (std::size_t di = 0; di < design_count; ++di)
    programs.push_back([&, di](const UnitRunner* runner) {
      const Model& m = *res.models[di];
      res.searches[di] = searchGridSweep(m, res.taskGrid(), cfg.ik, ctx.threads,
                                         cfg.collisionFor(m), cfg.search, res.maps[di], runner);
    });
  const auto t0 = Clock::now();
  // The runner may search the designs in groups of its processes: a design's search then travels
  // as its summary and changed rows to the processes that did not run it. A search's predicted
  // cost: its reachable poses (the best-manipulability rounds visit them), a tenth as much for an
  // arm of six joints or fewer (defaults::kSearchWeightNonRedundant; assumption,
  // docs/distributed.md "Rank groups"), plus one (a design that reaches nothing still gets a group
  // of its own when there are enough groups).
  ProgramResults results;
  results.weight = [&res](std::size_t di) {
    return 1.0 + double(res.maps[di].countReachable()) *
                     (res.models[di]->dof() > 6 ? 1.0 : defaults::kSearchWeightNonRedundant);
  };
  results.pack = [&res](std::size_t di) {
    return packSearchResult(res.maps[di], res.searches[di]);
  };
  results.unpack = [&res](std::size_t di, const std::string& bytes) {
    unpackSearchResult(bytes, res.maps[di], res.searches[di]);
  };
  runInterleaved(&ctx.units, programs, &results);
  // One wall time for the grid's searches (they ran together; each search's own wall time would
  // include the waits for the others).
  sum.timings.push_back({res.folder + "/search", secondsSince(t0)});
  for (std::size_t di = 0; di < design_count; ++di)
    addUnitMetrics(sum.metrics, res.folder + "/" + res.models[di]->name, res.maps[di]);
}

// The audits (docs/reachability.md "The audit"), interleaved like the searches.
void auditMaps(const StageContext& ctx, const ReachConfig& cfg, ReachGridResults& res,
               StageResult& sum) {
  res.audits.assign(res.designCount(), {});
  if (cfg.audit_poses <= 0) return;
  std::vector<InterleavedProgram> programs;
  for (std::size_t di = 0; di < res.designCount(); ++di)
    programs.push_back([&, di](const UnitRunner* runner) {
      const Model& m = *res.models[di];
      res.audits[di] =
          auditGridSweep(m, res.taskGrid(), cfg.ik, cfg.collisionFor(m), res.maps[di],
                         cfg.audit_poses, cfg.audit_starts, cfg.audit_seed, ctx.threads, runner);
    });
  const auto t0 = Clock::now();
  runInterleaved(&ctx.units, programs);
  sum.timings.push_back({res.folder + "/audit", secondsSince(t0)});
}

}  // namespace

std::vector<DesignPair> comparedPairs(std::size_t design_count) {
  std::vector<DesignPair> pairs;
  for (std::size_t a = 0; a < design_count; ++a)
    for (std::size_t b = a + 1; b < design_count; ++b)
      if (!(design_count > kMaxComparedDesigns && a > 0)) pairs.emplace_back(a, b);
  return pairs;
}

ReachGridResults solveReachGrid(const StageContext& ctx, const ReachConfig& cfg,
                                const TaskGrid& grid, Progress& progress, StageResult& sum) {
  ReachGridResults res = gridLayout(ctx.study, grid);
  // Every design's units in one pool (one hand-out and exchange among the runner's processes).
  res.maps = solveGridDesigns(ctx, sum, res.folder, res.models, grid, cfg, progress);
  searchMaps(ctx, cfg, res, sum);
  auditMaps(ctx, cfg, res, sum);
  for (std::size_t di = 0; di < res.designCount(); ++di)
    reach_counts::addDescentCounts(res.folder + "/" + res.models[di]->name, res.maps[di],
                                   res.searches[di],
                                   cfg.audit_poses > 0 ? &res.audits[di] : nullptr, sum.counts);
  return res;
}

}  // namespace armstudy
