#pragma once
// Running a study: options in, summary out. The foundation writes the manifest and the resolved
// designs; evaluation stages (reachability, dexterity, ...) plug in here.
#include <string>
#include <vector>

#include "io/study_io.hpp"

namespace armstudy {

struct RunOptions {
  std::string output_root = "output";  // results go to <output_root>/<study name>/
  int threads = 0;                     // 0 = OpenMP default
  bool overwrite = false;              // replace an existing output folder's results
  bool progress = true;                // progress on stderr (only when it is a terminal)
  std::string validate() const;        // empty when valid, else the reason
};

struct StageTiming {
  std::string stage;
  double seconds = 0;
};

struct RunSummary {
  std::string output_dir;
  int designs = 0;
  int threads = 1;
  std::vector<StageTiming> timings;
  std::vector<std::string> files_written;  // relative to output_dir
};

RunSummary runStudy(const Study& study, const RunOptions& options);

// JSON describing a model's resolved table (used in manifests and `describe --json`).
std::string modelToJson(const Model& model, int indent = 2);

}  // namespace armstudy
