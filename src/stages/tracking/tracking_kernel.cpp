#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/collision_term.hpp"
#include "common/errors.hpp"
#include "stages/tracking/tracking_stage.hpp"

namespace armstudy::tracking {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

const char* toString(RunKind k) { return k == RunKind::Plain ? "plain" : "with_hc"; }

std::string RunResult::statusText(const Model& model) const {
  std::string s = ik::toString(status);
  if (status == ik::TrackingStatus::JointLimitReached && limit_joint >= 0)
    s += " (" + model.joints[limit_joint].name + ")";
  return s;
}

// ---------------------------------------------------------------------------------------------
// Evaluation
// ---------------------------------------------------------------------------------------------

ik::ReferencePoint LineReference::operator()(double t) const {
  ik::ReferencePoint r;
  r.pose.kind = task;
  const double s = std::clamp(t / duration_s, 0.0, 1.0);
  r.pose.p_WT = p0_W + (p1_W - p0_W) * s;
  r.pose.R_WT = R_WT;
  r.pose.axis_W = axis_W;
  r.v_W = (p1_W - p0_W) / duration_s;  // constant speed; omega = 0 (orientation held)
  return r;
}

LineReference lineReference(const Model& model, const TrackingEntry& entry) {
  KinematicsWorkspace ws(model);
  forwardKinematics(model, ws, entry.q0);
  LineReference l;
  l.p0_W = ws.p_WT;
  l.p1_W = entry.line_is_delta ? Eigen::Vector3d(ws.p_WT + entry.line) : entry.line;
  l.R_WT = ws.R_WT;
  l.axis_W = ws.a_WT;
  l.duration_s = entry.duration_s;
  l.task = entry.task;
  return l;
}

namespace {

int internName(std::vector<std::string>& names, const std::string& s) {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == s) return static_cast<int>(i);
  names.push_back(s);
  return static_cast<int>(names.size()) - 1;
}

}  // namespace

RunResult evaluateTrackingRun(const Model& model, const TrackingEntry& e, const LineReference& line,
                              RunKind kind) {
  KinematicsWorkspace ws(model);
  ik::ObjectiveContext ctx(model, ws);
  // Thesis eq. (5.51): H = w_j H_j + w_c H_c + w_m H_m; H_c only in the second run.
  ik::WeightedObjective objective;
  if (e.w_joint_limits > 0)
    objective.add(e.w_joint_limits,
                  std::make_shared<ik::JointLimitTerm>(model, e.joint_limit_activation));
  if (e.w_manipulability > 0)
    objective.add(e.w_manipulability,
                  std::make_shared<ik::ManipulabilityTerm>(
                      e.task == PoseTaskKind::FullPose ? metrics::MeasureSpace::Full
                                                       : metrics::MeasureSpace::Translational));
  if (kind == RunKind::WithHc)
    objective.add(e.avoidance.weight,
                  std::make_shared<collision::CollisionTerm>(e.avoidance.potential, e.obstacles));
  ik::TrackingOptions to;
  to.redundancy = e.redundancy;
  to.dt = 1.0 / e.rate_Hz;
  to.stop_at_joint_limit = e.stop_at_joint_limit;
  const ik::Reference ref = [&line](double t) { return line(t); };
  const ik::TrackingSummary ts = ik::trackReference(
      model, ws, ref, e.q0, e.duration_s, objective.empty() ? nullptr : &objective, &ctx, to);

  RunResult r;
  r.kind = kind;
  r.status = ts.status;
  r.limit_joint = ts.limit_joint;
  r.max_joint_speed = ts.max_joint_speed;
  for (const ik::TrackingSample& s : ts.samples)
    for (int i = 0; i < model.dof(); ++i) {
      const double lim = model.joints[i].limits.qd_max;
      if (lim > 0 && std::abs(s.qdot[i]) / lim > r.max_speed_ratio) {
        r.max_speed_ratio = std::abs(s.qdot[i]) / lim;
        r.max_speed_joint = i;
      }
    }
  r.min_obstacle_distance_m = r.min_self_distance_m = kInf;
  auto cws = std::make_unique<collision::CollisionWorkspace>(model);
  r.samples.reserve(ts.samples.size());
  for (const ik::TrackingSample& s : ts.samples) {
    RunSample rs;
    rs.t = s.t;
    rs.q = s.q;
    rs.position_error_m = s.position_error_m;
    rs.orientation_error_rad = s.orientation_error_rad;
    forwardKinematics(model, ws, s.q);
    rs.p_WT = ws.p_WT;
    collision::collisionDistances(model, ws, e.obstacles, *cws);
    rs.obstacle_distance_m = collision::minEnvironmentDistance(*cws);
    rs.self_distance_m = collision::minSelfDistance(*cws);
    if (cws->closest_env >= 0)
      rs.obstacle_pair = internName(
          r.pair_names, collision::pairName(model, cws->env[cws->closest_env], true, e.obstacles));
    if (cws->closest_self >= 0)
      rs.self_pair =
          internName(r.pair_names, collision::pairName(model, cws->self[cws->closest_self], false));
    if (rs.obstacle_distance_m < r.min_obstacle_distance_m) {
      r.min_obstacle_distance_m = rs.obstacle_distance_m;
      r.min_obstacle_time_s = rs.t;
      r.min_obstacle_pair = rs.obstacle_pair;
    }
    if (rs.self_distance_m < r.min_self_distance_m) {
      r.min_self_distance_m = rs.self_distance_m;
      r.min_self_time_s = rs.t;
      r.min_self_pair = rs.self_pair;
    }
    r.max_position_error_m = std::max(r.max_position_error_m, rs.position_error_m);
    r.max_orientation_error_rad = std::max(r.max_orientation_error_rad, rs.orientation_error_rad);
    if (!r.first_contact_s && (rs.obstacle_distance_m < 0 || rs.self_distance_m < 0)) {
      r.first_contact_s = rs.t;
      r.first_contact_pair =
          rs.obstacle_distance_m <= rs.self_distance_m ? rs.obstacle_pair : rs.self_pair;
    }
    r.samples.push_back(std::move(rs));
  }
  if (!r.samples.empty()) r.final_position_error_m = r.samples.back().position_error_m;
  return r;
}

EntryResult evaluateTrackingEntry(const Model& model, const TrackingEntry& entry) {
  const std::string why = entry.validate(model.dof());
  ARMSTUDY_CHECK(why.empty(), "tracking entry must validate: " + why);
  EntryResult res;
  res.name = entry.name;
  res.line = lineReference(model, entry);
  res.plain = evaluateTrackingRun(model, entry, res.line, RunKind::Plain);
  res.with_hc = evaluateTrackingRun(model, entry, res.line, RunKind::WithHc);
  return res;
}

}  // namespace armstudy::tracking
