#pragma once
// Joint-drive feasibility of a sampled joint trajectory (docs/dynamics.md, "Drive feasibility"):
// inverse dynamics (eq. 3.28) at every sample, then the drive chain per joint (eq. 3.27, 3.29,
// friction eq. 3.30/3.33/3.35) gives motor speed, current and voltage, each checked against the
// drive's limits with a margin. A limit that is exceeded is a result (status), never an error.
//
// Quantities and how they fail "first in time" (the time reported with a failure):
//   peak current     max_k |I_k|            vs peak_current        first k with |I_k| > limit
//   RMS current      sqrt(mean_k I_k^2)     vs continuous_current  first k with
//                                                                  sum_{j<=k} I_j^2 > N_s limit^2
//                    (the thermal budget of the whole trajectory, N_s samples, is used up at t_k;
//                    it happens for some k exactly when the RMS exceeds the limit)
//   motor speed      max_k |N qd_k|         vs max_motor_speed     first k over the limit
//   voltage          max_k |U_k| (eq. 3.29) vs max_voltage         first k over the limit
// Limits that are 0 in the design are "not given" and not checked (margin NaN). Margins are
// relative: (limit - value) / limit, negative when exceeded.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "drive/drive_chain.hpp"
#include "drive/friction.hpp"
#include "dynamics/dynamics.hpp"
#include "model/model.hpp"

namespace armstudy {

// A joint trajectory sampled at a fixed step (sample k at t[k] = t0 + k dt).
struct JointTrajectory {
  double dt = 0;
  std::vector<double> t;
  std::vector<JointVector> q, qd, qdd;
  int size() const { return static_cast<int>(t.size()); }
};

enum class DriveQuantity { PeakCurrent = 0, RmsCurrent = 1, MotorSpeed = 2, Voltage = 3 };
inline constexpr int kDriveQuantityCount = 4;
const char* toString(DriveQuantity q);  // "peak_current", "rms_current", "motor_speed", "voltage"

struct QuantityCheck {
  double value = 0;   // the peak or RMS value (A, rad/s, V)
  double limit = 0;   // 0 = not given / not checked
  double margin = 0;  // (limit - value) / limit; NaN when not checked
  bool checked = false;
  bool exceeded = false;
  double first_exceeded_s = 0;  // time of the first violation (see the header comment)
  int first_exceeded_k = -1;
};

struct JointDriveSummary {
  std::string joint;
  bool has_drive = false;
  double peak_effort = 0;  // max |Q| at the joint [N m or N]
  double peak_motor_torque_Nm = 0;
  std::array<QuantityCheck, kDriveQuantityCount> checks;  // indexed by DriveQuantity
  const QuantityCheck& check(DriveQuantity q) const { return checks[static_cast<int>(q)]; }
};

struct DriveFeasibilityOptions {
  bool friction = true;         // friction laws of the design's [[drive]] sections
  double temperature_C = 20.0;  // for temperature-dependent friction terms
  bool keep_profiles = true;    // fill the per-sample profiles below
  // The drive chain adds J_rotor N qdd (drive::DriveChainOptions). Must be false when the
  // RigidBodyModel already includes the rotor inertia (DynamicsOptions::include_rotor_inertia).
  bool drive_rotor_inertia = true;
};

struct DriveFeasibility {
  bool feasible = true;
  int failing_joint = -1;  // joint that fails first (earliest time)
  DriveQuantity failing_quantity = DriveQuantity::PeakCurrent;
  double failure_time_s = 0;
  std::vector<JointDriveSummary> joints;
  // Profiles (keep_profiles): per sample k, per joint i.
  std::vector<JointVector> effort, motor_torque, current, motor_speed, voltage;
  DriveFeasibilityOptions options_used;
};

// Evaluates the trajectory. The drive chain's friction parameters come from the model
// (drive::frictionParams, extra effects included) unless options.friction is false. Joints without
// a [[drive]] are reported with has_drive = false and not checked.
// Preconditions (programmer checks): rbm built from `model`; the trajectory has at least one
// sample, dt > 0 and vectors of the model's size; rotor inertia not counted twice.
DriveFeasibility evaluateDriveFeasibility(const Model& model, const RigidBodyModel& rbm,
                                          DynamicsWorkspace& ws, const JointTrajectory& traj,
                                          const DriveFeasibilityOptions& options = {});

// Static holding at one configuration (gravity plus payload, qd = qdd = 0): joint efforts
// g(q) = RNEA(q, 0, 0), motor currents I = g / (N k_m) (friction is zero at standstill in the
// drive model, docs/drives.md) and their ratio to the continuous current limit.
struct HoldingLoad {
  JointVector effort;         // g(q) [N m or N]
  JointVector current_A;      // 0 for joints without a drive
  JointVector current_ratio;  // |I| / continuous_current; 0 when no drive or no limit
  bool feasible = true;       // every checked ratio <= 1
  int limiting_joint = -1;    // joint with the largest checked ratio (-1: nothing checked)
  double max_ratio = 0;
};
HoldingLoad holdingLoad(const Model& model, const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                        const Eigen::Ref<const Eigen::VectorXd>& q);

}  // namespace armstudy
