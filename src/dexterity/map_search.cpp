#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/errors.hpp"
#include "dexterity/dexterity_map.hpp"

// The map search after the chained rows (dexterity_map.hpp, searchDexterityMap; docs/dexterity.md
// "How a map value is found").
namespace armstudy::dexterity {

namespace {

// Rank of a cell's verdict: reachable collision-free 2, on the pose only in collision 1, else 0.
int rank(const CellResult& c) {
  if (c.reachable) return 2;
  return c.status == ReachStatus::SelfCollision || c.status == ReachStatus::ObstacleCollision;
}

// True when `cand` should replace `cur`: a better verdict (collision-free before in collision
// before no posture), or both collision-free and a lower objective by more than the relative
// threshold (so rounding noise cannot keep the propagation going).
bool better(const CellResult& cand, const CellResult& cur) {
  const int rc = rank(cand), ru = rank(cur);
  if (rc != ru) return rc > ru;
  if (rc < 2) return false;
  return cand.H_opt <
         cur.H_opt - defaults::kMapImprovementRelative * std::max(std::abs(cur.H_opt), 1e-12);
}

// Replaces the optimised part of `cur` by the candidate's (the plain part stays the chained
// solution when `cur` was reachable: "plain" is the pose solution before any optimisation).
void adopt(CellResult& cur, const CellResult& cand, CellResult::Source source) {
  if (!cur.reachable || !cand.reachable) {
    cur = cand;
  } else {
    cur.optimised = cand.optimised;
    cur.q_opt = cand.q_opt;
    cur.opt = cand.opt;
    cur.ellipsoid_opt = cand.ellipsoid_opt;
    cur.H_opt = cand.H_opt;
    cur.nullspace_iterations = cand.nullspace_iterations;
    cur.nullspace_status = cand.nullspace_status;
    cur.min_distance_m = cand.min_distance_m;
  }
  cur.found_by = source;
}

// The up to eight neighbours of a cell (gamma wraps around on a full circle), in a fixed order.
int neighbours(const StemGrid& g, int idx, int out[8]) {
  const int G = g.gamma_rad.count, Z = g.z_m.count;
  const bool wrap = G > 2 && std::abs(g.gamma_rad.step() * G - 2 * M_PI) < 1e-9;
  const int ig = idx % G, iz = idx / G;
  int n = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dg = -1; dg <= 1; ++dg) {
      if (dz == 0 && dg == 0) continue;
      int jg = ig + dg;
      const int jz = iz + dz;
      if (jz < 0 || jz >= Z) continue;
      if (wrap) jg = (jg + G) % G;
      if (jg < 0 || jg >= G) continue;
      out[n++] = g.index(jg, jz);
    }
  return n;
}

// What the search steps share: the model, the options, the objective and the per-thread set-up.
struct SearchContext {
  const Model& model;
  const DexterityOptions& options;
  ik::WeightedObjective objective;
  int threads;
  bool check;  // collisions checked
};

// One thread's workspaces for the search's solves (built once per parallel region).
struct ThreadSolver {
  explicit ThreadSolver(const SearchContext& sc)
      : sc(sc), ws(sc.model), ctx(sc.model, ws), cws(sc.model) {}
  // The cell's optimum descended from q0 (dexterity::cellFromSeed).
  bool fromSeed(const StemGrid::Cell& cell, const JointVector& q0, CellResult& out) {
    return cellFromSeed(sc.model, ws, ctx, sc.objective, sc.options, cell, q0, out,
                        sc.check ? &cws : nullptr);
  }
  const SearchContext& sc;
  KinematicsWorkspace ws;
  ik::ObjectiveContext ctx;
  collision::CollisionWorkspace cws;
};

// `starts` random configurations for each cell of `list` (start numbers first .. first + starts - 1
// of the cell's counter-based stream: each cell depends only on its own index); a better
// candidate replaces the cell and marks it in `changed`. Returns the cells improved.
int multiStarts(const SearchContext& sc, std::vector<CellResult>& cells,
                const std::vector<int>& list, int first, int starts,
                std::vector<std::uint8_t>& changed, long& tries) {
  const StemGrid& g = sc.options.grid;
  const int G = g.gamma_rad.count;
  long n_tries = 0;
  int improved = 0;
#pragma omp parallel num_threads(sc.threads) reduction(+ : n_tries, improved)
  {
    ThreadSolver solver(sc);
    JointVector q0(sc.model.dof());
#pragma omp for schedule(dynamic, 1)
    for (int k = 0; k < static_cast<int>(list.size()); ++k) {
      const int idx = list[k];
      const StemGrid::Cell cell = g.cell(idx % G, idx / G);
      CellResult& cur = cells[idx];
      for (int s = first; s < first + starts; ++s) {
        randomConfiguration(sc.model, sc.options.search_seed, static_cast<std::uint64_t>(idx), s,
                            q0);
        CellResult cand;
        ++n_tries;
        if (!solver.fromSeed(cell, q0, cand) || !better(cand, cur)) continue;
        if (cur.found_by != CellResult::Source::MultiStart) ++improved;
        adopt(cur, cand, CellResult::Source::MultiStart);
        changed[idx] = 1;
      }
    }
  }
  tries += n_tries;
  return improved;
}

// Neighbour propagation, Jacobi rounds, until no cell changes or the round cap (counted over the
// whole search). With `all_first`, the first round tries every better neighbour (the chain's
// branch choices are not marked); later rounds only neighbours that changed in the round before.
void propagate(const SearchContext& sc, std::vector<CellResult>& cells,
               std::vector<std::uint8_t>& changed, bool all_first, MapSearchSummary& sum) {
  const StemGrid& g = sc.options.grid;
  const int N = g.size(), G = g.gamma_rad.count;
  bool first = all_first;
  sum.converged = false;
  while (sum.rounds < sc.options.propagation_rounds) {
    std::vector<CellResult> next = cells;
    std::vector<std::uint8_t> now(N, 0);
    long round_tries = 0;
    int round_improved = 0;
#pragma omp parallel num_threads(sc.threads) reduction(+ : round_tries, round_improved)
    {
      ThreadSolver solver(sc);
      int nb[8];
#pragma omp for schedule(dynamic, 16)
      for (int idx = 0; idx < N; ++idx) {
        const CellResult& cur = cells[idx];
        const int count = neighbours(g, idx, nb);
        CellResult best = cur;
        bool any = false;
        for (int k = 0; k < count; ++k) {
          const CellResult& src = cells[nb[k]];
          if (!src.reachable || !(first || changed[nb[k]])) continue;
          if (cur.reachable && !(src.H_opt < cur.H_opt)) continue;
          // A neighbour whose optimum is this cell's posture (every joint within kMapSameBasin)
          // would descend to this cell's optimum again.
          if (cur.reachable &&
              (src.q_opt - cur.q_opt).cwiseAbs().maxCoeff() < defaults::kMapSameBasin)
            continue;
          CellResult cand;
          ++round_tries;
          if (!solver.fromSeed(g.cell(idx % G, idx / G), src.q_opt, cand) || !better(cand, best))
            continue;
          adopt(best, cand, CellResult::Source::Neighbour);
          any = true;
        }
        if (any) {
          next[idx] = std::move(best);
          now[idx] = 1;
          ++round_improved;
        }
      }
    }
    ++sum.rounds;
    sum.neighbour_tries += round_tries;
    sum.neighbour_improved += round_improved;
    cells.swap(next);
    changed.swap(now);
    first = false;
    if (round_improved == 0) {
      sum.converged = true;
      return;
    }
  }
}

bool inCollision(const CellResult& c) {
  return c.status == ReachStatus::SelfCollision || c.status == ReachStatus::ObstacleCollision;
}

}  // namespace

void searchDexterityMap(const Model& model, const DexterityOptions& options, DexterityMap& map,
                        int threads) {
  const auto t0 = std::chrono::steady_clock::now();
  const StemGrid& g = options.grid;
  const int N = g.size(), G = g.gamma_rad.count;
  ARMSTUDY_CHECK(static_cast<int>(map.cells.size()) == N, "dexterity map does not match its grid");
  const SearchContext sc{model, options, options.buildObjective(model),
                         threads > 0 ? threads : omp_get_max_threads(),
                         options.collisionFor(model).enabled()};
  MapSearchSummary& sum = map.search;
  sum = MapSearchSummary{};
  // Cells that changed in the last step: the sources of the next propagation round.
  std::vector<std::uint8_t> changed(N, 0);

  // (1) Seeded multi-starts on the sub-grid.
  std::vector<int> seeding;
  if (options.seed_starts > 0) {
    const int st = std::max(1, options.seed_stride);
    for (int iz = 0; iz < g.z_m.count; iz += st)
      for (int ig = 0; ig < G; ig += st) seeding.push_back(g.index(ig, iz));
  }
  sum.seeding_cells = static_cast<int>(seeding.size());
  sum.multistart_improved =
      multiStarts(sc, map.cells, seeding, 0, options.seed_starts, changed, sum.multistart_tries);

  // (2) Neighbour propagation.
  sum.converged = options.propagation_rounds == 0;
  if (options.propagation_rounds > 0) propagate(sc, map.cells, changed, true, sum);

  // (3) Collision maps: every cell still reached only in collision gets collision_starts further
  // random starts (new numbers of its stream), then propagation from the cells they freed.
  std::vector<int> colliding;
  if (sc.check && options.collision_starts > 0)
    for (int i = 0; i < N; ++i)
      if (inCollision(map.cells[i])) colliding.push_back(i);
  sum.collision_cells = static_cast<int>(colliding.size());
  if (!colliding.empty()) {
    std::fill(changed.begin(), changed.end(), 0);
    multiStarts(sc, map.cells, colliding, options.seed_starts, options.collision_starts, changed,
                sum.collision_tries);
    for (int i : colliding) sum.collision_freed += map.cells[i].reachable ? 1 : 0;
    if (sum.collision_freed > 0 && options.propagation_rounds > 0)
      propagate(sc, map.cells, changed, false, sum);
  }
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  map.seconds += sum.seconds;
}

}  // namespace armstudy::dexterity
