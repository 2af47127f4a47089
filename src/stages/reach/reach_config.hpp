#pragma once
// The [reach] section of a study (docs/reachability.md): task grids and pose lists, the task
// space, tolerances, starts, seed and which outputs to write.
#include <string>
#include <utility>
#include <vector>

#include "ik/reach_solver.hpp"
#include "reach/reach_sweep.hpp"
#include "tasks/task_grid.hpp"

namespace armstudy {

namespace io {
class TableReader;
}

struct ReachOutputs {
  bool vtk = true;      // .vti per grid and design, .vtp per pose list and design
  bool images = true;   // PNG maps in the report
  bool surface = true;  // boundary surface (.vtp) and volume for 3-D grids
};

struct ReachConfig {
  bool enabled = false;              // the study has a [reach] section
  std::vector<std::string> designs;  // the designs the stage evaluates (key designs); empty: all
  // [reach.tool_axis]: a design's tool axis for this stage (TCP frame, unit), overriding its own.
  std::vector<std::pair<std::string, Eigen::Vector3d>> tool_axes;
  IkOptions ik = studyDefaults();  // tolerances, starts, seed, classification
  static IkOptions studyDefaults() {
    IkOptions o;
    o.max_starts = defaults::kReachStudyStarts;  // grid poses get warm starts from their neighbours
    return o;
  }
  std::vector<TaskGrid> grids;
  std::vector<PoseList> pose_lists;
  ReachOutputs outputs;
  // Collision-aware sweeps (docs/reachability.md): poses reachable only in self-collision get
  // status SelfCollision, those reachable only in contact with an obstacle ObstacleCollision,
  // and the smallest distance at the solution is stored. collision.self (key self_collision)
  // defaults to on when a design of the study has a collision model; collision.obstacles (key
  // obstacles = true, the default when the study declares [[obstacle]]s) are the study's. Both
  // apply per design (collisionFor): a design without collision volumes is evaluated without them
  // and marked so, and never changes how the others are evaluated.
  SweepCollision collision;
  // What a design's sweep checks: `collision`, or nothing for a design without collision volumes.
  SweepCollision collisionFor(const Model& model) const {
    return model.collision.empty() ? SweepCollision{false, {}, collision.nullspace_escape}
                                   : collision;
  }
  SweepSearch search;  // [reach.search]: the map search after the sweeps of a grid
  // [reach.audit]: poses drawn per grid and design, searched from `audit_starts` random starts
  // each, independently of the sweep (reach_audit.hpp); 0 = no audit.
  int audit_poses = 0;
  int audit_starts = defaults::kAuditReachStarts;
  std::uint64_t audit_seed = defaults::kAuditSeed;
  std::string validate() const;  // empty when valid (programmer check after parsing)
};

// Reads the optional [reach] section from the study's top-level table. Relative pose-list paths
// are resolved against `study_dir`; every file read is appended to `files_read` as (path, hash).
// `models` are the study's designs and variants (for the self_collision default and check);
// `obstacles` the study's [[obstacle]] entries. Throws InputError (file, line, key) on bad input.
void readReachSection(io::TableReader& top, const std::string& study_dir,
                      const std::vector<const Model*>& models,
                      const std::vector<collision::Obstacle>& obstacles, ReachConfig& out,
                      std::vector<std::pair<std::string, std::string>>& files_read);

}  // namespace armstudy
