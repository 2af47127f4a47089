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
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/defaults.hpp"
#include "study/checkpoint.hpp"
#include "study/metrics.hpp"
#include "study/study.hpp"
#include "study/writer.hpp"

namespace armstudy {

class CheckpointStore;
class RankGroups;
class UnitRunner;
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
  std::string validate() const;  // empty when valid, else the reason
};

struct StageTiming {
  std::string stage;
  double seconds = 0;
};

// What one stage run gives back to the runner. Timings go to the manifest only, so result files
// stay byte-identical across runs.
struct StageResult {
  std::vector<std::string> files;    // relative to the study output folder, in writing order
  StudyMetrics metrics;              // "<stage>/<design>/..." for baselines and checks
  double seconds = 0;                // the stage's wall time
  std::vector<StageTiming> timings;  // finer timings (per grid, per map, ...)
  long units_resumed = 0;  // work units loaded from the checkpoint store instead of computed
  // The answer to the stage's question, with its numbers (Markdown sentences, one per item), and
  // what a reader must know before trusting it: report.md and report.html open with them.
  std::vector<std::string> answer, warnings;
};

// A stage's work, cut into units: the grain of checkpointing and of distribution. Ids are stable
// ("<stage>/<design>/<range>") and unique within a run; units are independent of each other, and
// a unit's bytes (UnitWriter) hold its whole result bit for bit, so a loaded unit equals the
// computed one and the stage's merge does not depend on where or in which order units ran.
//
// A runner may call `compute` several times for one batch (disjoint lists: units handed out one
// after another, or one per call when unit costs are recorded); each call replaces what an earlier
// call computed, i.e. the stage keeps the results of the latest call only. Afterwards `load` is
// called for every other unit the stage needs: units saved by an interrupted run, units an earlier
// call computed, units other processes computed (docs/distributed.md).
struct UnitBatch {
  std::vector<std::string> ids;  // index order
  // Takes the bytes of unit k saved by an earlier run (or computed by another call or process);
  // false when they do not fit (the unit is then computed again). Called from one thread.
  std::function<bool(std::size_t k, const std::string& bytes)> load;
  // Computes the listed units (indices into ids, ascending) with the run's threads and calls
  // done(k, bytes) once per unit as soon as it is complete (concurrently for distinct units). The
  // list may be empty (runUnitBatches: this batch has no units in that call).
  using Done = std::function<void(std::size_t k, const std::string& bytes)>;
  std::function<void(const std::vector<std::size_t>& todo, const Done& done)> compute;
  // False when a unit's result is not all in its bytes: it also writes files into the output
  // folder whose content names that folder (calibration entries). Such a batch is never split
  // across processes: in a distributed run every process computes all of it in its own folder and
  // only the first process uses the checkpoint store.
  bool portable = true;
};

// A loop over items [0, items) that a distributed run shares among its processes
// (UnitRunner::share): `compute(mine)` computes the chunks this process owns (ascending k), all in
// one call with the run's threads (so per-call set-up, such as solver workspaces, is paid once per
// loop and process), before `finish(mine)`, which takes the owned chunks' results (e.g. a Jacobi
// step adopts them only then, so no chunk sees another's results). Then `pack(k, r)` returns an
// owned chunk's results as bytes and the other processes apply them with `unpack(k, r, bytes)`;
// empty bytes mean "nothing to apply" (a runner need not send them, and unpack must accept them).
// A single process owns one chunk, all items (pack and unpack are not called) or, when unit costs
// are recorded, its chunks (`chunks()`), each computed and timed in a call of its own.
struct SharedLoop {
  using Chunk = std::pair<std::size_t, ItemRange>;
  static constexpr long kDefaultChunk = 64;
  std::string id;  // names the loop in the unit-cost record ("share:<id>", one line per chunk)
  long items = 0;
  // Items per chunk among processes (owned round-robin) and in a unit-cost record: small for
  // items that each cost much (e.g. an audit's many-start searches), so that they spread.
  long chunk = kDefaultChunk;
  // When not empty: the chunks' ends instead (ascending, the last one `items`), for chunks of
  // different sizes (e.g. interleave.cpp's combined loop keeps each program's own chunks).
  std::vector<long> ends;
  // Optional: the part chunk k belongs to (interleave.cpp: the program whose loop it is), only
  // written to a unit-cost record.
  std::function<std::size_t(std::size_t k)> part;
  // The chunks, in order (chunk k is the k-th range).
  std::vector<ItemRange> chunks() const;
  std::function<void(const std::vector<Chunk>& mine)> compute;
  std::function<void(const std::vector<Chunk>& mine)> finish;  // optional
  std::function<std::string(std::size_t k, const ItemRange& r)> pack;
  std::function<void(std::size_t k, const ItemRange& r, const std::string& bytes)> unpack;
  // The items of `mine`, ascending (the index space a compute call's parallel loop runs over).
  static std::vector<long> itemsOf(const std::vector<Chunk>& mine);
  // Computes `mine` and finishes (the part every runner does alike).
  void computeAll(const std::vector<Chunk>& mine) const;
};

// Opt-in record of per-unit costs (docs/distributed.md, "Unit costs"): when the environment
// variable ARMSTUDY_UNIT_TIMES names a CSV file, every computed unit is computed in a call of its
// own and one line "unit,seconds,cpu_seconds,threads,rank,bytes,part" is appended per unit (wall
// and process CPU seconds of its call, the threads and rank that computed it, the size of its
// result, and for a shared loop's chunk the part it belongs to, SharedLoop::part, else empty).
// Outside the result files; tests/benchmarks/simulate_distribution.py reads it.
struct UnitTimeRecord {
  std::string path;  // empty: off
  static UnitTimeRecord fromEnvironment();
  bool enabled() const { return !path.empty(); }
  struct Line {
    std::string unit;
    double seconds = 0, cpu_seconds = 0;
    int threads = 1, rank = 0;
    std::size_t bytes = 0;
    long part = -1;  // SharedLoop::part of a chunk; -1: none
  };
  void append(const std::vector<Line>& lines) const;
  // CPU seconds of this process so far (all threads).
  static double processCpuSeconds();
};

// How a distributed run's processes split into groups for independent programs
// (UnitRunner::groups): the group of each program and the processes of each group, consecutive
// ranks. planRankGroups makes it from the programs' predicted costs: min(programs, ranks /
// min_ranks) groups; the programs dealt out costliest first, each to the group with the least
// cost so far (lowest index on ties); the ranks shared out in proportion to the groups' costs
// (at least one each; the largest remainders get the rest). Fewer than two groups: `ranks` empty.
// tests/benchmarks/simulate_distribution.py (--groups) mirrors it.
struct RankGroupPlan {
  std::vector<std::size_t> group_of;  // per program
  std::vector<int> ranks;             // per group
};
RankGroupPlan planRankGroups(const std::vector<double>& weights, int ranks, int min_ranks);

// One process's view of rank groups (UnitRunner::groups).
class RankGroups {
 public:
  virtual ~RankGroups() = default;
  std::vector<std::size_t> group_of;  // per program
  std::size_t mine = 0;               // this process's group
  bool sends = true;                  // this process sends its group's results (one per group)
  // The runner of this process's group: its shared loops span the group's processes only.
  virtual const UnitRunner& runner() const = 0;
  // Every program's result bytes on every process: `mine` holds those of this group's programs
  // (one process of the group sends them; the other entries are ignored). Collective.
  virtual std::vector<std::string> exchange(const std::vector<std::string>& mine) const = 0;
};

// Runs the units of batches: loads those an interrupted run saved (same fingerprint), computes
// the rest and saves each as soon as it is done. One per study run; stages only see this. This
// class is the single-process runner; a distributed run uses a subclass (study/distributed.hpp)
// that splits each batch's units among the processes.
class UnitRunner {
 public:
  explicit UnitRunner(const CheckpointStore& store, int threads = 1,
                      UnitTimeRecord times = UnitTimeRecord::fromEnvironment())
      : store_(store), threads_(threads), times_(std::move(times)) {}
  virtual ~UnitRunner() = default;
  // Returns the number of units loaded instead of computed.
  virtual long run(const UnitBatch& batch) const;
  // A collective loop (every process calls it with the same loop.items): the items are cut into
  // chunks, each process computes the chunks it owns, and every process ends up with every chunk's
  // results (not checkpointed: for the steps of a search over a whole batch, e.g. the reach map
  // search's Jacobi rounds). Results must not depend on which process computes a chunk.
  virtual void share(const SharedLoop& loop) const;
  // The runner for work nested inside one unit (e.g. the stages an exploration runs for one
  // candidate): this process alone, the same store. A distributed runner's run and share are
  // collective, so a unit that one rank computes must not call them.
  virtual const UnitRunner& local() const { return *this; }
  // Rank groups for independent programs (study/interleave.hpp) of predicted costs `weights`:
  // each group of processes runs some of the programs on its own, and the programs' results then
  // travel to every process. Null when every process runs every program (a single process, or too
  // few processes for two groups). Collective.
  virtual std::unique_ptr<RankGroups> groups(const std::vector<double>& weights) const;
  const CheckpointStore& store() const { return store_; }

 protected:
  const CheckpointStore& store_;
  int threads_ = 1;  // recorded with unit times
  UnitTimeRecord times_;
};

// Runs several batches as one (one pool of units: one hand-out and one exchange in a distributed
// run instead of one per batch). Every batch sees what it would see run alone: its own indices,
// and every call of the combined compute calls every batch's compute (an empty list for a batch
// without units in that call), so each call replaces every batch's previous units as UnitBatch
// requires. Batches that are not portable run one by one. Returns the units loaded.
long runUnitBatches(const UnitRunner& runner, const std::vector<UnitBatch>& batches);

// Runs `loop` through `runner` (shared among the processes of a distributed run) or, when runner is
// null (library calls outside a study run), in this process alone.
void runSharedLoop(const UnitRunner* runner, const SharedLoop& loop);

// What a stage gets to run: the study, the options, where to write, the unit runner.
struct StageContext {
  const Study& study;
  const RunOptions& options;
  const std::string& output_dir;  // <output_root>/<study name>
  const UnitRunner& units;
  int threads = 1;  // resolved thread count (options.threads or the OpenMP default)
  // False on the ranks of a distributed run other than 0, whose output folder is a private scratch
  // folder nobody reads: a stage may list files there without writing them when it only passes on
  // bytes that other ranks rendered (docs/distributed.md).
  bool writes_results = true;
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

// A stage made of a section reader and a run function, which is what most stages are:
//   const Stage& trackingStage() {
//     static const auto stage = FunctionStage<Entries>::ofEntries("tracking", readEntries,
//     runTrackingStage); return stage;
//   }
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
