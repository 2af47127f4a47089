#pragma once
// Private to reach/reach_search.cpp: the Jacobi step a map search is made of. A step computes each
// pose's candidate of its active set from the sweep as it was before the step, then the poses that
// found one adopt it. A step is a loop shared among the processes of a distributed run
// (UnitRunner::share: each computes the poses of its chunks and sends the adopted rows), so the
// map is the same whichever process computed a pose.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "reach/sweep_internal.hpp"
#include "study/shared_loop.hpp"

namespace armstudy::sweep_detail {

// Poses per chunk of a search step's shared loop for an active set of `active` poses: at most 8,
// fewer for a small active set (see search_steps.cpp).
long searchStepChunk(std::size_t active);

class SearchSteps {
 public:
  // A step's totals of its two counts, its pose solves (changed: the poses that adopted a
  // candidate) and the poses that adopted a candidate (ascending).
  struct StepResult {
    long a = 0, b = 0;
    SolveTally tally;
    std::vector<long> adopted;
  };
  // Computes pose i's candidate into found_[i] (marking now_[i]) and counts into a and b; nb holds
  // room for 28 neighbours.
  using Body = std::function<void(PoseSolver& solver, long i, long* nb, long& a, long& b)>;

 protected:
  SearchSteps(const Model& model, const std::function<PoseTask(long)>& target,
              const SweepCollision& collision, const UnitRunner* runner, int threads, PoseSweep& s);

  // One step over the poses `active` (ascending), in chunks of `chunk` poses (a loop shared among
  // the processes of a distributed run), `grain` poses per thread at a time: body computes each
  // pose's candidate and counts into a and b (a: the starts it spent, which count into the pose's
  // starts when `spends` is set). The spent starts travel with the adopted rows, so that every
  // process counts them whichever process computed a pose.
  StepResult step(const char* phase, int grain, long chunk, bool spends,
                  const std::vector<long>& active, const Body& body);

  const Model& model_;
  const std::function<PoseTask(long)>& target_;
  const SweepCollision& collision_;
  const UnitRunner* runner_;
  PoseSweep& s_;
  const long N_;
  const int nt_;
  std::vector<int> extra_;  // starts spent on the pose by the search (every process counts all)
  std::vector<PoseResult> found_;      // per-step candidates (allocated once)
  std::vector<std::uint8_t> now_;      // found_[i] is this step's candidate where now_[i]
  std::vector<std::uint8_t> touched_;  // rows the search changed (summary.changed)

 private:
  // A chunk's totals of the two counts and of its poses' solves.
  struct ChunkCount {
    long a = 0, b = 0;
    SolveTally tally;
  };
  using ChunkCounts = std::map<std::size_t, ChunkCount>;  // per chunk computed here

  void computeItems(const std::vector<long>& active, const std::vector<long>& items, int grain,
                    const Body& body);
  std::string packChunk(const std::vector<long>& active, const ChunkCount& counts,
                        const ItemRange& r, bool spends) const;
  void unpackChunk(const std::vector<long>& active, const ItemRange& r, const std::string& bytes,
                   bool spends, StepResult& res);

  std::vector<long> item_a_, item_b_;   // a step's counts per pose (summed per chunk)
  std::vector<SolveTally> item_tally_;  // ... and its pose solves
  // One pose solver per thread for the whole search, built on first use (a step's compute may be
  // called once per chunk, e.g. when unit costs are recorded; the solvers hold workspaces only).
  std::vector<std::unique_ptr<PoseSolver>> solvers_;
  int steps_ = 0;  // steps so far (names them in the unit-cost record)
};

}  // namespace armstudy::sweep_detail
