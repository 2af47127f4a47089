#include "dynamics/approach_tracking.hpp"

#include <algorithm>
#include <cmath>

#include "common/enum_names.hpp"
#include "common/errors.hpp"

namespace armstudy {

constexpr const char* kApproachTrackingStatusNames[] = {"ok", "start_unreachable",
                                                        "tracking_failed"};
const char* toString(ApproachTrackingStatus s) { return enumName(s, kApproachTrackingStatusNames); }

std::string ApproachTrackingOptions::validate(int dof) const {
  if (std::string why = tracking.validate(dof); !why.empty()) return why;
  if (std::string why = start_optimisation.validate(); !why.empty()) return why;
  if (std::string why = start_ik.validate(); !why.empty()) return why;
  if (!R_tool.allFinite() ||
      (R_tool.transpose() * R_tool - Eigen::Matrix3d::Identity()).norm() > 1e-9 ||
      R_tool.determinant() < 0)
    return "tool rotation is not a rotation matrix";
  return "";
}

JointTrajectory differentiateTracking(const ik::TrackingSummary& tracking, double dt) {
  const int ns = static_cast<int>(tracking.samples.size());
  ARMSTUDY_CHECK(ns >= 2 && dt > 0, "differentiateTracking: need two samples and dt > 0");
  JointTrajectory jt;
  jt.dt = dt;
  jt.t.resize(ns);
  jt.q.resize(ns);
  jt.qd.resize(ns);
  jt.qdd.resize(ns);
  for (int k = 0; k < ns; ++k) {
    jt.t[k] = tracking.samples[k].t;
    jt.q[k] = tracking.samples[k].q;
    jt.qd[k] = tracking.samples[k].qdot;
  }
  const auto& v = jt.qd;
  for (int k = 0; k < ns; ++k) {
    if (ns == 2) {
      jt.qdd[k] = (v[1] - v[0]) / dt;
    } else if (k == 0) {  // second-order one-sided difference
      jt.qdd[k] = (-3.0 * v[0] + 4.0 * v[1] - v[2]) / (2 * dt);
    } else if (k == ns - 1) {
      jt.qdd[k] = (3.0 * v[k] - 4.0 * v[k - 1] + v[k - 2]) / (2 * dt);
    } else {
      jt.qdd[k] = (v[k + 1] - v[k - 1]) / (2 * dt);
    }
  }
  return jt;
}

TrackedApproach trackApproach(const Model& model, IkWorkspace& ws, ik::ObjectiveContext& ctx,
                              const ApproachTrajectory& approach,
                              const ik::WeightedObjective& objective,
                              const ApproachTrackingOptions& options, std::uint64_t pose_id) {
  const int n = model.dof();
  const std::string why = options.validate(n);
  ARMSTUDY_CHECK(why.empty(), why);
  ARMSTUDY_CHECK(approach.status() == ApproachStatus::Ok, "trackApproach: approach not planned");
  TrackedApproach out;

  // Step 1: start configuration (reach solver, then null-space optimisation at the start pose).
  const PoseReference start = poseReference(approach.sample(0.0), options.R_tool);
  const PoseTask pose0 = fullPoseTask(start.p_WT, start.R_WT);
  const IkResult ik0 = solvePose(model, ws, pose0, options.start_ik, pose_id);
  if (!ik0.reachable()) {
    out.status = ApproachTrackingStatus::StartUnreachable;
    return out;
  }
  const JointVector w_inv = options.tracking.redundancy.weightInverse(n);
  const ik::NullspaceResult opt = ik::optimiseAtPose(model, ws.kin, ctx, pose0, ik0.q, objective,
                                                     w_inv, options.start_optimisation);
  const Eigen::VectorXd q0 = opt.status == ik::NullspaceStatus::NotOnPose ? ik0.q : opt.q;

  // Step 2: velocity-level tracking at the fixed step.
  const Eigen::Matrix3d R_tool = options.R_tool;
  ik::Reference ref = [&approach, R_tool](double t) {
    const PoseReference p = poseReference(approach.sample(t), R_tool);
    ik::ReferencePoint r;
    r.pose = fullPoseTask(p.p_WT, p.R_WT);
    r.v_W = p.v_W;
    r.omega_W = p.omega_W;
    return r;
  };
  const ik::TrackingSummary tr = ik::trackReference(model, ws.kin, ref, q0, approach.duration(),
                                                    &objective, &ctx, options.tracking);
  out.tracking_status = tr.status;
  out.limit_joint = tr.limit_joint;
  out.limit_q = tr.limit_q;
  out.min_manipulability = tr.samples.empty() ? 0.0 : tr.samples.front().manipulability;
  for (const auto& s : tr.samples) {
    out.max_position_error_m = std::max(out.max_position_error_m, s.position_error_m);
    out.max_orientation_error_rad =
        std::max(out.max_orientation_error_rad, s.orientation_error_rad);
    out.min_manipulability = std::min(out.min_manipulability, s.manipulability);
  }
  if (tr.status != ik::TrackingStatus::Completed || tr.samples.size() < 2) {
    out.status = ApproachTrackingStatus::TrackingFailed;
    return out;
  }
  // Step 3: qd from the tracker, qdd by differentiating qd.
  out.trajectory = differentiateTracking(tr, options.tracking.dt);
  return out;
}

}  // namespace armstudy
