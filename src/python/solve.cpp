// Pose solves through the reach stage's solver (ik/reach_solver: taskTarget, then solvePose with
// the pose's id seeding its starts), one pose or a batch on threads.
#include <pybind11/stl.h>

#include <limits>
#include <optional>
#include <stdexcept>

#include "collision/reach_collision.hpp"
#include "ik/reach_solver.hpp"
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

TaskVector6 poseVector(const Rows& rows, long i) {
  return Eigen::Map<const TaskVector6>(rows.row(i));
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
  collision::CollisionReachResult solve(const Model& m, const IkTarget& target,
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

// Self-collision as the reach stage decides it: on when the design has collision volumes.
bool selfCollision(const Model& m, const std::optional<bool>& self_collision) {
  const bool on = self_collision.value_or(!m.collision.empty());
  if (on && m.collision.empty())
    throw std::invalid_argument("self_collision: design '" + m.name + "' has no collision volumes");
  return on;
}

py::dict solveOne(const Design& d, const py::handle& pose, const std::string& task,
                  std::uint64_t pose_id, const py::handle& warm_start,
                  const std::optional<bool>& self_collision,
                  const std::optional<double>& position_tolerance,
                  const std::optional<double>& orientation_tolerance,
                  const std::optional<int>& max_starts, const std::optional<std::uint64_t>& seed) {
  const Model& m = *d.model;
  const IkOptions options = ikOptions(position_tolerance, orientation_tolerance, max_starts, seed);
  const Rows p = readRows(pose, 6, "pose");
  if (!p.single) throw std::invalid_argument("pose: expected 6 values; use solve_batch for many");
  const IkTarget target = taskTarget(taskSpace(task), poseVector(p, 0));
  std::optional<JointVector> warm;
  if (!warm_start.is_none()) {
    const Rows w = readRows(warm_start, m.dof(), "warm_start");
    warm = Eigen::Map<const Eigen::VectorXd>(w.row(0), m.dof());
  }
  const bool collision = selfCollision(m, self_collision);
  collision::CollisionReachResult c;
  {
    py::gil_scoped_release release;
    Solver solver(m, collision);
    c = solver.solve(m, target, options, pose_id, warm ? &*warm : nullptr);
  }
  const IkResult& r = c.ik;
  py::array_t<double> q(m.dof());
  for (int i = 0; i < m.dof(); ++i) q.mutable_at(i) = r.q[i];
  py::dict out;
  out["status"] = static_cast<int>(r.status);
  out["status_name"] = toString(r.status);
  out["reachable"] = r.reachable();
  out["q"] = q;
  out["manipulability"] = r.manipulability;
  out["position_error"] = r.position_error_m;
  out["orientation_error"] = r.orientation_error_rad;
  out["joint_limit_margin"] = r.joint_limit_margin;
  out["starts"] = r.starts;
  out["iterations"] = r.iterations;
  out["min_distance"] = c.min_distance_m;
  out["colliding_pair"] = c.colliding_pair;
  return out;
}

py::dict solveBatch(const Design& d, const py::handle& poses, const std::string& task,
                    const py::handle& pose_ids, const py::handle& warm_starts, int threads,
                    const std::optional<bool>& self_collision,
                    const std::optional<double>& position_tolerance,
                    const std::optional<double>& orientation_tolerance,
                    const std::optional<int>& max_starts,
                    const std::optional<std::uint64_t>& seed) {
  const Model& m = *d.model;
  const int n = m.dof();
  const IkOptions options = ikOptions(position_tolerance, orientation_tolerance, max_starts, seed);
  const TaskSpace space = taskSpace(task);
  const Rows p = readRows(poses, 6, "poses");
  const long count = p.n;
  const std::vector<std::uint64_t> ids = poseIds(pose_ids, count);
  const Rows w = warm_starts.is_none() ? Rows{} : readRows(warm_starts, n, "warm_starts");
  if (w.cols > 0 && w.n != count)
    throw std::invalid_argument("warm_starts: expected one row per pose");
  py::array_t<std::uint8_t> status(count);
  py::array_t<double> q({count, static_cast<long>(n)});
  const bool collision = selfCollision(m, self_collision);
  py::array_t<double> manip(count), position_error(count), orientation_error(count);
  py::array_t<double> min_distance(count);
  py::array_t<int> starts(count);
  std::uint8_t* s = status.mutable_data();
  double *qo = q.mutable_data(), *mo = manip.mutable_data();
  double *pe = position_error.mutable_data(), *oe = orientation_error.mutable_data();
  double* md = min_distance.mutable_data();
  int* so = starts.mutable_data();
  const int t = threadCount(threads);
  {
    py::gil_scoped_release release;
#pragma omp parallel num_threads(t)
    {
      Solver solver(m, collision);
      JointVector warm(n);
#pragma omp for schedule(dynamic, 16)
      for (long i = 0; i < count; ++i) {
        if (w.cols > 0) warm = Eigen::Map<const Eigen::VectorXd>(w.row(i), n);
        const collision::CollisionReachResult c = solver.solve(
            m, taskTarget(space, poseVector(p, i)), options, ids[i], w.cols > 0 ? &warm : nullptr);
        const IkResult& r = c.ik;
        md[i] = c.min_distance_m;
        s[i] = static_cast<std::uint8_t>(r.status);
        for (int j = 0; j < n; ++j) qo[i * n + j] = r.q[j];
        mo[i] = r.manipulability;
        pe[i] = r.position_error_m;
        oe[i] = r.orientation_error_rad;
        so[i] = r.starts;
      }
    }
  }
  py::dict out;
  out["status"] = status;
  out["q"] = q;
  out["manipulability"] = manip;
  out["position_error"] = position_error;
  out["orientation_error"] = orientation_error;
  out["starts"] = starts;
  out["min_distance"] = min_distance;
  return out;
}

}  // namespace

void bindSolve(py::module_& m, py::class_<Design>& design) {
  std::vector<std::string> names;
  for (int k = 0; k < kReachStatusCount; ++k)
    names.push_back(toString(static_cast<ReachStatus>(k)));
  m.attr("STATUS_NAMES") = names;
  design
      .def("solve", &solveOne, py::arg("pose"), py::arg("task") = "spraying",
           py::arg("pose_id") = 0, py::arg("warm_start") = py::none(),
           py::arg("self_collision") = py::none(), py::arg("position_tolerance") = py::none(),
           py::arg("orientation_tolerance") = py::none(), py::arg("max_starts") = py::none(),
           py::arg("seed") = py::none(),
           R"(Solves one pose w_d = (x, y, z, alpha, beta, gamma) in W with the reach maps' solver.
task: 'spraying' (position and the tool axis along the spray direction of alpha, gamma), 'full',
'position' or a Cardan selection. pose_id seeds the random starts (the same id, the same starts);
warm_start (dof,) is tried first. self_collision (default: whether the design has collision
volumes, as the reach stage) makes a colliding solution escape, else report self_collision.
Returns a dict: status, status_name, reachable, q, manipulability, position_error,
orientation_error, joint_limit_margin, starts, iterations, min_distance (smallest self-collision
distance at q, NaN without the check or a solution), colliding_pair.)")
      .def("solve_batch", &solveBatch, py::arg("poses"), py::arg("task") = "spraying",
           py::arg("pose_ids") = py::none(), py::arg("warm_starts") = py::none(),
           py::arg("threads") = 0, py::arg("self_collision") = py::none(),
           py::arg("position_tolerance") = py::none(),
           py::arg("orientation_tolerance") = py::none(), py::arg("max_starts") = py::none(),
           py::arg("seed") = py::none(),
           R"(Solves N poses (N, 6) on threads, each exactly as solve() with pose_id = pose_ids[i]
(default: the row index) and warm_starts[i]. Returns a dict of arrays: status (uint8; names in
armstudy.STATUS_NAMES), q (N, dof), manipulability, position_error, orientation_error, starts,
min_distance.)");
}

}  // namespace armstudy::python
