// The kernels on arrays: forward kinematics, Jacobians, task manipulability, dynamics and
// self-collision distances of N configurations at once. Each OpenMP thread owns one workspace of
// the library (as the stages do); rows are independent, so results do not depend on the thread
// count. The GIL is released while they run.
#include <omp.h>
#include <pybind11/stl.h>

#include <limits>
#include <optional>
#include <stdexcept>

#include "collision/collision.hpp"
#include "dynamics/dynamics.hpp"
#include "ik/reach_solver.hpp"
#include "kinematics/kinematics.hpp"
#include "python/bindings.hpp"

namespace armstudy::python {

namespace {

// Runs body(workspace, row) for every row on `threads` threads, one workspace per thread.
template <class MakeWorkspace, class Body>
void forEachRow(long n, int threads, const MakeWorkspace& make, const Body& body) {
  py::gil_scoped_release release;
  if (n == 1 || threads == 1) {
    auto ws = make();
    for (long i = 0; i < n; ++i) body(ws, i);
    return;
  }
#pragma omp parallel num_threads(threads)
  {
    auto ws = make();
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) body(ws, i);
  }
}

void storeTransform(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double* out) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out[r * 4 + c] = R(r, c);
    out[r * 4 + 3] = p[r];
  }
  out[12] = out[13] = out[14] = 0.0;
  out[15] = 1.0;
}

Eigen::Map<const Eigen::VectorXd> rowVector(const Rows& rows, long i) {
  return Eigen::Map<const Eigen::VectorXd>(rows.row(i), rows.cols);
}

// The result of a kernel on the configurations q (rows of dof values): an array of shape (N,
// extra...), row i written by body(workspace, q_i, out_i) with out_i its first element, on
// `threads` threads with a workspace from make() each.
template <class MakeWorkspace, class Body>
py::array_t<double> mapRows(const py::handle& q, int dof, const std::vector<py::ssize_t>& extra,
                            int threads, const MakeWorkspace& make, const Body& body) {
  const Rows rows = readRows(q, dof, "q");
  py::array_t<double> out = makeResult(rows, extra);
  long block = 1;
  for (const py::ssize_t e : extra) block *= e;
  double* o = out.mutable_data();
  forEachRow(rows.n, threadCount(threads), make,
             [&](auto& ws, long i) { body(ws, rowVector(rows, i), o + block * i); });
  return out;
}

// A row-major (C order, as numpy's) rows x cols matrix at o.
using RowMajorMap =
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
RowMajorMap rowMajor(double* o, long rows, long cols) { return RowMajorMap(o, rows, cols); }

// The target whose Jacobian rows a task kind constrains (the pose itself plays no part).
PoseTask taskOfKind(const std::string& task) {
  TaskSpace space;
  std::string error;
  if (!parseTaskSpace(task, space, error)) throw std::invalid_argument("task: " + error);
  return taskTarget(space, TaskVector6::Zero());
}

py::array_t<double> fk(const Design& d, const py::handle& q, int threads) {
  const Model& m = *d.model;
  return mapRows(
      q, m.dof(), {4, 4}, threads, [&] { return KinematicsWorkspace(m); },
      [&](KinematicsWorkspace& ws, const Eigen::VectorXd::ConstMapType& qi, double* o) {
        forwardKinematics(m, ws, qi);
        storeTransform(ws.R_WT, ws.p_WT, o);
      });
}

py::array_t<double> frames(const Design& d, const py::handle& q, int threads) {
  const Model& m = *d.model;
  const int n = m.dof();
  return mapRows(
      q, n, {n, 4, 4}, threads, [&] { return KinematicsWorkspace(m); },
      [&](KinematicsWorkspace& ws, const Eigen::VectorXd::ConstMapType& qi, double* o) {
        forwardKinematics(m, ws, qi);
        for (int j = 0; j < n; ++j) storeTransform(ws.R_WF[j], ws.p_WF[j], o + 16 * j);
      });
}

py::array_t<double> jacobian(const Design& d, const py::handle& q, int threads) {
  const Model& m = *d.model;
  const int n = m.dof();
  return mapRows(
      q, n, {6, n}, threads, [&] { return KinematicsWorkspace(m); },
      [&](KinematicsWorkspace& ws, const Eigen::VectorXd::ConstMapType& qi, double* o) {
        forwardKinematicsAndJacobian(m, ws, qi);
        rowMajor(o, 6, n) = ws.J_W_tcp;
      });
}

py::array_t<double> taskJacobian(const Design& d, const py::handle& q, const std::string& task,
                                 int threads) {
  const Model& m = *d.model;
  const int n = m.dof();
  const PoseTask target = taskOfKind(task);
  const int rows_m = target.rows();
  return mapRows(
      q, n, {rows_m, n}, threads, [&] { return KinematicsWorkspace(m); },
      [&](KinematicsWorkspace& ws, const Eigen::VectorXd::ConstMapType& qi, double* o) {
        forwardKinematicsAndJacobian(m, ws, qi);
        Jacobian6 J(6, n);
        const int got = taskJacobianRows(ws, target, J);
        if (got == rows_m)
          rowMajor(o, rows_m, n) = J.topRows(rows_m);
        else
          rowMajor(o, rows_m, n).setConstant(std::numeric_limits<double>::quiet_NaN());  // Cardan
      });
}

py::array_t<double> manipulability(const Design& d, const py::handle& q, const std::string& task,
                                   int threads) {
  const Model& m = *d.model;
  const PoseTask target = taskOfKind(task);
  return mapRows(
      q, m.dof(), {}, threads, [&] { return KinematicsWorkspace(m); },
      [&](KinematicsWorkspace& ws, const Eigen::VectorXd::ConstMapType& qi, double* o) {
        forwardKinematicsAndJacobian(m, ws, qi);
        *o = taskManipulability(ws, target);
      });
}

DynamicsOptions dynamicsOptions(const std::optional<std::vector<double>>& gravity, bool payload,
                                bool rotor_inertia) {
  DynamicsOptions o;
  if (gravity) {
    if (gravity->size() != 3) throw std::invalid_argument("gravity: expected 3 values (m/s^2)");
    o.g_W = Eigen::Vector3d((*gravity)[0], (*gravity)[1], (*gravity)[2]);
  }
  o.include_payload = payload;
  o.include_rotor_inertia = rotor_inertia;
  std::string error;
  if (!o.validate(error)) throw std::invalid_argument(error);
  return o;
}

py::array_t<double> inverseDynamicsRows(const Design& d, const py::handle& q, const py::handle& qd,
                                        const py::handle& qdd,
                                        const std::optional<std::vector<double>>& gravity,
                                        bool payload, bool rotor_inertia, int threads) {
  const Model& m = *d.model;
  const int n = m.dof();
  const RigidBodyModel rbm =
      makeRigidBodyModel(m, dynamicsOptions(gravity, payload, rotor_inertia));
  const Rows rq = readRows(q, n, "q");
  const Rows rqd = qd.is_none() ? Rows{} : readRows(qd, n, "qd");
  const Rows rqdd = qdd.is_none() ? Rows{} : readRows(qdd, n, "qdd");
  for (const Rows* r : {&rqd, &rqdd})
    if (r->cols > 0 && (r->n != rq.n || r->single != rq.single))
      throw std::invalid_argument("qd and qdd must have the shape of q");
  py::array_t<double> out = makeResult(rq, {n});
  double* o = out.mutable_data();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  forEachRow(
      rq.n, threadCount(threads), [&] { return DynamicsWorkspace(rbm); },
      [&](DynamicsWorkspace& ws, long i) {
        Eigen::Map<Eigen::VectorXd> tau(o + static_cast<long>(n) * i, n);
        inverseDynamics(rbm, ws, rowVector(rq, i),
                        rqd.cols ? Eigen::Ref<const Eigen::VectorXd>(rowVector(rqd, i))
                                 : Eigen::Ref<const Eigen::VectorXd>(zero),
                        rqdd.cols ? Eigen::Ref<const Eigen::VectorXd>(rowVector(rqdd, i))
                                  : Eigen::Ref<const Eigen::VectorXd>(zero),
                        tau);
      });
  return out;
}

py::array_t<double> massMatrixRows(const Design& d, const py::handle& q, bool rotor_inertia,
                                   int threads) {
  const Model& m = *d.model;
  const int n = m.dof();
  DynamicsOptions options;
  options.include_rotor_inertia = rotor_inertia;
  const RigidBodyModel rbm = makeRigidBodyModel(m, options);
  return mapRows(
      q, n, {n, n}, threads, [&] { return DynamicsWorkspace(rbm); },
      [&](DynamicsWorkspace& ws, const Eigen::VectorXd::ConstMapType& qi, double* o) {
        massMatrix(rbm, ws, qi);
        rowMajor(o, n, n) = ws.M;
      });
}

// Kinematics and collision scratch of one thread.
struct CollisionScratch {
  KinematicsWorkspace kin;
  collision::CollisionWorkspace col;
  explicit CollisionScratch(const Model& m) : kin(m), col(m) {}
};

py::array_t<double> selfDistances(const Design& d, const py::handle& q, int threads) {
  const Model& m = *d.model;
  if (m.collision.empty())
    throw std::invalid_argument("design '" + m.name + "' has no collision volumes");
  const int pairs = collision::CollisionWorkspace(m).num_self;
  collision::CollisionQueryOptions query;
  query.environment = false;
  return mapRows(
      q, m.dof(), {pairs}, threads, [&] { return CollisionScratch(m); },
      [&](CollisionScratch& s, const Eigen::VectorXd::ConstMapType& qi, double* o) {
        forwardKinematics(m, s.kin, qi);
        collision::collisionDistances(m, s.kin, {}, s.col, query);
        for (int k = 0; k < pairs; ++k) o[k] = s.col.self[k].distance_m;
      });
}

}  // namespace

void bindKernels(py::class_<Design>& design) {
  design
      .def("fk", &fk, py::arg("q"), py::arg("threads") = 0,
           R"(TCP pose in W as 4x4 homogeneous transforms: q (dof,) -> (4, 4), q (N, dof) ->
(N, 4, 4). threads: OpenMP threads for a batch (0 = all cores).)")
      .def("frames", &frames, py::arg("q"), py::arg("threads") = 0,
           "Every joint's body frame in W: (dof, 4, 4) per configuration.")
      .def("jacobian", &jacobian, py::arg("q"), py::arg("threads") = 0,
           "Geometric TCP Jacobian in W, [J_T; J_R]: (6, dof) per configuration.")
      .def("task_jacobian", &taskJacobian, py::arg("q"), py::arg("task") = "full",
           py::arg("threads") = 0,
           R"(The rows of the geometric Jacobian a task constrains, whose Yoshikawa value is the
map's manipulability. task: 'full' (default: all 6 rows), 'position' (x, y, z), 'spraying'
(x, y, z and the 2 angular rows perpendicular to the tool axis), or a Cardan selection such as
'x,y,z,gamma' (analytic rows; NaN at its singularity). (m, dof) per configuration.)")
      .def("manipulability", &manipulability, py::arg("q"), py::arg("task") = "full",
           py::arg("threads") = 0,
           R"(Task manipulability sqrt(det(J_t J_t^T)) of task_jacobian's rows (thesis eq. 5.59);
task as there, default 'full'. The reach maps report it for the study's task (e.g. 'spraying').
Unit: m^k for k position rows.)")
      .def("inverse_dynamics", &inverseDynamicsRows, py::arg("q"), py::arg("qd") = py::none(),
           py::arg("qdd") = py::none(), py::arg("gravity") = py::none(), py::arg("payload") = true,
           py::arg("rotor_inertia") = false, py::arg("threads") = 0,
           R"(Joint forces (N m / N) for q, qd, qdd (None = zero) by recursive Newton-Euler, as
`armstudy dynamics`. gravity: 3 values in W (default (0, 0, -g)). Raises InputError when the
design has no inertia data.)")
      .def("mass_matrix", &massMatrixRows, py::arg("q"), py::arg("rotor_inertia") = false,
           py::arg("threads") = 0, "Mass matrix M(q): (dof, dof) per configuration.")
      .def("self_distances", &selfDistances, py::arg("q"), py::arg("threads") = 0,
           R"(Signed distance [m] of every self-collision body pair (negative = overlap), columns
in the order of collision_pairs.)");
}

}  // namespace armstudy::python
