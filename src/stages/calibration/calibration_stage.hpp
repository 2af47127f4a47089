#pragma once
// The [[calibration]] study stage (docs/calibration.md, "As a study stage"): model versus
// measurement as part of `armstudy run`. Each entry does what `armstudy fit` (or `compare`) does
// for one data file and one design of the study, then compares the calibrated design copy with the
// same data, so the loop "compare, see where it fails, add the missing effect, watch the error
// fall" is reproducible (data files hashed into the manifest) and checkable (summary metrics for
// `armstudy baseline` / `armstudy check`).
//
//   [[calibration]]
//   name = "b2_friction"             # letters, digits, _ -; names the output folder
//   kind = "drive"                   # drive | tcp | trajectory
//   design = "final_prototype_9dof"  # a design or variant of the study
//   data = "data/drive_testbed_module_b2.csv"   # CSV, relative to the study file
//   drive = "j6"                     # kind drive only: the joint whose drive was measured
//   mode = "fit"                     # fit (default) | compare
//   auto = true                      # fit --auto (default false)
//   add = ["stribeck"]               # fit --add: effects to add first, in this order
//   folds = 5                        # fit --folds
//   seed = 1                         # fit --seed
//   speed_bins = 8                   # drive kind: --speed-bins, --load-bins
//   load_bins = 4
//   variable_bins = 4                # tcp/trajectory: --variable-bins, --workspace-bins
//   workspace_bins = 4
//   [calibration.measured]           # trajectory kind, instead of data: a robot's own logs
//   [calibration.reference]          # values of another identification, shown beside the fit
//                                    # (docs/calibration.md, "Bring your own robot's logs")
//
// The data file is read (and every option checked, effect names against the kind's catalogue for
// this design and data) when the study loads, so a study that loads runs without input errors.
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "calibration/calibration_run.hpp"
#include "calibration/joint_log.hpp"
#include "model/model.hpp"
#include "study/stage.hpp"

namespace armstudy {
namespace io {
class TableReader;
}

namespace calibration {

// Values another identification found (the study's [calibration.reference]), keyed by effect
// instance ("joint_1.viscous"), shown next to the fitted ones.
struct ReferenceValues {
  std::string source;
  int line = 0;
  std::vector<std::pair<std::string, double>> values;
};

struct CalibrationEntry {
  std::string name;
  const Kind* kind = nullptr;               // parsed from the entry's kind key
  std::string design;                       // model name of a study design or variant
  std::string data_file;                    // resolved path of the data CSV
  bool fit = true;                          // false: compare only
  ProblemOptions problem;                   // the drive kind: joint, speed_bins, load_bins
  ArmFitOptions options;                    // folds, seed, auto, add; tcp/trajectory: bins
  KindData data;                            // read when the study loads
  std::shared_ptr<const JointLogSpec> log;  // trajectory data from [calibration.measured]
  ReferenceValues reference;
  const std::string& dataHash() const { return data.hash(); }
};

// Reads every [[calibration]] entry of a study (none when absent); the study folder resolves the
// data paths; the entries name the study's designs and variants. Appends every data file read to
// the study's inputs. Throws InputError (file, line, key) for an unknown kind, design, joint,
// effect or key, a missing or malformed data file, options of the other kind, ...
std::vector<CalibrationEntry> readCalibrationEntries(const SectionInput& in);

// One step of the error ladder (as designed, refit, +effect, ...).
struct LadderStep {
  std::string label;
  int n_params = 0;
  double train_rmse = 0, heldout_rmse = 0;
};

// What one entry found; also the content of calibration/<name>/summary.json.
struct EntrySummary {
  std::string name, kind, design, data_file, data_hash, joint, mode, unit;
  double noise_estimate = 0;
  double as_designed_rmse = 0;  // design as is, all rows (what `compare` prints)
  int as_designed_flagged = 0, bins = 0;
  std::vector<LadderStep> ladder;
  std::vector<std::string> catalogue;     // candidate effects in catalogue order
  std::vector<std::uint8_t> significant;  // per catalogue effect: significant in the first ranking
  std::vector<std::string> added;         // in the order they were added
  std::string verdict;
  double rmse_before = 0, rmse_after = 0;  // held-out, fit mode
  std::vector<FittedParameter> final_params;
  std::vector<std::string> notes, warnings;
  // Fit mode: the calibrated copy compared with the same data.
  std::string calibrated_design;  // relative to the stage folder
  double calibrated_rmse = 0;     // all rows
  int calibrated_flagged = 0;
  std::vector<std::string> files;  // relative to the study output folder
  // Measured logs: the identification report's numbers (per-joint ladder, fitted values, width
  // sweep).
  std::vector<std::pair<std::string, double>> extra_metrics;
  // The answer per joint in the user's terms (measured logs; empty otherwise) and the remainders
  // that stand after the fit (they go into the study's warnings).
  std::vector<std::string> answers, remainders;
  // Where in the workspace the model fails (calibration/arm_view.hpp): the study's 3-D view. Kept
  // in the checkpoint, not in summary.json.
  std::vector<report::ViewCloud> view;
  // The entry's report documents (measured logs: identification.md), paths relative to the study
  // output folder; report.html renders them. Kept in the checkpoint, not in summary.json.
  std::vector<report::ReportFile> reports;
};

// Words for the report's sentences and tables. An effect or parameter key ("joint_1.viscous",
// "joint_1.viscous.viscous", "link_length.j4.x") in words ("joint_1 viscous friction", "j4 link
// length x"); the same key stays in result.json and summary.json.
std::string effectWords(const std::string& key);
// A value of `unit` as shown: lengths in mm to 0.01 mm (the TCP figures are in mm and the noise of
// a TCP log is a tenth of a millimetre or more), others to 4 significant digits.
struct ShownUnit {
  double scale = 1;  // shown value = scale * value
  std::string unit;
  int decimals = -1;  // fixed decimals; -1: 4 significant digits
};
ShownUnit shownUnit(const std::string& unit);
std::string shown(double v, const ShownUnit& u);  // number only

std::string entrySummaryToJson(const EntrySummary& s);
EntrySummary entrySummaryFromJson(const std::string& json);  // throws std::exception when malformed
// The view's maps of an entry as JSON (the checkpoint) and back; throws std::exception when
// malformed.
std::string viewCloudsToJson(const std::vector<report::ViewCloud>& clouds);
std::vector<report::ViewCloud> viewCloudsFromJson(const std::string& json);

// Runs every entry (OpenMP over entries; each entry is sequential, so results do not depend on the
// thread count) and writes under <output_dir>/calibration/: per entry <name>/ (the fit or compare
// report), <name>/calibrated/ (fit: the compare report of the calibrated copy),
// <name>/summary.json; then report.md and summary.json. Metrics "calibration/<name>/...". With
// `results`, the entries' summaries go there (tests). Each entry is one work unit (id
// calibration-<name>).
StageResult runCalibrationStage(const StageContext& ctx,
                                const std::vector<CalibrationEntry>& entries,
                                std::vector<EntrySummary>* results = nullptr);

}  // namespace calibration
}  // namespace armstudy
