#pragma once
// Running a study: options in, summary out. The foundation writes the manifest and the resolved
// designs; evaluation stages (reachability, dexterity, ...) plug in here.
#include <string>
#include <vector>

#include "io/study_io.hpp"
#include "study/checkpoint.hpp"
#include "study/metrics.hpp"

namespace armstudy {

struct RunOptions {
  std::string output_root = "output";  // results go to <output_root>/<study name>/
  int threads = 0;                     // 0 = OpenMP default
  bool overwrite = false;              // replace an existing output folder's results
  bool progress = true;                // progress on stderr (only when it is a terminal)
  // Work items per checkpoint unit in every stage (reach: poses, rounded to whole grid lines;
  // dexterity: map cells, rounded to whole rows; harvest: approaches and holding-grid points).
  // 0 = each stage's default (defaults::k*Unit*). Results do not depend on it.
  long unit_items = 0;
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
  StudyMetrics metrics;                    // summary metrics (baselines, checks)
  std::string resume_message;              // "resuming: ..." / "starting fresh because ..."
  long units_resumed = 0;                  // checkpoint units loaded instead of computed (all stages)
};

// What an evaluation stage gets: the study, the options, where to write, the checkpoint store
// for its units, and the summary to add files, timings and metrics to. Stages write result files
// with writeFileAtomic and list them in summary.files_written (relative to output_dir).
struct StageContext {
  const Study& study;
  const RunOptions& options;
  const std::string& output_dir;
  const CheckpointStore& checkpoints;
  RunSummary& summary;
};

// Fingerprint of everything a study's results depend on (engine version and revision, study and
// design file hashes); one "key=value" per line. Thread count and dates are not part of it.
std::string studyFingerprint(const Study& study);

RunSummary runStudy(const Study& study, const RunOptions& options);

// JSON describing a model's resolved table (used in manifests and `describe --json`).
std::string modelToJson(const Model& model, int indent = 2);

}  // namespace armstudy
