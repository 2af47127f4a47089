#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>

#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "reach/grid_neighbours.hpp"
#include "reach/reach_sweep.hpp"
#include "reach/search_steps.hpp"

namespace armstudy {

using namespace sweep_detail;

namespace {

// The map search over a whole sweep; `neighbours(i, out)` lists pose i's neighbours (none for a
// pose list, whose poses need not lie next to each other). Neighbourhoods must be symmetric (j is a
// neighbour of i exactly when i is one of j), which both grid neighbourhoods are: a step's active
// set is found from the poses that changed in the step before.
//
// Every phase is a sequence of Jacobi steps (search_steps.hpp). A step's loop runs over its active
// set only: the poses for which the step's rule can do anything (e.g. in a
// propagation round, the unsettled poses next to a pose that changed in the round before); the rule
// does nothing at the others, so the map is the same as with a loop over every pose.
using Neighbours = std::function<int(long, long*)>;

class MapSearch : SearchSteps {
 public:
  MapSearch(const Model& model, const std::function<PoseTask(long)>& target,
            const Neighbours& neighbours, const Neighbours& box, const IkOptions& options,
            int threads, const SweepCollision& collision, const SweepSearch& search,
            const UnitRunner* runner, PoseSweep& s)
      : SearchSteps(model, target, collision, runner, threads, s),
        neighbours_(neighbours),
        box_(box),
        search_(search),
        one_(options),
        changed_(N_, 0),
        mark_(N_, 0) {
    one_.max_starts = 1;  // one start from the given configuration
    one_.classify_failures = false;
  }

  SweepSearchSummary run() {
    const auto t0 = std::chrono::steady_clock::now();
    propagate(true, {});
    if (collision_.enabled() && search_.collision_starts > 0) multistart();
    if (collision_.enabled() && box_) boxRound();
    if (search_.best_manipulability) bestManipulability();
    // The starts the search spent (every process has every pose's count).
    for (long i = 0; i < N_; ++i) {
      s_.starts[i] = static_cast<std::uint8_t>(std::min(255, s_.starts[i] + extra_[i]));
      if (touched_[i] || extra_[i] > 0) sum_.changed.push_back(i);
    }
    sum_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return sum_;
  }

 private:
  static bool settle(ReachStatus st) { return st == ReachStatus::Reachable; }
  // Adopts a candidate: collision-free wins; an unreachable pose also takes a solution in
  // collision.
  static bool improves(const PoseResult& pr, ReachStatus cur) {
    return pr.ik.reachable() ||
           (inCollision(pr.ik.status) && !inCollision(cur) && cur != ReachStatus::Reachable);
  }
  // A round's step into its phase's counts: one more round, its tries (a), updates (b) and
  // solves.
  static void countRound(const StepResult& r, int& rounds, long& tries, long& updates,
                         SolveTally& tally) {
    ++rounds;
    tries += r.a;
    updates += r.b;
    tally.add(r.tally);
  }
  bool unsettled(long i) const { return !settle(static_cast<ReachStatus>(s_.status[i])); }
  bool colliding(long i) const { return inCollision(static_cast<ReachStatus>(s_.status[i])); }

  // The poses (ascending) next to any of `from` that pass `keep`.
  template <class Keep>
  std::vector<long> around(const std::vector<long>& from, Keep&& keep) {
    std::vector<long> out;
    long nb[8];
    for (const long j : from) {
      const int count = neighbours_(j, nb);
      for (int k = 0; k < count; ++k)
        if (!mark_[nb[k]] && keep(nb[k])) {
          mark_[nb[k]] = 1;
          out.push_back(nb[k]);
        }
    }
    for (const long i : out) mark_[i] = 0;
    std::sort(out.begin(), out.end());
    return out;
  }
  // The poses (ascending) that pass `keep`.
  template <class Keep>
  std::vector<long> every(Keep&& keep) const {
    std::vector<long> out;
    for (long i = 0; i < N_; ++i)
      if (keep(i)) out.push_back(i);
    return out;
  }

  // Neighbour propagation (Jacobi rounds: a round reads only the previous round's results). The
  // first round with all_sources visits every unsettled pose; a later round those next to a pose
  // that changed in the round before (`from`).
  void propagate(bool all_sources, std::vector<long> from) {
    bool first = all_sources;
    const auto unsettled = [this](long i) { return this->unsettled(i); };
    for (;;) {
      if (sum_.rounds >= search_.propagation_rounds) {
        sum_.converged = false;
        return;
      }
      const std::vector<long> active =
          first || search_.every_pose_each_step ? every(unsettled) : around(from, unsettled);
      const StepResult r =
          step("propagate", 4, searchStepChunk(active.size()), true, active,
               [&](PoseSolver& solver, long i, long* nb, long& tries, long& updates) {
                 propagateFrom(solver, i, nb, first, tries);
                 updates += now_[i];
               });
      countRound(r, sum_.rounds, sum_.neighbour_tries, sum_.neighbour_updates, sum_.propagation);
      changed_.swap(now_);
      from = r.adopted;
      first = false;
      if (r.b == 0) return;
    }
  }
  // Starts pose i from neighbour j's solution and, with `branches` = 2, from its second branch,
  // one start each: a candidate that `accept`s is adopted as the step's (found_, now_), and the
  // starts end at the first adopted one that is reachable (then true).
  template <class Accept>
  bool seedFrom(PoseSolver& solver, long i, long j, int branches, long& tries, Accept&& accept) {
    for (int a = 0; a < branches; ++a) {
      const JointVector w = a == 0 ? solutionOf(s_, j) : alternativeOf(s_, j);
      PoseResult pr = solver.solve(i, one_, &w, 0);
      ++tries;
      if (!accept(pr)) continue;
      found_[i] = std::move(pr);
      now_[i] = 1;
      if (found_[i].ik.reachable()) return true;
    }
    return false;
  }

  // Pose i's candidate in a propagation round: one start from each collision-free neighbour that
  // changed in the round before (every neighbour in the first round, then also its second branch).
  void propagateFrom(PoseSolver& solver, long i, long* nb, bool first, long& tries) {
    const auto cur = static_cast<ReachStatus>(s_.status[i]);
    if (settle(cur)) return;
    const int count = neighbours_(i, nb);
    for (int k = 0; k < count; ++k) {
      if (!s_.reachable(nb[k]) || !(first || changed_[nb[k]])) continue;
      // The neighbour's solution, and in the first round also the other chain's (a second
      // branch, which never changes).
      const int seeds = first && hasAlternative(s_, nb[k]) ? 2 : 1;
      if (seedFrom(solver, i, nb[k], seeds, tries, [&](const PoseResult& pr) {
            return improves(pr, now_[i] ? found_[i].ik.status : cur);
          }))
        break;
    }
  }

  // One seeded start of a pose in collision: the solution from q0 as it is, and when it collides,
  // the H_c descent from it (solvePoseCollisionAware) unless an earlier start of this pose
  // descended from the same posture (every joint within defaults::kMapSameBasin), which would
  // descend to the same end again. A start that does descend gives the result of one call with
  // the descent.
  PoseResult escapeOnce(PoseSolver& solver, long i, const JointVector& q0,
                        std::vector<JointVector>& descended) {
    const IkResult ik = solver.solveIgnoringCollisions(i, one_, &q0);
    PoseResult pr = solver.solve(i, one_, &q0, 0, false, &ik);
    if (pr.ik.reachable() || !inCollision(pr.ik.status)) return pr;
    for (const JointVector& q : descended)
      if ((q - pr.ik.q).cwiseAbs().maxCoeff() < defaults::kMapSameBasin) return pr;
    descended.push_back(pr.ik.q);
    return solver.solve(i, one_, &q0, 0, true, &ik);
  }

  // Seeded multi-starts for every pose still reachable only in collision, then propagation from
  // the poses they freed.
  void multistart() {
    const std::vector<long> active = every([this](long i) { return colliding(i); });
    sum_.multistart_poses += static_cast<long>(active.size());
    const StepResult r =
        step("multistart", 1, 1, true, active,
             [&](PoseSolver& solver, long i, long*, long& tries, long& freed) {
               if (!inCollision(static_cast<ReachStatus>(s_.status[i]))) return;
               JointVector q0(model_.dof());
               std::vector<JointVector> descended;
               for (int k = 0; k < search_.collision_starts; ++k) {
                 randomConfiguration(model_, search_.seed, static_cast<std::uint64_t>(i), k, q0);
                 PoseResult pr = escapeOnce(solver, i, q0, descended);
                 ++tries;
                 if (!pr.ik.reachable()) continue;
                 found_[i] = std::move(pr);
                 now_[i] = 1;
                 ++freed;
                 break;
               }
             });
    freeAndPropagate(r, sum_.multistart_tries, sum_.multistart_freed, sum_.collision_starts);
  }

  // A step that frees poses in collision: its tries (a), the poses it freed (b) and its solves
  // into the phase's counts, then propagation from the freed poses.
  void freeAndPropagate(const StepResult& r, long& tries, long& freed, SolveTally& tally) {
    tally.add(r.tally);
    tries = r.a;
    freed = r.b;
    changed_ = now_;
    if (r.b > 0) propagate(false, r.adopted);
  }

  // Poses still in collision: one round from the solutions (and second branches) of every
  // collision-free pose in their wider neighbourhood (the 3 x 3 x 3 box), then propagation from
  // the poses it freed.
  void boxRound() {
    const std::vector<long> active = every([this](long i) { return colliding(i); });
    const StepResult r =
        step("box", 1, 1, true, active,
             [&](PoseSolver& solver, long i, long* nb, long& tries, long& freed) {
               if (!inCollision(static_cast<ReachStatus>(s_.status[i]))) return;
               const int count = box_(i, nb);
               for (int k = 0; k < count && !now_[i]; ++k)
                 if (s_.reachable(nb[k]))
                   seedFrom(solver, i, nb[k], hasAlternative(s_, nb[k]) ? 2 : 1, tries,
                            [](const PoseResult& pr) { return pr.ik.reachable(); });
               freed += now_[i];
             });
    freeAndPropagate(r, sum_.box_tries, sum_.box_freed, sum_.box);
  }

  // The best solution found at each reachable pose: Jacobi rounds in which a reachable pose
  // retries from every collision-free neighbour whose manipulability is higher and keeps a
  // collision-free solution that raises its own by more than
  // defaults::kReachManipulabilityImprovement (a step to a better posture, not a creep along a
  // continuous family of solutions), until nothing changes. The first round visits every reachable
  // pose, a later one those next to a pose that improved in the round before.
  void bestManipulability() {
    std::vector<std::uint8_t> src(N_, 1);
    const auto reachable = [this](long i) { return s_.reachable(i); };
    std::vector<long> from;
    for (int round = 0; round < search_.propagation_rounds; ++round) {
      const std::vector<long> active =
          round == 0 || search_.every_pose_each_step ? every(reachable) : around(from, reachable);
      const StepResult r =
          step("best", 4, searchStepChunk(active.size()), false, active,
               [&](PoseSolver& solver, long i, long* nb, long& tries, long& updates) {
                 if (!s_.reachable(i)) return;
                 double best = s_.manipulability[i];
                 const int count = neighbours_(i, nb);
                 for (int k = 0; k < count; ++k) {
                   if (!src[nb[k]] || !s_.reachable(nb[k]) || !(s_.manipulability[nb[k]] > best))
                     continue;
                   const JointVector w = solutionOf(s_, nb[k]);
                   // The manipulability first, the collision check only for a candidate that
                   // would be adopted (the same result as one collision-aware solve from w).
                   const IkResult ik = solver.solveIgnoringCollisions(i, one_, &w);
                   ++tries;
                   if (!ik.reachable() ||
                       !(ik.manipulability >
                         best + defaults::kReachManipulabilityImprovement * std::abs(best)))
                     continue;
                   PoseResult pr = solver.solve(i, one_, &w, 0, false, &ik);
                   if (!pr.ik.reachable()) continue;
                   best = pr.ik.manipulability;
                   found_[i] = std::move(pr);
                   now_[i] = 1;
                 }
                 updates += now_[i];
               });
      countRound(r, sum_.best_rounds, sum_.best_tries, sum_.best_updates, sum_.best);
      src.swap(now_);
      from = r.adopted;
      if (r.b == 0) break;
    }
  }

  const Neighbours& neighbours_;
  const Neighbours& box_;
  const SweepSearch& search_;
  IkOptions one_;
  SweepSearchSummary sum_;
  std::vector<std::uint8_t> changed_;
  std::vector<std::uint8_t> mark_;  // scratch of `around`
};

SweepSearchSummary searchSweep(const Model& model, const std::function<PoseTask(long)>& target,
                               const Neighbours& neighbours, const Neighbours& box,
                               const IkOptions& options, int threads,
                               const SweepCollision& collision, const SweepSearch& search,
                               const UnitRunner* runner, PoseSweep& s) {
  return MapSearch(model, target, neighbours, box, options, threads, collision, search, runner, s)
      .run();
}

}  // namespace

SweepSearchSummary searchGridSweep(const Model& model, const TaskGrid& grid,
                                   const IkOptions& options, int threads,
                                   const SweepCollision& collision, const SweepSearch& search,
                                   PoseSweep& sweep, const UnitRunner* runner) {
  ARMSTUDY_CHECK(sweep.offset == 0 && sweep.size == grid.size(),
                 "the map search needs the whole sweep of the grid");
  return searchSweep(
      model, [&grid](long i) { return taskTarget(grid.task_space, grid.pose(i)); },
      [shape = GridShape(grid)](long i, long* out) { return gridNeighbours(shape, i, out); },
      [shape = GridShape(grid)](long i, long* out) { return gridBoxNeighbours(shape, i, out); },
      options, threads, collision, search, runner, sweep);
}

SweepSearchSummary searchPoseListSweep(const Model& model, const PoseList& list,
                                       const IkOptions& options, int threads,
                                       const SweepCollision& collision, const SweepSearch& search,
                                       PoseSweep& sweep, const UnitRunner* runner) {
  ARMSTUDY_CHECK(sweep.offset == 0 && sweep.size == static_cast<long>(list.poses.size()),
                 "the map search needs the whole sweep of the pose list");
  return searchSweep(
      model, [&list](long i) { return taskTarget(list.task_space, list.poses[i]); },
      [](long, long*) { return 0; }, Neighbours{}, options, threads, collision, search, runner,
      sweep);
}

}  // namespace armstudy
