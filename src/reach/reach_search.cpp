#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string_view>

#include "collision/reach_collision.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "reach/reach_sweep.hpp"
#include "reach/sweep_internal.hpp"
#include "study/shared_loop.hpp"

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
        if ((dx == 0 && dy == 0 && dz == 0) || x < 0 || y < 0 || z < 0 || x >= d[0] || y >= d[1] ||
            z >= d[2])
          continue;
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

class MapSearch {
 public:
  MapSearch(const Model& model, const std::function<PoseTask(long)>& target,
            const Neighbours& neighbours, const Neighbours& box, const IkOptions& options,
            int threads, const SweepCollision& collision, const SweepSearch& search,
            const UnitRunner* runner, PoseSweep& s)
      : model_(model),
        target_(target),
        neighbours_(neighbours),
        box_(box),
        collision_(collision),
        search_(search),
        runner_(runner),
        s_(s),
        N_(s.size),
        nt_(threads > 0 ? threads : omp_get_max_threads()),
        one_(options),
        changed_(N_, 0),
        extra_(N_, 0),
        found_(N_),
        now_(N_, 0),
        item_a_(N_, 0),
        item_b_(N_, 0),
        mark_(N_, 0),
        touched_(N_, 0),
        solvers_(static_cast<std::size_t>(nt_)) {
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
  // A step's totals of its two counts and the poses that adopted a candidate (ascending).
  struct StepResult {
    long a = 0, b = 0;
    std::vector<long> adopted;
  };
  using ChunkCounts = std::map<std::size_t, std::pair<long, long>>;  // per chunk computed here

  static bool settle(ReachStatus st) { return st == ReachStatus::Reachable; }
  // Adopts a candidate: collision-free wins; an unreachable pose also takes a solution in
  // collision.
  static bool improves(const PoseResult& pr, ReachStatus cur) {
    return pr.ik.reachable() ||
           (inCollision(pr.ik.status) && !inCollision(cur) && cur != ReachStatus::Reachable);
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

  // Computes the candidates of the poses of `items` (indices into `active`) on the run's threads:
  // body(solver, i, nb, a, b) computes pose i's candidate and counts into a and b.
  template <class Body>
  void computeItems(const std::vector<long>& active, const std::vector<long>& items, int grain,
                    Body& body) {
    const long n = static_cast<long>(items.size());
    for (const long t : items) item_a_[active[t]] = item_b_[active[t]] = 0;
#pragma omp parallel num_threads(nt_)
    {
      std::unique_ptr<PoseSolver>& solver =
          solvers_[static_cast<std::size_t>(omp_get_thread_num())];
      if (!solver) solver = std::make_unique<PoseSolver>(model_, collision_, target_);
      long nb[28];
#pragma omp for schedule(dynamic, grain)
      for (long t = 0; t < n; ++t) {
        const long i = active[items[t]];
        body(*solver, i, nb, item_a_[i], item_b_[i]);
      }
    }
  }

  // A chunk's adopted rows and spent starts as bytes, by item index (its position in the active
  // set); empty when nothing was tried there.
  std::string packChunk(const std::vector<long>& active, const std::pair<long, long>& counts,
                        const ItemRange& r, bool spends) const {
    if (counts.first == 0 && counts.second == 0) return std::string();
    UnitWriter w(kStepMagic);
    w.put<std::int64_t>(counts.first);
    w.put<std::int64_t>(counts.second);
    for (long t = r.begin; t < r.end; ++t)
      if (now_[active[t]]) {
        w.put<std::int64_t>(t);
        putPose(w, s_, active[t]);
      }
    w.put<std::int64_t>(-1);
    if (spends)
      for (long t = r.begin; t < r.end; ++t)
        if (item_a_[active[t]] > 0) {
          w.put<std::int64_t>(t);
          w.put<std::int64_t>(item_a_[active[t]]);
        }
    return w.bytes();
  }
  // The inverse, on a process that did not compute the chunk: adopts its rows and counts.
  void unpackChunk(const std::vector<long>& active, const ItemRange& r, const std::string& bytes,
                   bool spends, StepResult& res) {
    if (bytes.empty()) return;
    UnitReader rd(bytes, kStepMagic);
    res.a += static_cast<long>(rd.get<std::int64_t>());
    res.b += static_cast<long>(rd.get<std::int64_t>());
    for (long t = static_cast<long>(rd.get<std::int64_t>()); rd.ok() && t >= 0;
         t = static_cast<long>(rd.get<std::int64_t>())) {
      ARMSTUDY_CHECK(t >= r.begin && t < r.end && getPose(rd, s_, active[t]),
                     "a search step's rows arrive whole");
      now_[active[t]] = 1;
      res.adopted.push_back(active[t]);
    }
    while (rd.ok() && !rd.finished()) {
      const long t = static_cast<long>(rd.get<std::int64_t>());
      const long spent = static_cast<long>(rd.get<std::int64_t>());
      ARMSTUDY_CHECK(rd.ok() && spends && t >= r.begin && t < r.end,
                     "a search step's start counts arrive whole");
      extra_[active[t]] += static_cast<int>(spent);
    }
    ARMSTUDY_CHECK(rd.finished(), "a search step's rows arrive whole");
  }

  // One step over the poses `active` (ascending), in chunks of `chunk` poses (a loop shared among
  // the processes of a distributed run): body computes each pose's candidate and counts into a and
  // b (a: the starts it spent, which count into the pose's starts when `spends` is set). The spent
  // starts travel with the adopted rows, so that every process counts them whichever process
  // computed a pose.
  template <class Body>
  StepResult step(const char* phase, int grain, long chunk, bool spends,
                  const std::vector<long>& active, Body&& body) {
    std::fill(now_.begin(), now_.end(), 0);
    StepResult res;
    ChunkCounts counts;
    SharedLoop loop;
    loop.id = "search/" + s_.design + "/" + std::to_string(steps_++) + "_" + phase;
    loop.items = static_cast<long>(active.size());
    loop.chunk = chunk;
    loop.compute = [&](const std::vector<SharedLoop::Chunk>& mine) {
      computeItems(active, SharedLoop::itemsOf(mine), grain, body);
      for (const SharedLoop::Chunk& c : mine) {
        std::pair<long, long>& ab = counts[c.first];
        for (long t = c.second.begin; t < c.second.end; ++t) {
          ab.first += item_a_[active[t]];
          ab.second += item_b_[active[t]];
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
          if (spends) extra_[i] += static_cast<int>(item_a_[i]);
          if (now_[i]) {
            store(s_, i, found_[i].ik, s_.starts[i]);
            storeCollision(s_, i, found_[i]);
            res.adopted.push_back(i);
          }
        }
      }
    };
    loop.pack = [&](std::size_t k, const ItemRange& r) {
      return packChunk(active, counts.at(k), r, spends);
    };
    loop.unpack = [&](std::size_t, const ItemRange& r, const std::string& bytes) {
      unpackChunk(active, r, bytes, spends, res);
    };
    runSharedLoop(runner_, loop);
    std::sort(res.adopted.begin(), res.adopted.end());
    for (const long i : res.adopted) touched_[i] = 1;
    return res;
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
      ++sum_.rounds;
      sum_.neighbour_tries += r.a;
      sum_.neighbour_updates += r.b;
      changed_.swap(now_);
      from = r.adopted;
      first = false;
      if (r.b == 0) return;
    }
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
      for (int a = 0; a < seeds; ++a) {
        const JointVector w = a == 0 ? solutionOf(s_, nb[k]) : alternativeOf(s_, nb[k]);
        PoseResult pr = solver.solve(i, one_, &w, 0);
        ++tries;
        if (!improves(pr, now_[i] ? found_[i].ik.status : cur)) continue;
        found_[i] = std::move(pr);
        now_[i] = 1;
        if (found_[i].ik.reachable()) break;
      }
      if (now_[i] && found_[i].ik.reachable()) break;
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
    sum_.multistart_tries = r.a;
    sum_.multistart_freed = r.b;
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
               for (int k = 0; k < count && !now_[i]; ++k) {
                 if (!s_.reachable(nb[k])) continue;
                 for (int a = 0; a < (hasAlternative(s_, nb[k]) ? 2 : 1) && !now_[i]; ++a) {
                   const JointVector w = a == 0 ? solutionOf(s_, nb[k]) : alternativeOf(s_, nb[k]);
                   PoseResult pr = solver.solve(i, one_, &w, 0);
                   ++tries;
                   if (!pr.ik.reachable()) continue;
                   found_[i] = std::move(pr);
                   now_[i] = 1;
                   ++freed;
                 }
               }
             });
    sum_.box_tries = r.a;
    sum_.box_freed = r.b;
    changed_ = now_;
    if (r.b > 0) propagate(false, r.adopted);
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
      ++sum_.best_rounds;
      sum_.best_tries += r.a;
      sum_.best_updates += r.b;
      src.swap(now_);
      from = r.adopted;
      if (r.b == 0) break;
    }
  }

  const Model& model_;
  const std::function<PoseTask(long)>& target_;
  const Neighbours& neighbours_;
  const Neighbours& box_;
  const SweepCollision& collision_;
  const SweepSearch& search_;
  const UnitRunner* runner_;
  PoseSweep& s_;
  const long N_;
  const int nt_;
  IkOptions one_;
  SweepSearchSummary sum_;
  std::vector<std::uint8_t> changed_;
  std::vector<int> extra_;  // starts spent on the pose by the search (every process counts all)
  std::vector<PoseResult> found_;      // per-step candidates (allocated once)
  std::vector<std::uint8_t> now_;      // found_[i] is this step's candidate where now_[i]
  std::vector<long> item_a_, item_b_;  // a step's counts per pose (summed per chunk)
  std::vector<std::uint8_t> mark_;     // scratch of `around`
  std::vector<std::uint8_t> touched_;  // rows the search changed (summary.changed)
  // One pose solver per thread for the whole search, built on first use (a step's compute may be
  // called once per chunk, e.g. when unit costs are recorded; the solvers hold workspaces only).
  std::vector<std::unique_ptr<PoseSolver>> solvers_;
  int steps_ = 0;  // steps so far (names them in the unit-cost record)
};

SweepSearchSummary searchSweep(const Model& model, const std::function<PoseTask(long)>& target,
                               const Neighbours& neighbours, const Neighbours& box,
                               const IkOptions& options, int threads,
                               const SweepCollision& collision, const SweepSearch& search,
                               const UnitRunner* runner, PoseSweep& s) {
  return MapSearch(model, target, neighbours, box, options, threads, collision, search, runner, s)
      .run();
}

constexpr std::string_view kResultMagic = "armstudy-search-result-1";

}  // namespace

std::string packSearchResult(const PoseSweep& s, const SweepSearchSummary& sum) {
  UnitWriter w(kResultMagic);
  w.put<std::int64_t>(s.size);
  w.put<std::int64_t>(sum.rounds);
  for (const long v : {sum.neighbour_tries, sum.neighbour_updates, sum.multistart_poses,
                       sum.multistart_tries, sum.multistart_freed, sum.box_tries, sum.box_freed})
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
  for (long* v : {&sum.neighbour_tries, &sum.neighbour_updates, &sum.multistart_poses,
                  &sum.multistart_tries, &sum.multistart_freed, &sum.box_tries, &sum.box_freed})
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
    ARMSTUDY_CHECK(rd.ok() && i >= 0 && i < s.size && getPose(rd, s, i),
                   "a search result's rows arrive whole");
    sum.changed.push_back(i);
  }
  ARMSTUDY_CHECK(rd.finished(), "a search result arrives whole");
}

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
