#pragma once
// Parallel, deterministic reachability sweeps of one design over a task grid or a pose list.
//
// Work is split into independent units: the lines of a grid (consecutive cells along its first
// multi-valued axis) or fixed chunks of a pose list. Each unit is solved in order, warm-starting
// every pose from the last reachable solution of the same unit, then swept once backwards so a
// reachable region entered from its far side is not missed. Units never read each other's
// results, so results are bit-identical for any thread count and schedule (and units could be
// distributed across processes). A chunk (a contiguous range of units, the checkpoint grain of
// the reach stage) is therefore bit-identical whether it is swept alone or as part of the whole.
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "collision/collision.hpp"
#include "ik/nullspace.hpp"
#include "ik/reach_solver.hpp"
#include "study/checkpoint.hpp"
#include "tasks/task_grid.hpp"

namespace armstudy {

class UnitRunner;

// What a collision-aware sweep checks (docs/reachability.md): the design's self-collision pairs
// and/or environment obstacles fixed in the task frame W. Both need the design's collision model.
struct SweepCollision {
  bool self = false;
  std::vector<collision::Obstacle> obstacles;
  bool nullspace_escape =
      true;  // descend H_c in the null space before restarts (reach_collision.hpp)
  bool enabled() const { return self || !obstacles.empty(); }
};

// Counts of a set of pose solves of a reach map (the chains', a search phase's, the audit's): a
// descent is one pose solve from one start configuration (a chain's solve: from its warm start,
// with the solver's own restarts), with its collision check and escape. Integer sums: the same
// on any thread count, schedule and rank count.
struct SolveTally {
  long descents = 0;
  long changed = 0;     // descents whose result a pose's row took
  long iterations = 0;  // Levenberg-Marquardt / Newton iterations of every local solve in them
  // Forward-kinematics evaluations (with or without the TCP Jacobian), collision checks and
  // escapes included (kinematics/kernel_count.hpp).
  long kernel_evaluations = 0;
  std::array<long, kReachStatusCount> ended{};  // by the status the descent ended with
  ik::DescentTally escape;  // the H_c null-space descents of the collision escape among them
  void add(const SolveTally& other);  // integer counts only (escape's step sums stay 0)
  void addEscape(const ik::DescentTally& descents);  // ... of a solve's escape
};
// A tally as bytes (in units, search steps and audit rows) and back.
void putTally(UnitWriter& w, const SolveTally& t);
void getTally(UnitReader& r, SolveTally& t);

// Per-pose results of one design, stored column-wise (one vector per quantity).
struct PoseSweep {
  std::string design;
  int dof = 0;
  long offset = 0;                   // index of the first pose (chunks; 0 for a whole sweep)
  long size = 0;                     // poses held; entry i is pose offset + i
  std::vector<std::uint8_t> status;  // ReachStatus
  std::vector<std::uint8_t> starts;  // starts used (saturated at 255)
  std::vector<double> position_error_m, orientation_error_rad, manipulability, joint_limit_margin;
  std::vector<double> q;  // size * dof, pose-major
  // The other chain's collision-free solution where it differs from q (each line is chained both
  // ways), NaN otherwise: a second branch the map search starts from; not an output.
  std::vector<double> q_alt;  // size * dof, pose-major
  // Collision-aware sweeps only (empty otherwise): the smallest checked distance at the solution
  // (self pairs and obstacles; negative: penetration; NaN when unreachable) and, for poses
  // reachable only in collision (SelfCollision / ObstacleCollision), the colliding pair as an
  // index into pair_names (-1 otherwise).
  bool collision = false;
  std::vector<double> min_distance_m;
  std::vector<std::int16_t> colliding_pair;
  std::vector<std::string>
      pair_names;  // collision::collisionPairNames: "j2-j5", "j4-obstacle:stem"
  // Sweeps with obstacles only: the smallest body-obstacle distance at the solution (NaN when
  // unreachable), the clearance of the arm from its environment.
  bool obstacles = false;
  std::vector<double> obstacle_distance_m;
  // The chains' pose solves that made these rows (changed: one per pose).
  SolveTally chain;
  double wall_seconds = 0;
  int threads = 1;
  double solve_seconds_reachable =
      0;  // summed per-pose solve time of reachable poses (all threads)
  double solve_seconds_unreachable = 0;  // ... of unreachable poses (timings only, not results)
  bool reachable(long i) const {
    return status[i] == static_cast<std::uint8_t>(ReachStatus::Reachable);
  }
  long countReachable() const;
};

// Calls f(a.x, b.x, ...) for every per-pose array x of the sweeps a, b, ... (status ..
// obstacle_distance_m, in declaration order): the one list that assembling and checkpointing use.
template <class F, class... Sweep>
void forEachPoseArray(F&& f, Sweep&... s) {
  f(s.status...);
  f(s.starts...);
  f(s.position_error_m...);
  f(s.orientation_error_rad...);
  f(s.manipulability...);
  f(s.joint_limit_margin...);
  f(s.q...);
  f(s.q_alt...);
  f(s.min_distance_m...);
  f(s.colliding_pair...);
  f(s.obstacle_distance_m...);
}

// Progress on stderr: a bar with elapsed time and ETA redrawn in place, only when enabled and
// stderr is a terminal.
class Progress {
 public:
  Progress(long total, bool enabled, std::string label);
  ~Progress();
  void advance(long n);  // thread-safe
 private:
  long total_;
  bool enabled_;
  std::string label_;
  std::atomic<long> done_{0};
  std::atomic<int> last_permille_{-1};
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// threads <= 0: OpenMP default. `progress` may be null. With collision.enabled() every pose is
// solved collision-aware (collision::solvePoseCollisionAware); that needs a collision model.
PoseSweep sweepGrid(const Model& model, const TaskGrid& grid, const IkOptions& options, int threads,
                    Progress* progress, const SweepCollision& collision = {});
PoseSweep sweepPoseList(const Model& model, const PoseList& list, const IkOptions& options,
                        int threads, Progress* progress, const SweepCollision& collision = {});

// The sweep units of a grid (its lines) or pose list (chunks of defaults::kPoseListChunk poses):
// unit u covers poses [u * unitLength, min((u + 1) * unitLength, size)).
long sweepUnitLength(const TaskGrid& grid);
long sweepUnitLength(const PoseList& list);
long sweepUnitCount(const TaskGrid& grid);
long sweepUnitCount(const PoseList& list);

// Sweeps the units of every range in `ranges` (ranges of sweep units, within [0, unit count),
// non-empty) in one parallel loop over all their units and returns one chunk per range (offset =
// its first pose), each bit-identical to the same poses of sweepGrid / sweepPoseList. `on_done`
// (may be empty) is called once per range, as soon as its last unit is solved, from the thread
// that solved it (concurrently for distinct ranges), with the range's index and finished chunk;
// the chunk's wall_seconds then holds the time from the start of the call. An exception thrown by
// on_done is rethrown after the loop.
using SweepChunkDone = std::function<void(std::size_t range, const PoseSweep& chunk)>;
std::vector<PoseSweep> sweepGridRanges(const Model& model, const TaskGrid& grid,
                                       const std::vector<ItemRange>& ranges,
                                       const IkOptions& options, int threads, Progress* progress,
                                       const SweepCollision& collision = {},
                                       const SweepChunkDone& on_done = {});
std::vector<PoseSweep> sweepPoseListRanges(const Model& model, const PoseList& list,
                                           const std::vector<ItemRange>& ranges,
                                           const IkOptions& options, int threads,
                                           Progress* progress, const SweepCollision& collision = {},
                                           const SweepChunkDone& on_done = {});

// The map search after the unit sweeps of a grid (docs/reachability.md, "What a status
// claims"): a status must not depend on the order the grid was traversed in.
//  1. Neighbour propagation: every pose not reachable collision-free retries from the solution of
//     each collision-free neighbour (+-1 along x, y, z; the previous and next orientation), one
//     start each; Jacobi rounds (a round reads only the previous one) until nothing changes.
//  2. Every pose still reachable only in collision gets `collision_starts` seeded random starts
//     (collision-aware, deterministic per pose), then propagation from the poses they freed.
//     Grids: then one round for every pose still in collision from the solutions (and second
//     branches, PoseSweep::q_alt) of every collision-free pose in its 3 x 3 x 3 box and at its
//     point in the neighbouring orientations, then propagation again.
//  3. Every reachable pose retries from each collision-free neighbour with a higher manipulability
//     (eq. 5.59 of the task Jacobian) and keeps the collision-free solution with the highest
//     manipulability found (Jacobi rounds until nothing changes), so the quantities shown at a
//     reachable pose are those of the best solution found, not of the first.
// A pose then reports SelfCollision / ObstacleCollision only when none of its starts (its own,
// the escapes, the neighbour seeds and the seeded starts; counted in `starts`) found a
// collision-free solution. Bit-identical for any thread count.
struct SweepSearch {
  int propagation_rounds = defaults::kMapPropagationRounds;  // 0: no propagation
  int collision_starts = defaults::kReachCollisionStarts;    // 0: no multi-starts
  bool best_manipulability =
      true;  // 3. reachable poses keep the best-manipulability solution found
  std::uint64_t seed = defaults::kMapSearchSeed;
  // The oracle of the active sets (tests/collision/reach_search_test.cpp): every step visits every
  // pose its phase may change (every unsettled pose in a propagation round, every reachable one in
  // a best-manipulability round), not only those next to a pose that changed in the step before.
  // The map and the summary's counts must be the same; it only costs more.
  bool every_pose_each_step = false;
};
struct SweepSearchSummary {
  int rounds = 0;
  long neighbour_tries = 0, neighbour_updates = 0;
  long multistart_poses = 0, multistart_tries = 0, multistart_freed = 0;
  long box_tries = 0, box_freed = 0;  // grids: starts from the wider neighbourhood, poses freed
  int best_rounds = 0;
  long best_tries = 0, best_updates = 0;
  bool converged = true;
  // The pose solves of each phase (descents: neighbour_tries, multistart_tries, box_tries and
  // best_tries; changed: the poses that adopted a candidate in a step).
  SolveTally propagation, collision_starts, box, best;
  double seconds = 0;
  // The poses whose row the search changed (adopted a candidate, or spent starts on), ascending:
  // what packSearchResult sends.
  std::vector<long> changed;
};
// A finished search's results as bytes (its summary and the rows of the poses it changed), and
// applying them to the sweep it started from, which then equals the searched sweep (for a
// distributed run whose rank groups each search some of the designs: study/interleave.hpp).
std::string packSearchResult(const PoseSweep& sweep, const SweepSearchSummary& summary);
// Bytes that do not fit the sweep fail an internal check (they come from the same run).
void unpackSearchResult(const std::string& bytes, PoseSweep& sweep, SweepSearchSummary& summary);
// `runner`: the run's unit runner; a distributed run shares each step of the search among its
// processes (the result does not depend on it). Null: this process alone.
SweepSearchSummary searchGridSweep(const Model& model, const TaskGrid& grid,
                                   const IkOptions& options, int threads,
                                   const SweepCollision& collision, const SweepSearch& search,
                                   PoseSweep& sweep, const UnitRunner* runner = nullptr);
// The same for a pose list (fruit lists): its poses need not be neighbours, so no propagation;
// steps 2 and 3 run without neighbour seeds (the seeded starts for poses in collision).
SweepSearchSummary searchPoseListSweep(const Model& model, const PoseList& list,
                                       const IkOptions& options, int threads,
                                       const SweepCollision& collision, const SweepSearch& search,
                                       PoseSweep& sweep, const UnitRunner* runner = nullptr);

// Joins chunks of one design's sweep, given in any order, into the whole sweep of `size` poses:
// ordered by offset, they must tile [0, size) without gap or overlap and agree on dof and the
// collision columns (programmer checks). Solve times add up; wall_seconds is the largest.
PoseSweep assembleSweep(std::vector<PoseSweep> chunks, long size);

}  // namespace armstudy
