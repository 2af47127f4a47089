#pragma once
// Private to reach/reach_sweep.cpp and reach/reach_search.cpp: one pose's solve and how a pose's
// result is stored, compared (a symmetric total order, so results never depend on the traversal)
// and copied between sweeps.
#include <functional>
#include <optional>

#include "collision/reach_collision.hpp"
#include "kinematics/kernel_count.hpp"
#include "reach/reach_sweep.hpp"

namespace armstudy::sweep_detail {

inline PoseSweep makeSweep(const Model& model, long size, const SweepCollision& collision) {
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

inline void store(PoseSweep& s, long i, const IkResult& r, int extra_starts) {
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

inline void storeCollision(PoseSweep& s, long i, const PoseResult& r) {
  if (!s.collision) return;
  s.min_distance_m[i] = r.min_distance_m;
  s.colliding_pair[i] = static_cast<std::int16_t>(r.pair);
  if (s.obstacles) s.obstacle_distance_m[i] = r.obstacle_distance_m;
}

inline bool inCollision(ReachStatus st) {
  return st == ReachStatus::SelfCollision || st == ReachStatus::ObstacleCollision;
}

inline JointVector solutionOf(const PoseSweep& s, long i) {
  JointVector q(s.dof);
  for (int k = 0; k < s.dof; ++k) q[k] = s.q[static_cast<std::size_t>(i) * s.dof + k];
  return q;
}

inline bool hasAlternative(const PoseSweep& s, long i) {
  return !s.q_alt.empty() && !std::isnan(s.q_alt[static_cast<std::size_t>(i) * s.dof]);
}

inline JointVector alternativeOf(const PoseSweep& s, long i) {
  JointVector q(s.dof);
  for (int k = 0; k < s.dof; ++k) q[k] = s.q_alt[static_cast<std::size_t>(i) * s.dof + k];
  return q;
}

// One pose, plain IK or collision-aware (reachable only in collision -> Self/ObstacleCollision),
// with per-thread workspaces. Target and seed follow the pose's index in the whole sweep, never
// its place in a chunk. Counts what it solves (take()): a call without `solved` begins a descent,
// one with it goes on with the descent that solveIgnoringCollisions began.
class PoseSolver {
 public:
  PoseSolver(const Model& model, const SweepCollision& collision,
             const std::function<PoseTask(long)>& target)
      : model_(model), collision_(collision), target_(target), ws_(model) {
    if (collision.enabled()) cws_.emplace(model);
    copts_.self = collision.self;
    if (!collision.nullspace_escape) copts_.escape_safety_distance_m = 0;
  }
  // escape_attempts < 0: the default number of random escapes after a colliding solution.
  // escape = false: no H_c descent either (a colliding solution stays in collision).
  // solved: the result of solveIgnoringCollisions(i, o, warm_start), when the caller has it.
  PoseResult solve(long i, const IkOptions& o, const JointVector* warm_start,
                   int escape_attempts = -1, bool escape = true, const IkResult* solved = nullptr) {
    const long k0 = kernelEvaluationsOnThisThread();
    if (!solved) begin();
    PoseResult r = solveCounted(i, o, warm_start, escape_attempts, escape, solved);
    end(r.ik.status, k0);
    return r;
  }

  // The solution alone, without the collision check (its status says only whether the tool
  // reaches the pose); begins a descent.
  IkResult solveIgnoringCollisions(long i, const IkOptions& o, const JointVector* warm_start) {
    const long k0 = kernelEvaluationsOnThisThread();
    begin();
    IkResult r = solvePose(model_, ws_, target_(i), o, static_cast<std::uint64_t>(i), warm_start);
    tally_.iterations += r.iterations;
    end(r.status, k0);
    return r;
  }

  // The counts of the descents since the last take() (each ended with its last status), and
  // starts afresh.
  SolveTally take() {
    if (open_) ++tally_.ended[status_];
    open_ = false;
    SolveTally t = tally_;
    tally_ = SolveTally{};
    return t;
  }

 private:
  void begin() {
    if (open_) ++tally_.ended[status_];
    ++tally_.descents;
    open_ = true;
  }
  void end(ReachStatus status, long kernels_before) {
    status_ = static_cast<int>(status);
    tally_.kernel_evaluations += kernelEvaluationsOnThisThread() - kernels_before;
  }

  PoseResult solveCounted(long i, const IkOptions& o, const JointVector* warm_start,
                          int escape_attempts, bool escape, const IkResult* solved) {
    PoseResult r;
    if (!collision_.enabled()) {
      r.ik = solved
                 ? *solved
                 : solvePose(model_, ws_, target_(i), o, static_cast<std::uint64_t>(i), warm_start);
      if (!solved) tally_.iterations += r.ik.iterations;
      return r;
    }
    collision::CollisionReachOptions copts = copts_;
    if (escape_attempts >= 0) copts.escape_attempts = escape_attempts;
    if (!escape) copts.escape_safety_distance_m = 0;
    collision::CollisionReachResult c = collision::solvePoseCollisionAware(
        model_, ws_, *cws_, target_(i), o, copts, static_cast<std::uint64_t>(i),
        collision_.obstacles, warm_start, solved);
    tally_.iterations += c.iterations;
    tally_.addEscape(c.escape);
    r.ik = std::move(c.ik);
    if (r.ik.reachable() || inCollision(r.ik.status)) {
      r.min_distance_m = c.min_distance_m;
      r.obstacle_distance_m = c.obstacle_distance_m;
    }
    r.pair = c.colliding_pair_index;
    return r;
  }

  const Model& model_;
  const SweepCollision& collision_;
  const std::function<PoseTask(long)>& target_;
  IkWorkspace ws_;
  std::optional<collision::CollisionWorkspace> cws_;
  collision::CollisionReachOptions copts_;
  SolveTally tally_;
  bool open_ = false;  // a descent has begun and not yet ended
  int status_ = 0;     // ... its status so far
};

// Rank of a pose result: collision-free reachable, then reachable only in collision, then the rest.
inline int poseClass(const PoseSweep& s, long i) {
  if (s.reachable(i)) return 0;
  return inCollision(static_cast<ReachStatus>(s.status[i])) ? 1 : 2;
}

// True when entry i of a is better than entry i of b: class, then manipulability (reachable),
// the smallest distance (less penetration, in collision) or the position error (unreachable),
// then status and joint values. A total order, symmetric in a and b.
inline bool betterPose(const PoseSweep& a, const PoseSweep& b, long i) {
  const int ca = poseClass(a, i), cb = poseClass(b, i);
  if (ca != cb) return ca < cb;
  auto key = [&](const PoseSweep& s) {
    if (ca == 0) return -s.manipulability[i];
    if (ca == 1 && s.collision) return -s.min_distance_m[i];
    return s.position_error_m[i];
  };
  auto finite = [](double v) {
    return std::isnan(v) ? std::numeric_limits<double>::infinity() : v;
  };
  const double ka = finite(key(a)), kb = finite(key(b));
  if (ka != kb) return ka < kb;
  if (a.status[i] != b.status[i]) return a.status[i] < b.status[i];
  for (int k = 0; k < a.dof; ++k) {
    const double qa = a.q[static_cast<std::size_t>(i) * a.dof + k],
                 qb = b.q[static_cast<std::size_t>(i) * b.dof + k];
    if (qa != qb) return qa < qb;
  }
  return false;
}

// Copies entry i of from to entry j of to, with the given start count (saturated at 255).
inline void copyPose(const PoseSweep& from, long i, PoseSweep& to, long j, int starts) {
  to.status[j] = from.status[i];
  to.starts[j] = static_cast<std::uint8_t>(std::min(255, starts));
  to.position_error_m[j] = from.position_error_m[i];
  to.orientation_error_rad[j] = from.orientation_error_rad[i];
  to.manipulability[j] = from.manipulability[i];
  to.joint_limit_margin[j] = from.joint_limit_margin[i];
  for (int k = 0; k < from.dof; ++k)
    to.q[static_cast<std::size_t>(j) * to.dof + k] =
        from.q[static_cast<std::size_t>(i) * from.dof + k];
  if (to.collision) {
    to.min_distance_m[j] = from.min_distance_m[i];
    to.colliding_pair[j] = from.colliding_pair[i];
  }
  if (to.obstacles) to.obstacle_distance_m[j] = from.obstacle_distance_m[i];
}

// One pose's row (what store / storeCollision write; not q_alt, which the search never changes),
// for the rows a distributed search step sends.
inline void putPose(UnitWriter& w, const PoseSweep& s, long i) {
  w.put(s.status[i]);
  w.put(s.starts[i]);
  w.put(s.position_error_m[i]);
  w.put(s.orientation_error_rad[i]);
  w.put(s.manipulability[i]);
  w.put(s.joint_limit_margin[i]);
  for (int k = 0; k < s.dof; ++k) w.put(s.q[static_cast<std::size_t>(i) * s.dof + k]);
  if (s.collision) {
    w.put(s.min_distance_m[i]);
    w.put(s.colliding_pair[i]);
  }
  if (s.obstacles) w.put(s.obstacle_distance_m[i]);
}
inline bool getPose(UnitReader& r, PoseSweep& s, long i) {
  s.status[i] = r.get<std::uint8_t>();
  s.starts[i] = r.get<std::uint8_t>();
  s.position_error_m[i] = r.get<double>();
  s.orientation_error_rad[i] = r.get<double>();
  s.manipulability[i] = r.get<double>();
  s.joint_limit_margin[i] = r.get<double>();
  for (int k = 0; k < s.dof; ++k) s.q[static_cast<std::size_t>(i) * s.dof + k] = r.get<double>();
  if (s.collision) {
    s.min_distance_m[i] = r.get<double>();
    s.colliding_pair[i] = r.get<std::int16_t>();
  }
  if (s.obstacles) s.obstacle_distance_m[i] = r.get<double>();
  return r.ok();
}

}  // namespace armstudy::sweep_detail
