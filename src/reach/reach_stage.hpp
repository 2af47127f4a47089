#pragma once
// The reachability stage of a study run (docs/reachability.md): sweeps every design (and
// variant) over every task grid and pose list of the study's [reach] section, then writes
//   reach/<grid>/<design>.vti, reach/<grid>/comparison.vti, reach/<grid>/<design>_surface_o<k>.vtp,
//   reach/<list>/<design>.vtp, reach/images/*.png, summary.json and report.md
// into the study's output folder.
#include <string>
#include <vector>

#include "io/study_io.hpp"

namespace armstudy {

struct ReachStageOptions {
  std::string output_dir;  // output/<study>/
  int threads = 0;         // 0 = OpenMP default
  bool progress = true;    // progress bar on stderr when it is a terminal
};

struct ReachStageSummary {
  std::vector<std::string> files_written;  // relative to output_dir
  double seconds = 0;
  long poses = 0;                          // poses solved (all designs, grids and lists)
};

ReachStageSummary runReachStage(const Study& study, const ReachStageOptions& options);

}  // namespace armstudy
