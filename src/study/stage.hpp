#pragma once
// The Stage interface (docs/architecture.md, "Stages"): every evaluation stage of a study
// (reachability, dexterity, harvest, tracking, calibration, ...) looks the same from outside.
//
// A stage
//   - reads its own section(s) of a study file into immutable settings (`read`, null when the
//     study has none), checking every key with file, line and key on bad input;
//   - runs (`run`): it cuts its work into work units (one design x a contiguous range of its
//     independent work items), hands them as a UnitBatch to the run's UnitRunner, which loads
//     the units saved by an interrupted run and has the others computed (and saves each as it
//     completes), then merges the units in index order and writes its files through the Writer;
//   - returns one StageResult: files written, summary metrics, timings, units resumed.
// Only the registry (engine/registry.cpp) names concrete stages; the study-file parser and the
// runner ask it. Adding a stage means a folder under src/stages/ and one registry line.
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/defaults.hpp"
#include "report/view3d.hpp"
#include "study/checkpoint.hpp"
#include "study/metrics.hpp"
#include "study/study.hpp"
#include "study/unit_runner.hpp"
#include "study/writer.hpp"

namespace armstudy {

namespace io {
class TableReader;
}

// How a study is run: options in (the CLI fills them), a RunSummary out (engine/run.hpp).
struct RunOptions {
  std::string output_root = "output";  // results go to <output_root>/<study name>/
  int threads = 0;                     // 0 = OpenMP default
  bool overwrite = false;              // replace an existing output folder's results
  bool progress = true;                // progress on stderr (only when it is a terminal)
  // Work items per checkpoint unit in every stage (reach: poses, rounded to whole grid lines;
  // dexterity: map cells, rounded to whole rows; harvest: approaches and holding-grid points).
  // 0 = each stage's default (defaults::k*Unit*). Results do not depend on it.
  long unit_items = 0;
  // A distributed run's rank groups (docs/distributed.md, "Rank groups"): a grid's map searches
  // run in groups of at least this many ranks, each group searching some of the designs; 0 = every
  // rank in every search. Results do not depend on it.
  int search_group_ranks = defaults::kSearchGroupRanks;
  // Progressive maps: before a stage computes its maps, a preview of each design's stem map on
  // every k-th gamma and z value, and of each reach grid on every k-th value of each axis (chained
  // rows or sweeps alone, without the map search), is written to dexterity/preview/ or
  // reach/preview/ and its file passed to on_preview (the CLI names it on stderr); 0 = no preview.
  // The other files do not depend on it.
  int preview_stride = 0;
  std::function<void(const std::string& file)> on_preview;
  // Cancellation (the Python module's Ctrl-C): when set, a single-process run computes its units a
  // few at a time (as many as it has threads) and asks this between them; true stops the run with
  // RunCancelled (study/unit_runner.hpp), the completed units saved, so the folder resumes as
  // after the CLI's Ctrl-C. Results do not depend on it.
  std::function<bool()> cancelled;
  // The tops of colour scales shared with designs outside this run, by scale
  // ("dexterity/manipulability", "dexterity/transmission"): an exploration runs each front design
  // alone and passes the largest value over all of them, so that their maps share one scale. A
  // stage's scale reaches the larger of this and its own designs' top. Empty: its own designs'.
  std::map<std::string, double> shared_scale_tops;
  std::string validate() const;  // empty when valid, else the reason
};

struct StageTiming {
  std::string stage;
  double seconds = 0;
};

// A count beside the timings (what a search did: descents, iterations, kernel evaluations), written
// with them to the manifest; `integer` values are written without a fraction.
struct StageCount {
  std::string name;
  double value = 0;
  bool integer = true;
};

// What one stage run gives back to the runner. Timings go to the manifest only, so result files
// stay byte-identical across runs.
struct StageResult {
  std::vector<std::string> files;  // relative to the study output folder, in writing order
  // Progressive previews (RunOptions::preview_stride): in the manifest's file list, not in the
  // reports, so that every other file is the same with and without them.
  std::vector<std::string> previews;
  // The documents of its report files (the .md files among `files`): report.html renders them.
  std::vector<report::ReportFile> reports;
  StudyMetrics metrics;              // "<stage>/<design>/..." for baselines and checks
  double seconds = 0;                // the stage's wall time
  std::vector<StageTiming> timings;  // finer timings (per grid, per map, ...)
  std::vector<StageCount> counts;    // the work behind them (manifest timings, after the seconds)
  long units_resumed = 0;  // work units loaded from the checkpoint store instead of computed
  // The answer to the stage's question, with its numbers (Markdown sentences, one per item), and
  // what a reader must know before trusting it: report.md and report.html open with them.
  std::vector<std::string> answer, warnings;
  // The assumptions the answer rests on (a design's lines that change a count, "`<design>`: ..."):
  // listed with the study's own assumptions under the answer.
  std::vector<std::string> assumptions;
  // The stage's maps as points in the world frame, with the arm at its best pose: the study's
  // interactive 3-D view (view.html) shows them with the study's obstacles.
  std::vector<report::ViewCloud> view;
  std::vector<report::ViewSolid> view_solids;  // the stage's own obstacles (e.g. a map's stem)
  // What the stage's maps show (points, values, the arm's pose) for view.html's header and the
  // colour choice's name; "" = reach and dexterity maps (manipulability, the best pose).
  std::string view_about, view_value_label;
  // The largest value of each shared colour scale over the run's own designs ("dexterity/<measure>"
  // for each declared measure with a figure): what a caller that runs designs apart passes back as
  // RunOptions::shared_scale_tops.
  std::map<std::string, double> scale_tops;
};

// What a stage gets to run: the study, the options, where to write, the unit runner. Where the
// stage's files and warnings end up is the runner's business: the stage writes every file into
// output_dir and says every warning through warn(), and the runner decides which are kept (a
// distributed run keeps one process's, docs/distributed.md "Files").
struct StageContext {
  const Study& study;
  const RunOptions& options;
  const std::string& output_dir;  // where the stage writes its files (<output_root>/<study name>)
  const UnitRunner& units;
  int threads = 1;  // resolved thread count (options.threads or the OpenMP default)
  // The study's output folder, where a loop shared among the runner's processes
  // (study/rendered_part.hpp) writes each piece's files from the process that renders it (empty:
  // output_dir).
  std::string results_dir;
  // Where warnings go: the runner's sink prints each once per run; empty: stderr.
  std::function<void(const std::string&)> warnings;
  const std::string& resultsDir() const { return results_dir.empty() ? output_dir : results_dir; }
  // Prints "armstudy: warning: <text>" through the runner's sink.
  void warn(const std::string& text) const;
  // The same run for another study (a stage's selection of the study's designs).
  StageContext forStudy(const Study& selected) const {
    return {selected, options, output_dir, units, threads, results_dir, warnings};
  }
};

// What a stage's section reader gets from the study-file parser.
struct SectionInput {
  io::TableReader& top;                               // the study file's top-level table
  const std::string& study_dir;                       // relative paths resolve here
  const std::vector<const Model*>& designs;           // designs and variants, study order
  const std::vector<collision::Obstacle>& obstacles;  // the study's [[obstacle]] entries
  std::vector<InputFile>& inputs;                     // append every data file read (path, hash)
};

class Stage {
 public:
  virtual ~Stage() = default;
  // Short name: the study-file section, the output folder and the metric prefix by convention.
  virtual std::string name() const = 0;
  // Manifest timing key of the whole stage (defaults to name()).
  virtual std::string timingName() const { return name(); }
  // Reads this stage's section(s) of a study file; null when the study has none. Throws
  // InputError (file, line, key) on bad input.
  virtual std::shared_ptr<const StageSettings> read(const SectionInput& in) const = 0;
  // Runs the stage with settings this stage's `read` returned.
  virtual StageResult run(const StageContext& ctx, const StageSettings& settings) const = 0;
};

// Typed settings of a stage: what `read` returns and `run` receives.
template <class T>
struct SettingsOf : StageSettings {
  explicit SettingsOf(T v) : value(std::move(v)) {}
  T value;
};

template <class T>
const T& settingsAs(const StageSettings& s) {
  return dynamic_cast<const SettingsOf<T>&>(s).value;
}

// Calls `parse` with a reader of the study file's table [key], then finishes that reader (unknown
// keys are input errors); false, without calling it, when the study has no such table.
bool readSectionTable(const SectionInput& in, const std::string& key,
                      const std::function<void(io::TableReader&)>& parse);

// A stage made of a section reader and a run function, which is what every stage is; the registry
// (engine/registry.cpp) makes each one, e.g.
//   static const auto tracking_stage = FunctionStage<Entries>::ofEntries("tracking", readEntries,
//                                                                       runTrackingStage);
// `read` returns no value when the study has no section for the stage.
template <class Settings>
class FunctionStage final : public Stage {
 public:
  using Read = std::function<std::optional<Settings>(const SectionInput&)>;
  using Run = std::function<StageResult(const StageContext&, const Settings&)>;
  FunctionStage(std::string name, Read read, Run run, std::string timing_name = "")
      : name_(std::move(name)),
        timing_(timing_name.empty() ? name_ : std::move(timing_name)),
        read_(std::move(read)),
        run_(std::move(run)) {}
  // A run function with a last results pointer (tests pass one to see the results): the stage
  // passes none.
  template <class Results>
  FunctionStage(std::string name, Read read,
                StageResult (*run)(const StageContext&, const Settings&, Results*),
                std::string timing_name = "")
      : FunctionStage(
            std::move(name), std::move(read),
            [run](const StageContext& ctx, const Settings& s) { return run(ctx, s, nullptr); },
            std::move(timing_name)) {}
  // A stage whose section is a list of entries (the [[name]] tables), which `read` returns: no
  // entries, no stage.
  template <class RunFunction>
  static FunctionStage ofEntries(const std::string& name,
                                 std::function<Settings(const SectionInput&)> read,
                                 RunFunction run) {
    Read entries = [read](const SectionInput& in) -> std::optional<Settings> {
      Settings s = read(in);
      if (s.empty()) return std::nullopt;
      return s;
    };
    return FunctionStage(name, std::move(entries), run);
  }
  // A stage whose section is the one table [name], which `parse` reads: no table, no stage.
  using ParseTable = std::function<Settings(io::TableReader&, const SectionInput&)>;
  template <class RunFunction>
  static FunctionStage ofTable(const std::string& name, ParseTable parse, RunFunction run) {
    Read read = [name, parse](const SectionInput& in) -> std::optional<Settings> {
      std::optional<Settings> s;
      readSectionTable(in, name, [&](io::TableReader& r) { s = parse(r, in); });
      return s;
    };
    return FunctionStage(name, std::move(read), run);
  }
  std::string name() const override { return name_; }
  std::string timingName() const override { return timing_; }
  std::shared_ptr<const StageSettings> read(const SectionInput& in) const override {
    std::optional<Settings> s = read_(in);
    if (!s) return nullptr;
    return std::make_shared<SettingsOf<Settings>>(std::move(*s));
  }
  StageResult run(const StageContext& ctx, const StageSettings& settings) const override {
    return run_(ctx, settingsAs<Settings>(settings));
  }

 private:
  std::string name_, timing_;
  Read read_;
  Run run_;
};

// The settings of the stage `name` in a loaded study, as its type; null when the study has no
// such section (tests, benchmarks and tools look at them this way).
template <class T>
const T* stageSettings(const Study& study, const std::string& name) {
  const StageSettings* s = study.settings(name);
  return s ? &settingsAs<T>(*s) : nullptr;
}

}  // namespace armstudy
