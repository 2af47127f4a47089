#include "dynamics/dynamics.hpp"

#include <cmath>

#include "common/enum_names.hpp"
#include "common/errors.hpp"

namespace armstudy {
namespace {

// Inertia of a point mass m at c about the origin: m (|c|^2 1 - c c^T) (parallel-axis term).
Eigen::Matrix3d pointInertia(double m, const Eigen::Vector3d& c) {
  return m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
}

// Joint transforms of all links in their parent frames: R = R0 Rz(q) (revolute) or p = p0 + q z0
// (prismatic), Appendix B eq. (B.9), (B.16).
inline void jointTransforms(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                            const Eigen::Ref<const Eigen::VectorXd>& q) {
  for (int i = 0; i < rbm.n; ++i) {
    const Eigen::Matrix3d& R0 = rbm.R_PJ0[i];
    if (rbm.type[i] == JointType::Revolute) {
      const double c = std::cos(q[i]), s = std::sin(q[i]);
      ws.R[i].col(0) = c * R0.col(0) + s * R0.col(1);
      ws.R[i].col(1) = c * R0.col(1) - s * R0.col(0);
      ws.R[i].col(2) = R0.col(2);
      ws.p[i] = rbm.p_PJ0[i];
    } else {
      ws.R[i] = R0;
      ws.p[i] = rbm.p_PJ0[i] + q[i] * R0.col(2);
    }
  }
}

// Recursive Newton-Euler. kVel/kAcc drop the velocity/acceleration terms at compile time (bias and
// gravity vectors); kGravity drops gravity (mass-matrix columns by unit accelerations).
template <bool kVel, bool kAcc, bool kGravity>
void rnea(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
          const Eigen::Ref<const Eigen::VectorXd>& q, const double* qd, const double* qdd,
          Eigen::Ref<Eigen::VectorXd> tau) {
  const int n = rbm.n;
  ARMSTUDY_CHECK(q.size() == n && tau.size() == n,
                 "inverse dynamics: vector size does not match the model");
  jointTransforms(rbm, ws, q);
  // Forward recursion (Appendix B, eq. B.4-B.6, B.10-B.13, B.17-B.19), all in link coordinates.
  // Gravity enters as an upward acceleration of the base: a_0 = -g.
  Eigen::Vector3d w = Eigen::Vector3d::Zero(), wd = Eigen::Vector3d::Zero();
  Eigen::Vector3d a = kGravity ? Eigen::Vector3d(-rbm.g_B) : Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix3d& R = ws.R[i];
    const Eigen::Vector3d& p = ws.p[i];
    // Acceleration of origin i in parent coordinates, eq. (B.11)/(B.18) without the joint terms.
    Eigen::Vector3d a_p = a;
    if constexpr (kVel || kAcc) a_p += wd.cross(p);
    if constexpr (kVel) a_p += w.cross(w.cross(p));
    Eigen::Vector3d wi = Eigen::Vector3d::Zero(), wdi = Eigen::Vector3d::Zero();
    if constexpr (kVel) wi.noalias() = R.transpose() * w;
    if constexpr (kVel || kAcc) wdi.noalias() = R.transpose() * wd;
    Eigen::Vector3d ai;
    ai.noalias() = R.transpose() * a_p;
    const double qdi = kVel ? qd[i] : 0.0;
    const double qddi = kAcc ? qdd[i] : 0.0;
    if (rbm.type[i] == JointType::Revolute) {
      // eq. (B.12), (B.13): omega_rel = qd e_z, omegadot_rel = omega x e_z qd + qdd e_z.
      if constexpr (kVel) {
        wdi.x() += wi.y() * qdi;
        wdi.y() -= wi.x() * qdi;
        wi.z() += qdi;
      }
      if constexpr (kAcc) wdi.z() += qddi;
    } else {
      // eq. (B.18): Coriolis 2 omega x (e_z qd) and qdd e_z.
      if constexpr (kVel) {
        ai.x() += 2.0 * wi.y() * qdi;
        ai.y() -= 2.0 * wi.x() * qdi;
      }
      if constexpr (kAcc) ai.z() += qddi;
    }
    ws.w[i] = wi;
    ws.wd[i] = wdi;
    ws.a[i] = ai;
    // Momentum rates about the link origin, eq. (3.22)-(3.25): f = m a_C, n = I_O wd + w x I_O w +
    // h x a.
    const Eigen::Vector3d& h = rbm.h[i];
    const Eigen::Matrix3d& I = rbm.I_O[i];
    ws.f[i] = rbm.mass[i] * ai;
    ws.nm[i] = h.cross(ai);
    if constexpr (kVel || kAcc) {
      ws.f[i] += wdi.cross(h);
      ws.nm[i].noalias() += I * wdi;
    }
    if constexpr (kVel) {
      ws.f[i] += wi.cross(wi.cross(h));
      ws.nm[i] += wi.cross(I * wi);
    }
    w = wi;
    wd = wdi;
    a = ai;
  }
  // Backward recursion, eq. (3.22), (3.23a): F_i = f_i + F_{i+1}, T_i = n_i + T_{i+1} + r_rel x
  // F_{i+1}.
  Eigen::Vector3d F = Eigen::Vector3d::Zero(), T = Eigen::Vector3d::Zero();
  for (int i = n - 1; i >= 0; --i) {
    if (i + 1 < n) {
      const Eigen::Vector3d Fc = ws.R[i + 1] * F;
      T = ws.R[i + 1] * T + ws.p[i + 1].cross(Fc);
      F = Fc;
    }
    F += ws.f[i];
    T += ws.nm[i];
    // eq. (3.26): the component along the joint axis e_z.
    tau[i] = rbm.type[i] == JointType::Revolute ? T.z() : F.z();
    if constexpr (kAcc) tau[i] += rbm.armature[i] * qdd[i];
  }
}

}  // namespace

bool DynamicsOptions::validate(std::string& error) const {
  if (!g_W.allFinite()) {
    error = "gravity vector must be finite";
    return false;
  }
  return true;
}

RigidBodyModel makeRigidBodyModel(const Model& model, const DynamicsOptions& options) {
  std::string err;
  ARMSTUDY_CHECK(options.validate(err), err);
  const int n = model.dof();
  ARMSTUDY_CHECK(n > 0 && n <= kMaxDof, "model DoF outside 1.." + std::to_string(kMaxDof));
  if (model.inertias.empty())
    throw InputError(
        model.file, 1, "inertia",
        "design '" + model.name + "' has no [[inertia]] data; dynamics needs link masses");
  ARMSTUDY_CHECK(static_cast<int>(model.inertias.size()) == n,
                 "one LinkInertia per joint expected");
  RigidBodyModel rbm;
  rbm.n = n;
  rbm.options = options;
  for (int i = 0; i < n; ++i) {
    const Joint& j = model.joints[i];
    rbm.type[i] = j.type;
    rbm.R_PJ0[i] = j.T_PJ0.linear();
    rbm.p_PJ0[i] = j.T_PJ0.translation();
    const LinkInertia& li = model.inertias[i];
    rbm.mass[i] = li.given ? li.mass_kg : 0.0;
    rbm.h[i] = rbm.mass[i] * li.p_com_m;
    rbm.I_O[i] = li.given ? Eigen::Matrix3d(li.I_com_kgm2 + pointInertia(li.mass_kg, li.p_com_m))
                          : Eigen::Matrix3d::Zero();
    rbm.armature[i] = 0.0;
  }
  if (options.include_payload && model.payload_kg > 0) {
    // The payload (end-effector and fruit) is a point mass rigidly attached to the last link.
    const Eigen::Vector3d c = model.T_NT * model.p_payload_com_T;
    rbm.mass[n - 1] += model.payload_kg;
    rbm.h[n - 1] += model.payload_kg * c;
    rbm.I_O[n - 1] += pointInertia(model.payload_kg, c);
  }
  if (options.include_rotor_inertia) {
    for (const Drive& d : model.drives) {
      const int i = model.jointIndex(d.joint);
      ARMSTUDY_CHECK(i >= 0, "drive for an unknown joint survived validation");
      if (!(d.gear_ratio > 0))
        throw InputError(model.file, d.source_line, "drive.gear_ratio",
                         "gear ratio must be positive");
      // Rotor inertia reflected through the transmission (eq. 3.27): N^2 J_rotor.
      rbm.armature[i] = d.gear_ratio * d.gear_ratio * d.rotor_inertia_kgm2;
    }
  }
  rbm.R_WB = model.T_WB.linear();
  rbm.p_WB = model.T_WB.translation();
  rbm.g_B = rbm.R_WB.transpose() * options.g_W;
  return rbm;
}

DynamicsWorkspace::DynamicsWorkspace(const RigidBodyModel& rbm) : n(rbm.n) {
  ARMSTUDY_CHECK(n > 0 && n <= kMaxDof,
                 "dynamics workspace: DoF outside 1.." + std::to_string(kMaxDof));
  for (int i = 0; i < kMaxDof; ++i) {
    R[i].setIdentity();
    p[i].setZero();
    w[i].setZero();
    wd[i].setZero();
    a[i].setZero();
    f[i].setZero();
    nm[i].setZero();
    hc[i].setZero();
    Ic[i].setZero();
  }
  M.setZero(n, n);
  L.setZero(n, n);
  rhs.setZero(n);
}

void inverseDynamics(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                     const Eigen::Ref<const Eigen::VectorXd>& q,
                     const Eigen::Ref<const Eigen::VectorXd>& qd,
                     const Eigen::Ref<const Eigen::VectorXd>& qdd,
                     Eigen::Ref<Eigen::VectorXd> tau_out) {
  ARMSTUDY_CHECK(qd.size() == rbm.n && qdd.size() == rbm.n,
                 "inverse dynamics: vector size mismatch");
  rnea<true, true, true>(rbm, ws, q, qd.data(), qdd.data(), tau_out);
}

void biasForces(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                const Eigen::Ref<const Eigen::VectorXd>& q,
                const Eigen::Ref<const Eigen::VectorXd>& qd, Eigen::Ref<Eigen::VectorXd> h_out) {
  ARMSTUDY_CHECK(qd.size() == rbm.n, "bias forces: vector size mismatch");
  rnea<true, false, true>(rbm, ws, q, qd.data(), nullptr, h_out);
}

void gravityForces(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                   const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Ref<Eigen::VectorXd> g_out) {
  rnea<false, false, true>(rbm, ws, q, nullptr, nullptr, g_out);
}

void massMatrix(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                const Eigen::Ref<const Eigen::VectorXd>& q) {
  const int n = rbm.n;
  ARMSTUDY_CHECK(q.size() == n, "mass matrix: vector size does not match the model");
  jointTransforms(rbm, ws, q);
  // Composite rigid bodies: subtree mass, first moment and inertia about each frame origin.
  for (int i = 0; i < n; ++i) {
    ws.mc[i] = rbm.mass[i];
    ws.hc[i] = rbm.h[i];
    ws.Ic[i] = rbm.I_O[i];
  }
  for (int i = n - 1; i > 0; --i) {
    const Eigen::Matrix3d& R = ws.R[i];
    const Eigen::Vector3d& p = ws.p[i];
    const Eigen::Vector3d hR = R * ws.hc[i];
    const double m = ws.mc[i];
    ws.mc[i - 1] += m;
    ws.hc[i - 1] += hR + m * p;
    // Shift to the parent origin: sum m (r~)^T r~ with r = p + r' gives
    // R Ic R^T - m p~ p~ - p~ hR~ - hR~ p~, expanded with a~ b~ = b a^T - (a . b) 1.
    Eigen::Matrix3d& Ip = ws.Ic[i - 1];
    Ip.noalias() += R * ws.Ic[i] * R.transpose();
    Ip.noalias() -= m * p * p.transpose() + hR * p.transpose() + p * hR.transpose();
    Ip.diagonal().array() += m * p.squaredNorm() + 2.0 * p.dot(hR);
  }
  ws.M.resize(n, n);
  for (int i = 0; i < n; ++i) {
    // Spatial force of the composite body i moving with unit speed of joint i.
    Eigen::Vector3d F, T;
    if (rbm.type[i] == JointType::Revolute) {
      F = Eigen::Vector3d::UnitZ().cross(ws.hc[i]);
      T = ws.Ic[i].col(2);
    } else {
      F = ws.mc[i] * Eigen::Vector3d::UnitZ();
      T = ws.hc[i].cross(Eigen::Vector3d::UnitZ());
    }
    ws.M(i, i) = (rbm.type[i] == JointType::Revolute ? T.z() : F.z()) + rbm.armature[i];
    for (int j = i; j > 0; --j) {
      const Eigen::Vector3d Fp = ws.R[j] * F;
      T = ws.R[j] * T + ws.p[j].cross(Fp);
      F = Fp;
      const double Mji = rbm.type[j - 1] == JointType::Revolute ? T.z() : F.z();
      ws.M(j - 1, i) = Mji;
      ws.M(i, j - 1) = Mji;
    }
  }
}

constexpr const char* kForwardDynamicsStatusNames[] = {"ok", "singular_mass_matrix"};
const char* toString(ForwardDynamicsStatus s) { return enumName(s, kForwardDynamicsStatusNames); }

ForwardDynamicsStatus forwardDynamics(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                                      const Eigen::Ref<const Eigen::VectorXd>& q,
                                      const Eigen::Ref<const Eigen::VectorXd>& qd,
                                      const Eigen::Ref<const Eigen::VectorXd>& Q,
                                      Eigen::Ref<Eigen::VectorXd> qdd_out) {
  const int n = rbm.n;
  ARMSTUDY_CHECK(Q.size() == n && qdd_out.size() == n, "forward dynamics: vector size mismatch");
  ws.rhs.resize(n);
  biasForces(rbm, ws, q, qd, ws.rhs);
  ws.rhs = Q - ws.rhs;
  massMatrix(rbm, ws, q);
  // Unblocked Cholesky M = L L^T; for n <= kMaxDof it beats a general blocked factorisation.
  MassMatrix& L = ws.L;
  L.resize(n, n);
  for (int j = 0; j < n; ++j) {
    double d = ws.M(j, j);
    for (int k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
    if (!(d > 0.0) || !std::isfinite(d)) return ForwardDynamicsStatus::SingularMassMatrix;
    d = std::sqrt(d);
    L(j, j) = d;
    for (int i = j + 1; i < n; ++i) {
      double v = ws.M(i, j);
      for (int k = 0; k < j; ++k) v -= L(i, k) * L(j, k);
      L(i, j) = v / d;
    }
  }
  // Forward substitution L y = rhs, then back substitution L^T qdd = y (in place in rhs).
  for (int i = 0; i < n; ++i) {
    double v = ws.rhs[i];
    for (int k = 0; k < i; ++k) v -= L(i, k) * ws.rhs[k];
    ws.rhs[i] = v / L(i, i);
  }
  for (int i = n - 1; i >= 0; --i) {
    double v = ws.rhs[i];
    for (int k = i + 1; k < n; ++k) v -= L(k, i) * ws.rhs[k];
    ws.rhs[i] = v / L(i, i);
  }
  qdd_out = ws.rhs;
  return ForwardDynamicsStatus::Ok;
}

MechanicalEnergy mechanicalEnergy(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                                  const Eigen::Ref<const Eigen::VectorXd>& q,
                                  const Eigen::Ref<const Eigen::VectorXd>& qd) {
  const int n = rbm.n;
  ARMSTUDY_CHECK(q.size() == n && qd.size() == n, "mechanical energy: vector size mismatch");
  jointTransforms(rbm, ws, q);
  MechanicalEnergy e;
  // Velocities in link coordinates (eq. B.3, B.5, B.10, B.12, B.17) and poses in B (eq. B.2).
  Eigen::Vector3d w = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_B = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_B = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix3d& R = ws.R[i];
    const Eigen::Vector3d& p = ws.p[i];
    Eigen::Vector3d vi = R.transpose() * (v + w.cross(p));
    Eigen::Vector3d wi = R.transpose() * w;
    if (rbm.type[i] == JointType::Revolute)
      wi.z() += qd[i];
    else
      vi.z() += qd[i];
    p_B += R_B * p;
    R_B = R_B * R;
    // T = 1/2 m v^2 + v . (w x h) + 1/2 w^T I_O w for a body with origin velocity v.
    e.kinetic_J += 0.5 * rbm.mass[i] * vi.squaredNorm() + vi.dot(wi.cross(rbm.h[i])) +
                   0.5 * wi.dot(rbm.I_O[i] * wi) + 0.5 * rbm.armature[i] * qd[i] * qd[i];
    // V = -m g . p_C with p_C = p_B + R_B c.
    e.potential_J -= rbm.g_B.dot(rbm.mass[i] * p_B + R_B * rbm.h[i]);
    w = wi;
    v = vi;
  }
  // The base offset in W shifts V by a constant: -(total mass) g_W . p_WB.
  double m_total = 0;
  for (int i = 0; i < n; ++i) m_total += rbm.mass[i];
  e.potential_J -= m_total * rbm.options.g_W.dot(rbm.p_WB);
  return e;
}

}  // namespace armstudy
