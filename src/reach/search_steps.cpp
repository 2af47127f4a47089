#include "reach/search_steps.hpp"

#include <omp.h>

#include <algorithm>
#include <string_view>

#include "common/errors.hpp"

namespace armstudy::sweep_detail {

namespace {
constexpr std::string_view kStepMagic = "armstudy-search-step-3";
// Poses per chunk of a search step's shared loop. A step visits only the poses that can change (its
// active set), which are mostly costly ones, so chunks are small: at most 8 poses, fewer when the
// active set has fewer than 8 x kSearchStepChunks poses, so that a step has that many chunks to
// spread over the ranks of a distributed run (owned round-robin; a unit-cost record holds the step
// at this grain). Steps whose every pose is a many-start search (multistart, box) use single poses.
constexpr long kSearchStepMaxChunk = 8;
constexpr long kSearchStepChunks = 1024;
}  // namespace

long searchStepChunk(std::size_t active) {
  return std::clamp(static_cast<long>(active) / kSearchStepChunks, 1L, kSearchStepMaxChunk);
}

SearchSteps::SearchSteps(const Model& model, const std::function<PoseTask(long)>& target,
                         const SweepCollision& collision, const UnitRunner* runner, int threads,
                         PoseSweep& s)
    : model_(model),
      target_(target),
      collision_(collision),
      runner_(runner),
      s_(s),
      N_(s.size),
      nt_(threads > 0 ? threads : omp_get_max_threads()),
      extra_(N_, 0),
      found_(N_),
      now_(N_, 0),
      touched_(N_, 0),
      item_a_(N_, 0),
      item_b_(N_, 0),
      item_tally_(N_),
      solvers_(static_cast<std::size_t>(nt_)) {}

// Computes the candidates of the poses of `items` (indices into `active`) on the run's threads:
// body(solver, i, nb, a, b) computes pose i's candidate and counts into a and b.
void SearchSteps::computeItems(const std::vector<long>& active, const std::vector<long>& items,
                               int grain, const Body& body) {
  const long n = static_cast<long>(items.size());
  for (const long t : items) item_a_[active[t]] = item_b_[active[t]] = 0;
#pragma omp parallel num_threads(nt_)
  {
    std::unique_ptr<PoseSolver>& solver = solvers_[static_cast<std::size_t>(omp_get_thread_num())];
    if (!solver) solver = std::make_unique<PoseSolver>(model_, collision_, target_);
    long nb[28];
#pragma omp for schedule(dynamic, grain)
    for (long t = 0; t < n; ++t) {
      const long i = active[items[t]];
      body(*solver, i, nb, item_a_[i], item_b_[i]);
      item_tally_[i] = solver->take();
    }
  }
}

// A chunk's adopted rows and spent starts as bytes, by item index (its position in the active
// set); empty when nothing was tried there.
std::string SearchSteps::packChunk(const std::vector<long>& active, const ChunkCount& counts,
                                   const ItemRange& r, bool spends) const {
  if (counts.a == 0 && counts.b == 0) return std::string();
  UnitWriter w(kStepMagic);
  w.put<std::int64_t>(counts.a);
  w.put<std::int64_t>(counts.b);
  putTally(w, counts.tally);
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
void SearchSteps::unpackChunk(const std::vector<long>& active, const ItemRange& r,
                              const std::string& bytes, bool spends, StepResult& res) {
  if (bytes.empty()) return;
  UnitReader rd(bytes, kStepMagic);
  res.a += static_cast<long>(rd.get<std::int64_t>());
  res.b += static_cast<long>(rd.get<std::int64_t>());
  SolveTally tally;
  getTally(rd, tally);
  res.tally.add(tally);
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
SearchSteps::StepResult SearchSteps::step(const char* phase, int grain, long chunk, bool spends,
                                          const std::vector<long>& active, const Body& body) {
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
      ChunkCount& ab = counts[c.first];
      for (long t = c.second.begin; t < c.second.end; ++t) {
        ab.a += item_a_[active[t]];
        ab.b += item_b_[active[t]];
        ab.tally.add(item_tally_[active[t]]);
      }
    }
  };
  // The step ends: the poses computed here adopt their candidates.
  loop.finish = [&](const std::vector<SharedLoop::Chunk>& mine) {
    for (const SharedLoop::Chunk& c : mine) {
      res.a += counts.at(c.first).a;
      res.b += counts.at(c.first).b;
      res.tally.add(counts.at(c.first).tally);
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
  res.tally.changed = static_cast<long>(res.adopted.size());
  return res;
}

}  // namespace armstudy::sweep_detail
