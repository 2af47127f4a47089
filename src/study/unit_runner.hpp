#pragma once
// Work units and the runner that computes, saves, loads and (in a distributed run) shares them
// (docs/architecture.md, "Stages"; docs/distributed.md).
#include <cstddef>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "study/checkpoint.hpp"
#include "study/shared_loop.hpp"

namespace armstudy {

class CheckpointStore;

// A stage's work, cut into units: the grain of checkpointing and of distribution. Ids are stable
// ("<stage>/<design>/<range>") and unique within a run; units are independent of each other, and
// a unit's bytes (UnitWriter) hold its whole result bit for bit, so a loaded unit equals the
// computed one and the stage's merge does not depend on where or in which order units ran.
//
// A runner may call `compute` several times for one batch (disjoint lists: units handed out one
// after another, or one per call when unit costs are recorded); each call replaces what an earlier
// call computed, i.e. the stage keeps the results of the latest call only. Afterwards `load` is
// called for every other unit the stage needs: units saved by an interrupted run, units an earlier
// call computed, units other processes computed (docs/distributed.md).
struct UnitBatch {
  std::vector<std::string> ids;  // index order
  // Takes the bytes of unit k saved by an earlier run (or computed by another call or process);
  // false when they do not fit (the unit is then computed again). Called from one thread.
  std::function<bool(std::size_t k, const std::string& bytes)> load;
  // Computes the listed units (indices into ids, ascending) with the run's threads and calls
  // done(k, bytes) once per unit as soon as it is complete (concurrently for distinct units). The
  // list may be empty (runUnitBatches: this batch has no units in that call).
  using Done = std::function<void(std::size_t k, const std::string& bytes)>;
  std::function<void(const std::vector<std::size_t>& todo, const Done& done)> compute;
  // False when a unit's result is not all in its bytes: it also writes files into the output
  // folder whose content names that folder (calibration entries). Such a batch is never split
  // across processes: in a distributed run every process computes all of it in its own folder and
  // only the first process uses the checkpoint store.
  bool portable = true;
};

// Opt-in record of per-unit costs (docs/distributed.md, "Unit costs"): when the environment
// variable ARMSTUDY_UNIT_TIMES names a CSV file, every computed unit is computed in a call of its
// own and one line "unit,seconds,cpu_seconds,threads,rank,bytes,part" is appended per unit (wall
// and process CPU seconds of its call, the threads and rank that computed it, the size of its
// result, and for a shared loop's chunk the part it belongs to, SharedLoop::part, else empty).
// Outside the result files; tests/benchmarks/simulate_distribution.py reads it.
struct UnitTimeRecord {
  std::string path;  // empty: off
  static UnitTimeRecord fromEnvironment();
  bool enabled() const { return !path.empty(); }
  struct Line {
    std::string unit;
    double seconds = 0, cpu_seconds = 0;
    int threads = 1, rank = 0;
    std::size_t bytes = 0;
    long part = -1;  // SharedLoop::part of a chunk; -1: none
  };
  void append(const std::vector<Line>& lines) const;
  // CPU seconds of this process so far (all threads).
  static double processCpuSeconds();
};

// How a distributed run's processes split into groups for independent programs
// (UnitRunner::groups): the group of each program and the processes of each group, consecutive
// ranks. planRankGroups makes it from the programs' predicted costs: min(programs, ranks /
// min_ranks) groups; the programs dealt out costliest first, each to the group with the least
// cost so far (lowest index on ties); the ranks shared out in proportion to the groups' costs
// (at least one each; the largest remainders get the rest). Fewer than two groups: `ranks` empty.
// tests/benchmarks/simulate_distribution.py (--groups) mirrors it.
struct RankGroupPlan {
  std::vector<std::size_t> group_of;  // per program
  std::vector<int> ranks;             // per group
};
RankGroupPlan planRankGroups(const std::vector<double>& weights, int ranks, int min_ranks);

// One process's view of rank groups (UnitRunner::groups).
class RankGroups {
 public:
  virtual ~RankGroups() = default;
  std::vector<std::size_t> group_of;  // per program
  std::size_t mine = 0;               // this process's group
  bool sends = true;                  // this process sends its group's results (one per group)
  // The runner of this process's group: its shared loops span the group's processes only.
  virtual const UnitRunner& runner() const = 0;
  // Every program's result bytes on every process: `mine` holds those of this group's programs
  // (one process of the group sends them; the other entries are ignored). Collective.
  virtual std::vector<std::string> exchange(const std::vector<std::string>& mine) const = 0;
};

// Runs the units of batches: loads those an interrupted run saved (same fingerprint), computes
// the rest and saves each as soon as it is done. One per study run; stages only see this. This
// class is the single-process runner; a distributed run uses a subclass (study/distributed.hpp)
// that splits each batch's units among the processes.
// Thrown by a runner between units when RunOptions::cancelled says so: what was computed is saved,
// the run resumes.
struct RunCancelled : std::runtime_error {
  RunCancelled() : std::runtime_error("the run was cancelled; its completed units are saved") {}
};

class UnitRunner {
 public:
  explicit UnitRunner(const CheckpointStore& store, int threads = 1,
                      UnitTimeRecord times = UnitTimeRecord::fromEnvironment())
      : store_(store), threads_(threads), times_(std::move(times)) {}
  virtual ~UnitRunner() = default;
  // Returns the number of units loaded instead of computed.
  virtual long run(const UnitBatch& batch) const;
  // A collective loop (every process calls it with the same loop.items): the items are cut into
  // chunks, each process computes the chunks it owns, and every process ends up with every chunk's
  // results (not checkpointed: for the steps of a search over a whole batch, e.g. the reach map
  // search's Jacobi rounds). Results must not depend on which process computes a chunk.
  virtual void share(const SharedLoop& loop) const;
  // The runner for work nested inside one unit (e.g. the stages an exploration runs for one
  // candidate): this process alone, the same store. A distributed runner's run and share are
  // collective, so a unit that one rank computes must not call them.
  virtual const UnitRunner& local() const { return *this; }
  // Rank groups for independent programs (study/interleave.hpp) of predicted costs `weights`:
  // each group of processes runs some of the programs on its own, and the programs' results then
  // travel to every process. Null when every process runs every program (a single process, or too
  // few processes for two groups). Collective.
  virtual std::unique_ptr<RankGroups> groups(const std::vector<double>& weights) const;
  const CheckpointStore& store() const { return store_; }
  // RunOptions::cancelled: asked between slices of units by run() (single process only).
  void setCancelled(std::function<bool()> cancelled) { cancelled_ = std::move(cancelled); }

 protected:
  std::function<bool()> cancelled_;
  const CheckpointStore& store_;
  int threads_ = 1;  // recorded with unit times
  UnitTimeRecord times_;
};

// A batch whose unit k covers the items ranges[k] and is named ids[k] (unitIds: "<prefix><range>"),
// with the bookkeeping between the runner's unit indices and the ranges done here: `load(k,
// bytes)` takes unit k's saved bytes (false: they do not fit); `compute(units, todo, done)`
// computes the listed units (ascending) whose ranges are todo (todo[j] = ranges[units[j]]) and
// calls done(j, bytes) as soon as todo[j] is complete.
using RangeDone = std::function<void(std::size_t j, const std::string& bytes)>;
using RangeCompute = std::function<void(const std::vector<std::size_t>& units,
                                        const std::vector<ItemRange>& todo, const RangeDone& done)>;
UnitBatch rangeUnitBatch(std::vector<std::string> ids, std::vector<ItemRange> ranges,
                         std::function<bool(std::size_t k, const std::string& bytes)> load,
                         RangeCompute compute);
std::vector<std::string> unitIds(const std::string& prefix, const std::vector<ItemRange>& ranges);

// Runs several batches as one (one pool of units: one hand-out and one exchange in a distributed
// run instead of one per batch). Every batch sees what it would see run alone: its own indices,
// and every call of the combined compute calls every batch's compute (an empty list for a batch
// without units in that call), so each call replaces every batch's previous units as UnitBatch
// requires. Batches that are not portable run one by one. Returns the units loaded.
long runUnitBatches(const UnitRunner& runner, const std::vector<UnitBatch>& batches);

}  // namespace armstudy
