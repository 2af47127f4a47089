// Pose solves through the reach stage's solver (ik/reach_solver: taskTarget, then solvePose with
// the pose's id seeding its starts), one pose or a batch on threads.
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "collision/reach_collision.hpp"
#include "ik/reach_solver.hpp"
#include "kinematics/kinematics.hpp"
#include "python/bindings.hpp"

namespace armstudy::python {

namespace {

IkOptions ikOptions(const std::optional<double>& position_tolerance,
                    const std::optional<double>& orientation_tolerance,
                    const std::optional<int>& max_starts,
                    const std::optional<std::uint64_t>& seed) {
  IkOptions o;
  if (position_tolerance) o.position_tolerance_m = *position_tolerance;
  if (orientation_tolerance) o.orientation_tolerance_rad = *orientation_tolerance;
  if (max_starts) o.max_starts = *max_starts;
  if (seed) o.seed = *seed;
  if (const std::string error = o.validate(); !error.empty()) throw std::invalid_argument(error);
  return o;
}

TaskSpace taskSpace(const std::string& task) {
  TaskSpace space;
  std::string error;
  if (!parseTaskSpace(task, space, error)) throw std::invalid_argument("task: " + error);
  return space;
}

// The task of the transform (p_WT, R_WT) in `space`: the full space holds R_WT itself, a space
// without angles only the position; the spaces defined by angles (spraying's alpha and gamma, a
// selection of Cardan angles) take R_WT's Cardan parameters (cardanForDisplay).
PoseTask transformTask(const TaskSpace& space, const Eigen::Vector3d& p_WT,
                       const Eigen::Matrix3d& R_WT) {
  const auto& s = space.selected;
  TaskVector6 w = TaskVector6::Zero();
  w.head<3>() = p_WT;
  if (!s[3] && !s[4] && !s[5]) return taskTarget(space, w);
  if (s[3] && s[4] && s[5]) {
    PoseTask t = taskTarget(space, w);
    t.R_WT = R_WT;
    return t;
  }
  const CardanAngles a = cardanForDisplay(R_WT);
  w.tail<3>() = Eigen::Vector3d(a.alpha, a.beta, a.gamma);
  return taskTarget(space, w);
}

// The targets of `target`: study poses (6,)/(N, 6) (x, y, z, alpha, beta, gamma) of `task`, or
// SE(3) transforms (4, 4)/(N, 4, 4) (transformTask), or with `axis` tool-axis targets: positions
// (3,)/(N, 3) and the directions (3,)/(N, 3) the design's tool axis must point along, roll free
// (the spraying task with a direction given directly). `single`: one target was given.
std::vector<PoseTask> targets(const py::handle& target, const std::string& task,
                              const py::handle& axis, bool& single) {
  std::vector<PoseTask> out;
  if (!axis.is_none()) {
    const Rows p = readRows(target, 3, "target (a position with axis)");
    const Rows a = readRows(axis, 3, "axis");
    if (!(a.single || a.n == p.n)) throw std::invalid_argument("axis: one row, or one per target");
    if (task != "spraying" && task != "full")
      throw std::invalid_argument("task: an axis target is its own task (leave task out)");
    single = p.single;
    for (long i = 0; i < p.n; ++i) {
      Eigen::Vector3d d(a.row(a.single ? 0 : i));
      if (d.norm() < 1e-12) throw std::invalid_argument("axis: zero vector");
      out.push_back(
          positionAxisTask(Eigen::Vector3d(p.row(i)),
                           std::abs(d.norm() - 1.0) > 1e-12 ? Eigen::Vector3d(d.normalized()) : d));
    }
    return out;
  }
  const TaskSpace space = taskSpace(task);
  const auto raw = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(target);
  if (raw && raw.ndim() >= 2 && raw.shape(raw.ndim() - 1) == 4 && raw.shape(raw.ndim() - 2) == 4) {
    single = raw.ndim() == 2;
    if (raw.ndim() > 3) throw std::invalid_argument("target: expected (4, 4) or (N, 4, 4)");
    const long n = single ? 1 : static_cast<long>(raw.shape(0));
    for (long i = 0; i < n; ++i) {
      const double* T = raw.data() + 16 * i;
      Eigen::Matrix3d R;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) R(r, c) = T[4 * r + c];
      if (!R.allFinite() || !std::isfinite(T[3] + T[7] + T[11]) ||
          (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9 ||
          R.determinant() < 0)
        throw std::invalid_argument("target: transform " + std::to_string(i) +
                                    " has no rotation matrix (to 1e-9) or is not finite");
      out.push_back(transformTask(space, Eigen::Vector3d(T[3], T[7], T[11]), R));
    }
    return out;
  }
  const Rows r = readRows(target, 6, "target");
  single = r.single;
  for (long i = 0; i < r.n; ++i)
    out.push_back(taskTarget(space, Eigen::Map<const TaskVector6>(r.row(i))));
  return out;
}

std::vector<std::uint64_t> poseIds(const py::handle& ids, long n) {
  std::vector<std::uint64_t> out(n);
  if (ids.is_none()) {
    for (long i = 0; i < n; ++i) out[i] = static_cast<std::uint64_t>(i);
    return out;
  }
  auto a = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>::ensure(ids);
  if (!a || a.ndim() != 1 || a.shape(0) != n)
    throw std::invalid_argument("pose_ids: expected " + std::to_string(n) + " integers");
  for (long i = 0; i < n; ++i) out[i] = a.at(i);
  return out;
}

// One thread's solver: the reach stage's (reach/sweep_internal.hpp PoseSolver) without obstacles:
// with self-collision, solvePoseCollisionAware (a colliding solution escapes by the null-space
// descent, then by further seeded solves); without, solvePose.
struct Solver {
  IkWorkspace ws;
  std::optional<collision::CollisionWorkspace> cws;
  Solver(const Model& m, bool collision) : ws(m) {
    if (collision) cws.emplace(m);
  }
  collision::CollisionReachResult solve(const Model& m, const PoseTask& target,
                                        const IkOptions& options, std::uint64_t id,
                                        const JointVector* warm) {
    if (!cws) {
      collision::CollisionReachResult r;
      r.ik = solvePose(m, ws, target, options, id, warm);
      r.min_distance_m = std::numeric_limits<double>::quiet_NaN();
      return r;
    }
    collision::CollisionReachResult r = collision::solvePoseCollisionAware(
        m, ws, *cws, target, options, collision::CollisionReachOptions{}, id, {}, warm);
    if (!r.ik.reachable() && r.ik.status != ReachStatus::SelfCollision)
      r.min_distance_m = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
};

const IkOptions defaultIk{};

// One solve's fields, or a batch's arrays of them (solve returns what solve_batch returns, per
// row).
struct Results {
  long n;
  int dof;
  std::vector<collision::CollisionReachResult> r;
  Results(long count, int joints) : n(count), dof(joints), r(count) {}

  // The fields of the first solve: each of batch()'s columns at row 0, a number as a Python
  // scalar (int, float or bool), q as an array of its own.
  py::dict one() const {
    py::dict out;
    for (const auto& [key, column] : batch()) {
      const py::object first = column[py::int_(0)];
      if (py::isinstance<py::str>(first))
        out[key] = first;
      else if (py::isinstance<py::array>(first))
        out[key] = first.attr("copy")();
      else
        out[key] = first.attr("item")();  // a numpy scalar
    }
    return out;
  }

  template <class T, class F>
  py::array_t<T> column(const F& f) const {
    py::array_t<T> a(n);
    T* p = a.mutable_data();
    for (long i = 0; i < n; ++i) p[i] = f(r[i]);
    return a;
  }

  py::dict batch() const {
    using R = collision::CollisionReachResult;
    py::array_t<double> q({n, static_cast<long>(dof)});
    double* qo = q.mutable_data();
    py::list names, pairs;
    for (long i = 0; i < n; ++i) {
      for (int j = 0; j < dof; ++j) qo[i * dof + j] = r[i].ik.q[j];
      names.append(toString(r[i].ik.status));
      pairs.append(r[i].colliding_pair);
    }
    py::dict out;
    out["status"] = column<std::uint8_t>([](const R& x) { return std::uint8_t(x.ik.status); });
    out["status_name"] = names;
    out["reachable"] = column<bool>([](const R& x) { return x.ik.reachable(); });
    out["q"] = q;
    out["manipulability"] = column<double>([](const R& x) { return x.ik.manipulability; });
    out["position_error"] = column<double>([](const R& x) { return x.ik.position_error_m; });
    out["orientation_error"] =
        column<double>([](const R& x) { return x.ik.orientation_error_rad; });
    out["joint_limit_margin"] = column<double>([](const R& x) { return x.ik.joint_limit_margin; });
    out["starts"] = column<int>([](const R& x) { return x.ik.starts; });
    out["iterations"] = column<int>([](const R& x) { return x.ik.iterations; });
    out["min_distance"] = column<double>([](const R& x) { return x.min_distance_m; });
    out["colliding_pair"] = pairs;
    return out;
  }
};

// Self-collision only when asked (a general arm user's default); asking without volumes is an
// error.
bool selfCollision(const Model& m, bool on) {
  if (on && m.collision.empty())
    throw std::invalid_argument("self_collision: design '" + m.name + "' has no collision volumes");
  return on;
}

Results solveAll(const Design& d, const py::handle& target, const std::string& task,
                 const py::handle& axis, const py::handle& pose_ids, const py::handle& warm_starts,
                 int threads, bool self_collision, double position_tolerance,
                 double orientation_tolerance, int max_starts, std::uint64_t seed, bool& single) {
  const Model& m = *d.model;
  const int n = m.dof();
  const IkOptions options = ikOptions(position_tolerance, orientation_tolerance, max_starts, seed);
  const std::vector<PoseTask> goals = targets(target, task, axis, single);
  const long count = static_cast<long>(goals.size());
  const std::vector<std::uint64_t> ids = poseIds(pose_ids, count);
  const Rows w = warm_starts.is_none() ? Rows{} : readRows(warm_starts, n, "warm_start");
  if (w.cols > 0 && w.n != count && !(w.single && count == 1))
    throw std::invalid_argument("warm_starts: expected one row per target");
  const bool collision = selfCollision(m, self_collision);
  Results res(count, n);
  const int t = count == 1 ? 1 : threadCount(threads);
  py::gil_scoped_release release;
#pragma omp parallel num_threads(t)
  {
    Solver solver(m, collision);
    JointVector warm(n);
#pragma omp for schedule(dynamic, 16)
    for (long i = 0; i < count; ++i) {
      if (w.cols > 0) warm = Eigen::Map<const Eigen::VectorXd>(w.row(i), n);
      res.r[i] = solver.solve(m, goals[i], options, ids[i], w.cols > 0 ? &warm : nullptr);
    }
  }
  return res;
}

py::dict solveOne(const Design& d, const py::handle& target, const std::string& task,
                  const py::handle& axis, std::uint64_t pose_id, const py::handle& warm_start,
                  bool self_collision, double position_tolerance, double orientation_tolerance,
                  int max_starts, std::uint64_t seed) {
  bool single = true;
  const Results r =
      solveAll(d, target, task, axis, py::cast(std::vector<std::uint64_t>{pose_id}), warm_start, 1,
               self_collision, position_tolerance, orientation_tolerance, max_starts, seed, single);
  if (!single) throw std::invalid_argument("target: expected one target; use solve_batch for many");
  return r.one();
}

py::dict solveBatch(const Design& d, const py::handle& targets_, const std::string& task,
                    const py::handle& axis, const py::handle& pose_ids,
                    const py::handle& warm_starts, int threads, bool self_collision,
                    double position_tolerance, double orientation_tolerance, int max_starts,
                    std::uint64_t seed) {
  bool single = false;
  return solveAll(d, targets_, task, axis, pose_ids, warm_starts, threads, self_collision,
                  position_tolerance, orientation_tolerance, max_starts, seed, single)
      .batch();
}

}  // namespace

void bindSolve(py::module_& m, py::class_<Design>& design) {
  std::vector<std::string> names;
  for (int k = 0; k < kReachStatusCount; ++k)
    names.push_back(toString(static_cast<ReachStatus>(k)));
  m.attr("STATUS_NAMES") = names;
  design
      .def("solve", &solveOne, py::arg("target"), py::arg("task") = "full",
           py::arg("axis") = py::none(), py::arg("pose_id") = 0, py::arg("warm_start") = py::none(),
           py::arg("self_collision") = false,
           py::arg("position_tolerance") = defaultIk.position_tolerance_m,
           py::arg("orientation_tolerance") = defaultIk.orientation_tolerance_rad,
           py::arg("max_starts") = defaultIk.max_starts, py::arg("seed") = defaultIk.seed,
           R"(Solves one target with the reach maps' solver; returns a dict (below).
target: a study pose (x, y, z, alpha, beta, gamma) [m, rad] in W of `task`; or an SE(3)
transform (4, 4) in W (task 'full': position and the whole rotation); or, with `axis` (3,), a
position (3,) [m] where the design's tool axis must point along `axis` with the roll about it
free (the spraying task with its direction given; armstudy.spray_direction(alpha, gamma) gives
the study's).
task: 'full' (default: position and orientation), 'spraying' (position and the tool axis along
d(alpha, gamma); beta is ignored), 'position', or a Cardan selection such as 'x,y,z,gamma'.
self_collision: False (default) solves without collision volumes; True (the reach stage's choice
for a design with volumes) makes a colliding solution escape through the null space or further
seeded starts, else reports status 'self_collision'.
position_tolerance [m] (default 1e-3) and orientation_tolerance [rad] (default 0.5 deg =
0.008727: the angle of the rotation error, or between the axes for an axis task) decide
'reachable'; max_starts (default 64) counts the random starts, seeded by seed and pose_id (the
same id, the same starts); warm_start (dof,) is tried first.
Returns: status, status_name, reachable, q (dof,), manipulability (of the task's rows),
position_error [m], orientation_error [rad], joint_limit_margin, starts, iterations,
min_distance [m] (NaN without the check or a solution), colliding_pair.)")
      .def("solve_batch", &solveBatch, py::arg("targets"), py::arg("task") = "full",
           py::arg("axis") = py::none(), py::arg("pose_ids") = py::none(),
           py::arg("warm_starts") = py::none(), py::arg("threads") = 0,
           py::arg("self_collision") = false,
           py::arg("position_tolerance") = defaultIk.position_tolerance_m,
           py::arg("orientation_tolerance") = defaultIk.orientation_tolerance_rad,
           py::arg("max_starts") = defaultIk.max_starts, py::arg("seed") = defaultIk.seed,
           R"(Solves N targets on threads, row i exactly as solve() with pose_id = pose_ids[i]
(default: the row index) and warm_starts[i]. targets: poses (N, 6), transforms (N, 4, 4), or with
axis ((3,) for all or (N, 3)) positions (N, 3); task, self_collision and the tolerances as solve().
Returns solve()'s fields as arrays of N (status uint8 with names in armstudy.STATUS_NAMES,
status_name and colliding_pair as lists, reachable bool, q (N, dof), ...).)");
}

}  // namespace armstudy::python
