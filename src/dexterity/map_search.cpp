#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/angles.hpp"
#include "common/errors.hpp"
#include "dexterity/dexterity_map.hpp"
#include "study/shared_loop.hpp"

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
  const bool wrap = G > 2 && std::abs(g.gamma_rad.step() * G - kFullTurn_rad) < 1e-9;
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

// What the search steps share: the model, the options, the objective and the per-thread set-up,
// and the runner whose processes share each step (null: this process alone).
struct SearchContext {
  const Model& model;
  const DexterityOptions& options;
  ik::WeightedObjective objective;
  int threads;
  bool check;  // collisions checked
  const UnitRunner* runner;
  std::string id;  // the steps' loop ids start with it ("dexterity-search/<design>/")
  mutable int steps = 0;
  std::string stepId(const char* phase) const { return id + std::to_string(steps++) + "_" + phase; }
};

// One thread's workspaces for the search's solves (built once per parallel region).
struct ThreadSolver {
  explicit ThreadSolver(const SearchContext& sc)
      : sc(sc), ws(sc.model), ik_ws(sc.model), ctx(sc.model, ws), cws(sc.model) {}
  // The cell's optimum descended from q0 (dexterity::cellFromSeed), without its measures; not
  // descended when the start lies on the proven optimum `proven` (may be null).
  bool fromSeed(const StemGrid::Cell& cell, const JointVector& q0, CellResult& out,
                const JointVector* proven) {
    return cellFromSeed(sc.model, ws, ik_ws, ctx, sc.objective, sc.options, cell, q0, out,
                        sc.check ? &cws : nullptr, false, proven);
  }
  // Whether the cell's optimum is proven (dexterity::provenOptimum).
  bool proven(const StemGrid::Cell& cell, const CellResult& c) {
    return provenOptimum(sc.model, ws, ctx, sc.objective, sc.options, cell, c);
  }
  // The measures of a candidate about to be adopted (dexterity::measureCell).
  void measure(const StemGrid::Cell& cell, CellResult& c) {
    measureCell(sc.model, ws, sc.options, cell, c);
  }
  const SearchContext& sc;
  KinematicsWorkspace ws;
  IkWorkspace ik_ws;
  ik::ObjectiveContext ctx;
  collision::CollisionWorkspace cws;
};

// One step over a list of cells, per item: the candidates it tried, whether its cell improved (a
// counter of the step) and whether it changed (then its new state is the step's output).
struct StepItems {
  explicit StepItems(std::size_t n) : tries(n, 0), descent(n), improved(n, 0), changed(n, 0) {}
  std::vector<long> tries;
  std::vector<ik::DescentTally> descent;  // the item's candidates' descents
  std::vector<std::uint8_t> improved, changed;
};

constexpr char kStepMagic[] = "armstudy-dexterity-search-step-v3";

// The items of chunk `r` that tried or changed anything, with the new state of each changed cell
// (`at(t)`), as bytes; empty when there is nothing to apply.
template <class At>
std::string packStep(const ItemRange& r, const StepItems& it, At&& at) {
  UnitWriter w(kStepMagic);
  bool any = false;
  for (long t = r.begin; t < r.end; ++t) {
    if (it.tries[t] == 0 && !it.changed[t]) continue;
    any = true;
    w.put<std::int64_t>(t);
    w.put<std::int64_t>(it.tries[t]);
    w.put<std::uint8_t>(it.improved[t]);
    w.put<std::uint8_t>(it.changed[t]);
    putTally(w, it.descent[t]);
    if (!it.changed[t]) continue;
    putCell(w, at(t));
    w.put<std::uint8_t>(static_cast<std::uint8_t>(at(t).found_by));
  }
  return any ? w.bytes() : std::string();
}

// The inverse, on a process that did not compute the chunk.
template <class At>
void unpackStep(const ItemRange& r, const std::string& bytes, StepItems& it, At&& at) {
  if (bytes.empty()) return;
  UnitReader rd(bytes, kStepMagic);
  while (rd.ok() && !rd.finished()) {
    const long t = static_cast<long>(rd.get<std::int64_t>());
    ARMSTUDY_CHECK(rd.ok() && t >= r.begin && t < r.end, "a map search step's cells arrive whole");
    it.tries[t] = static_cast<long>(rd.get<std::int64_t>());
    it.improved[t] = rd.get<std::uint8_t>();
    it.changed[t] = rd.get<std::uint8_t>();
    getTally(rd, it.descent[t]);
    if (!it.changed[t]) continue;
    CellResult& c = at(t);
    getCell(rd, c);
    const auto source = rd.get<std::uint8_t>();
    if (source > static_cast<std::uint8_t>(CellResult::Source::Neighbour)) rd.fail();
    c.found_by = static_cast<CellResult::Source>(source);
  }
  ARMSTUDY_CHECK(rd.finished(), "a map search step's cells arrive whole");
}

// Runs one step over `n` items on sc.runner's processes: body(t, solver) computes item t on a
// thread (into `it` and its cell); pack and unpack move the items' outcome (`at(t)`: item t's
// cell).
template <class Body, class At>
void runStep(const SearchContext& sc, const char* phase, std::size_t n, long chunk, StepItems& it,
             Body&& body, At&& at) {
  SharedLoop loop;
  loop.id = sc.stepId(phase);
  loop.items = static_cast<long>(n);
  loop.chunk = chunk;
  loop.compute = [&](const std::vector<SharedLoop::Chunk>& mine) {
    const std::vector<long> items = SharedLoop::itemsOf(mine);
    const long m = static_cast<long>(items.size());
#pragma omp parallel num_threads(sc.threads)
    {
      ThreadSolver solver(sc);
#pragma omp for schedule(dynamic, 1)
      for (long k = 0; k < m; ++k) body(items[static_cast<std::size_t>(k)], solver);
    }
  };
  loop.pack = [&](std::size_t, const ItemRange& r) { return packStep(r, it, at); };
  loop.unpack = [&](std::size_t, const ItemRange& r, const std::string& bytes) {
    unpackStep(r, bytes, it, at);
  };
  runSharedLoop(sc.runner, loop);
}

// `starts` random configurations for each cell of `list` (start numbers first .. first + starts - 1
// of the cell's counter-based stream: each cell depends only on its own index); a better
// candidate replaces the cell and marks it in `changed`. Returns the cells improved. A step shared
// among the processes (chunks of a few cells: each is `starts` solves).
int multiStarts(const SearchContext& sc, std::vector<CellResult>& cells,
                const std::vector<int>& list, int first, int starts,
                std::vector<std::uint8_t>& changed, long& tries, ik::DescentTally& descent,
                const char* phase) {
  const StemGrid& g = sc.options.grid;
  const int G = g.gamma_rad.count;
  StepItems it(list.size());
  const auto cellOf = [&](long t) -> CellResult& { return cells[list[t]]; };
  runStep(
      sc, phase, list.size(), 4, it,
      [&](long t, ThreadSolver& solver) {
        const int idx = list[t];
        const StemGrid::Cell cell = g.cell(idx % G, idx / G);
        CellResult& cur = cells[idx];
        // Starts that land on the cell's proven optimum are not descended; that optimum stays the
        // test after a better candidate replaced it (such a start would descend to a worse one).
        const JointVector proven_q = cur.q_opt;
        const JointVector* proven = solver.proven(cell, cur) ? &proven_q : nullptr;
        JointVector q0(sc.model.dof());
        for (int s = first; s < first + starts; ++s) {
          randomConfiguration(sc.model, sc.options.search_seed, static_cast<std::uint64_t>(idx), s,
                              q0);
          CellResult cand;
          ++it.tries[t];
          const bool landed = solver.fromSeed(cell, q0, cand, proven);
          it.descent[t].add(cand.descent);
          if (!landed || !better(cand, cur)) continue;
          it.descent[t].changed += cand.descent.descents > 0;
          solver.measure(cell, cand);
          if (cur.found_by != CellResult::Source::MultiStart) it.improved[t] = 1;
          adopt(cur, cand, CellResult::Source::MultiStart);
          it.changed[t] = 1;
        }
      },
      cellOf);
  int improved = 0;
  for (std::size_t t = 0; t < list.size(); ++t) {
    tries += it.tries[t];
    descent.add(it.descent[t]);
    improved += it.improved[t];
    if (it.changed[t]) changed[list[t]] = 1;
  }
  return improved;
}

// Neighbour propagation, Jacobi rounds, until no cell changes or the round cap (counted over the
// whole search). With `all_first`, the first round tries every better neighbour (the chain's
// branch choices are not marked); later rounds only neighbours that changed in the round before.
// A round is a step shared among the processes over the cells next to a source.
void propagate(const SearchContext& sc, std::vector<CellResult>& cells,
               std::vector<std::uint8_t>& changed, bool all_first, MapSearchSummary& sum) {
  const StemGrid& g = sc.options.grid;
  const int N = g.size(), G = g.gamma_rad.count;
  bool first = all_first;
  sum.converged = false;
  int nb[8];
  const auto source = [&](int j) { return cells[j].reachable && (first || changed[j]); };
  while (sum.rounds < sc.options.propagation_rounds) {
    // The round's cells: those with a source among their neighbours (the others try nothing).
    std::vector<int> active;
    for (int idx = 0; idx < N; ++idx) {
      const int count = neighbours(g, idx, nb);
      for (int k = 0; k < count; ++k)
        if (source(nb[k])) {
          active.push_back(idx);
          break;
        }
    }
    StepItems it(active.size());
    std::vector<CellResult> next(active.size());  // a changed cell's new state
    runStep(
        sc, "propagate", active.size(), 16, it,
        [&](long t, ThreadSolver& solver) {
          const int idx = active[t];
          const CellResult& cur = cells[idx];
          int nbt[8];
          const int count = neighbours(g, idx, nbt);
          CellResult best = cur;
          const StemGrid::Cell cell = g.cell(idx % G, idx / G);
          const JointVector* proven = nullptr;
          bool proof_known = false;
          for (int k = 0; k < count; ++k) {
            const CellResult& src = cells[nbt[k]];
            if (!source(nbt[k])) continue;
            if (cur.reachable && !(src.H_opt < cur.H_opt)) continue;
            // A neighbour whose optimum is this cell's posture (every joint within kMapSameBasin)
            // would descend to this cell's optimum again.
            if (cur.reachable &&
                (src.q_opt - cur.q_opt).cwiseAbs().maxCoeff() < defaults::kMapSameBasin)
              continue;
            if (!proof_known) {  // once per cell and round, for cells that try a neighbour
              proven = solver.proven(cell, cur) ? &cur.q_opt : nullptr;
              proof_known = true;
            }
            CellResult cand;
            ++it.tries[t];
            const bool landed = solver.fromSeed(cell, src.q_opt, cand, proven);
            it.descent[t].add(cand.descent);
            if (!landed || !better(cand, best)) continue;
            it.descent[t].changed += cand.descent.descents > 0;
            solver.measure(cell, cand);
            adopt(best, cand, CellResult::Source::Neighbour);
            it.changed[t] = it.improved[t] = 1;
          }
          if (it.changed[t]) next[t] = std::move(best);
        },
        [&](long t) -> CellResult& { return next[t]; });
    std::vector<std::uint8_t> now(N, 0);
    long round_tries = 0;
    int round_improved = 0;
    for (std::size_t t = 0; t < active.size(); ++t) {
      round_tries += it.tries[t];
      sum.neighbour.add(it.descent[t]);
      round_improved += it.improved[t];
      if (!it.changed[t]) continue;
      cells[active[t]] = std::move(next[t]);
      now[active[t]] = 1;
    }
    ++sum.rounds;
    sum.neighbour_tries += round_tries;
    sum.neighbour_improved += round_improved;
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
                        int threads, const UnitRunner* runner) {
  const auto t0 = std::chrono::steady_clock::now();
  const StemGrid& g = options.grid;
  const int N = g.size(), G = g.gamma_rad.count;
  ARMSTUDY_CHECK(static_cast<int>(map.cells.size()) == N, "dexterity map does not match its grid");
  const SearchContext sc{model,
                         options,
                         options.buildObjective(model),
                         threads > 0 ? threads : omp_get_max_threads(),
                         options.collisionFor(model).enabled(),
                         runner,
                         "dexterity-search/" + map.design + "/"};
  MapSearchSummary& sum = map.search;
  sum = MapSearchSummary{};
  // The chained rows' descents, as the cells hold them before the search replaces any.
  for (const CellResult& c : map.cells) {
    sum.chain.add(c.descent);
    sum.chain.changed += c.optimised;
  }
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
  auto tk = std::chrono::steady_clock::now();
  const auto lap = [&tk] {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - tk).count();
    tk = now;
    return s;
  };
  sum.multistart_improved = multiStarts(sc, map.cells, seeding, 0, options.seed_starts, changed,
                                        sum.multistart_tries, sum.seed, "multistart");

  sum.seed_seconds = lap();
  // (2) Neighbour propagation.
  sum.converged = options.propagation_rounds == 0;
  if (options.propagation_rounds > 0) propagate(sc, map.cells, changed, true, sum);
  sum.neighbour_seconds = lap();

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
                sum.collision_tries, sum.collision, "collision_starts");
    sum.collision_seconds = lap();
    for (int i : colliding) sum.collision_freed += map.cells[i].reachable ? 1 : 0;
    if (sum.collision_freed > 0 && options.propagation_rounds > 0)
      propagate(sc, map.cells, changed, false, sum);
  }
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  map.seconds += sum.seconds;
}

}  // namespace armstudy::dexterity
