#pragma once
// The reachability stage of a study run (docs/reachability.md): sweeps every design (and
// variant) over every task grid and pose list of the study's [reach] section, then writes
//   reach/<grid>/<design>.vti, reach/<grid>/comparison.vti, reach/<grid>/<design>_surface_o<k>.vtp,
//   reach/<list>/<design>.vtp, reach/images/*.png, summary.json and report.md
// into the study's output folder.
#include <string>
#include <vector>

#include "io/study_io.hpp"
#include "study/checkpoint.hpp"
#include "study/metrics.hpp"

namespace armstudy {

struct ReachStageOptions {
  std::string output_dir;  // output/<study>/
  int threads = 0;         // 0 = OpenMP default
  bool progress = true;    // progress bar on stderr when it is a terminal
  // Completed units (one design x one chunk of a grid's lines or a pose list's chunks, about
  // unit_poses poses) are saved here and, on a resumed run, loaded instead of solved again.
  // Null: no checkpointing.
  const CheckpointStore* checkpoints = nullptr;
  // Poses per unit, rounded down to whole sweep units (at least one); 0 = defaults::kReachUnitPoses.
  // Results do not depend on it.
  long unit_poses = 0;
};

struct ReachStageSummary {
  std::vector<std::string> files_written;  // relative to output_dir
  double seconds = 0;
  long poses = 0;                          // poses solved (all designs, grids and lists)
  long units_resumed = 0;                  // units (chunks) loaded from checkpoints instead of solved
  StudyMetrics metrics;                    // reach/<grid>/<design>/... (regression checks)
  // Timings live only in the run manifest (result files stay byte-identical across runs).
  std::vector<std::pair<std::string, double>> timings;
};

ReachStageSummary runReachStage(const Study& study, const ReachStageOptions& options);

}  // namespace armstudy
