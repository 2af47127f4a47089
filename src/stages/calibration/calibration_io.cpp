// Reading the [[calibration]] entries of a study (docs/calibration.md, "As a study stage").
// Everything is checked here, before any work: a study that loads runs without input errors
// (except a data file too short for the fit, which the engine reports when the stage runs).
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>

#include "common/angles.hpp"
#include "io/csv_io.hpp"
#include "io/toml_reader.hpp"
#include "stages/calibration/calibration_stage.hpp"

namespace armstudy::calibration {

using io::TableReader;
namespace fs = std::filesystem;

namespace {

constexpr long long kMaxFolds = 1000;

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

// "<number> <unit>" with the unit one of `units` (name, factor to SI); the unit is required.
double quantityIn(TableReader& r, const std::string& key,
                  const std::vector<std::pair<std::string, double>>& units) {
  std::string names;
  for (const auto& u : units) names += (names.empty() ? "" : ", ") + u.first;
  const toml::node* n = r.node(key);
  if (!n) r.fail(key, "missing '" + key + "' (a number with a unit: " + names + ")");
  if (!n->is_string()) r.fail(key, "give '" + key + "' as a string with a unit (" + names + ")");
  const std::string text = n->as_string()->get();
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    r.fail(key, "'" + text + "' is not a number with a unit (" + names + ")");
  }
  std::string unit = text.substr(used);
  unit.erase(0, unit.find_first_not_of(' '));
  for (const auto& u : units)
    if (u.first == unit && std::isfinite(v)) return v * u.second;
  r.fail(key, "'" + text + "': the unit must be one of " + names);
}

// A column list: header names, or 1-based column numbers looked up in the file's header line.
std::vector<std::string> readColumns(TableReader& r, const std::string& key,
                                     const std::string& path) {
  const toml::array* a = r.array(key);
  if (!a) r.fail(key, "missing '" + key + "' (the column names or 1-based numbers, one per joint)");
  std::vector<std::string> header;
  std::vector<std::string> out;
  for (const toml::node& n : *a) {
    if (n.is_string()) {
      out.push_back(n.as_string()->get());
      continue;
    }
    if (!n.is_integer()) r.fail(key, "columns are names (strings) or 1-based numbers");
    if (header.empty()) {
      std::ifstream in(path);
      std::string line;
      while (std::getline(in, line) &&
             (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#')) {
      }
      const auto lines = io::splitCsvLines(line);
      if (!lines.empty()) header = lines.front().cells;
    }
    const long long c = n.as_integer()->get();
    if (c < 1 || c > static_cast<long long>(header.size()))
      r.fail(key, "column " + std::to_string(c) + " does not exist (" + path + " has " +
                      std::to_string(header.size()) + " columns)");
    out.push_back(header[static_cast<std::size_t>(c - 1)]);
  }
  return out;
}

// Units of each logged quantity (name, factor to SI).
std::vector<std::pair<std::string, double>> logUnits(const std::string& key) {
  if (key == "positions") return {{"rad", 1.0}, {"deg", kDegToRad}, {"m", 1.0}, {"mm", 1e-3}};
  if (key == "velocities")
    return {{"rad/s", 1.0}, {"deg/s", kDegToRad}, {"m/s", 1.0}, {"mm/s", 1e-3}};
  if (key == "accelerations")
    return {{"rad/s^2", 1.0}, {"deg/s^2", kDegToRad}, {"m/s^2", 1.0}, {"mm/s^2", 1e-3}};
  return {{"N m", 1.0}, {"Nm", 1.0}, {"N", 1.0}, {"A", 1.0}, {"mA", 1e-3}};
}

// One logged file's table: file, columns, unit, optional own time column; for efforts logged as
// current (unit A or mA) the torque constants per column and, joint side, the reduction ratios.
LogFile readLogFileSpec(TableReader& m, const std::string& key, const fs::path& dir,
                        JointLogSpec& spec) {
  TableReader r = m.requiredTable(key, " (file, columns and unit of the logged " + key + ")");
  LogFile f;
  const std::string file = r.string("file");
  f.path = (fs::path(file).is_absolute() ? fs::path(file) : dir / file).lexically_normal().string();
  if (!fs::is_regular_file(f.path))
    r.fail("file", "log file '" + file + "' does not exist (looked for " + f.path + ")");
  f.columns = readColumns(r, "columns", f.path);
  const auto units = logUnits(key);
  std::string names;
  for (const auto& u : units) names += (names.empty() ? "" : ", ") + u.first;
  if (!r.has("unit")) r.fail("unit", "missing 'unit' of the logged " + key + " (" + names + ")");
  const std::string unit = r.string("unit");
  bool known = false;
  for (const auto& u : units)
    if (u.first == unit) {
      f.scale = u.second;
      known = true;
    }
  if (!known) r.fail("unit", "unknown unit '" + unit + "' (" + names + ")");
  if (r.has("time_column")) f.time_column = r.string("time_column");
  if (key == "efforts") {
    const bool current = unit == "A" || unit == "mA";
    if (current) {
      if (!r.has("torque_constants"))
        r.fail("torque_constants",
               "efforts logged as current need 'torque_constants' (N m/A, or N/A for a linear "
               "motor; one per column, sign included)");
      spec.torque_constants = r.numberArray("torque_constants");
      for (std::size_t c = 0; c < spec.torque_constants.size(); ++c)
        if (spec.torque_constants[c] == 0)
          r.fail("torque_constants",
                 "the torque constant of column '" + (c < f.columns.size() ? f.columns[c] : "?") +
                     "' (entry " + std::to_string(c + 1) + ") is 0: current would give no torque");
      if (r.has("ratios")) spec.effort_ratios = r.numberArray("ratios");
    } else {
      for (const char* k : {"torque_constants", "ratios"})
        rejectKey(r, k, std::string("'") + k + "' belongs to efforts logged as current (unit A)");
    }
  }
  r.finish();
  return f;
}

// R of a motor-side log: `coupling_matrix` (rows = motors) or diag(`ratios`) plus `coupling`
// entries { motor = joint name, joint = joint name, ratio = R[motor, joint] }.
Eigen::MatrixXd readCoupling(TableReader& r, const std::vector<std::string>& joints) {
  const auto n = static_cast<Eigen::Index>(joints.size());
  if (r.has("coupling_matrix")) {
    if (r.has("ratios") || r.has("coupling"))
      r.fail("coupling_matrix", "give either coupling_matrix or ratios (+ coupling)");
    const toml::array* rows = r.array("coupling_matrix");
    Eigen::MatrixXd R(n, n);
    if (!rows || static_cast<Eigen::Index>(rows->size()) != n)
      r.fail("coupling_matrix", "one row per joint");
    for (Eigen::Index i = 0; i < n; ++i) {
      const toml::array* row = (*rows)[static_cast<std::size_t>(i)].as_array();
      if (!row || static_cast<Eigen::Index>(row->size()) != n)
        r.fail("coupling_matrix", "one column per joint");
      for (Eigen::Index j = 0; j < n; ++j) {
        const auto v = (*row)[static_cast<std::size_t>(j)].value<double>();
        if (!v || !std::isfinite(*v)) r.fail("coupling_matrix", "entries are numbers");
        R(i, j) = *v;
      }
    }
    return R;
  }
  const std::vector<double> ratios = r.numberArray("ratios");
  if (static_cast<Eigen::Index>(ratios.size()) != n)
    r.fail("ratios", "one reduction ratio per joint");
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) R(i, i) = ratios[static_cast<std::size_t>(i)];
  auto index = [&](TableReader& c, const std::string& key) {
    const std::string name = c.string(key);
    for (Eigen::Index i = 0; i < n; ++i)
      if (joints[static_cast<std::size_t>(i)] == name) return i;
    c.fail(key, "'" + name + "' is not one of the logged joints");
  };
  r.forEachTable("coupling", [&](TableReader& c) {
    const Eigen::Index k = index(c, "motor"), j = index(c, "joint");
    R(k, j) = c.number("ratio");
  });
  return R;
}

JointLogSpec readMeasured(TableReader& e, const fs::path& dir) {
  TableReader r = e.requiredTable("measured");
  JointLogSpec s;
  s.study_file = r.file();
  s.study_line = r.line();
  s.study_key = r.path();
  s.joints = r.stringArray("joints");
  const auto n = static_cast<Eigen::Index>(s.joints.size());
  s.positions = readLogFileSpec(r, "positions", dir, s);
  s.efforts = readLogFileSpec(r, "efforts", dir, s);
  if (r.has("velocities")) s.velocities = readLogFileSpec(r, "velocities", dir, s);
  if (r.has("accelerations")) {
    if (!r.has("velocities"))
      r.fail("accelerations", "logged accelerations need logged velocities too");
    s.accelerations = readLogFileSpec(r, "accelerations", dir, s);
  }
  if (r.has("gravity_compensated")) {
    s.gravity_compensated = r.stringArray("gravity_compensated");
    for (std::size_t a = 0; a < s.gravity_compensated.size(); ++a)
      for (std::size_t b = 0; b < a; ++b)
        if (s.gravity_compensated[a] == s.gravity_compensated[b])
          r.fail("gravity_compensated", "joint '" + s.gravity_compensated[a] + "' is listed twice");
  }
  s.resample = r.boolean("resample", false);
  if (!s.positions.time_column.empty()) {
    if (r.has("time_column"))
      r.fail("time_column", "the positions' time column is given twice (here and in positions)");
    if (r.has("sample_period")) r.fail("sample_period", "give either sample_period or time_column");
    s.time_column = s.positions.time_column;
  } else if (r.has("time_column")) {
    if (r.has("sample_period")) r.fail("sample_period", "give either sample_period or time_column");
    s.time_column = r.string("time_column");
  } else {
    s.sample_period_s = quantityIn(r, "sample_period", {{"s", 1.0}, {"ms", 1e-3}, {"us", 1e-6}});
    if (!(s.sample_period_s > 0)) r.fail("sample_period", "the sample period must be positive");
  }
  const std::string side = r.string("side");
  if (side != "motor" && side != "joint") r.fail("side", "side is \"motor\" or \"joint\"");
  s.motor_side = side == "motor";
  if (s.motor_side) {
    s.coupling = readCoupling(r, s.joints);
  } else {
    for (const char* k : {"ratios", "coupling", "coupling_matrix"})
      rejectKey(r, k, std::string("'") + k + "' belongs to side = \"motor\"");
    s.coupling = Eigen::MatrixXd::Identity(n, n);
  }
  s.offsets = Eigen::VectorXd::Zero(n);
  if (const toml::array* a = r.array("offsets")) {
    if (static_cast<Eigen::Index>(a->size()) != n) r.fail("offsets", "one offset per joint");
    for (Eigen::Index j = 0; j < n; ++j)
      s.offsets[j] = io::nodeQuantity((*a)[static_cast<std::size_t>(j)], Dimension::Angle, r.file(),
                                      r.keyPath("offsets"));
  }
  s.friction_width_fraction = r.number("friction_width", defaults::kFrictionWidthFraction);
  if (!(s.friction_width_fraction > 0))
    r.fail("friction_width", "the friction width fraction must be positive");
  TableReader f = r.requiredTable("filter", " (cutoff, and optionally order, decimate, trim)");
  s.cutoff_Hz = quantityIn(f, "cutoff", {{"Hz", 1.0}, {"kHz", 1e3}});
  s.filter_order = f.integerIn("order", 2, 2, 8);
  s.decimate = f.integerIn("decimate", 1, 1, 100000);
  s.trim_s = f.has("trim") ? quantityIn(f, "trim", {{"s", 1.0}, {"ms", 1e-3}}) : 0.0;
  f.finish();
  r.finish();
  return s;
}

// [calibration.reference]: another identification's values, shown next to the fitted ones.
// Arrays are per logged joint (`<joint>.<key>`), numbers name one effect instance.
ReferenceValues readReference(TableReader& e, const std::vector<std::string>& joints) {
  ReferenceValues ref;
  if (!e.has("reference")) return ref;
  TableReader r = e.requiredTable("reference");
  ref.source = r.string("source");
  ref.line = r.line();
  for (const auto& [k, node] : *e.table("reference")) {
    const std::string key(k.str());
    if (key == "source") continue;
    r.markRead(key);
    if (const toml::array* a = node.as_array()) {
      if (a->size() != joints.size()) r.fail(key, "one reference value per logged joint");
      for (std::size_t j = 0; j < joints.size(); ++j) {
        const auto v = (*a)[j].value<double>();
        if (!v) r.fail(key, "reference values are numbers");
        ref.values.emplace_back(joints[j] + "." + key, *v);
      }
    } else if (const auto v = node.value<double>()) {
      ref.values.emplace_back(key, *v);
    } else {
      r.fail(key, "a number or an array of numbers (one per logged joint)");
    }
  }
  r.finish();
  return ref;
}

// The keys of mode = "fit" (rejected in compare mode).
struct FitKeys {
  bool auto_add = false;
  std::vector<std::string> add;
  int folds = defaults::kCvFolds;
  std::uint64_t seed = defaults::kCvSeed;
};

FitKeys readFitKeys(TableReader& r, bool fit) {
  FitKeys k;
  k.auto_add = r.boolean("auto", false);
  if (r.has("add")) k.add = r.stringArray("add");
  if (fit) {
    k.folds = readCount(r, "folds", defaults::kCvFolds, 2, kMaxFolds);
    const long long s = r.integer("seed", static_cast<long long>(defaults::kCvSeed));
    if (s < 0) r.fail("seed", "seed must not be negative");
    k.seed = static_cast<std::uint64_t>(s);
  } else {
    for (const char* key : {"auto", "add", "folds", "seed"})
      rejectKey(r, key, std::string("'") + key + "' belongs to mode = \"fit\"");
  }
  return k;
}

// The drive kind's keys: the measured drive's joint and the residual grid's bins.
void readDriveKeys(TableReader& r, const Model& model, CalibrationEntry& e) {
  ProblemOptions& p = e.problem;
  p.joint = r.string("drive");
  if (model.jointIndex(p.joint) < 0)
    r.fail("drive", "design '" + model.name + "' has no joint '" + p.joint + "'");
  bool has_drive = false;
  for (const Drive& d : model.drives) has_drive = has_drive || d.joint == p.joint;
  if (!has_drive)
    r.fail("drive", "design '" + model.name + "' has no [[drive]] for joint '" + p.joint + "'");
  for (const char* k : {"variable_bins", "workspace_bins"})
    rejectKey(r, k, std::string("'") + k + "' belongs to the tcp and trajectory kinds");
  p.speed_bins = readCount(r, "speed_bins", p.speed_bins, 1, defaults::kMaxResidualBins);
  p.load_bins = readCount(r, "load_bins", p.load_bins, 1, defaults::kMaxResidualBins);
  for (const std::string& n : e.options.add)
    parseDriveEffect(n, r.file(), r.line("add"), r.keyPath("add"));
}

// The keys of the kinds that use every joint: the residual map's bins.
void readArmKeys(TableReader& r, CalibrationEntry& e) {
  rejectKey(r, "drive",
            "'drive' belongs to kind = \"drive\"; the " + std::string(e.kind->name()) +
                " kind uses every joint");
  for (const char* k : {"speed_bins", "load_bins"})
    rejectKey(r, k, std::string("'") + k + "' belongs to the drive kind");
  ArmFitOptions& o = e.options;
  o.variable_bins = readCount(r, "variable_bins", o.variable_bins, 1, defaults::kMaxResidualBins);
  o.workspace_bins =
      readCount(r, "workspace_bins", o.workspace_bins, 1, defaults::kMaxResidualBins);
}

// Where the measurements come from: [calibration.measured] logs (returned) or a data file.
std::optional<JointLogSpec> readDataSource(TableReader& r, const fs::path& dir,
                                           CalibrationEntry& e) {
  std::optional<JointLogSpec> log;
  if (r.has("measured")) {
    if (!e.kind->readsJointLogs())
      r.fail("measured", "[calibration.measured] belongs to kind = \"trajectory\"");
    if (r.has("data"))
      r.fail("data", "give either data (a trajectory CSV) or [calibration.measured] (logs)");
    log = readMeasured(r, dir);
    e.reference = readReference(r, log->joints);
    e.data_file = log->positions.path;
  } else {
    const std::string data = r.string("data");
    const fs::path resolved =
        (fs::path(data).is_absolute() ? fs::path(data) : dir / data).lexically_normal();
    if (!fs::is_regular_file(resolved))
      r.fail("data",
             "data file '" + data + "' does not exist (looked for " + resolved.string() + ")");
    e.data_file = resolved.string();
  }
  return log;
}

// The data (InputErrors name the data file, line and column), then the effect names of the kinds
// whose catalogue depends on the design and the data.
void loadEntryData(TableReader& r, const Model& model, const std::optional<JointLogSpec>& log,
                   CalibrationEntry& e) {
  if (log) {
    e.data = trajectoryKindData(readJointLog(*log, model));
    e.log = std::make_shared<const JointLogSpec>(*log);
  } else {
    e.data = e.kind->read(e.data_file, model, e.problem);
  }
  if (e.kind->measuresOneDrive()) return;  // its effect names were checked with the keys
  if (!e.options.add.empty() || !e.reference.values.empty()) {
    const auto P = e.kind->problem(model, e.data, e.problem);
    for (const std::string& n : e.options.add)
      if (P->findEffect(n) < 0)
        r.fail("add", "unknown effect '" + n +
                          "' for this design and data (candidates: " + P->effectNames() + ")");
    for (const auto& [key, v] : e.reference.values)
      if (P->findEffect(key) < 0)
        throw InputError(r.file(), e.reference.line, key,
                         "reference value for '" + key +
                             "', which is no candidate effect of this design and data");
  }
}

CalibrationEntry readEntry(TableReader& r, const fs::path& dir,
                           const std::vector<const Model*>& designs) {
  CalibrationEntry e;
  e.name = r.string("name");
  if (!validName(e.name))
    r.fail("name",
           "calibration names use letters, digits, '_' and '-' only (they name the output folder)");
  const std::string kind = r.string("kind");
  e.kind = findKind(kind);
  if (!e.kind) r.fail("kind", "unknown kind '" + kind + "' (expected " + kindNames(" or ") + ")");
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
  if (mode != "fit" && mode != "compare")
    r.fail("mode", "unknown mode '" + mode + "' (expected fit or compare)");
  e.fit = mode == "fit";
  const FitKeys fit = readFitKeys(r, e.fit);
  e.options.folds = fit.folds;
  e.options.seed = fit.seed;
  e.options.auto_add = fit.auto_add;
  e.options.add = fit.add;
  if (e.kind->measuresOneDrive())
    readDriveKeys(r, *model, e);
  else
    readArmKeys(r, e);
  ARMSTUDY_CHECK(e.options.validate().empty(), "calibration options were checked one by one");
  const std::optional<JointLogSpec> log = readDataSource(r, dir, e);
  r.finish();
  loadEntryData(r, *model, log, e);
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
