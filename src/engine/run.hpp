#pragma once
// Running a study: options in, summary out. The runner writes the resolved designs, runs every
// stage the study has a section for (in registry order, each through the Stage interface), and
// writes the manifest last.
#include <string>
#include <vector>

#include "study/checkpoint.hpp"
#include "study/distributed.hpp"
#include "study/metrics.hpp"
#include "study/stage.hpp"
#include "study/study.hpp"

namespace armstudy {

struct RunSummary {
  std::string output_dir;
  int designs = 0;
  int threads = 1;
  std::vector<StageTiming> timings;
  std::vector<StageCount> counts;          // written into the manifest's timings after them
  std::vector<std::string> files_written;  // relative to output_dir
  StudyMetrics metrics;                    // summary metrics (baselines, checks)
  std::string resume_message;              // "resuming: ..." / "starting fresh because ..."
  long units_resumed = 0;  // checkpoint units loaded instead of computed (all stages)
  int ranks = 1;           // processes of a distributed run (docs/distributed.md)
};

// Fingerprint of everything a study's results depend on (engine version and revision, study and
// design file hashes); one "key=value" per line. Thread count and dates are not part of it.
std::string studyFingerprint(const Study& study);

RunSummary runStudy(const Study& study, const RunOptions& options);
// The same run by every rank of a distributed job (every rank calls it; docs/distributed.md): rank
// 0 takes the output-folder lock, prepares the checkpoint store and writes every file; the other
// ranks compute their share of the units, save them into the store and merge in a private scratch
// folder that is removed at the end. Errors before the stages are reported once, by the lowest
// failing rank (the others throw OtherRankFailed).
RunSummary runStudy(const Study& study, const RunOptions& options, const Ranks& ranks);

// Runs the stage `name` of a loaded study alone, writing into `output_dir`, with the units of
// `store` (null: nothing saved or loaded). No manifest, no designs.json, no lock: for tests,
// benchmarks and tools. The study must hold a section for that stage.
StageResult runStage(const Study& study, const std::string& name, const std::string& output_dir,
                     const RunOptions& options = {}, const CheckpointStore* store = nullptr);

// JSON describing a model's resolved table (used in manifests and `describe --json`).
std::string modelToJson(const Model& model, int indent = 2);

}  // namespace armstudy
