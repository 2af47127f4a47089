#include "reach/reach_sweep.hpp"
#include "reach/sweep_internal.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string_view>

#include "collision/reach_collision.hpp"
#include "common/errors.hpp"
#include "common/defaults.hpp"
#include "study/stage.hpp"

namespace armstudy {

using namespace sweep_detail;

namespace {

// A grid's index layout, computed once per search (TaskGrid::dims() recomputes each axis' count
// from floating-point ranges; the neighbour look-ups below run millions of times per search).
struct GridShape {
  long d[3];
  long P, O;  // points, orientations
  explicit GridShape(const TaskGrid& g) {
    const auto dims = g.dims();
    for (int a = 0; a < 3; ++a) d[a] = dims[a];
    P = d[0] * d[1] * d[2];
    O = static_cast<long>(g.orientations.size());
  }
};

// The neighbours of grid pose i: +-1 along each spatial axis, and the same point in the previous
// and next orientation of the grid's list, in a fixed order.
int gridNeighbours(const GridShape& g, long i, long out[8]) {
  const long* d = g.d;
  const long P = g.P, O = g.O;
  const long o = i / P, p = i % P;
  const long ix = p % d[0], iy = (p / d[0]) % d[1], iz = p / (d[0] * d[1]);
  const long c[3] = {ix, iy, iz};
  const long stride[3] = {1, d[0], d[0] * d[1]};
  int n = 0;
  for (int a = 0; a < 3; ++a) {
    if (c[a] > 0) out[n++] = i - stride[a];
    if (c[a] + 1 < d[a]) out[n++] = i + stride[a];
  }
  if (o > 0) out[n++] = i - P;
  if (o + 1 < O) out[n++] = i + P;
  return n;
}

// Pose i's wider neighbourhood: the other points of the 3 x 3 x 3 box around it (same orientation)
// and the previous and next orientation at its point, in a fixed order; at most 28.
int gridBoxNeighbours(const GridShape& g, long i, long out[28]) {
  const long* d = g.d;
  const long P = g.P, O = g.O;
  const long o = i / P, p = i % P;
  const long ix = p % d[0], iy = (p / d[0]) % d[1], iz = p / (d[0] * d[1]);
  int n = 0;
  for (long dz = -1; dz <= 1; ++dz)
    for (long dy = -1; dy <= 1; ++dy)
      for (long dx = -1; dx <= 1; ++dx) {
        const long x = ix + dx, y = iy + dy, z = iz + dz;
        if ((dx == 0 && dy == 0 && dz == 0) || x < 0 || y < 0 || z < 0 || x >= d[0] || y >= d[1] || z >= d[2]) continue;
        out[n++] = o * P + x + d[0] * (y + d[1] * z);
      }
  if (o > 0) out[n++] = i - P;
  if (o + 1 < O) out[n++] = i + P;
  return n;
}

constexpr std::string_view kStepMagic = "armstudy-search-step-2";
// Poses per chunk of a search step's shared loop. A step visits only the poses that can change (its
// active set), which are mostly costly ones, so chunks are small: at most 8 poses, fewer when the
// active set has fewer than 8 x kSearchStepChunks poses, so that a step has that many chunks to
// spread over the ranks of a distributed run (owned round-robin; a unit-cost record holds the step
// at this grain). Steps whose every pose is a many-start search (multistart, box) use single poses.
constexpr long kSearchStepMaxChunk = 8;
constexpr long kSearchStepChunks = 1024;
long searchStepChunk(std::size_t active) {
  return std::clamp(static_cast<long>(active) / kSearchStepChunks, 1L, kSearchStepMaxChunk);
}

// The map search over a whole sweep; `neighbours(i, out)` lists pose i's neighbours (none for a
// pose list, whose poses need not lie next to each other). Neighbourhoods must be symmetric (j is a
// neighbour of i exactly when i is one of j), which both grid neighbourhoods are: a step's active
// set is found from the poses that changed in the step before.
//
// Every phase is a sequence of Jacobi steps: a step computes each pose's candidate from the sweep
// as it was before the step, then the poses that found one adopt it. A step is a loop shared among
// the processes of a distributed run (UnitRunner::share: each computes the poses of its chunks and
// sends the adopted rows), so the map is the same whichever process computed a pose. A step's loop
// runs over its active set only: the poses for which the step's rule can do anything (e.g. in a
// propagation round, the unsettled poses next to a pose that changed in the round before); the rule
// does nothing at the others, so the map is the same as with a loop over every pose.
using Neighbours = std::function<int(long, long*)>;
SweepSearchSummary searchSweep(const Model& model, const std::function<IkTarget(long)>& target,
                               const Neighbours& neighbours, const Neighbours& box, const IkOptions& options, int threads,
                               const SweepCollision& collision, const SweepSearch& search, const UnitRunner* runner,
                               PoseSweep& s) {
  const auto t0 = std::chrono::steady_clock::now();
  SweepSearchSummary sum;
  const long N = s.size;
  const int nt = threads > 0 ? threads : omp_get_max_threads();
  IkOptions one = options;  // one start from the given configuration
  one.max_starts = 1;
  one.classify_failures = false;
  auto settle = [](ReachStatus st) { return st == ReachStatus::Reachable; };
  // Adopts a candidate: collision-free wins; an unreachable pose also takes a solution in collision.
  auto improves = [](const PoseResult& pr, ReachStatus cur) {
    return pr.ik.reachable() || (inCollision(pr.ik.status) && !inCollision(cur) && cur != ReachStatus::Reachable);
  };
  std::vector<std::uint8_t> changed(N, 0);
  std::vector<int> extra(N, 0);  // starts spent on the pose by the search (every process counts all)
  std::vector<PoseResult> found(N);  // per-step candidates (allocated once)
  std::vector<std::uint8_t> now(N, 0);  // found[i] is this step's candidate where now[i]
  std::vector<long> item_a(N, 0), item_b(N, 0);  // a step's counts per pose (summed per chunk)
  std::vector<std::uint8_t> mark(N, 0);  // scratch of `around`
  std::vector<std::uint8_t> touched(N, 0);  // rows the search changed (summary.changed)
  // One pose solver per thread for the whole search, built on first use (a step's compute may be
  // called once per chunk, e.g. when unit costs are recorded; the solvers hold workspaces only).
  std::vector<std::unique_ptr<PoseSolver>> solvers(static_cast<std::size_t>(nt));
  // The poses (ascending) next to any of `from` that pass `keep`.
  auto around = [&](const std::vector<long>& from, auto&& keep) {
    std::vector<long> out;
    long nb[8];
    for (const long j : from) {
      const int count = neighbours(j, nb);
      for (int k = 0; k < count; ++k)
        if (!mark[nb[k]] && keep(nb[k])) {
          mark[nb[k]] = 1;
          out.push_back(nb[k]);
        }
    }
    for (const long i : out) mark[i] = 0;
    std::sort(out.begin(), out.end());
    return out;
  };
  // The poses (ascending) that pass `keep`.
  auto every = [&](auto&& keep) {
    std::vector<long> out;
    for (long i = 0; i < N; ++i)
      if (keep(i)) out.push_back(i);
    return out;
  };
  // One step over the poses `active` (ascending), in chunks of `chunk` poses: body(solver, i, nb,
  // a, b) computes pose i's candidate and counts into a and b (a: the starts it spent, which count
  // into the pose's starts when `spends` is set). Returns the totals of a and b over all poses and
  // the poses that adopted a candidate (ascending). The spent starts travel with the adopted rows,
  // so that every process counts them whichever process computed a pose.
  struct StepResult {
    long a = 0, b = 0;
    std::vector<long> adopted;
  };
  int steps = 0;  // steps so far (names them in the unit-cost record)
  auto step = [&](const char* phase, int grain, long chunk, bool spends, const std::vector<long>& active,
                  auto&& body) {
    std::fill(now.begin(), now.end(), 0);
    StepResult res;
    std::map<std::size_t, std::pair<long, long>> counts;  // per chunk computed here
    SharedLoop loop;
    loop.id = "search/" + s.design + "/" + std::to_string(steps++) + "_" + phase;
    loop.items = static_cast<long>(active.size());
    loop.chunk = chunk;
    loop.compute = [&](const std::vector<SharedLoop::Chunk>& mine) {
      const std::vector<long> items = SharedLoop::itemsOf(mine);
      const long n = static_cast<long>(items.size());
      for (const long t : items) item_a[active[t]] = item_b[active[t]] = 0;
#pragma omp parallel num_threads(nt)
      {
        std::unique_ptr<PoseSolver>& solver = solvers[static_cast<std::size_t>(omp_get_thread_num())];
        if (!solver) solver = std::make_unique<PoseSolver>(model, collision, target);
        long nb[28];
#pragma omp for schedule(dynamic, grain)
        for (long t = 0; t < n; ++t) {
          const long i = active[items[t]];
          body(*solver, i, nb, item_a[i], item_b[i]);
        }
      }
      for (const SharedLoop::Chunk& c : mine) {
        std::pair<long, long>& ab = counts[c.first];
        for (long t = c.second.begin; t < c.second.end; ++t) {
          ab.first += item_a[active[t]];
          ab.second += item_b[active[t]];
        }
      }
    };
    // The step ends: the poses computed here adopt their candidates.
    loop.finish = [&](const std::vector<SharedLoop::Chunk>& mine) {
      for (const SharedLoop::Chunk& c : mine) {
        res.a += counts.at(c.first).first;
        res.b += counts.at(c.first).second;
        for (long t = c.second.begin; t < c.second.end; ++t) {
          const long i = active[t];
          if (spends) extra[i] += static_cast<int>(item_a[i]);
          if (now[i]) {
            store(s, i, found[i].ik, s.starts[i]);
            storeCollision(s, i, found[i]);
            res.adopted.push_back(i);
          }
        }
      }
    };
    // A chunk's rows travel by item index (its position in the active set).
    loop.pack = [&](std::size_t k, const ItemRange& r) {
      // Nothing tried (so nothing adopted, no starts spent): nothing to send.
      if (counts.at(k).first == 0 && counts.at(k).second == 0) return std::string();
      UnitWriter w(kStepMagic);
      w.put<std::int64_t>(counts.at(k).first);
      w.put<std::int64_t>(counts.at(k).second);
      for (long t = r.begin; t < r.end; ++t)
        if (now[active[t]]) {
          w.put<std::int64_t>(t);
          putPose(w, s, active[t]);
        }
      w.put<std::int64_t>(-1);
      if (spends)
        for (long t = r.begin; t < r.end; ++t)
          if (item_a[active[t]] > 0) {
            w.put<std::int64_t>(t);
            w.put<std::int64_t>(item_a[active[t]]);
          }
      return w.bytes();
    };
    loop.unpack = [&](std::size_t, const ItemRange& r, const std::string& bytes) {
      if (bytes.empty()) return;
      UnitReader rd(bytes, kStepMagic);
      res.a += static_cast<long>(rd.get<std::int64_t>());
      res.b += static_cast<long>(rd.get<std::int64_t>());
      for (long t = static_cast<long>(rd.get<std::int64_t>()); rd.ok() && t >= 0;
           t = static_cast<long>(rd.get<std::int64_t>())) {
        ARMSTUDY_CHECK(t >= r.begin && t < r.end && getPose(rd, s, active[t]), "a search step's rows arrive whole");
        now[active[t]] = 1;
        res.adopted.push_back(active[t]);
      }
      while (rd.ok() && !rd.finished()) {
        const long t = static_cast<long>(rd.get<std::int64_t>());
        const long spent = static_cast<long>(rd.get<std::int64_t>());
        ARMSTUDY_CHECK(rd.ok() && spends && t >= r.begin && t < r.end, "a search step's start counts arrive whole");
        extra[active[t]] += static_cast<int>(spent);
      }
      ARMSTUDY_CHECK(rd.finished(), "a search step's rows arrive whole");
    };
    runSharedLoop(runner, loop);
    std::sort(res.adopted.begin(), res.adopted.end());
    for (const long i : res.adopted) touched[i] = 1;
    return res;
  };
  auto unsettled = [&](long i) { return !settle(static_cast<ReachStatus>(s.status[i])); };
  auto colliding = [&](long i) { return inCollision(static_cast<ReachStatus>(s.status[i])); };
  // Neighbour propagation (Jacobi rounds: a round reads only the previous round's results). The
  // first round with all_sources visits every unsettled pose; a later round those next to a pose
  // that changed in the round before (`from`).
  auto propagate = [&](bool all_sources, std::vector<long> from) {
    bool first = all_sources;
    for (;;) {
      if (sum.rounds >= search.propagation_rounds) {
        sum.converged = false;
        return;
      }
      const std::vector<long> active =
          first || search.every_pose_each_step ? every(unsettled) : around(from, unsettled);
      const StepResult r = step("propagate", 4, searchStepChunk(active.size()), true, active, [&](PoseSolver& solver, long i, long* nb, long& tries, long& updates) {
        const auto cur = static_cast<ReachStatus>(s.status[i]);
        if (settle(cur)) return;
        const int count = neighbours(i, nb);
        for (int k = 0; k < count; ++k) {
          if (!s.reachable(nb[k]) || !(first || changed[nb[k]])) continue;
          // The neighbour's solution, and in the first round also the other chain's (a second
          // branch, which never changes).
          const int seeds = first && hasAlternative(s, nb[k]) ? 2 : 1;
          for (int a = 0; a < seeds; ++a) {
            const JointVector w = a == 0 ? solutionOf(s, nb[k]) : alternativeOf(s, nb[k]);
            PoseResult pr = solver.solve(i, one, &w, 0);
            ++tries;
            if (!improves(pr, now[i] ? found[i].ik.status : cur)) continue;
            found[i] = std::move(pr);
            now[i] = 1;
            if (found[i].ik.reachable()) break;
          }
          if (now[i] && found[i].ik.reachable()) break;
        }
        updates += now[i];
      });
      ++sum.rounds;
      sum.neighbour_tries += r.a;
      sum.neighbour_updates += r.b;
      changed.swap(now);
      from = r.adopted;
      first = false;
      if (r.b == 0) return;
    }
  };
  propagate(true, {});
  // Seeded multi-starts for every pose still reachable only in collision, then propagation
  // from the poses they freed.
  if (collision.enabled() && search.collision_starts > 0) {
    const std::vector<long> active = every(colliding);
    sum.multistart_poses += static_cast<long>(active.size());
    const StepResult r = step("multistart", 1, 1, true, active, [&](PoseSolver& solver, long i, long*, long& tries, long& freed) {
      if (!inCollision(static_cast<ReachStatus>(s.status[i]))) return;
      JointVector q0(model.dof());
      for (int k = 0; k < search.collision_starts; ++k) {
        randomConfiguration(model, search.seed, static_cast<std::uint64_t>(i), k, q0);
        PoseResult pr = solver.solve(i, one, &q0, 0);
        ++tries;
        if (!pr.ik.reachable()) continue;
        found[i] = std::move(pr);
        now[i] = 1;
        ++freed;
        break;
      }
    });
    sum.multistart_tries = r.a;
    sum.multistart_freed = r.b;
    changed = now;
    if (r.b > 0) propagate(false, r.adopted);
  }
  // Poses still in collision: one round from the solutions (and second branches) of every
  // collision-free pose in their wider neighbourhood (the 3 x 3 x 3 box), then propagation from
  // the poses it freed.
  if (collision.enabled() && box) {
    const std::vector<long> active = every(colliding);
    const StepResult r = step("box", 1, 1, true, active, [&](PoseSolver& solver, long i, long* nb, long& tries, long& freed) {
      if (!inCollision(static_cast<ReachStatus>(s.status[i]))) return;
      const int count = box(i, nb);
      for (int k = 0; k < count && !now[i]; ++k) {
        if (!s.reachable(nb[k])) continue;
        for (int a = 0; a < (hasAlternative(s, nb[k]) ? 2 : 1) && !now[i]; ++a) {
          const JointVector w = a == 0 ? solutionOf(s, nb[k]) : alternativeOf(s, nb[k]);
          PoseResult pr = solver.solve(i, one, &w, 0);
          ++tries;
          if (!pr.ik.reachable()) continue;
          found[i] = std::move(pr);
          now[i] = 1;
          ++freed;
        }
      }
    });
    sum.box_tries = r.a;
    sum.box_freed = r.b;
    changed = now;
    if (r.b > 0) propagate(false, r.adopted);
  }
  // The best solution found at each reachable pose: Jacobi rounds in which a reachable pose
  // retries from every collision-free neighbour whose manipulability is higher and keeps a
  // collision-free solution that raises its own by more than defaults::kReachManipulabilityImprovement
  // (a step to a better posture, not a creep along a continuous family of solutions), until
  // nothing changes. The first round visits every reachable pose, a later one those next to a pose
  // that improved in the round before.
  if (search.best_manipulability) {
    std::vector<std::uint8_t> src(N, 1);
    auto reachable = [&](long i) { return s.reachable(i); };
    std::vector<long> from;
    for (int round = 0; round < search.propagation_rounds; ++round) {
      const std::vector<long> active =
          round == 0 || search.every_pose_each_step ? every(reachable) : around(from, reachable);
      const StepResult r = step("best", 4, searchStepChunk(active.size()), false, active, [&](PoseSolver& solver, long i, long* nb, long& tries, long& updates) {
        if (!s.reachable(i)) return;
        double best = s.manipulability[i];
        const int count = neighbours(i, nb);
        for (int k = 0; k < count; ++k) {
          if (!src[nb[k]] || !s.reachable(nb[k]) || !(s.manipulability[nb[k]] > best)) continue;
          const JointVector w = solutionOf(s, nb[k]);
          PoseResult pr = solver.solve(i, one, &w, 0, false);
          ++tries;
          if (!pr.ik.reachable() ||
              !(pr.ik.manipulability > best + defaults::kReachManipulabilityImprovement * std::abs(best)))
            continue;
          best = pr.ik.manipulability;
          found[i] = std::move(pr);
          now[i] = 1;
        }
        updates += now[i];
      });
      ++sum.best_rounds;
      sum.best_tries += r.a;
      sum.best_updates += r.b;
      src.swap(now);
      from = r.adopted;
      if (r.b == 0) break;
    }
  }
  // The starts the search spent (every process has every pose's count).
  for (long i = 0; i < N; ++i) {
    s.starts[i] = static_cast<std::uint8_t>(std::min(255, s.starts[i] + extra[i]));
    if (touched[i] || extra[i] > 0) sum.changed.push_back(i);
  }
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sum;
}

constexpr std::string_view kResultMagic = "armstudy-search-result-1";

}  // namespace

std::string packSearchResult(const PoseSweep& s, const SweepSearchSummary& sum) {
  UnitWriter w(kResultMagic);
  w.put<std::int64_t>(s.size);
  w.put<std::int64_t>(sum.rounds);
  for (const long v : {sum.neighbour_tries, sum.neighbour_updates, sum.multistart_poses, sum.multistart_tries,
                       sum.multistart_freed, sum.box_tries, sum.box_freed})
    w.put<std::int64_t>(v);
  w.put<std::int64_t>(sum.best_rounds);
  w.put<std::int64_t>(sum.best_tries);
  w.put<std::int64_t>(sum.best_updates);
  w.put<std::uint8_t>(sum.converged ? 1 : 0);
  w.put(sum.seconds);
  w.put<std::int64_t>(static_cast<std::int64_t>(sum.changed.size()));
  for (const long i : sum.changed) {
    w.put<std::int64_t>(i);
    putPose(w, s, i);
  }
  return w.bytes();
}

void unpackSearchResult(const std::string& bytes, PoseSweep& s, SweepSearchSummary& sum) {
  UnitReader rd(bytes, kResultMagic);
  ARMSTUDY_CHECK(rd.get<std::int64_t>() == s.size, "a search result fits its sweep");
  sum = SweepSearchSummary{};
  sum.rounds = static_cast<int>(rd.get<std::int64_t>());
  for (long* v : {&sum.neighbour_tries, &sum.neighbour_updates, &sum.multistart_poses, &sum.multistart_tries,
                  &sum.multistart_freed, &sum.box_tries, &sum.box_freed})
    *v = static_cast<long>(rd.get<std::int64_t>());
  sum.best_rounds = static_cast<int>(rd.get<std::int64_t>());
  sum.best_tries = static_cast<long>(rd.get<std::int64_t>());
  sum.best_updates = static_cast<long>(rd.get<std::int64_t>());
  sum.converged = rd.get<std::uint8_t>() != 0;
  sum.seconds = rd.get<double>();
  const auto n = rd.get<std::int64_t>();
  ARMSTUDY_CHECK(rd.ok() && n >= 0 && n <= s.size, "a search result fits its sweep");
  sum.changed.reserve(static_cast<std::size_t>(n));
  for (std::int64_t k = 0; k < n; ++k) {
    const long i = static_cast<long>(rd.get<std::int64_t>());
    ARMSTUDY_CHECK(rd.ok() && i >= 0 && i < s.size && getPose(rd, s, i), "a search result's rows arrive whole");
    sum.changed.push_back(i);
  }
  ARMSTUDY_CHECK(rd.finished(), "a search result arrives whole");
}

SweepSearchSummary searchGridSweep(const Model& model, const TaskGrid& grid, const IkOptions& options, int threads,
                                   const SweepCollision& collision, const SweepSearch& search, PoseSweep& sweep,
                                   const UnitRunner* runner) {
  ARMSTUDY_CHECK(sweep.offset == 0 && sweep.size == grid.size(), "the map search needs the whole sweep of the grid");
  return searchSweep(
      model, [&grid](long i) { return taskTarget(grid.task_space, grid.pose(i)); },
      [shape = GridShape(grid)](long i, long* out) { return gridNeighbours(shape, i, out); },
      [shape = GridShape(grid)](long i, long* out) { return gridBoxNeighbours(shape, i, out); }, options, threads,
      collision, search,
      runner, sweep);
}

SweepSearchSummary searchPoseListSweep(const Model& model, const PoseList& list, const IkOptions& options, int threads,
                                       const SweepCollision& collision, const SweepSearch& search, PoseSweep& sweep,
                                       const UnitRunner* runner) {
  ARMSTUDY_CHECK(sweep.offset == 0 && sweep.size == static_cast<long>(list.poses.size()),
                 "the map search needs the whole sweep of the pose list");
  return searchSweep(
      model, [&list](long i) { return taskTarget(list.task_space, list.poses[i]); }, [](long, long*) { return 0; },
      Neighbours{}, options, threads, collision, search, runner, sweep);
}

}  // namespace armstudy
