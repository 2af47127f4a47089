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
#include <limits>
#include <optional>

#include "collision/reach_collision.hpp"
#include "common/errors.hpp"
#include "common/defaults.hpp"

namespace armstudy {

using namespace sweep_detail;

namespace {

// The neighbours of grid pose i: +-1 along each spatial axis, and the same point in the previous
// and next orientation of the grid's list, in a fixed order.
int gridNeighbours(const TaskGrid& g, long i, long out[8]) {
  const auto d = g.dims();
  const long P = g.points(), O = static_cast<long>(g.orientations.size());
  const long o = i / P, p = i % P;
  const long ix = p % d[0], iy = (p / d[0]) % d[1], iz = p / (static_cast<long>(d[0]) * d[1]);
  const long c[3] = {ix, iy, iz};
  const long stride[3] = {1, d[0], static_cast<long>(d[0]) * d[1]};
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
int gridBoxNeighbours(const TaskGrid& g, long i, long out[28]) {
  const auto d = g.dims();
  const long P = g.points(), O = static_cast<long>(g.orientations.size());
  const long o = i / P, p = i % P;
  const long ix = p % d[0], iy = (p / d[0]) % d[1], iz = p / (static_cast<long>(d[0]) * d[1]);
  int n = 0;
  for (long dz = -1; dz <= 1; ++dz)
    for (long dy = -1; dy <= 1; ++dy)
      for (long dx = -1; dx <= 1; ++dx) {
        const long x = ix + dx, y = iy + dy, z = iz + dz;
        if ((dx == 0 && dy == 0 && dz == 0) || x < 0 || y < 0 || z < 0 || x >= d[0] || y >= d[1] || z >= d[2]) continue;
        out[n++] = o * P + x + d[0] * (y + static_cast<long>(d[1]) * z);
      }
  if (o > 0) out[n++] = i - P;
  if (o + 1 < O) out[n++] = i + P;
  return n;
}

// The map search over a whole sweep; `neighbours(i, out)` lists pose i's neighbours (none for a
// pose list, whose poses need not lie next to each other).
using Neighbours = std::function<int(long, long*)>;
SweepSearchSummary searchSweep(const Model& model, const std::function<IkTarget(long)>& target,
                               const Neighbours& neighbours, const Neighbours& box, const IkOptions& options, int threads,
                               const SweepCollision& collision, const SweepSearch& search, PoseSweep& s) {
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
  std::vector<int> extra(N, 0);  // starts spent on the pose by the search
  std::vector<PoseResult> found(N);  // per-round candidates (allocated once)
  // The end of a Jacobi round: the candidates of the poses marked in `now` replace their results.
  auto adoptRound = [&](const std::vector<std::uint8_t>& now) {
    for (long i = 0; i < N; ++i)
      if (now[i]) {
        store(s, i, found[i].ik, s.starts[i]);
        storeCollision(s, i, found[i]);
      }
  };
  // Neighbour propagation (Jacobi rounds: a round reads only the previous round's results).
  auto propagate = [&](bool all_sources) {
    bool first = all_sources;
    for (;;) {
      if (sum.rounds >= search.propagation_rounds) {
        sum.converged = false;
        return;
      }
      std::vector<std::uint8_t> now(N, 0);  // found[i] is this round's candidate where now[i]
      long tries = 0;
      long updates = 0;
#pragma omp parallel num_threads(nt) reduction(+ : tries, updates)
      {
        PoseSolver solver(model, collision, target);
        long nb[8];
#pragma omp for schedule(dynamic, 64)
        for (long i = 0; i < N; ++i) {
          const auto cur = static_cast<ReachStatus>(s.status[i]);
          if (settle(cur)) continue;
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
              ++extra[i];
              if (!improves(pr, now[i] ? found[i].ik.status : cur)) continue;
              found[i] = std::move(pr);
              now[i] = 1;
              if (found[i].ik.reachable()) break;
            }
            if (now[i] && found[i].ik.reachable()) break;
          }
          updates += now[i];
        }
      }
      adoptRound(now);
      ++sum.rounds;
      sum.neighbour_tries += tries;
      sum.neighbour_updates += updates;
      changed.swap(now);
      first = false;
      if (updates == 0) return;
    }
  };
  propagate(true);
  // Seeded multi-starts for every pose still reachable only in collision, then propagation
  // from the poses they freed.
  if (collision.enabled() && search.collision_starts > 0) {
    std::vector<long> todo;
    for (long i = 0; i < N; ++i)
      if (inCollision(static_cast<ReachStatus>(s.status[i]))) todo.push_back(i);
    sum.multistart_poses = static_cast<long>(todo.size());
    std::fill(changed.begin(), changed.end(), 0);
    long tries = 0, freed = 0;
#pragma omp parallel num_threads(nt) reduction(+ : tries, freed)
    {
      PoseSolver solver(model, collision, target);
      JointVector q0(model.dof());
#pragma omp for schedule(dynamic, 8)
      for (long t = 0; t < static_cast<long>(todo.size()); ++t) {
        const long i = todo[t];
        for (int k = 0; k < search.collision_starts; ++k) {
          randomConfiguration(model, search.seed, static_cast<std::uint64_t>(i), k, q0);
          const PoseResult pr = solver.solve(i, one, &q0, 0);
          ++tries;
          ++extra[i];
          if (!pr.ik.reachable()) continue;
          store(s, i, pr.ik, s.starts[i]);
          storeCollision(s, i, pr);
          changed[i] = 1;
          ++freed;
          break;
        }
      }
    }
    sum.multistart_tries = tries;
    sum.multistart_freed = freed;
    if (freed > 0) propagate(false);
  }
  // Poses still in collision: one round from the solutions (and second branches) of every
  // collision-free pose in their wider neighbourhood (the 3 x 3 x 3 box), then propagation from
  // the poses it freed.
  if (collision.enabled() && box) {
    std::vector<std::uint8_t> now(N, 0);
    long tries = 0, freed = 0;
#pragma omp parallel num_threads(nt) reduction(+ : tries, freed)
    {
      PoseSolver solver(model, collision, target);
      long nb[28];
#pragma omp for schedule(dynamic, 16)
      for (long i = 0; i < N; ++i) {
        if (!inCollision(static_cast<ReachStatus>(s.status[i]))) continue;
        const int count = box(i, nb);
        for (int k = 0; k < count && !now[i]; ++k) {
          if (!s.reachable(nb[k])) continue;
          for (int a = 0; a < (hasAlternative(s, nb[k]) ? 2 : 1) && !now[i]; ++a) {
            const JointVector w = a == 0 ? solutionOf(s, nb[k]) : alternativeOf(s, nb[k]);
            PoseResult pr = solver.solve(i, one, &w, 0);
            ++tries;
            ++extra[i];
            if (!pr.ik.reachable()) continue;
            found[i] = std::move(pr);
            now[i] = 1;
            ++freed;
          }
        }
      }
    }
    adoptRound(now);
    sum.box_tries = tries;
    sum.box_freed = freed;
    changed = now;
    if (freed > 0) propagate(false);
  }
  // The best solution found at each reachable pose: Jacobi rounds in which a reachable pose
  // retries from every collision-free neighbour whose manipulability is higher and keeps a
  // collision-free solution that raises its own by more than defaults::kReachManipulabilityImprovement
  // (a step to a better posture, not a creep along a continuous family of solutions), until
  // nothing changes.
  if (search.best_manipulability) {
    std::vector<std::uint8_t> src(N, 1);
    for (int round = 0; round < search.propagation_rounds; ++round) {
      std::vector<std::uint8_t> now(N, 0);  // found[i] is this round's candidate where now[i]
      long tries = 0, updates = 0;
#pragma omp parallel num_threads(nt) reduction(+ : tries, updates)
      {
        PoseSolver solver(model, collision, target);
        long nb[8];
#pragma omp for schedule(dynamic, 64)
        for (long i = 0; i < N; ++i) {
          if (!s.reachable(i)) continue;
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
        }
      }
      adoptRound(now);
      ++sum.best_rounds;
      sum.best_tries += tries;
      sum.best_updates += updates;
      src.swap(now);
      if (updates == 0) break;
    }
  }
  for (long i = 0; i < N; ++i)
    s.starts[i] = static_cast<std::uint8_t>(std::min(255, s.starts[i] + extra[i]));
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sum;
}

}  // namespace

SweepSearchSummary searchGridSweep(const Model& model, const TaskGrid& grid, const IkOptions& options, int threads,
                                   const SweepCollision& collision, const SweepSearch& search, PoseSweep& sweep) {
  ARMSTUDY_CHECK(sweep.offset == 0 && sweep.size == grid.size(), "the map search needs the whole sweep of the grid");
  return searchSweep(
      model, [&grid](long i) { return IkTarget{grid.task_space, grid.pose(i)}; },
      [&grid](long i, long* out) { return gridNeighbours(grid, i, out); },
      [&grid](long i, long* out) { return gridBoxNeighbours(grid, i, out); }, options, threads, collision, search,
      sweep);
}

SweepSearchSummary searchPoseListSweep(const Model& model, const PoseList& list, const IkOptions& options, int threads,
                                       const SweepCollision& collision, const SweepSearch& search, PoseSweep& sweep) {
  ARMSTUDY_CHECK(sweep.offset == 0 && sweep.size == static_cast<long>(list.poses.size()),
                 "the map search needs the whole sweep of the pose list");
  return searchSweep(
      model, [&list](long i) { return IkTarget{list.task_space, list.poses[i]}; }, [](long, long*) { return 0; },
      Neighbours{}, options, threads, collision, search, sweep);
}

}  // namespace armstudy
