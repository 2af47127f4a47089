#pragma once
// Tracking a planned approach (thesis section 5.3.2) with the null-space IK of section 5.4 and
// turning the result into a joint trajectory for inverse dynamics (docs/dynamics.md, "Tracking").
//
// Scheme (one fixed step dt, 1 kHz by default):
//  1. start configuration: the reach solver (robust per-pose IK) at the start pose, then the
//     null-space optimisation of the same objective at that pose, so the null-space term of the
//     tracker starts near zero (no jump from rest);
//  2. ik::trackReference with the planner's pose reference (eq. 5.46, 5.49, 5.50): q_k and the
//     IK's own joint velocity qd_k. Euler integration makes qd_k = (q_{k+1} - q_k) / dt exactly;
//  3. joint accelerations by differentiating qd: qdd_k = (qd_{k+1} - qd_{k-1}) / (2 dt), one-sided
//     second-order differences at both ends. No further filter.
#include <Eigen/Core>
#include <string>

#include "dynamics/drive_feasibility.hpp"
#include "ik/nullspace.hpp"
#include "ik/objectives.hpp"
#include "ik/reach_solver.hpp"
#include "trajectory/approach_planner.hpp"

namespace armstudy {

struct ApproachTrackingOptions {
  ik::TrackingOptions tracking;                          // dt = 1 ms by default (1 kHz)
  ik::NullspaceOptions start_optimisation;               // step 1
  IkOptions start_ik;                                    // reach solver at the start pose
  Eigen::Matrix3d R_tool = Eigen::Matrix3d::Identity();  // planner tool frame -> design TCP frame
  std::string validate(int dof) const;                   // empty when valid
};

enum class ApproachTrackingStatus {
  Ok,
  StartUnreachable,  // the reach solver found no configuration for the start pose
  TrackingFailed,    // trackReference stopped (joint limit or singular Jacobian)
};
const char* toString(ApproachTrackingStatus s);

struct TrackedApproach {
  ApproachTrackingStatus status = ApproachTrackingStatus::Ok;
  ik::TrackingStatus tracking_status = ik::TrackingStatus::Completed;
  int limit_joint = -1;        // the joint that left its limits (TrackingFailed at a joint limit)
  double limit_q = 0;          // the limit it crossed, rad or m
  JointTrajectory trajectory;  // complete only when status == Ok
  double max_position_error_m = 0, max_orientation_error_rad = 0;
  double min_manipulability = 0;
};

// Step 3 of the scheme: the joint trajectory (t, q, qd, qdd) from the tracker's samples.
// Precondition: at least two samples at the fixed step dt.
JointTrajectory differentiateTracking(const ik::TrackingSummary& tracking, double dt);

// Steps 1-3. The objective (e.g. joint limits + manipulability, eq. 5.51) drives both the start
// optimisation and the null-space term of the tracker; ctx must belong to ws.kin.
// `pose_id` seeds the reach solver's random starts (deterministic).
TrackedApproach trackApproach(const Model& model, IkWorkspace& ws, ik::ObjectiveContext& ctx,
                              const ApproachTrajectory& approach,
                              const ik::WeightedObjective& objective,
                              const ApproachTrackingOptions& options, std::uint64_t pose_id);

}  // namespace armstudy
