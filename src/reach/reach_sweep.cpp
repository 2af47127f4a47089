#include "reach/reach_sweep.hpp"

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
#include <span>

#include "collision/reach_collision.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "common/first_exception.hpp"
#include "reach/sweep_internal.hpp"

namespace armstudy {

long PoseSweep::countReachable() const {
  long n = 0;
  for (long i = 0; i < size; ++i) n += reachable(i) ? 1 : 0;
  return n;
}

namespace {
// 42 s, 3 min 05 s, 1 h 02 min
std::string formatDuration(double seconds) {
  const long s = static_cast<long>(seconds + 0.5);
  char b[32];
  if (s < 60)
    std::snprintf(b, sizeof b, "%ld s", s);
  else if (s < 3600)
    std::snprintf(b, sizeof b, "%ld min %02ld s", s / 60, s % 60);
  else
    std::snprintf(b, sizeof b, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  return b;
}
}  // namespace

Progress::Progress(long total, bool enabled, std::string label)
    : total_(std::max(1L, total)),
      enabled_(enabled && isatty(STDERR_FILENO)),
      label_(std::move(label)) {}

Progress::~Progress() {
  if (enabled_ && last_permille_ >= 0) std::fprintf(stderr, "\n");
}

void Progress::advance(long n) {
  if (!enabled_) return;
  const long done = done_.fetch_add(n) + n;
  const int permille = static_cast<int>(1000 * done / total_);
  int last = last_permille_.load();
  if (permille / 5 == last / 5 && last >= 0) return;
  if (!last_permille_.compare_exchange_strong(last, permille)) return;
  const int width = 40, fill = permille * width / 1000;
  // Elapsed time and the remaining time extrapolated from the rate so far (the first 2 % are too
  // few to extrapolate from: no ETA yet).
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  char eta[32] = "";
  if (done >= total_)
    std::snprintf(eta, sizeof eta, "done");
  else if (permille >= 20)
    std::snprintf(eta, sizeof eta, "ETA %s",
                  formatDuration(elapsed * double(total_ - done) / double(done)).c_str());
  std::fprintf(stderr, "\r%-32.32s [%.*s%*s] %5.1f %% %8s %-12s", label_.c_str(), fill,
               "########################################", width - fill, "", permille / 10.0,
               formatDuration(elapsed).c_str(), eta);
  std::fflush(stderr);
}

using namespace sweep_detail;

namespace {
// One chain along poses [begin, end) in direction dir, into out (entry i - out_off); `retry` is
// the one-start solve of the backward pass. Adds the solve times to t_reach / t_unreach.
void chainLine(PoseSolver& solver, const IkOptions& options, const IkOptions& retry, long begin,
               long end, long dir, PoseSweep& out, long out_off, double& t_reach,
               double& t_unreach) {
  JointVector warm(out.dof);
  bool have_warm = false;
  const long first = dir > 0 ? begin : end - 1, past = dir > 0 ? end : begin - 1;
  for (long i = first; i != past; i += dir) {
    const auto p0 = std::chrono::steady_clock::now();
    const PoseResult pr = solver.solve(i, options, have_warm ? &warm : nullptr);
    const IkResult& r = pr.ik;
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - p0).count();
    (r.reachable() ? t_reach : t_unreach) += dt;
    store(out, i - out_off, r, 0);
    storeCollision(out, i - out_off, pr);
    if (r.reachable()) {
      warm = r.q;
      have_warm = true;
    }
  }
  // Backward pass: an unreachable pose next to a reachable one gets one more start from its
  // neighbour's solution (the one after it in the chain's direction). A pose reachable only
  // in collision keeps its result unless the retry finds a collision-free solution; an
  // unreachable one also takes a solution in collision.
  for (long i = past - 2 * dir; i != first - dir; i -= dir) {
    const long li = i - out_off;
    if (out.reachable(li) || !out.reachable(li + dir)) continue;
    const JointVector w = solutionOf(out, li + dir);
    const auto p0 = std::chrono::steady_clock::now();
    const PoseResult pr = solver.solve(i, retry, &w);
    const IkResult& r = pr.ik;
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - p0).count();
    (r.reachable() ? t_reach : t_unreach) += dt;
    if (r.reachable() ||
        (inCollision(r.status) && !inCollision(static_cast<ReachStatus>(out.status[li])))) {
      store(out, li, r, out.starts[li]);
      storeCollision(out, li, pr);
    }
  }
}

// Every pose of the line [begin, begin + n) keeps the better of the two chains' results (one
// chain when passes == 1) in s, and the other chain's distinct collision-free solution in q_alt.
void keepBetterChain(const PoseSweep& first_chain, const PoseSweep& second_chain, int passes,
                     long begin, long n, PoseSweep& s) {
  const long off = s.offset;
  for (long li = 0; li < n; ++li) {
    const bool second = passes == 2 && betterPose(second_chain, first_chain, li);
    const PoseSweep &kept = second ? second_chain : first_chain,
                    &other = second ? first_chain : second_chain;
    copyPose(kept, li, s, begin - off + li,
             first_chain.starts[li] + (passes == 2 ? second_chain.starts[li] : 0));
    // The other chain's collision-free solution, where it differs: a second seed for the
    // search.
    const std::size_t to = static_cast<std::size_t>(begin - off + li) * s.dof,
                      from = static_cast<std::size_t>(li) * s.dof;
    const bool distinct =
        passes == 2 && other.reachable(li) &&
        !std::equal(other.q.begin() + from, other.q.begin() + from + s.dof, kept.q.begin() + from);
    for (int j = 0; j < s.dof; ++j)
      s.q_alt[to + j] = distinct ? other.q[from + j] : std::numeric_limits<double>::quiet_NaN();
  }
}

// Solves the units of every range (unit u covers poses [u * len, min((u+1) * len, size))) into
// one chunk per range; see sweepGridRanges.
std::vector<PoseSweep> sweepRanges(const Model& model, long size, long len,
                                   const std::function<PoseTask(long)>& target,
                                   const std::vector<ItemRange>& ranges, const IkOptions& options,
                                   int threads, Progress* progress, const SweepCollision& collision,
                                   const SweepChunkDone& on_done) {
  ARMSTUDY_CHECK(options.validate().empty(), options.validate());
  ARMSTUDY_CHECK(!collision.enabled() || !model.collision.empty(),
                 "collision-aware sweep of design '" + model.name + "' without a collision model");
  ARMSTUDY_CHECK(static_cast<int>(collision.obstacles.size()) <= collision::kMaxObstacles,
                 "too many obstacles");
  const long units = (size + len - 1) / len;
  const int nt = threads > 0 ? threads : omp_get_max_threads();
  std::vector<PoseSweep> chunks;
  std::vector<std::pair<std::size_t, long>> work;  // (range, unit), in order
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    const ItemRange& r = ranges[k];
    ARMSTUDY_CHECK(0 <= r.begin && r.begin < r.end && r.end <= units,
                   "sweep unit range out of bounds");
    const long first = r.begin * len, last = std::min(size, r.end * len);
    chunks.push_back(makeSweep(model, last - first, collision));
    chunks.back().offset = first;
    chunks.back().threads = nt;
    for (long u = r.begin; u < r.end; ++u) work.emplace_back(k, u);
  }
  RangeCountdown countdown(ranges);
  FirstException failure;
  IkOptions retry = options;
  retry.max_starts = 1;
  retry.classify_failures = false;
  const auto t0 = std::chrono::steady_clock::now();
  const long n_work = static_cast<long>(work.size());
#pragma omp parallel num_threads(nt)
  {
    PoseSolver solver(model, collision, target);
    PoseSweep first_chain = makeSweep(model, len, collision), second_chain = first_chain;
#pragma omp for schedule(dynamic, 1)
    for (long w = 0; w < n_work; ++w) {
      const std::size_t k = work[w].first;  // not a structured binding: captured below (clang)
      const long u = work[w].second;
      PoseSweep& s = chunks[k];
      const long begin = u * len, end = std::min(size, begin + len);
      double t_reach = 0, t_unreach = 0;
      // Each line is chained in both directions (forward from its start, forward from its end),
      // each with its own backward pass; every pose keeps the better of the two results
      // (betterPose, a total order that does not know which direction came first). So the result
      // does not depend on the traversal direction (IkOptions::sweep_descending only decides
      // which chain runs first).
      const long n = end - begin;
      const int passes = options.sweep_both_directions ? 2 : 1;
      for (int pass = 0; pass < passes; ++pass) {
        PoseSweep& out = pass == 0 ? first_chain : second_chain;
        const long dir = (pass == 0) != options.sweep_descending ? 1 : -1;
        chainLine(solver, options, retry, begin, end, dir, out, begin, t_reach, t_unreach);
      }
      keepBetterChain(first_chain, second_chain, passes, begin, n, s);
      SolveTally line = solver.take();
      line.changed = n;  // each pose's row is one of the chains' results
#pragma omp critical(reach_chain_tally)
      s.chain.add(line);
#pragma omp atomic
      s.solve_seconds_reachable += t_reach;
#pragma omp atomic
      s.solve_seconds_unreachable += t_unreach;
      if (progress) progress->advance(end - begin);
      if (countdown.itemDone(k)) {
        s.wall_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (on_done) failure.call([&] { on_done(k, s); });
      }
    }
  }
  failure.rethrow();
  return chunks;
}

PoseSweep wholeSweep(std::vector<PoseSweep> chunks, long size, const Model& model,
                     const SweepCollision& collision) {
  if (chunks.empty()) {  // an empty grid or list
    PoseSweep s = makeSweep(model, size, collision);
    s.threads = 1;
    return s;
  }
  return std::move(chunks.front());
}

}  // namespace

long sweepUnitLength(const TaskGrid& grid) { return grid.lineLength(); }
long sweepUnitLength(const PoseList&) { return defaults::kPoseListChunk; }
long sweepUnitCount(const TaskGrid& grid) {
  return (grid.size() + grid.lineLength() - 1) / grid.lineLength();
}
long sweepUnitCount(const PoseList& list) {
  return (static_cast<long>(list.poses.size()) + defaults::kPoseListChunk - 1) /
         defaults::kPoseListChunk;
}

std::vector<PoseSweep> sweepGridRanges(const Model& model, const TaskGrid& grid,
                                       const std::vector<ItemRange>& ranges,
                                       const IkOptions& options, int threads, Progress* progress,
                                       const SweepCollision& collision,
                                       const SweepChunkDone& on_done) {
  ARMSTUDY_CHECK(grid.validate().empty(), grid.validate());
  return sweepRanges(
      model, grid.size(), sweepUnitLength(grid),
      [&grid](long i) { return taskTarget(grid.task_space, grid.pose(i)); }, ranges, options,
      threads, progress, collision, on_done);
}

std::vector<PoseSweep> sweepPoseListRanges(const Model& model, const PoseList& list,
                                           const std::vector<ItemRange>& ranges,
                                           const IkOptions& options, int threads,
                                           Progress* progress, const SweepCollision& collision,
                                           const SweepChunkDone& on_done) {
  return sweepRanges(
      model, static_cast<long>(list.poses.size()), sweepUnitLength(list),
      [&list](long i) { return taskTarget(list.task_space, list.poses[i]); }, ranges, options,
      threads, progress, collision, on_done);
}

PoseSweep sweepGrid(const Model& model, const TaskGrid& grid, const IkOptions& options, int threads,
                    Progress* progress, const SweepCollision& collision) {
  const long units = sweepUnitCount(grid);
  std::vector<ItemRange> all;
  if (units > 0) all.push_back({0, units});
  return wholeSweep(sweepGridRanges(model, grid, all, options, threads, progress, collision),
                    grid.size(), model, collision);
}

PoseSweep sweepPoseList(const Model& model, const PoseList& list, const IkOptions& options,
                        int threads, Progress* progress, const SweepCollision& collision) {
  const long units = sweepUnitCount(list);
  std::vector<ItemRange> all;
  if (units > 0) all.push_back({0, units});
  return wholeSweep(sweepPoseListRanges(model, list, all, options, threads, progress, collision),
                    static_cast<long>(list.poses.size()), model, collision);
}

PoseSweep assembleSweep(std::vector<PoseSweep> chunks, long size) {
  ARMSTUDY_CHECK(!chunks.empty(), "no chunks to assemble");
  std::sort(chunks.begin(), chunks.end(),
            [](const PoseSweep& a, const PoseSweep& b) { return a.offset < b.offset; });
  // The first chunk, with the others' poses appended.
  PoseSweep s = std::move(chunks.front());
  long next = s.size;
  ARMSTUDY_CHECK(s.offset == 0,
                 "sweep chunks of '" + s.design + "' leave a gap or overlap at pose 0");
  for (const PoseSweep& c : std::span(chunks).subspan(1)) {
    ARMSTUDY_CHECK(c.offset == next, "sweep chunks of '" + s.design +
                                         "' leave a gap or overlap at pose " +
                                         std::to_string(next));
    ARMSTUDY_CHECK(c.dof == s.dof && c.collision == s.collision && c.obstacles == s.obstacles &&
                       c.pair_names == s.pair_names,
                   "sweep chunks of '" + s.design + "' do not match");
    next += c.size;
    forEachPoseArray(
        [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); }, s, c);
    s.wall_seconds = std::max(s.wall_seconds, c.wall_seconds);
    s.threads = std::max(s.threads, c.threads);
    s.solve_seconds_reachable += c.solve_seconds_reachable;
    s.solve_seconds_unreachable += c.solve_seconds_unreachable;
    s.chain.add(c.chain);
  }
  ARMSTUDY_CHECK(next == size, "sweep chunks of '" + s.design + "' cover " + std::to_string(next) +
                                   " of " + std::to_string(size) + " poses");
  s.size = size;
  return s;
}

}  // namespace armstudy
