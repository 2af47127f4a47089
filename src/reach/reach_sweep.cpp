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

#include "collision/reach_collision.hpp"
#include "common/errors.hpp"
#include "common/defaults.hpp"

namespace armstudy {

long PoseSweep::countReachable() const {
  long n = 0;
  for (long i = 0; i < size; ++i) n += reachable(i) ? 1 : 0;
  return n;
}

Progress::Progress(long total, bool enabled, std::string label)
    : total_(std::max(1L, total)), enabled_(enabled && isatty(STDERR_FILENO)), label_(std::move(label)) {}

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
  std::fprintf(stderr, "\r%-32.32s [%.*s%*s] %5.1f %%", label_.c_str(), fill,
               "########################################", width - fill, "", permille / 10.0);
  std::fflush(stderr);
}

namespace {

PoseSweep makeSweep(const Model& model, long size, const SweepCollision& collision) {
  PoseSweep s;
  s.design = model.name;
  s.dof = model.dof();
  s.size = size;
  s.status.assign(size, 0);
  s.starts.assign(size, 0);
  s.position_error_m.assign(size, 0);
  s.orientation_error_rad.assign(size, 0);
  s.manipulability.assign(size, 0);
  s.joint_limit_margin.assign(size, 0);
  s.q.assign(static_cast<std::size_t>(size) * s.dof, 0);
  s.q_alt.assign(static_cast<std::size_t>(size) * s.dof, std::numeric_limits<double>::quiet_NaN());
  s.collision = collision.enabled();
  if (s.collision) {
    s.min_distance_m.assign(size, std::numeric_limits<double>::quiet_NaN());
    s.colliding_pair.assign(size, -1);
    s.pair_names = collision::collisionPairNames(model, collision.obstacles, collision.self);
  }
  s.obstacles = !collision.obstacles.empty();
  if (s.obstacles) s.obstacle_distance_m.assign(size, std::numeric_limits<double>::quiet_NaN());
  return s;
}

void store(PoseSweep& s, long i, const IkResult& r, int extra_starts) {
  s.status[i] = static_cast<std::uint8_t>(r.status);
  s.starts[i] = static_cast<std::uint8_t>(std::min(255, r.starts + extra_starts));
  s.position_error_m[i] = r.position_error_m;
  s.orientation_error_rad[i] = r.orientation_error_rad;
  s.manipulability[i] = r.manipulability;
  s.joint_limit_margin[i] = r.joint_limit_margin;
  for (int k = 0; k < s.dof; ++k) s.q[static_cast<std::size_t>(i) * s.dof + k] = r.q[k];
}

// A pose's result with or without the collision check (min_distance_m / pair only with it).
struct PoseResult {
  IkResult ik;
  double min_distance_m = std::numeric_limits<double>::quiet_NaN();
  double obstacle_distance_m = std::numeric_limits<double>::quiet_NaN();
  int pair = -1;
};

void storeCollision(PoseSweep& s, long i, const PoseResult& r) {
  if (!s.collision) return;
  s.min_distance_m[i] = r.min_distance_m;
  s.colliding_pair[i] = static_cast<std::int16_t>(r.pair);
  if (s.obstacles) s.obstacle_distance_m[i] = r.obstacle_distance_m;
}

bool inCollision(ReachStatus st) {
  return st == ReachStatus::SelfCollision || st == ReachStatus::ObstacleCollision;
}

JointVector solutionOf(const PoseSweep& s, long i) {
  JointVector q(s.dof);
  for (int k = 0; k < s.dof; ++k) q[k] = s.q[static_cast<std::size_t>(i) * s.dof + k];
  return q;
}

bool hasAlternative(const PoseSweep& s, long i) {
  return !s.q_alt.empty() && !std::isnan(s.q_alt[static_cast<std::size_t>(i) * s.dof]);
}

JointVector alternativeOf(const PoseSweep& s, long i) {
  JointVector q(s.dof);
  for (int k = 0; k < s.dof; ++k) q[k] = s.q_alt[static_cast<std::size_t>(i) * s.dof + k];
  return q;
}

// One pose, plain IK or collision-aware (reachable only in collision -> Self/ObstacleCollision),
// with per-thread workspaces. Target and seed follow the pose's index in the whole sweep, never
// its place in a chunk.
class PoseSolver {
 public:
  PoseSolver(const Model& model, const SweepCollision& collision, const std::function<IkTarget(long)>& target)
      : model_(model), collision_(collision), target_(target), ws_(model) {
    if (collision.enabled()) cws_.emplace(model);
    copts_.self = collision.self;
    if (!collision.nullspace_escape) copts_.escape_safety_distance_m = 0;
  }
  // escape_attempts < 0: the default number of random escapes after a colliding solution.
  // escape = false: no H_c descent either (a colliding solution stays in collision).
  PoseResult solve(long i, const IkOptions& o, const JointVector* warm_start, int escape_attempts = -1,
                   bool escape = true) {
    PoseResult r;
    if (!collision_.enabled()) {
      r.ik = solvePose(model_, ws_, target_(i), o, static_cast<std::uint64_t>(i), warm_start);
      return r;
    }
    collision::CollisionReachOptions copts = copts_;
    if (escape_attempts >= 0) copts.escape_attempts = escape_attempts;
    if (!escape) copts.escape_safety_distance_m = 0;
    collision::CollisionReachResult c = collision::solvePoseCollisionAware(
        model_, ws_, *cws_, target_(i), o, copts, static_cast<std::uint64_t>(i), collision_.obstacles, warm_start);
    r.ik = std::move(c.ik);
    if (r.ik.reachable() || inCollision(r.ik.status)) {
      r.min_distance_m = c.min_distance_m;
      r.obstacle_distance_m = c.obstacle_distance_m;
    }
    r.pair = c.colliding_pair_index;
    return r;
  }

 private:
  const Model& model_;
  const SweepCollision& collision_;
  const std::function<IkTarget(long)>& target_;
  IkWorkspace ws_;
  std::optional<collision::CollisionWorkspace> cws_;
  collision::CollisionReachOptions copts_;
};

// Rank of a pose result: collision-free reachable, then reachable only in collision, then the rest.
int poseClass(const PoseSweep& s, long i) {
  if (s.reachable(i)) return 0;
  return inCollision(static_cast<ReachStatus>(s.status[i])) ? 1 : 2;
}

// True when entry i of a is better than entry i of b: class, then manipulability (reachable),
// the smallest distance (less penetration, in collision) or the position error (unreachable),
// then status and joint values. A total order, symmetric in a and b.
bool betterPose(const PoseSweep& a, const PoseSweep& b, long i) {
  const int ca = poseClass(a, i), cb = poseClass(b, i);
  if (ca != cb) return ca < cb;
  auto key = [&](const PoseSweep& s) {
    if (ca == 0) return -s.manipulability[i];
    if (ca == 1 && s.collision) return -s.min_distance_m[i];
    return s.position_error_m[i];
  };
  auto finite = [](double v) { return std::isnan(v) ? std::numeric_limits<double>::infinity() : v; };
  const double ka = finite(key(a)), kb = finite(key(b));
  if (ka != kb) return ka < kb;
  if (a.status[i] != b.status[i]) return a.status[i] < b.status[i];
  for (int k = 0; k < a.dof; ++k) {
    const double qa = a.q[static_cast<std::size_t>(i) * a.dof + k], qb = b.q[static_cast<std::size_t>(i) * b.dof + k];
    if (qa != qb) return qa < qb;
  }
  return false;
}

// Copies entry i of from to entry j of to, with the given start count (saturated at 255).
void copyPose(const PoseSweep& from, long i, PoseSweep& to, long j, int starts) {
  to.status[j] = from.status[i];
  to.starts[j] = static_cast<std::uint8_t>(std::min(255, starts));
  to.position_error_m[j] = from.position_error_m[i];
  to.orientation_error_rad[j] = from.orientation_error_rad[i];
  to.manipulability[j] = from.manipulability[i];
  to.joint_limit_margin[j] = from.joint_limit_margin[i];
  for (int k = 0; k < from.dof; ++k) to.q[static_cast<std::size_t>(j) * to.dof + k] = from.q[static_cast<std::size_t>(i) * from.dof + k];
  if (to.collision) {
    to.min_distance_m[j] = from.min_distance_m[i];
    to.colliding_pair[j] = from.colliding_pair[i];
  }
  if (to.obstacles) to.obstacle_distance_m[j] = from.obstacle_distance_m[i];
}

// Solves the units of every range (unit u covers poses [u * len, min((u+1) * len, size))) into
// one chunk per range; see sweepGridRanges.
std::vector<PoseSweep> sweepRanges(const Model& model, long size, long len,
                                   const std::function<IkTarget(long)>& target,
                                   const std::vector<ItemRange>& ranges, const IkOptions& options, int threads,
                                   Progress* progress, const SweepCollision& collision,
                                   const SweepChunkDone& on_done) {
  ARMSTUDY_CHECK(options.validate().empty(), options.validate());
  ARMSTUDY_CHECK(!collision.enabled() || !model.collision.empty(),
                 "collision-aware sweep of design '" + model.name + "' without a collision model");
  ARMSTUDY_CHECK(static_cast<int>(collision.obstacles.size()) <= collision::kMaxObstacles, "too many obstacles");
  const long units = (size + len - 1) / len;
  const int nt = threads > 0 ? threads : omp_get_max_threads();
  std::vector<PoseSweep> chunks;
  std::vector<std::pair<std::size_t, long>> work;  // (range, unit), in order
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    const ItemRange& r = ranges[k];
    ARMSTUDY_CHECK(0 <= r.begin && r.begin < r.end && r.end <= units, "sweep unit range out of bounds");
    const long first = r.begin * len, last = std::min(size, r.end * len);
    chunks.push_back(makeSweep(model, last - first, collision));
    chunks.back().offset = first;
    chunks.back().threads = nt;
    for (long u = r.begin; u < r.end; ++u) work.emplace_back(k, u);
  }
  RangeCountdown countdown(ranges);
  std::exception_ptr failure;
  IkOptions retry = options;
  retry.max_starts = 1;
  retry.classify_failures = false;
  const auto t0 = std::chrono::steady_clock::now();
  const long n_work = static_cast<long>(work.size());
#pragma omp parallel num_threads(nt)
  {
    PoseSolver solver(model, collision, target);
    auto solve = [&](long i, const IkOptions& o, const JointVector* warm_start) { return solver.solve(i, o, warm_start); };
    PoseSweep first_chain = makeSweep(model, len, collision), second_chain = first_chain;
    // One chain along poses [begin, end) in direction dir, into out (entry i - out_off).
    auto chainLine = [&](long begin, long end, long dir, PoseSweep& out, long out_off, double& t_reach,
                         double& t_unreach) {
      JointVector warm(model.dof());
      bool have_warm = false;
      const long first = dir > 0 ? begin : end - 1, past = dir > 0 ? end : begin - 1;
      for (long i = first; i != past; i += dir) {
        const auto p0 = std::chrono::steady_clock::now();
        const PoseResult pr = solve(i, options, have_warm ? &warm : nullptr);
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
        const PoseResult pr = solve(i, retry, &w);
        const IkResult& r = pr.ik;
        const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - p0).count();
        (r.reachable() ? t_reach : t_unreach) += dt;
        if (r.reachable() || (inCollision(r.status) && !inCollision(static_cast<ReachStatus>(out.status[li])))) {
          store(out, li, r, out.starts[li]);
          storeCollision(out, li, pr);
        }
      }
    };
#pragma omp for schedule(dynamic, 1)
    for (long w = 0; w < n_work; ++w) {
      const auto [k, u] = work[w];
      PoseSweep& s = chunks[k];
      const long off = s.offset;
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
        chainLine(begin, end, dir, out, begin, t_reach, t_unreach);
      }
      for (long li = 0; li < n; ++li) {
        const bool second = passes == 2 && betterPose(second_chain, first_chain, li);
        const PoseSweep &kept = second ? second_chain : first_chain, &other = second ? first_chain : second_chain;
        copyPose(kept, li, s, begin - off + li, first_chain.starts[li] + (passes == 2 ? second_chain.starts[li] : 0));
        // The other chain's collision-free solution, where it differs: a second seed for the search.
        const std::size_t to = static_cast<std::size_t>(begin - off + li) * s.dof, from = static_cast<std::size_t>(li) * s.dof;
        const bool distinct = passes == 2 && other.reachable(li) &&
                              !std::equal(other.q.begin() + from, other.q.begin() + from + s.dof, kept.q.begin() + from);
        for (int j = 0; j < s.dof; ++j)
          s.q_alt[to + j] = distinct ? other.q[from + j] : std::numeric_limits<double>::quiet_NaN();
      }
#pragma omp atomic
      s.solve_seconds_reachable += t_reach;
#pragma omp atomic
      s.solve_seconds_unreachable += t_unreach;
      if (progress) progress->advance(end - begin);
      if (countdown.itemDone(k)) {
        s.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (on_done) {
          try {
            on_done(k, s);
          } catch (...) {
#pragma omp critical(armstudy_sweep_failure)
            if (!failure) failure = std::current_exception();
          }
        }
      }
    }
  }
  if (failure) std::rethrow_exception(failure);
  return chunks;
}

PoseSweep wholeSweep(std::vector<PoseSweep> chunks, long size, const Model& model, const SweepCollision& collision) {
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
long sweepUnitCount(const TaskGrid& grid) { return (grid.size() + grid.lineLength() - 1) / grid.lineLength(); }
long sweepUnitCount(const PoseList& list) {
  return (static_cast<long>(list.poses.size()) + defaults::kPoseListChunk - 1) / defaults::kPoseListChunk;
}

std::vector<PoseSweep> sweepGridRanges(const Model& model, const TaskGrid& grid, const std::vector<ItemRange>& ranges,
                                       const IkOptions& options, int threads, Progress* progress,
                                       const SweepCollision& collision, const SweepChunkDone& on_done) {
  ARMSTUDY_CHECK(grid.validate().empty(), grid.validate());
  return sweepRanges(
      model, grid.size(), sweepUnitLength(grid),
      [&grid](long i) { return IkTarget{grid.task_space, grid.pose(i)}; }, ranges, options, threads, progress,
      collision, on_done);
}

std::vector<PoseSweep> sweepPoseListRanges(const Model& model, const PoseList& list,
                                           const std::vector<ItemRange>& ranges, const IkOptions& options,
                                           int threads, Progress* progress, const SweepCollision& collision,
                                           const SweepChunkDone& on_done) {
  return sweepRanges(
      model, static_cast<long>(list.poses.size()), sweepUnitLength(list),
      [&list](long i) { return IkTarget{list.task_space, list.poses[i]}; }, ranges, options, threads, progress,
      collision, on_done);
}

PoseSweep sweepGrid(const Model& model, const TaskGrid& grid, const IkOptions& options,
                    int threads, Progress* progress, const SweepCollision& collision) {
  const long units = sweepUnitCount(grid);
  std::vector<ItemRange> all;
  if (units > 0) all.push_back({0, units});
  return wholeSweep(sweepGridRanges(model, grid, all, options, threads, progress, collision), grid.size(), model,
                    collision);
}

PoseSweep sweepPoseList(const Model& model, const PoseList& list, const IkOptions& options,
                        int threads, Progress* progress, const SweepCollision& collision) {
  const long units = sweepUnitCount(list);
  std::vector<ItemRange> all;
  if (units > 0) all.push_back({0, units});
  return wholeSweep(sweepPoseListRanges(model, list, all, options, threads, progress, collision),
                    static_cast<long>(list.poses.size()), model, collision);
}

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

namespace {
template <class T>
void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}
}  // namespace

PoseSweep assembleSweep(std::vector<PoseSweep> chunks, long size) {
  ARMSTUDY_CHECK(!chunks.empty(), "no chunks to assemble");
  std::sort(chunks.begin(), chunks.end(), [](const PoseSweep& a, const PoseSweep& b) { return a.offset < b.offset; });
  const PoseSweep& first = chunks.front();
  PoseSweep s;
  s.design = first.design;
  s.dof = first.dof;
  s.collision = first.collision;
  s.obstacles = first.obstacles;
  s.pair_names = first.pair_names;
  s.threads = 0;
  long next = 0;
  for (const PoseSweep& c : chunks) {
    ARMSTUDY_CHECK(c.offset == next, "sweep chunks of '" + s.design + "' leave a gap or overlap at pose " +
                                         std::to_string(next));
    ARMSTUDY_CHECK(c.dof == s.dof && c.collision == s.collision && c.obstacles == s.obstacles &&
                       c.pair_names == s.pair_names,
                   "sweep chunks of '" + s.design + "' do not match");
    next += c.size;
    append(s.status, c.status);
    append(s.starts, c.starts);
    append(s.position_error_m, c.position_error_m);
    append(s.orientation_error_rad, c.orientation_error_rad);
    append(s.manipulability, c.manipulability);
    append(s.joint_limit_margin, c.joint_limit_margin);
    append(s.q, c.q);
    append(s.q_alt, c.q_alt);
    append(s.min_distance_m, c.min_distance_m);
    append(s.colliding_pair, c.colliding_pair);
    append(s.obstacle_distance_m, c.obstacle_distance_m);
    s.wall_seconds = std::max(s.wall_seconds, c.wall_seconds);
    s.threads = std::max(s.threads, c.threads);
    s.solve_seconds_reachable += c.solve_seconds_reachable;
    s.solve_seconds_unreachable += c.solve_seconds_unreachable;
  }
  ARMSTUDY_CHECK(next == size, "sweep chunks of '" + s.design + "' cover " + std::to_string(next) + " of " +
                                   std::to_string(size) + " poses");
  s.size = size;
  return s;
}

}  // namespace armstudy
