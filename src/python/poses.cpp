// Poses both ways: 4x4 homogeneous transforms, position + rotation matrix or quaternion, the
// study's Cardan parameters w = (x, y, z, alpha, beta, gamma) with R = Rx(alpha) Ry(beta) Rz(gamma)
// (docs/conventions.md), and the spraying task's direction d(alpha, gamma) (docs/reachability.md),
// each through the library's own conversion (kinematics: rotationFromCardan, cardanForDisplay;
// ik/reach_solver: sprayDirection).
#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "ik/reach_solver.hpp"
#include "kinematics/kinematics.hpp"
#include "python/bindings.hpp"

namespace armstudy::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// `a` as rows of `tail` shape: (tail...) is one row (single), (N, tail...) N rows.
struct Batch {
  Array a;
  long n = 1;
  bool single = true;
};

Batch batchOf(const py::handle& object, std::vector<py::ssize_t> tail, const char* what) {
  Batch b;
  b.a = Array::ensure(object);
  if (!b.a) throw std::invalid_argument(std::string(what) + ": expected an array of numbers");
  const auto nd = static_cast<std::size_t>(b.a.ndim());
  const auto matches = [&](std::size_t offset) {
    if (nd != tail.size() + offset) return false;
    for (std::size_t k = 0; k < tail.size(); ++k)
      if (b.a.shape(static_cast<py::ssize_t>(k + offset)) != tail[k]) return false;
    return true;
  };
  if (matches(0)) {
    b.single = true;
    b.n = 1;
  } else if (matches(1)) {
    b.single = false;
    b.n = static_cast<long>(b.a.shape(0));
  } else {
    std::string want;
    for (auto t : tail) want += ", " + std::to_string(t);
    throw std::invalid_argument(std::string(what) + ": expected shape (" + want.substr(2) +
                                ") or (N" + want + ")");
  }
  const double* p = b.a.data();
  for (py::ssize_t i = 0; i < b.a.size(); ++i)
    if (!std::isfinite(p[i])) throw std::invalid_argument(std::string(what) + ": not finite");
  return b;
}

py::array_t<double> result(const Batch& b, std::vector<py::ssize_t> tail) {
  if (!b.single) tail.insert(tail.begin(), b.n);
  return py::array_t<double>(tail);
}

void storeMatrix(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double* o) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) o[4 * r + c] = R(r, c);
    o[4 * r + 3] = p[r];
  }
  o[12] = o[13] = o[14] = 0;
  o[15] = 1;
}

Eigen::Matrix3d rotationOf(const double* T, int stride) {
  Eigen::Matrix3d R;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R(r, c) = T[stride * r + c];
  return R;
}

// Throws unless R is a rotation to 1e-9 (orthonormal, det +1).
void checkRotation(const Eigen::Matrix3d& R, const char* what) {
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9 ||
      R.determinant() < 0)
    throw std::invalid_argument(std::string(what) +
                                ": the rotation part is not a rotation matrix (to 1e-9)");
}

py::array_t<double> poseToMatrix(const py::handle& pose) {
  const Batch b = batchOf(pose, {6}, "pose");
  py::array_t<double> out = result(b, {4, 4});
  const double* w = b.a.data();
  double* o = out.mutable_data();
  for (long i = 0; i < b.n; ++i, w += 6)
    storeMatrix(rotationFromCardan(w[3], w[4], w[5]), Eigen::Vector3d(w[0], w[1], w[2]),
                o + 16 * i);
  return out;
}

py::array_t<double> matrixToPose(const py::handle& matrix) {
  const Batch b = batchOf(matrix, {4, 4}, "matrix");
  py::array_t<double> out = result(b, {6});
  const double* T = b.a.data();
  double* o = out.mutable_data();
  for (long i = 0; i < b.n; ++i, T += 16) {
    const Eigen::Matrix3d R = rotationOf(T, 4);
    checkRotation(R, "matrix");
    const CardanAngles a = cardanForDisplay(R);
    const double w[6] = {T[3], T[7], T[11], a.alpha, a.beta, a.gamma};
    std::copy(w, w + 6, o + 6 * i);
  }
  return out;
}

py::array_t<double> makeTransform(const py::handle& position, const py::handle& rotation,
                                  const py::handle& quaternion) {
  if (!rotation.is_none() && !quaternion.is_none())
    throw std::invalid_argument("give rotation or quaternion, not both");
  const Batch p = batchOf(position, {3}, "position");
  Batch r;
  const bool quat = !quaternion.is_none();
  if (!rotation.is_none()) r = batchOf(rotation, {3, 3}, "rotation");
  if (quat) r = batchOf(quaternion, {4}, "quaternion");
  const bool any = quat || !rotation.is_none();
  if (any && (r.n != p.n || r.single != p.single))
    throw std::invalid_argument("position and rotation/quaternion: different batch sizes");
  py::array_t<double> out = result(p, {4, 4});
  double* o = out.mutable_data();
  for (long i = 0; i < p.n; ++i) {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    if (quat) {
      const double* q = r.a.data() + 4 * i;
      Eigen::Quaterniond e(q[0], q[1], q[2], q[3]);
      if (e.norm() < 1e-12) throw std::invalid_argument("quaternion: zero");
      R = e.normalized().toRotationMatrix();
    } else if (any) {
      R = rotationOf(r.a.data() + 9 * i, 3);
      checkRotation(R, "rotation");
    }
    const double* x = p.a.data() + 3 * i;
    storeMatrix(R, Eigen::Vector3d(x[0], x[1], x[2]), o + 16 * i);
  }
  return out;
}

py::array_t<double> matrixToQuaternion(const py::handle& matrix) {
  const Array raw = Array::ensure(matrix);
  const int stride = raw && raw.ndim() >= 2 && raw.shape(raw.ndim() - 1) == 4 ? 4 : 3;
  const Batch b = batchOf(matrix, {stride, stride}, "matrix");
  py::array_t<double> out = result(b, {4});
  double* o = out.mutable_data();
  const long step = stride == 4 ? 16 : 9;
  for (long i = 0; i < b.n; ++i) {
    const Eigen::Matrix3d R = rotationOf(b.a.data() + step * i, stride);
    checkRotation(R, "matrix");
    Eigen::Quaterniond q(R);
    if (q.w() < 0) q.coeffs() = -q.coeffs();  // the w >= 0 hemisphere
    o[4 * i] = q.w();
    o[4 * i + 1] = q.x();
    o[4 * i + 2] = q.y();
    o[4 * i + 3] = q.z();
  }
  return out;
}

py::array_t<double> sprayDirections(const py::handle& alpha, const py::handle& gamma) {
  const Array a = Array::ensure(alpha), g = Array::ensure(gamma);
  if (!a || !g || a.size() != g.size() || a.ndim() > 1 || g.ndim() > 1)
    throw std::invalid_argument("alpha, gamma: two numbers or two arrays of one length");
  const bool single = a.ndim() == 0 && g.ndim() == 0;
  const long n = static_cast<long>(a.size());
  py::array_t<double> out =
      single ? py::array_t<double>(std::vector<py::ssize_t>{3}) : py::array_t<double>({n, 3L});
  double* o = out.mutable_data();
  for (long i = 0; i < n; ++i) {
    const Eigen::Vector3d d = sprayDirection(a.data()[i], g.data()[i]);
    for (int k = 0; k < 3; ++k) o[3 * i + k] = d[k];
  }
  return out;
}

py::array_t<double> directionToAngles(const py::handle& direction) {
  const Batch b = batchOf(direction, {3}, "direction");
  py::array_t<double> out = result(b, {2});
  double* o = out.mutable_data();
  for (long i = 0; i < b.n; ++i) {
    Eigen::Vector3d d(b.a.data() + 3 * i);
    if (d.norm() < 1e-12) throw std::invalid_argument("direction: zero vector");
    d.normalize();
    // d = (-sin gamma, cos alpha cos gamma, sin alpha cos gamma), gamma in [-pi/2, pi/2].
    o[2 * i] = std::atan2(d[2], d[1]);
    o[2 * i + 1] = std::atan2(-d[0], std::hypot(d[1], d[2]));
  }
  return out;
}

}  // namespace

void bindPoses(py::module_& m) {
  m.def("pose_to_matrix", &poseToMatrix, py::arg("pose"),
        R"(The 4x4 homogeneous transform of a study pose w = (x, y, z, alpha, beta, gamma):
position in metres, R = Rx(alpha) Ry(beta) Rz(gamma) with the angles in radians (fixed x-y-z
Cardan angles, docs/conventions.md). (6,) -> (4, 4); (N, 6) -> (N, 4, 4).)");
  m.def("matrix_to_pose", &matrixToPose, py::arg("matrix"),
        R"(The study pose (x, y, z, alpha, beta, gamma) of a 4x4 transform (metres, radians;
beta in [-pi/2, pi/2]): pose_to_matrix of it gives the matrix back to rounding (near beta =
+-pi/2, where alpha and gamma turn about one axis, gamma is 0). Raises ValueError when the
rotation part is not a rotation to 1e-9. (4, 4) -> (6,); (N, 4, 4) -> (N, 6).)");
  m.def("make_transform", &makeTransform, py::arg("position"), py::arg("rotation") = py::none(),
        py::arg("quaternion") = py::none(),
        R"(A 4x4 transform from a position (3,) [m] and a rotation matrix (3, 3) or a unit
quaternion (w, x, y, z) (normalised here); neither: the identity rotation. Batches (N, ...) give
(N, 4, 4).)");
  m.def("matrix_to_quaternion", &matrixToQuaternion, py::arg("matrix"),
        R"(The unit quaternion (w, x, y, z), w >= 0, of a rotation matrix (3, 3) or of a
transform's rotation part (4, 4); batches (N, ...) give (N, 4).)");
  m.def("spray_direction", &sprayDirections, py::arg("alpha"), py::arg("gamma"),
        R"(The spraying task's direction d(alpha, gamma) = Rx(alpha) Rz(gamma) e_y =
(-sin gamma, cos alpha cos gamma, sin alpha cos gamma) in W (angles in radians; thesis eq. 3.1,
docs/reachability.md): the design's tool axis points along it. Numbers -> (3,); arrays (N,) ->
(N, 3).)");
  m.def("direction_to_angles", &directionToAngles, py::arg("direction"),
        R"(The (alpha, gamma) [rad] whose spray_direction is `direction` (normalised here):
alpha = atan2(d_z, d_y), gamma = atan2(-d_x, hypot(d_y, d_z)) in [-pi/2, pi/2]. (3,) -> (2,);
(N, 3) -> (N, 2).)");
}

}  // namespace armstudy::python
