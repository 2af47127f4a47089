#pragma once
// The [[tracking]] study stage (docs/tracking.md): thesis Fig. 5.13 as a study. The TCP of one
// design follows a straight line from its start configuration with the null-space IK (thesis
// section 5.4, Algorithm 5.3, eq. 5.46-5.50); each entry is run twice, without and with the
// collision-avoidance potential H_c (eq. 5.53-5.57) in the null-space objective (eq. 5.51), and
// every sample is checked for obstacle and self distances.
//
//   [[tracking]]
//   name = "fig5_13"                       # letters, digits, _ -; names the output files
//   design = "final_prototype_7dof"        # a design or variant of the study
//   q0 = [0, 0.2, 0.3, 1.2, 0, 0.6, 0]     # start configuration (SI or "30 deg", "200 mm")
//   task_space = "position"                # "position" | "position_axis" | "pose"
//   delta = ["0.6 m", 0, 0]                # the line: displacement from the start TCP ...
//   # to = [x, y, z]                       # ... or its end point in W (exactly one of the two)
//   duration = 4.0                         # s
//   rate = 1000                            # Hz, Euler step 1/rate (optional)
//   obstacles = ["sphere"]                 # study [[obstacle]] names (optional, default: all)
//   snapshots = 9                          # arm skeletons in the .vtp (optional)
//   stop_at_joint_limit = true             # optional
//   [tracking.nullspace]   gain, drift_gain, joint_weights, damping_lambda0, damping_m0,
//                          joint_limits (w_j), joint_limit_activation, manipulability (w_m1)
//   [tracking.avoidance]   safety_distance (d_a), weight (w_c), blend (t), h0 (H_0), self
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "collision/collision.hpp"
#include "collision/potential.hpp"
#include "ik/nullspace.hpp"
#include "model/model.hpp"
#include "study/stage.hpp"

namespace armstudy {
namespace io {
class TableReader;
}

namespace tracking {

inline constexpr int kDefaultSnapshots = 9;  // arm skeletons drawn per run in the .vtp

// H_c in the second run of an entry (thesis eq. 5.51, 5.53-5.57).
struct AvoidanceOptions {
  // d_a, t, H_0 and whether self pairs count; `environment` is set when the entry has obstacles.
  collision::CollisionPotentialOptions potential;
  double weight = 1.0;  // w_c of eq. (5.51)
};

struct TrackingEntry {
  std::string name;
  std::string design;  // model name of a study design or variant
  Eigen::VectorXd q0;  // start configuration (SI)
  PoseTaskKind task = PoseTaskKind::Position;
  bool line_is_delta = true;  // true: `line` is p1 - p0; false: `line` is p1 in W
  Eigen::Vector3d line = Eigen::Vector3d::Zero();  // [m]
  double duration_s = 0;
  double rate_Hz = 1.0 / defaults::kTrackingStep_s;
  bool stop_at_joint_limit = true;
  int snapshots = kDefaultSnapshots;
  std::vector<collision::Obstacle> obstacles;  // copies of the selected study obstacles
  // Null-space IK (eq. 5.46-5.50, 5.65-5.67) and the secondary objectives both runs share.
  ik::RedundancyOptions redundancy;
  double w_joint_limits = 0, w_manipulability = 0;  // w_j (eq. 5.52), w_m for H_m1 (eq. 5.59)
  double joint_limit_activation = defaults::kJointLimitActivation;
  AvoidanceOptions avoidance;
  // "" when valid for a model with `dof` joints, else the problem.
  std::string validate(int dof) const;
};

// Reads every [[tracking]] entry of a study (none when absent); entries name the study's designs,
// variants and [[obstacle]] entries. Throws InputError (file, line, key) for an
// unknown design or obstacle, q0 of the wrong length or outside the joint limits, a non-positive
// duration or rate, a non-positive safety distance, negative weights, unknown keys, ...
std::vector<TrackingEntry> readTrackingEntries(const SectionInput& in);

// The straight line of an entry: p(t) = p0 + (p1 - p0) t / T at constant speed, with the start
// tool orientation held (for the orientation rows of position_axis and pose tasks).
struct LineReference {
  Eigen::Vector3d p0_W = Eigen::Vector3d::Zero(), p1_W = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_WT = Eigen::Matrix3d::Identity();
  Eigen::Vector3d axis_W = Eigen::Vector3d::UnitZ();  // the tool axis held by position_axis tasks
  double duration_s = 1;
  PoseTaskKind task = PoseTaskKind::Position;
  ik::ReferencePoint operator()(double t) const;
};
LineReference lineReference(const Model& model, const TrackingEntry& entry);

// One time step of a run, with the distances checked at its configuration.
struct RunSample {
  double t = 0;
  JointVector q;
  Eigen::Vector3d p_WT = Eigen::Vector3d::Zero();
  double position_error_m = 0, orientation_error_rad = 0;
  double obstacle_distance_m = 0;          // min over body-obstacle pairs (+inf without obstacles)
  double self_distance_m = 0;              // min over self-collision pairs (+inf without pairs)
  int obstacle_pair = -1, self_pair = -1;  // indices into RunResult::pair_names (-1: none)
};

enum class RunKind { Plain, WithHc };
const char* toString(RunKind k);  // "plain", "with_hc"

struct RunResult {
  RunKind kind = RunKind::Plain;
  ik::TrackingStatus status = ik::TrackingStatus::Completed;
  int limit_joint = -1;  // the joint that left its limits (JointLimitReached)
  std::vector<RunSample> samples;
  std::vector<std::string> pair_names;  // closest pairs seen, first-seen order
  double max_joint_speed = 0;           // max |qdot_i| [rad/s or m/s]
  // max |qdot_i| / qd_max_i over the joints with a velocity limit, and that joint (-1: none). The
  // IK is kinematic: joint speeds are not limited, this says whether the drives could follow.
  double max_speed_ratio = 0;
  int max_speed_joint = -1;
  // Over the samples:
  double min_obstacle_distance_m = 0, min_obstacle_time_s = 0;  // +inf without obstacles
  int min_obstacle_pair = -1;
  double min_self_distance_m = 0, min_self_time_s = 0;
  int min_self_pair = -1;
  double max_position_error_m = 0, max_orientation_error_rad = 0;
  double final_position_error_m =
      0;  // |p_WT - p_ref| at the last sample (the line's end when completed)
  std::optional<double> first_contact_s;  // first sample with a negative obstacle or self distance
  int first_contact_pair = -1;
  bool completed() const { return status == ik::TrackingStatus::Completed; }
  bool collisionFree() const { return !first_contact_s.has_value(); }
  std::string statusText(const Model& model) const;  // "completed", "joint_limit_reached (j3)", ...
};

struct EntryResult {
  std::string name;
  LineReference line;
  RunResult plain, with_hc;
};

// One motion of an entry along its line, without or with H_c (single-threaded; deterministic).
RunResult evaluateTrackingRun(const Model& model, const TrackingEntry& entry,
                              const LineReference& line, RunKind kind);

// A run as work-unit bytes (every field, bit for bit), and back (false, run unchanged, when the
// bytes are not such a unit).
std::string serializeRun(const RunResult& run);
bool deserializeRun(const std::string& bytes, RunResult& run);

// Runs both motions of one entry (single-threaded; deterministic).
EntryResult evaluateTrackingEntry(const Model& model, const TrackingEntry& entry);

// Runs every entry (OpenMP over entries x runs; results do not depend on the thread count) and
// writes under <output_dir>/tracking/: per entry and run <name>_<run>.csv and <name>_<run>.vtp,
// per entry <name>_distance.svg and <name>_tcp_error.svg, then report.md and summary.json. Adds
// metrics "tracking/<name>/<run>/..." to ctx.summary.metrics.
// The entry's runs as maps of the study's 3-D view (tracking_view.cpp): the TCP path of each run,
// coloured by the distance to the obstacles (to the arm itself without obstacles) or by contact,
// with the arm at the run's closest approach.
std::vector<report::ViewCloud> trackingViewClouds(const Model& model, const TrackingEntry& e,
                                                  const EntryResult& er);

StageResult runTrackingStage(const StageContext& ctx, const std::vector<TrackingEntry>& entries,
                             std::vector<EntryResult>* results = nullptr);

}  // namespace tracking
}  // namespace armstudy
