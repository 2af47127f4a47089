#include "dynamics/drive_feasibility.hpp"

#include <cmath>
#include <iterator>
#include <limits>

#include "common/enum_names.hpp"
#include "common/errors.hpp"

namespace armstudy {

constexpr const char* kDriveQuantityNames[] = {"peak_current", "rms_current", "motor_speed",
                                               "voltage"};
static_assert(std::size(kDriveQuantityNames) == kDriveQuantityCount);
const char* toString(DriveQuantity q) { return enumName(q, kDriveQuantityNames); }

namespace {

const Drive* driveOf(const Model& model, const std::string& joint) {
  for (const Drive& d : model.drives)
    if (d.joint == joint) return &d;
  return nullptr;
}

void setLimit(QuantityCheck& c, double limit) {
  c.limit = limit;
  c.checked = limit > 0;
  c.margin = std::numeric_limits<double>::quiet_NaN();
}

void finishCheck(QuantityCheck& c) {
  if (!c.checked) return;
  c.margin = (c.limit - c.value) / c.limit;
  c.exceeded = c.first_exceeded_k >= 0;
}

// Marks the first sample k at which `over` holds.
void firstOver(QuantityCheck& c, bool over, int k, double t) {
  if (c.checked && over && c.first_exceeded_k < 0) {
    c.first_exceeded_k = k;
    c.first_exceeded_s = t;
  }
}

}  // namespace

DriveFeasibility evaluateDriveFeasibility(const Model& model, const RigidBodyModel& rbm,
                                          DynamicsWorkspace& ws, const JointTrajectory& traj,
                                          const DriveFeasibilityOptions& options) {
  const int n = model.dof();
  const int ns = traj.size();
  ARMSTUDY_CHECK(rbm.n == n, "evaluateDriveFeasibility: rigid-body model of another design");
  ARMSTUDY_CHECK(ns > 0 && traj.dt > 0, "evaluateDriveFeasibility: empty trajectory or dt <= 0");
  ARMSTUDY_CHECK(static_cast<int>(traj.q.size()) == ns && static_cast<int>(traj.qd.size()) == ns &&
                     static_cast<int>(traj.qdd.size()) == ns,
                 "evaluateDriveFeasibility: inconsistent trajectory arrays");
  ARMSTUDY_CHECK(!(options.drive_rotor_inertia && rbm.options.include_rotor_inertia),
                 "rotor inertia counted twice (dynamics and drive chain)");
  DriveFeasibility res;
  res.options_used = options;
  res.joints.resize(n);

  // Inverse dynamics at every sample (eq. 3.28).
  std::vector<JointVector> Q(ns, JointVector::Zero(n));
  Eigen::VectorXd tau(n);
  for (int k = 0; k < ns; ++k) {
    ARMSTUDY_CHECK(traj.q[k].size() == n && traj.qd[k].size() == n && traj.qdd[k].size() == n,
                   "evaluateDriveFeasibility: sample of the wrong size");
    inverseDynamics(rbm, ws, traj.q[k], traj.qd[k], traj.qdd[k], tau);
    Q[k] = tau;
  }
  if (options.keep_profiles) {
    res.effort = Q;
    res.motor_torque.assign(ns, JointVector::Zero(n));
    res.current.assign(ns, JointVector::Zero(n));
    res.motor_speed.assign(ns, JointVector::Zero(n));
    res.voltage.assign(ns, JointVector::Zero(n));
  }

  std::vector<double> I(ns), rate(ns);
  double earliest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    JointDriveSummary& js = res.joints[i];
    js.joint = model.joints[i].name;
    for (int k = 0; k < ns; ++k) js.peak_effort = std::max(js.peak_effort, std::abs(Q[k][i]));
    const Drive* d = driveOf(model, js.joint);
    if (!d) continue;
    js.has_drive = true;
    const drive::FrictionParams fp =
        options.friction ? drive::frictionParams(model, *d) : drive::FrictionParams{};
    drive::DriveChainOptions dco;
    dco.include_rotor_inertia = options.drive_rotor_inertia;
    // Pass 1: currents (independent of dI/dt).
    for (int k = 0; k < ns; ++k)
      I[k] = drive::motorState(*d, fp, traj.qd[k][i], traj.qdd[k][i], Q[k][i],
                               options.temperature_C, 0.0, dco)
                 .current_A;
    // dI/dt for the inductive voltage term: central differences, one-sided at the ends.
    for (int k = 0; k < ns; ++k) {
      if (ns == 1)
        rate[k] = 0;
      else if (k == 0)
        rate[k] = (I[1] - I[0]) / traj.dt;
      else if (k == ns - 1)
        rate[k] = (I[k] - I[k - 1]) / traj.dt;
      else
        rate[k] = (I[k + 1] - I[k - 1]) / (2 * traj.dt);
    }
    auto& pc = js.checks[static_cast<int>(DriveQuantity::PeakCurrent)];
    auto& rc = js.checks[static_cast<int>(DriveQuantity::RmsCurrent)];
    auto& sc = js.checks[static_cast<int>(DriveQuantity::MotorSpeed)];
    auto& vc = js.checks[static_cast<int>(DriveQuantity::Voltage)];
    setLimit(pc, d->peak_current_A);
    setLimit(rc, d->continuous_current_A);
    setLimit(sc, d->max_motor_speed_radps);
    setLimit(vc, d->resistance_ohm > 0 ? d->max_voltage_V : 0.0);  // eq. 3.29 needs R
    const double budget = rc.limit * rc.limit * ns;  // sum of I^2 allowed over the trajectory
    double sum_sq = 0;
    for (int k = 0; k < ns; ++k) {
      const drive::MotorState ms = drive::motorState(*d, fp, traj.qd[k][i], traj.qdd[k][i], Q[k][i],
                                                     options.temperature_C, rate[k], dco);
      const double t = traj.t[k];
      const double aI = std::abs(ms.current_A), aw = std::abs(ms.motor_speed_radps),
                   aU = std::abs(ms.voltage_V);
      js.peak_motor_torque_Nm = std::max(js.peak_motor_torque_Nm, std::abs(ms.motor_torque_Nm));
      pc.value = std::max(pc.value, aI);
      sc.value = std::max(sc.value, aw);
      vc.value = std::max(vc.value, aU);
      sum_sq += ms.current_A * ms.current_A;
      firstOver(pc, aI > pc.limit, k, t);
      firstOver(rc, sum_sq > budget, k, t);
      firstOver(sc, aw > sc.limit, k, t);
      firstOver(vc, aU > vc.limit, k, t);
      if (options.keep_profiles) {
        res.motor_torque[k][i] = ms.motor_torque_Nm;
        res.current[k][i] = ms.current_A;
        res.motor_speed[k][i] = ms.motor_speed_radps;
        res.voltage[k][i] = ms.voltage_V;
      }
    }
    rc.value = std::sqrt(sum_sq / ns);
    for (int qi = 0; qi < kDriveQuantityCount; ++qi) {
      QuantityCheck& c = js.checks[qi];
      finishCheck(c);
      // Earliest violation; ties go to the lower joint index, then the quantity order.
      if (c.exceeded && c.first_exceeded_s < earliest) {
        earliest = c.first_exceeded_s;
        res.feasible = false;
        res.failing_joint = i;
        res.failing_quantity = static_cast<DriveQuantity>(qi);
        res.failure_time_s = c.first_exceeded_s;
      }
    }
  }
  return res;
}

HoldingLoad holdingLoad(const Model& model, const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                        const Eigen::Ref<const Eigen::VectorXd>& q) {
  const int n = model.dof();
  HoldingLoad h;
  Eigen::VectorXd g(n);
  gravityForces(rbm, ws, q, g);
  h.effort = g;
  h.current_A = JointVector::Zero(n);
  h.current_ratio = JointVector::Zero(n);
  for (int i = 0; i < n; ++i) {
    const Drive* d = driveOf(model, model.joints[i].name);
    if (!d) continue;
    h.current_A[i] =
        g[i] / (d->gear_ratio * d->torque_constant_NmpA);  // eq. (3.27a), (4.5), standstill
    if (d->continuous_current_A <= 0) continue;
    h.current_ratio[i] = std::abs(h.current_A[i]) / d->continuous_current_A;
    if (h.limiting_joint < 0 || h.current_ratio[i] > h.max_ratio) {
      h.max_ratio = h.current_ratio[i];
      h.limiting_joint = i;
    }
  }
  h.feasible = h.max_ratio <= 1.0;
  return h;
}

}  // namespace armstudy
