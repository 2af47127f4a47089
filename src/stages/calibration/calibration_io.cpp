// Reading the [[calibration]] entries of a study (docs/calibration.md, "As a study stage").
// Everything is checked here, before any work: a study that loads runs without input errors
// (except a data file too short for the fit, which the engine reports when the stage runs).
#include <cctype>
#include <filesystem>

#include "stages/calibration/calibration_stage.hpp"
#include "io/toml_reader.hpp"

namespace armstudy::calibration {

using io::TableReader;
namespace fs = std::filesystem;

namespace {

constexpr long long kMaxFolds = 1000;
constexpr long long kMaxBins = 1000;

bool validName(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

int readCount(TableReader& r, const std::string& key, int fallback, long long lo, long long hi) {
  const long long v = r.integer(key, fallback);
  if (v < lo || v > hi)
    r.fail(key, "must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<int>(v);
}

// Keys that belong to another kind or mode are errors, not silently ignored options.
void rejectKey(TableReader& r, const std::string& key, const std::string& why) {
  if (r.has(key)) r.fail(key, why);
}

CalibrationEntry readEntry(TableReader& r, const fs::path& dir, const std::vector<const Model*>& designs) {
  CalibrationEntry e;
  e.name = r.string("name");
  if (!validName(e.name))
    r.fail("name", "calibration names use letters, digits, '_' and '-' only (they name the output folder)");
  e.kind = r.string("kind");
  if (!isKind(e.kind)) r.fail("kind", "unknown kind '" + e.kind + "' (expected drive, tcp or trajectory)");
  e.design = r.string("design");
  const Model* model = nullptr;
  for (const Model* m : designs)
    if (m->name == e.design) model = m;
  if (!model) {
    std::string names;
    for (const Model* m : designs) names += (names.empty() ? "" : ", ") + m->name;
    r.fail("design", "unknown design '" + e.design + "' (the study has: " + names + ")");
  }

  const std::string mode = r.string("mode", "fit");
  if (mode != "fit" && mode != "compare") r.fail("mode", "unknown mode '" + mode + "' (expected fit or compare)");
  e.fit = mode == "fit";
  const bool auto_add = r.boolean("auto", false);
  std::vector<std::string> add;
  if (r.has("add")) add = r.stringArray("add");
  int folds = defaults::kCvFolds;
  std::uint64_t seed = defaults::kCvSeed;
  if (e.fit) {
    folds = readCount(r, "folds", defaults::kCvFolds, 2, kMaxFolds);
    const long long s = r.integer("seed", static_cast<long long>(defaults::kCvSeed));
    if (s < 0) r.fail("seed", "seed must not be negative");
    seed = static_cast<std::uint64_t>(s);
  } else {
    for (const char* k : {"auto", "add", "folds", "seed"})
      rejectKey(r, k, std::string("'") + k + "' belongs to mode = \"fit\"");
  }

  if (e.kind == "drive") {
    e.joint = r.string("drive");
    if (model->jointIndex(e.joint) < 0) r.fail("drive", "design '" + model->name + "' has no joint '" + e.joint + "'");
    bool has_drive = false;
    for (const Drive& d : model->drives) has_drive = has_drive || d.joint == e.joint;
    if (!has_drive) r.fail("drive", "design '" + model->name + "' has no [[drive]] for joint '" + e.joint + "'");
    for (const char* k : {"variable_bins", "workspace_bins"})
      rejectKey(r, k, std::string("'") + k + "' belongs to the tcp and trajectory kinds");
    DriveFitOptions& o = e.drive_options;
    o.folds = folds;
    o.seed = seed;
    o.auto_add = auto_add;
    o.speed_bins = readCount(r, "speed_bins", o.speed_bins, 1, kMaxBins);
    o.load_bins = readCount(r, "load_bins", o.load_bins, 1, kMaxBins);
    for (const std::string& n : add) o.add.push_back(parseDriveEffect(n, r.file(), r.line("add"), r.keyPath("add")));
    ARMSTUDY_CHECK(o.validate().empty(), "calibration drive options were checked one by one");
  } else {
    rejectKey(r, "drive", "'drive' belongs to kind = \"drive\"; the " + e.kind + " kind uses every joint");
    for (const char* k : {"speed_bins", "load_bins"}) rejectKey(r, k, std::string("'") + k + "' belongs to the drive kind");
    ArmFitOptions& o = e.arm_options;
    o.folds = folds;
    o.seed = seed;
    o.auto_add = auto_add;
    o.add = add;
    o.variable_bins = readCount(r, "variable_bins", o.variable_bins, 1, kMaxBins);
    o.workspace_bins = readCount(r, "workspace_bins", o.workspace_bins, 1, kMaxBins);
    ARMSTUDY_CHECK(o.validate().empty(), "calibration arm options were checked one by one");
  }

  const std::string data = r.string("data");
  const fs::path resolved = (fs::path(data).is_absolute() ? fs::path(data) : dir / data).lexically_normal();
  if (!fs::is_regular_file(resolved))
    r.fail("data", "data file '" + data + "' does not exist (looked for " + resolved.string() + ")");
  e.data_file = resolved.string();
  r.finish();

  // The data (InputErrors name the data file, line and column), then the effect names of the arm
  // kinds, whose catalogue depends on the design and the data.
  if (e.kind == "drive") {
    e.drive_data = std::make_shared<const DriveData>(readDriveData(e.data_file));
  } else {
    e.arm_data = readArmData(e.kind, e.data_file, *model);
    if (!add.empty()) {
      const auto P = makeArmProblem(*model, e.arm_data);
      for (const std::string& n : add)
        if (P->findEffect(n) < 0) {
          std::string names;
          for (const ArmEffect& c : P->catalogue) names += (names.empty() ? "" : ", ") + c.name;
          r.fail("add", "unknown effect '" + n + "' for this design and data (candidates: " + names + ")");
        }
    }
  }
  return e;
}

}  // namespace

std::vector<CalibrationEntry> readCalibrationEntries(const SectionInput& in) {
  std::vector<CalibrationEntry> out;
  std::vector<std::pair<std::string, std::string>> files;  // (data file, hash), each once
  in.top.forEachTable("calibration", [&](TableReader& r) {
    CalibrationEntry e = readEntry(r, fs::path(in.study_dir), in.designs);
    for (const CalibrationEntry& other : out)
      if (other.name == e.name)
        r.fail("name", "calibration entry '" + e.name + "' is defined twice");
    bool listed = false;
    for (const auto& f : files) listed = listed || f.first == e.data_file;
    if (!listed) files.emplace_back(e.data_file, e.dataHash());
    out.push_back(std::move(e));
  });
  for (const auto& [f, h] : files) in.inputs.push_back({f, h});
  return out;
}

}  // namespace armstudy::calibration
