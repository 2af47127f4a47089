#include "kinematics/kinematics.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include "common/errors.hpp"
#include "kinematics/kernel_count.hpp"

namespace armstudy {

namespace {
thread_local long t_kernel_evaluations = 0;  // forwardKinematics calls on this thread
}  // namespace

long kernelEvaluationsOnThisThread() { return t_kernel_evaluations; }

KinematicsWorkspace::KinematicsWorkspace(const Model& model) : n(model.dof()) {
  ARMSTUDY_CHECK(n > 0 && n <= kMaxDof, "model DoF outside 1.." + std::to_string(kMaxDof));
  for (int i = 0; i < kMaxDof; ++i) {
    R_WF[i].setIdentity();
    p_WF[i].setZero();
  }
  R_WT.setIdentity();
  p_WT.setZero();
  a_WT = model.tool_axis_T;
  J_W_tcp.setZero(6, n);
}

void forwardKinematics(const Model& model, KinematicsWorkspace& ws,
                       const Eigen::Ref<const Eigen::VectorXd>& q) {
  const int n = ws.n;
  ARMSTUDY_CHECK(q.size() == n, "joint vector size does not match the model");
  ++t_kernel_evaluations;
  Eigen::Matrix3d R_Wp = model.T_WB.linear();
  Eigen::Vector3d p_Wp = model.T_WB.translation();
  for (int i = 0; i < n; ++i) {
    const Joint& jt = model.joints[i];
    const Eigen::Matrix3d& R0 = jt.T_PJ0.linear();
    // Appendix B, eq. (B.2): origin of frame i = parent origin + parent rotation * r_const.
    Eigen::Vector3d p = p_Wp + R_Wp * jt.T_PJ0.translation();
    Eigen::Matrix3d R = R_Wp * R0;
    if (jt.type == JointType::Revolute) {
      // Revolute: q adds to gamma, R = R0 * Rz(q), only the first two columns change.
      double s, c;
      ::sincos(q[i], &s, &c);  // one call for both (glibc)
      const Eigen::Vector3d c0 = R.col(0), c1 = R.col(1);
      R.col(0) = c * c0 + s * c1;
      R.col(1) = c * c1 - s * c0;
    } else {
      // Prismatic, eq. (B.16): translate by q along the new z axis.
      p += q[i] * R.col(2);
    }
    ws.R_WF[i] = R;
    ws.p_WF[i] = p;
    R_Wp = R;
    p_Wp = p;
  }
  ws.R_WT = R_Wp * model.T_NT.linear();
  ws.p_WT = p_Wp + R_Wp * model.T_NT.translation();
  ws.a_WT = ws.R_WT * model.tool_axis_T;
}

void tcpJacobian(const Model& model, KinematicsWorkspace& ws) {
  const int n = ws.n;
  ws.J_W_tcp.resize(6, n);
  for (int j = 0; j < n; ++j) {
    const Eigen::Vector3d z = ws.R_WF[j].col(2);
    if (model.joints[j].type == JointType::Revolute) {
      // eq. (B.14), (B.15): omega column e_z, translation z x (p_T - p_j).
      ws.J_W_tcp.col(j).head<3>() = z.cross(ws.p_WT - ws.p_WF[j]);
      ws.J_W_tcp.col(j).tail<3>() = z;
    } else {
      // eq. (B.20), (B.22): pure translation along z.
      ws.J_W_tcp.col(j).head<3>() = z;
      ws.J_W_tcp.col(j).tail<3>().setZero();
    }
  }
}

void forwardKinematicsAndJacobian(const Model& model, KinematicsWorkspace& ws,
                                  const Eigen::Ref<const Eigen::VectorXd>& q) {
  forwardKinematics(model, ws, q);
  tcpJacobian(model, ws);
}

void pointJacobian(const Model& model, const KinematicsWorkspace& ws, int link,
                   const Eigen::Vector3d& p_W, Eigen::Ref<Eigen::MatrixXd> J_out) {
  const int n = ws.n;
  ARMSTUDY_CHECK(J_out.rows() == 6 && J_out.cols() == n, "pointJacobian: J_out must be 6 x n");
  ARMSTUDY_CHECK(link >= -1 && link < n, "pointJacobian: link index out of range");
  J_out.setZero();
  for (int j = 0; j <= link; ++j) {
    const Eigen::Vector3d z = ws.R_WF[j].col(2);
    if (model.joints[j].type == JointType::Revolute) {
      J_out.col(j).head<3>() = z.cross(p_W - ws.p_WF[j]);
      J_out.col(j).tail<3>() = z;
    } else {
      J_out.col(j).head<3>() = z;
    }
  }
}

void tcpJacobianDerivative(const Model& model, const KinematicsWorkspace& ws, int i,
                           Eigen::Ref<Eigen::MatrixXd> dJ) {
  const int n = ws.n;
  ARMSTUDY_CHECK(dJ.rows() == 6 && dJ.cols() == n, "tcpJacobianDerivative: dJ must be 6 x n");
  ARMSTUDY_CHECK(i >= 0 && i < n, "tcpJacobianDerivative: joint index out of range");
  dJ.setZero();
  const bool i_rev = model.joints[i].type == JointType::Revolute;
  const Eigen::Vector3d z_i = ws.R_WF[i].col(2);
  // Velocity of the TCP due to joint i: d p_T / d q_i.
  const Eigen::Vector3d dpT = i_rev ? Eigen::Vector3d(z_i.cross(ws.p_WT - ws.p_WF[i])) : z_i;
  for (int j = 0; j < n; ++j) {
    const Eigen::Vector3d z_j = ws.R_WF[j].col(2);
    const bool j_rev = model.joints[j].type == JointType::Revolute;
    if (j_rev) {
      if (i < j) {
        if (!i_rev) continue;  // a prismatic joint before j shifts p_T and p_j alike
        const Eigen::Vector3d dz_j = z_i.cross(z_j);
        const Eigen::Vector3d r = ws.p_WT - ws.p_WF[j];
        dJ.col(j).head<3>() = dz_j.cross(r) + z_j.cross(z_i.cross(r));
        dJ.col(j).tail<3>() = dz_j;
      } else {
        // i >= j: z_j and p_j do not depend on q_i; only p_T moves.
        dJ.col(j).head<3>() = z_j.cross(dpT);
      }
    } else {
      // Prismatic column z_j rotates with revolute joints before j.
      if (i < j && i_rev) dJ.col(j).head<3>() = z_i.cross(z_j);
    }
  }
}

Eigen::Matrix3d rotationFromCardan(double alpha, double beta, double gamma) {
  return (Eigen::AngleAxisd(alpha, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(beta, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(gamma, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

CardanAngles cardanFromRotation(const Eigen::Matrix3d& R) {
  // R = Rx(a) Ry(b) Rz(g): R(0,2) = sin b, R(1,2) = -sin a cos b, R(2,2) = cos a cos b,
  // R(0,0) = cos b cos g, R(0,1) = -cos b sin g.
  CardanAngles c;
  const double cb = std::hypot(R(0, 0), R(0, 1));
  c.beta = std::atan2(R(0, 2), cb);
  if (cb < defaults::kCardanSingularCosBeta) {
    // Gimbal lock: only alpha +/- gamma is defined; report it and choose gamma = 0.
    c.singular = true;
    c.gamma = 0.0;
    c.alpha = std::atan2(R(2, 1), R(1, 1));
  } else {
    c.alpha = std::atan2(-R(1, 2), R(2, 2));
    c.gamma = std::atan2(-R(0, 1), R(0, 0));
  }
  return c;
}

CardanAngles cardanForDisplay(const Eigen::Matrix3d& R) {
  CardanAngles c = cardanFromRotation(R);
  if (!c.singular || std::hypot(R(0, 0), R(0, 1)) < defaults::kCardanRoundingCosBeta) return c;
  // Within the band: alpha + gamma (sin beta > 0) or alpha - gamma (sin beta < 0) from the large
  // entries R(1,1) = cos, R(2,1) = sin of it (up to terms of order 1 - sin|beta|), gamma from the
  // small ones; its error only scales terms of the size of cos(beta), so R is reproduced.
  c.gamma = std::atan2(-R(0, 1), R(0, 0));
  const double s = std::atan2(R(2, 1), R(1, 1));
  c.alpha = std::remainder(R(0, 2) > 0 ? s - c.gamma : s + c.gamma, 2 * std::numbers::pi);
  return c;
}

bool cardanRateMatrix(double alpha, double beta, Eigen::Matrix3d& T) {
  const double cb = std::cos(beta);
  if (std::abs(cb) < defaults::kCardanSingularCosBeta) return false;
  const double sb = std::sin(beta), sa = std::sin(alpha), ca = std::cos(alpha);
  // Thesis eq. (5.10).
  T << cb, sb * sa, -sb * ca,  //
      0, cb * ca, cb * sa,     //
      0, -sa, ca;
  T /= cb;
  return true;
}

int TaskSpace::dim() const {
  int d = 0;
  for (bool s : selected) d += s ? 1 : 0;
  return d;
}
TaskSpace TaskSpace::fullPose() { return TaskSpace{{true, true, true, true, true, true}}; }
TaskSpace TaskSpace::spraying() { return TaskSpace{{true, true, true, true, false, true}}; }
TaskSpace TaskSpace::position() { return TaskSpace{{true, true, true, false, false, false}}; }

static const char* kComponentNames[6] = {"x", "y", "z", "alpha", "beta", "gamma"};

std::string TaskSpace::toString() const {
  std::string s;
  for (int k = 0; k < 6; ++k)
    if (selected[k]) {
      if (!s.empty()) s += ',';
      s += kComponentNames[k];
    }
  return s;
}

bool parseTaskSpace(const std::string& text, TaskSpace& out, std::string& error) {
  if (text == "full" || text == "pose") return out = TaskSpace::fullPose(), true;
  if (text == "spraying") return out = TaskSpace::spraying(), true;
  if (text == "position") return out = TaskSpace::position(), true;
  TaskSpace t;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    int k = -1;
    for (int c = 0; c < 6; ++c)
      if (item == kComponentNames[c]) k = c;
    if (k < 0) {
      error = "unknown task-space component '" + item +
              "' (expected full, spraying, position, or a list of x, y, z, alpha, beta, gamma)";
      return false;
    }
    if (t.selected[k]) {
      error = "task-space component '" + item + "' listed twice";
      return false;
    }
    t.selected[k] = true;
  }
  if (t.dim() == 0) {
    error = "empty task space";
    return false;
  }
  out = t;
  return true;
}

TaskVector tcpTaskVector(const KinematicsWorkspace& ws) {
  TaskVector tv;
  const CardanAngles c = cardanFromRotation(ws.R_WT);
  tv.w << ws.p_WT, c.alpha, c.beta, c.gamma;
  tv.singular = c.singular;
  return tv;
}

bool analyticJacobian(const KinematicsWorkspace& ws, const TaskSpace& task,
                      Eigen::Ref<Eigen::MatrixXd> J_out) {
  const int n = ws.n;
  ARMSTUDY_CHECK(J_out.rows() == task.dim() && J_out.cols() == n,
                 "analyticJacobian: J_out must be task.dim() x n");
  Eigen::Matrix3d T_A_inv;
  if (task.hasOrientation()) {
    const CardanAngles c = cardanFromRotation(ws.R_WT);
    if (c.singular || !cardanRateMatrix(c.alpha, c.beta, T_A_inv)) return false;
  }
  int row = 0;
  for (int k = 0; k < 3; ++k)
    if (task.selected[k]) J_out.row(row++) = ws.J_W_tcp.row(k);
  for (int k = 0; k < 3; ++k)
    if (task.selected[3 + k])
      J_out.row(row++) = T_A_inv.row(k) * ws.J_W_tcp.bottomRows<3>();  // eq. (5.9)
  return true;
}

}  // namespace armstudy
