// Reading the [[tracking]] entries of a study (docs/tracking.md). Everything is checked here,
// before any work: a study that loads runs without input errors.
#include <cctype>
#include <cmath>
#include <set>

#include "common/defaults.hpp"
#include "io/toml_reader.hpp"
#include "io/units.hpp"
#include "model/model_notes.hpp"
#include "stages/tracking/tracking_stage.hpp"

namespace armstudy::tracking {

using io::TableReader;

namespace {

constexpr int kMaxSnapshots = 1000;

bool validName(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

Eigen::Vector3d readPoint(TableReader& r, const std::string& key) {
  const toml::array* a = r.array(key);
  if (!a || a->size() != 3) r.fail(key, "expected three lengths [x, y, z]");
  Eigen::Vector3d p;
  for (int i = 0; i < 3; ++i)
    p[i] = io::nodeQuantity(*a->get(i), Dimension::Length, r.file(), r.keyPath(key));
  return p;
}

void readNullspace(TableReader& r, const Model& model, TrackingEntry& e) {
  ik::RedundancyOptions& ro = e.redundancy;
  // A weight or gain read at `key`: plausible (io/units.hpp), 0 only where `zero_allowed`.
  auto weight = [&](const std::string& key, double fallback, bool zero_allowed) {
    const double w = r.number(key, fallback);
    if (const std::string bad = implausibleWeight(w, zero_allowed); !bad.empty()) r.fail(key, bad);
    return w;
  };
  ro.alpha = weight("gain", ro.alpha, true);                  // alpha [1/s]
  ro.drift_gain = weight("drift_gain", ro.drift_gain, true);  // K [1/s]
  if (r.has("joint_weights")) {
    ro.joint_weights = r.numberArray("joint_weights");
    if (static_cast<int>(ro.joint_weights.size()) != model.dof())
      r.fail("joint_weights",
             "expected one weight per joint (" + std::to_string(model.dof()) + ")");
    for (double w : ro.joint_weights)
      if (const std::string bad = implausibleWeight(w, false); !bad.empty())
        r.fail("joint_weights", "joint weight " + bad);
  }
  ro.damping_lambda0 = r.number("damping_lambda0", ro.damping_lambda0);
  if (ro.damping_lambda0 < 0) r.fail("damping_lambda0", "must be >= 0");
  ro.damping_m0 = r.number("damping_m0", ro.damping_m0);
  if (ro.damping_m0 < 0) r.fail("damping_m0", "must be >= 0");
  e.w_joint_limits = weight("joint_limits", e.w_joint_limits, true);
  e.joint_limit_activation = r.number("joint_limit_activation", e.joint_limit_activation);
  if (!(e.joint_limit_activation > 0 && e.joint_limit_activation < 0.5))
    r.fail("joint_limit_activation",
           "must lie in (0, 0.5) (fraction of the range inside each limit)");
  e.w_manipulability = weight("manipulability", e.w_manipulability, true);
}

void readAvoidance(TableReader& r, TrackingEntry& e) {
  collision::CollisionPotentialOptions& p = e.avoidance.potential;
  p.safety_distance_m = r.quantity("safety_distance", Dimension::Length, p.safety_distance_m);
  if (!(p.safety_distance_m > 0)) r.fail("safety_distance", "safety distance d_a must be > 0");
  e.avoidance.weight = r.number("weight", e.avoidance.weight);
  if (!(e.avoidance.weight > 0))
    r.fail("weight", "weight w_c must be > 0 (with 0 both runs would be the same)");
  if (const std::string bad = implausibleWeight(e.avoidance.weight, false); !bad.empty())
    r.fail("weight", bad);
  p.blend_t = r.number("blend", p.blend_t);
  if (!(p.blend_t > 0 && p.blend_t < 1)) r.fail("blend", "blend parameter t must lie in (0, 1)");
  p.h0 = r.number("h0", p.h0);
  if (const std::string bad = implausibleWeight(p.h0, false); !bad.empty()) r.fail("h0", bad);
  p.self = r.boolean("self", p.self);
}

TrackingEntry readEntry(TableReader& r, const std::vector<const Model*>& designs,
                        const std::vector<collision::Obstacle>& obstacles) {
  TrackingEntry e;
  e.name = r.string("name");
  if (!validName(e.name))
    r.fail("name", "tracking names use letters, digits, '_' and '-' only (they name output files)");
  e.design = r.string("design");
  const Model* model = nullptr;
  for (const Model* m : designs)
    if (m->name == e.design) model = m;
  if (!model) r.fail("design", "design '" + e.design + "' is not a design or variant of the study");
  if (model->collision.volumes.empty())
    r.fail("design",
           "design '" + e.design + "' has no [[collision]] volumes (distances need them)");
  const int n = model->dof();

  const toml::array* q = r.array("q0");
  if (!q) r.fail("q0", "missing start configuration q0");
  if (static_cast<int>(q->size()) != n)
    r.fail("q0", "expected " + std::to_string(n) + " joint values for '" + e.design + "', got " +
                     std::to_string(q->size()));
  e.q0.resize(n);
  for (int i = 0; i < n; ++i) {
    const Joint& j = model->joints[i];
    e.q0[i] = io::nodeQuantity(
        *q->get(i), j.type == JointType::Prismatic ? Dimension::Length : Dimension::Angle, r.file(),
        r.keyPath("q0"));
    if (e.q0[i] < j.limits.q_min || e.q0[i] > j.limits.q_max)
      r.fail("q0", "joint " + j.name + " = " + std::to_string(e.q0[i]) +
                       " lies outside its limits [" + std::to_string(j.limits.q_min) + ", " +
                       std::to_string(j.limits.q_max) + "]");
  }

  const std::string task = r.string("task_space", "position");
  if (task == "position")
    e.task = PoseTaskKind::Position;
  else if (task == "position_axis")
    e.task = PoseTaskKind::PositionAxis;
  else if (task == "full" || task == "pose")
    e.task = PoseTaskKind::FullPose;
  else
    r.fail("task_space", "unknown task space '" + task + "' (position, position_axis, full)");
  if (e.task == PoseTaskKind::PositionAxis)
    if (const std::string open = notes::toolAxisOpen(*model); !open.empty())
      r.fail("task_space", "a position_axis task holds the tool axis, and " + open);
  if (taskDim(e.task) >= n)
    r.fail("task_space", "'" + e.design + "' has no redundancy for a " + task +
                             " task (the null space would be empty)");

  if (r.has("to") == r.has("delta"))
    r.fail(r.has("to") ? "to" : "delta",
           "give the line either by its end point `to` or by its displacement `delta`");
  e.line_is_delta = r.has("delta");
  e.line = readPoint(r, e.line_is_delta ? "delta" : "to");

  e.duration_s = r.number("duration");
  if (!(e.duration_s > 0)) r.fail("duration", "duration must be > 0 [s]");
  e.rate_Hz = r.number("rate", e.rate_Hz);
  if (!(e.rate_Hz > 0) || e.rate_Hz > defaults::kMaxSampleRate_Hz)
    r.fail("rate", "rate must lie in (0, 100000] Hz");
  if (e.duration_s * e.rate_Hz > defaults::kMaxTrajectorySamples)
    r.fail("duration", "duration x rate exceeds 1e6 samples");
  // At least one Euler step (also rejects a rate so low that 1 / rate overflows).
  if (!(e.duration_s * e.rate_Hz >= 1))
    r.fail("rate", "rate x duration must give at least one step (rate >= 1 / duration)");
  e.stop_at_joint_limit = r.boolean("stop_at_joint_limit", e.stop_at_joint_limit);
  e.snapshots = static_cast<int>(r.integer("snapshots", e.snapshots));
  if (e.snapshots < 0 || e.snapshots > kMaxSnapshots)
    r.fail("snapshots", "snapshots must lie in [0, 1000]");

  if (r.has("obstacles")) {
    std::set<std::string> seen;
    for (const std::string& name : r.stringArray("obstacles")) {
      const collision::Obstacle* found = nullptr;
      for (const auto& o : obstacles)
        if (o.name == name) found = &o;
      if (!found)
        r.fail("obstacles", "unknown obstacle '" + name + "' (define it in an [[obstacle]] table)");
      if (!seen.insert(name).second) r.fail("obstacles", "obstacle '" + name + "' is listed twice");
      e.obstacles.push_back(*found);
    }
  } else {
    e.obstacles = obstacles;
  }

  if (const toml::table* t = r.table("nullspace")) {
    TableReader nr(*t, r.file(), r.keyPath("nullspace"));
    readNullspace(nr, *model, e);
    nr.finish();
  }
  if (const toml::table* t = r.table("avoidance")) {
    TableReader ar(*t, r.file(), r.keyPath("avoidance"));
    readAvoidance(ar, e);
    ar.finish();
  }
  e.avoidance.potential.environment = !e.obstacles.empty();
  if (!e.avoidance.potential.environment && !e.avoidance.potential.self)
    r.fail(r.has("avoidance") ? "avoidance" : "obstacles",
           "H_c has nothing to avoid: no obstacles selected and avoidance.self = false");
  r.finish();
  const std::string why = e.validate(n);
  ARMSTUDY_CHECK(why.empty(), "tracking reader and validate disagree: " + why);
  return e;
}

}  // namespace

std::string TrackingEntry::validate(int dof) const {
  if (!validName(name)) return "invalid name '" + name + "'";
  if (q0.size() != dof) return "q0 needs one value per joint";
  if (!q0.allFinite()) return "q0 must be finite";
  if (!line.allFinite()) return "line must be finite";
  if (!(duration_s > 0) || !std::isfinite(duration_s)) return "duration must be > 0";
  if (!(rate_Hz > 0) || !std::isfinite(rate_Hz)) return "rate must be > 0";
  if (snapshots < 0) return "snapshots must be >= 0";
  if (!(w_joint_limits >= 0) || !(w_manipulability >= 0)) return "objective weights must be >= 0";
  if (!(joint_limit_activation > 0 && joint_limit_activation < 0.5))
    return "joint_limit_activation must lie in (0, 0.5)";
  if (!(avoidance.weight > 0) || !std::isfinite(avoidance.weight))
    return "avoidance weight must be > 0";
  if (std::string why = avoidance.potential.validate(); !why.empty()) return "avoidance: " + why;
  if (avoidance.potential.environment != !obstacles.empty())
    return "avoidance.environment must be set exactly when there are obstacles";
  if (!avoidance.potential.environment && !avoidance.potential.self)
    return "H_c has nothing to avoid";
  if (static_cast<int>(obstacles.size()) > collision::kMaxObstacles) return "too many obstacles";
  ik::TrackingOptions t;
  t.redundancy = redundancy;
  t.dt = 1.0 / rate_Hz;
  return t.validate(dof);
}

std::vector<TrackingEntry> readTrackingEntries(const SectionInput& in) {
  std::vector<TrackingEntry> out;
  in.top.forEachTable("tracking", [&](TableReader& r) {
    TrackingEntry e = readEntry(r, in.designs, in.obstacles);
    for (const auto& other : out)
      if (other.name == e.name) r.fail("name", "tracking entry '" + e.name + "' is defined twice");
    out.push_back(std::move(e));
  });
  return out;
}

}  // namespace armstudy::tracking
