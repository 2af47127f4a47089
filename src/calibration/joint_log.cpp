#include "calibration/joint_log.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "calibration/stats.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"
#include "io/csv_io.hpp"
#include "io/files.hpp"

namespace armstudy::calibration {

namespace {

std::string keyOf(const JointLogSpec& s, const std::string& key) {
  return s.study_key.empty() ? key : s.study_key + "." + key;
}

struct LogTable {
  Eigen::MatrixXd values;  // rows x columns
  std::vector<double> time;
  std::vector<int> lines;
};

// The columns of one log file (and its time column: required when `time_required`, else read when
// the file has it), every row on consecutive lines: a blank line inside a sampled log would shift
// one file against the other.
LogTable readLogFile(const LogFile& f, const std::string& time_column, bool time_required) {
  io::CsvSchema schema;
  schema.required = f.columns;
  if (!time_column.empty())
    (time_required ? schema.required : schema.optional).push_back(time_column);
  const io::CsvTable t = io::readCsv(f.path, schema);
  LogTable out;
  out.lines = t.row_lines;
  for (int i = 1; i < t.rows(); ++i)
    if (t.row_lines[i] != t.row_lines[i - 1] + 1)
      throw InputError(f.path, t.row_lines[i - 1] + 1, f.columns.front(),
                       "empty or comment line inside the log (every sample is one line)");
  out.values.resize(t.rows(), static_cast<Eigen::Index>(f.columns.size()));
  for (std::size_t c = 0; c < f.columns.size(); ++c) {
    const std::vector<double>& v = t.column(f.columns[c]);
    for (int i = 0; i < t.rows(); ++i) out.values(i, static_cast<Eigen::Index>(c)) = v[i] * f.scale;
  }
  if (!time_column.empty() && t.has(time_column)) out.time = t.column(time_column);
  return out;
}

// Empty when a sample period h [s] lies within the plausible ones, else the reason.
std::string implausiblePeriod(double h) {
  if (h >= defaults::kMinLogSamplePeriod_s && h <= defaults::kMaxLogSamplePeriod_s) return {};
  return "a sample period of " + formatG(h, 6) + " s is not plausible (" +
         formatG(defaults::kMinLogSamplePeriod_s, 6) + " to " +
         formatG(defaults::kMaxLogSamplePeriod_s, 6) + " s)";
}

// The sample period of a time column (its median step): time must increase strictly, and a step
// over twice the median is a gap (missing samples); a spread of the steps beyond the sampling
// tolerance (controller jitter) is a warning: differences then use the actual times.
double samplePeriod(const LogTable& t, const std::string& file, const std::string& column,
                    std::vector<std::string>& warnings) {
  const int R = static_cast<int>(t.time.size());
  std::vector<double> steps;
  for (int i = 1; i < R; ++i) {
    if (!(t.time[i] > t.time[i - 1]))
      throw InputError(file, t.lines[i], column, "time must increase strictly from row to row");
    steps.push_back(t.time[i] - t.time[i - 1]);
  }
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                   sorted.end());
  const double h = sorted[sorted.size() / 2];
  if (const std::string bad = implausiblePeriod(h); !bad.empty())
    throw InputError(file, t.lines[1], column, "the median time step: " + bad);
  double lo = h, hi = h;
  for (int i = 1; i < R; ++i) {
    if (steps[i - 1] > defaults::kMaxLogStepRatio * h)
      throw InputError(file, t.lines[i], column,
                       "a gap of " + std::to_string(steps[i - 1]) +
                           " s in the log (the median step is " + std::to_string(h) +
                           " s): samples are missing");
    lo = std::min(lo, steps[i - 1]);
    hi = std::max(hi, steps[i - 1]);
  }
  if (hi - lo > defaults::kUniformSamplingTolerance * h)
    warnings.push_back(
        file + ": time steps vary from " + std::to_string(lo) + " to " + std::to_string(hi) +
        " s; the filter assumes the median step, the differences use the actual times");
  return h;
}

// Design joint index of every logged column; all design joints must be logged.
std::vector<int> jointMap(const JointLogSpec& s, const Model& model) {
  std::vector<int> map;
  std::vector<bool> seen(model.dof(), false);
  for (const std::string& name : s.joints) {
    const int j = model.jointIndex(name);
    if (j < 0) {
      std::string names;
      for (const auto& jt : model.joints) names += (names.empty() ? "" : ", ") + jt.name;
      throw InputError(
          s.study_file, s.study_line, keyOf(s, "joints"),
          "design '" + model.name + "' has no joint '" + name + "' (it has: " + names + ")");
    }
    if (seen[j])
      throw InputError(s.study_file, s.study_line, keyOf(s, "joints"),
                       "joint '" + name + "' is named twice");
    seen[j] = true;
    map.push_back(j);
  }
  for (int j = 0; j < model.dof(); ++j)
    if (!seen[j])
      throw InputError(
          s.study_file, s.study_line, keyOf(s, "joints"),
          "joint '" + model.joints[j].name + "' of design '" + model.name + "' is not in the log");
  return map;
}

// The current-to-torque conversion, the optional velocity and acceleration files and the
// gravity-compensated joints of a spec.
void checkConversion(const JointLogSpec& s) {
  const std::size_t n = s.joints.size();
  auto fail = [&](const std::string& key, const std::string& msg) {
    throw InputError(s.study_file, s.study_line, keyOf(s, key), msg);
  };
  auto perJoint = [&](const std::vector<double>& v, const std::string& key, const char* what) {
    if (v.empty()) return;
    if (v.size() != n)
      fail(key, "one " + std::string(what) + " per logged joint (" + std::to_string(n) + "), not " +
                    std::to_string(v.size()));
    for (std::size_t c = 0; c < n; ++c)
      if (!std::isfinite(v[c]) || v[c] == 0)
        fail(key, std::string("the ") + what + " of joint '" + s.joints[c] + "' (entry " +
                      std::to_string(c + 1) + ") is " + formatG(v[c], 6) +
                      ": give a finite value other than 0 (its sign is the motor's direction)");
  };
  perJoint(s.torque_constants, "efforts.torque_constants", "torque constant");
  perJoint(s.effort_ratios, "efforts.ratios", "reduction ratio");
  if (!s.effort_ratios.empty() && s.torque_constants.empty())
    fail("efforts.ratios", "efforts.ratios belong to efforts logged as current (unit = \"A\")");
  if (!s.effort_ratios.empty() && s.motor_side)
    fail("efforts.ratios",
         "a motor-side log takes its ratios from 'ratios' or 'coupling_matrix' (tau = R^T kt i)");
  for (const auto* f : {&s.velocities, &s.accelerations})
    if (!f->path.empty() && f->columns.size() != n)
      fail(f == &s.velocities ? "velocities.columns" : "accelerations.columns",
           "one column per joint");
  if (!s.accelerations.path.empty() && s.velocities.path.empty())
    fail("accelerations", "logged accelerations need logged velocities too");
  for (std::size_t a = 0; a < s.gravity_compensated.size(); ++a) {
    const std::string& g = s.gravity_compensated[a];
    if (std::find(s.joints.begin(), s.joints.end(), g) == s.joints.end()) {
      std::string names;
      for (const auto& j : s.joints) names += (names.empty() ? "" : ", ") + j;
      fail("gravity_compensated", "'" + g + "' is not a logged joint (the log has: " + names + ")");
    }
    for (std::size_t b = 0; b < a; ++b)
      if (s.gravity_compensated[b] == g)
        fail("gravity_compensated", "joint '" + g + "' is listed twice");
  }
}

void checkSpec(const JointLogSpec& s) {
  const auto n = static_cast<Eigen::Index>(s.joints.size());
  auto fail = [&](const std::string& key, const std::string& msg) {
    throw InputError(s.study_file, s.study_line, keyOf(s, key), msg);
  };
  if (static_cast<Eigen::Index>(s.positions.columns.size()) != n)
    fail("positions.columns", "one column per joint");
  if (static_cast<Eigen::Index>(s.efforts.columns.size()) != n)
    fail("efforts.columns", "one column per joint");
  if (s.coupling.rows() != n || s.coupling.cols() != n)
    fail("coupling", "the coupling matrix is joints x joints");
  if (s.offsets.size() != n) fail("offsets", "one offset per joint");
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(s.coupling);
  if (lu.rank() < n)
    fail("coupling", "the coupling matrix is singular (rank " + std::to_string(lu.rank()) + " of " +
                         std::to_string(n) + "): motor positions do not determine the joints");
  if (s.time_column.empty())
    if (const std::string bad = implausiblePeriod(s.sample_period_s); !bad.empty())
      fail("sample_period", bad);
  if (s.filter_order < 2 || s.filter_order % 2)
    fail("filter.order", "the filter order must be even and at least 2");
  if (s.decimate < 1) fail("filter.decimate", "decimation must be at least 1");
  if (!(s.trim_s >= 0)) fail("filter.trim", "trim must not be negative");
  checkConversion(s);
}

// Every file holds one row per sample (as many as the positions), and at least kMinLogRows.
void checkRows(const JointLogSpec& s, const LogTable& pos, const LogTable& other,
               const LogFile& file, const char* what) {
  const std::size_t R = pos.lines.size();
  if (other.lines.size() != R) {
    const bool pos_short = R < other.lines.size();
    const LogTable& shorter = pos_short ? pos : other;
    throw InputError(pos_short ? s.positions.path : file.path, shorter.lines.back() + 1,
                     (pos_short ? s.positions : file).columns.front(),
                     "the positions have " + std::to_string(R) + " rows and the " + what + " " +
                         std::to_string(other.lines.size()) +
                         ": the files must have one row per sample each");
  }
}

void checkMinRows(const JointLogSpec& s, const LogTable& pos) {
  const std::size_t R = pos.lines.size();
  if (R < static_cast<std::size_t>(defaults::kMinLogRows))
    throw InputError(s.positions.path, R ? pos.lines.back() : 1,
                     s.time_column.empty() ? s.positions.columns.front() : s.time_column,
                     "the log has " + std::to_string(R) + " row" + (R == 1 ? "" : "s") +
                         "; velocities and accelerations need at least " +
                         std::to_string(defaults::kMinLogRows));
}

// One log file besides the positions, with its table and time column.
struct OtherFile {
  const LogFile* file;
  const char* what;
  LogTable table;
  std::string time_column;  // empty: the file has none
};

// A file's time column against the positions' (period h): its own gaps and rate, then row by row
// its offset (more than half a step apart).
void checkTimeAgainst(const JointLogSpec& s, const LogTable& pos, double h, const OtherFile& o,
                      std::vector<std::string>& warnings) {
  const LogTable& f = o.table;
  const std::string& path = o.file->path;
  const double hf = samplePeriod(f, path, o.time_column, warnings);
  const std::string hint = " (resample = true interpolates it onto the positions' times)";
  if (std::abs(hf - h) > defaults::kUniformSamplingTolerance * h)
    throw InputError(path, f.lines[1], o.time_column,
                     "the " + std::string(o.what) + " are sampled every " + formatG(hf, 6) +
                         " s (median step) and the positions in " + s.positions.path + " every " +
                         formatG(h, 6) + " s: the rates differ" + hint);
  const std::size_t R = std::min(f.time.size(), pos.time.size());
  for (std::size_t i = 0; i < R; ++i)
    if (std::abs(f.time[i] - pos.time[i]) > 0.5 * h)
      throw InputError(path, f.lines[i], o.time_column,
                       "time " + formatG(f.time[i], 9) + " s here and " + formatG(pos.time[i], 9) +
                           " s on line " + std::to_string(pos.lines[i]) + " of " +
                           s.positions.path + ": the files are offset by " +
                           formatG(f.time[i] - pos.time[i], 6) + " s (more than half a step)" +
                           hint);
}

// Linear interpolation of a timed table's values at the times t (all within its span).
Eigen::MatrixXd interpolateAt(const LogTable& f, const std::vector<double>& t) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(t.size()), f.values.cols());
  std::size_t k = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    while (k + 2 < f.time.size() && f.time[k + 1] < t[i]) ++k;
    const double a = (t[i] - f.time[k]) / (f.time[k + 1] - f.time[k]);
    out.row(static_cast<Eigen::Index>(i)) = (1 - a) * f.values.row(static_cast<Eigen::Index>(k)) +
                                            a * f.values.row(static_cast<Eigen::Index>(k + 1));
  }
  return out;
}

// resample = true: the positions rows inside every timed file's span are kept, and every other
// file is interpolated at their times (each needs a time column).
void resampleOnto(const JointLogSpec& s, LogTable& pos, std::vector<OtherFile>& others) {
  if (pos.time.empty())
    throw InputError(s.study_file, s.study_line, keyOf(s, "resample"),
                     "resampling needs a time column in the positions file (time_column)");
  double lo = pos.time.front(), hi = pos.time.back();
  for (const OtherFile& o : others) {
    if (o.time_column.empty())
      throw InputError(o.file->path, 1,
                       s.time_column.empty() ? o.file->columns.front() : s.time_column,
                       std::string("resampling needs a time column in the ") + o.what +
                           " file (its own time_column, or the log's)");
    lo = std::max(lo, o.table.time.front());
    hi = std::min(hi, o.table.time.back());
  }
  std::vector<int> rows;
  for (int i = 0; i < static_cast<int>(pos.time.size()); ++i)
    if (pos.time[i] >= lo && pos.time[i] <= hi) rows.push_back(i);
  LogTable kept;
  kept.values.resize(static_cast<Eigen::Index>(rows.size()), pos.values.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    kept.values.row(static_cast<Eigen::Index>(k)) = pos.values.row(rows[k]);
    kept.time.push_back(pos.time[rows[k]]);
    kept.lines.push_back(pos.lines[rows[k]]);
  }
  pos = kept;
  for (OtherFile& o : others) {
    if (pos.time.empty()) break;
    o.table.values = interpolateAt(o.table, pos.time);
    o.table.time = pos.time;
    o.table.lines = pos.lines;
  }
}

// Samples cut at each end: trim / h, computed in double (any trim and period compare without
// overflow); a trim that leaves fewer than kMinLogRows is an input error naming filter.trim.
int trimSamples(const JointLogSpec& s, double h, int rows) {
  const double trim = std::max(0.0, std::ceil(s.trim_s / h - 1e-9));
  if (!(rows - 2 * trim >= defaults::kMinLogRows))
    throw InputError(s.study_file, s.study_line, keyOf(s, "filter.trim"),
                     "a trim of " + formatG(s.trim_s, 6) + " s is " + formatG(trim, 6) +
                         " samples at each end of a log of " + std::to_string(rows) +
                         " rows: fewer than " + std::to_string(defaults::kMinLogRows) +
                         " are left");
  return static_cast<int>(trim);
}

}  // namespace

void motorToJoint(const Eigen::MatrixXd& R, const Eigen::VectorXd& theta_m,
                  const Eigen::VectorXd& tau_m, Eigen::VectorXd& q, Eigen::VectorXd& tau) {
  q = R.fullPivLu().solve(theta_m);
  tau = R.transpose() * tau_m;
}

std::vector<double> zeroPhaseLowPass(const std::vector<double>& x, double h, double fc, int order) {
  ARMSTUDY_CHECK(order >= 2 && order % 2 == 0 && h > 0 && fc > 0 && fc * h < 0.5,
                 "low-pass settings");
  const int n = static_cast<int>(x.size());
  if (n < 2) return x;
  // Odd reflection at both ends (continues value and slope), then biquad sections forward and back.
  // In double: 1 / (fc h) may exceed any int.
  const int pad =
      static_cast<int>(std::min<double>(n - 1, 3.0 * order * std::ceil(1.0 / (fc * h))));
  std::vector<double> y;
  y.reserve(n + 2 * pad);
  for (int i = pad; i >= 1; --i) y.push_back(2 * x[0] - x[i]);
  y.insert(y.end(), x.begin(), x.end());
  for (int i = 1; i <= pad; ++i) y.push_back(2 * x[n - 1] - x[n - 1 - i]);
  // Analog Butterworth pole pairs, bilinear transform with the cut-off prewarped.
  const double K = std::tan(std::numbers::pi * fc * h);
  for (int pass = 0; pass < 2; ++pass) {
    for (int k = 0; k < order / 2; ++k) {
      const double Q = 1.0 / (2 * std::cos(std::numbers::pi * (2 * k + 1) / (2.0 * order)));
      const double norm = 1 / (1 + K / Q + K * K);
      const double b0 = K * K * norm, b1 = 2 * b0, b2 = b0;
      const double a1 = 2 * (K * K - 1) * norm, a2 = (1 - K / Q + K * K) * norm;
      // Transposed direct form II, started in the steady state of the first sample.
      double z2 = (b2 - a2) * y[0], z1 = (b1 - a1) * y[0] + z2;
      for (double& v : y) {
        const double in = v, out = b0 * in + z1;
        z1 = b1 * in - a1 * out + z2;
        z2 = b2 * in - a2 * out;
        v = out;
      }
    }
    std::reverse(y.begin(), y.end());
  }
  return std::vector<double>(y.begin() + pad, y.begin() + pad + n);
}

std::vector<double> centralDifference(const std::vector<double>& x, const std::vector<double>& t) {
  const int n = static_cast<int>(x.size());
  std::vector<double> d(n, 0.0);
  if (n < 2) return d;
  d[0] = (x[1] - x[0]) / (t[1] - t[0]);
  d[n - 1] = (x[n - 1] - x[n - 2]) / (t[n - 1] - t[n - 2]);
  for (int i = 1; i + 1 < n; ++i) d[i] = (x[i + 1] - x[i - 1]) / (t[i + 1] - t[i - 1]);
  return d;
}

std::vector<double> centralDifference(const std::vector<double>& x, double h) {
  const int n = static_cast<int>(x.size());
  std::vector<double> d(n, 0.0);
  if (n < 2) return d;
  d[0] = (x[1] - x[0]) / h;
  d[n - 1] = (x[n - 1] - x[n - 2]) / h;
  for (int i = 1; i + 1 < n; ++i) d[i] = (x[i + 1] - x[i - 1]) / (2 * h);
  return d;
}

namespace {

// The other files of a log, read with their time columns (a file's own, else the log's when the
// file has that column).
std::vector<OtherFile> readOtherFiles(const JointLogSpec& s) {
  std::vector<OtherFile> out;
  auto add = [&](const LogFile& f, const char* what) {
    if (f.path.empty()) return;
    const bool own = !f.time_column.empty();
    const std::string col = own ? f.time_column : s.time_column;
    OtherFile o{&f, what, readLogFile(f, col, own), {}};
    if (!o.table.time.empty()) o.time_column = col;
    out.push_back(std::move(o));
  };
  add(s.efforts, "efforts");
  add(s.velocities, "velocities");
  add(s.accelerations, "accelerations");
  return out;
}

// Time columns of the other files: each against the positions' (or resampled onto them), then
// one row per sample in every file.
void alignFiles(const JointLogSpec& s, LogTable& pos, double h, std::vector<OtherFile>& others,
                std::vector<std::string>& warnings) {
  for (const OtherFile& o : others) {
    if (o.time_column.empty()) continue;
    if (pos.time.empty())
      throw InputError(o.file->path, 1, o.time_column,
                       std::string("the ") + o.what + " file has a time column '" + o.time_column +
                           "' but the positions have none to compare it with (give the log's "
                           "time_column)");
    if (o.table.lines.size() < static_cast<std::size_t>(defaults::kMinLogRows))
      throw InputError(o.file->path, o.table.lines.empty() ? 1 : o.table.lines.back(),
                       o.time_column,
                       "fewer than " + std::to_string(defaults::kMinLogRows) + " rows");
    if (s.resample)
      samplePeriod(o.table, o.file->path, o.time_column, warnings);  // gaps and order
    else
      checkTimeAgainst(s, pos, h, o, warnings);
  }
  if (s.resample) {
    resampleOnto(s, pos, others);
    warnings.push_back("resampled onto the positions' times (" + s.positions.path +
                       "): " + std::to_string(pos.lines.size()) + " rows inside every file's span");
  }
  for (const OtherFile& o : others) checkRows(s, pos, o.table, *o.file, o.what);
  checkMinRows(s, pos);
}

// RMS over the kept rows of a minus b.
double rmsDifference(const std::vector<double>& a, const std::vector<double>& b,
                     const std::vector<int>& keep) {
  double sum = 0;
  for (int k : keep) sum += (a[k] - b[k]) * (a[k] - b[k]);
  return keep.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(keep.size()));
}

// Every sample on the joint side, in design joint order: positions with offsets, efforts (currents
// times kt and the joint-side ratio), logged velocities and accelerations where given.
struct JointSideSamples {
  Eigen::MatrixXd q, tau, qd_log, qdd_log;
};
JointSideSamples jointSideSamples(const JointLogSpec& s, const std::vector<int>& map, int n,
                                  const LogTable& pos, const LogTable& eff, const LogTable* vel,
                                  const LogTable* acc) {
  const int R = static_cast<int>(pos.lines.size());
  const auto N = static_cast<Eigen::Index>(map.size());
  Eigen::VectorXd effort_scale = Eigen::VectorXd::Ones(N);
  for (Eigen::Index c = 0; c < N && !s.torque_constants.empty(); ++c)
    effort_scale[c] =
        s.torque_constants[static_cast<std::size_t>(c)] *
        (s.effort_ratios.empty() ? 1.0 : s.effort_ratios[static_cast<std::size_t>(c)]);
  JointSideSamples js{Eigen::MatrixXd(R, n), Eigen::MatrixXd(R, n), Eigen::MatrixXd(R, n),
                      Eigen::MatrixXd(R, n)};
  Eigen::VectorXd qi, ti, vi, ai;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(N);
  for (int i = 0; i < R; ++i) {
    const Eigen::VectorXd e = eff.values.row(i).transpose().cwiseProduct(effort_scale);
    if (vel) motorToJoint(s.coupling, vel->values.row(i).transpose(), zero, vi, ti);
    if (acc) motorToJoint(s.coupling, acc->values.row(i).transpose(), zero, ai, ti);
    motorToJoint(s.coupling, pos.values.row(i).transpose(), e, qi, ti);
    for (std::size_t c = 0; c < map.size(); ++c) {
      const auto C = static_cast<Eigen::Index>(c);
      js.q(i, map[c]) = qi[C] + s.offsets[C];
      js.tau(i, map[c]) = ti[C];
      if (vel) js.qd_log(i, map[c]) = vi[C];
      if (acc) js.qdd_log(i, map[c]) = ai[C];
    }
  }
  return js;
}

// Filters every joint's samples, differentiates the positions (or takes the logged velocities and
// accelerations, noting their RMS difference from the differentiated ones), keeps rows `keep` in d.
void filteredRows(const JointLogSpec& s, const Model& model, const JointSideSamples& js,
                  const std::vector<double>& time, const std::vector<int>& keep, double h, bool vel,
                  bool acc, TrajectoryData& d) {
  const int n = model.dof(), K = static_cast<int>(keep.size());
  const auto R = static_cast<std::size_t>(js.q.rows());
  d.q.resize(K, n);
  d.qd.resize(K, n);
  d.qdd.resize(K, n);
  d.measured.resize(K, n);
  auto lowPass = [&](const Eigen::MatrixXd& m, int j) {
    return zeroPhaseLowPass(std::vector<double>(m.col(j).data(), m.col(j).data() + R), h,
                            s.cutoff_Hz, s.filter_order);
  };
  std::string vel_note, acc_note;
  for (int j = 0; j < n; ++j) {
    const std::vector<double> qf = lowPass(js.q, j), tf = lowPass(js.tau, j);
    d.effort_resolution.push_back(loggingResolution(
        std::vector<double>(js.tau.col(j).data(), js.tau.col(j).data() + R)));  // unfiltered
    std::vector<double> v = centralDifference(qf, time);
    std::vector<double> a = centralDifference(v, time);
    if (vel) {
      const std::vector<double> vl = lowPass(js.qd_log, j);
      const double rms = rmsDifference(vl, v, keep);
      d.velocity_difference_rms.push_back(rms);
      const bool rev = model.joints[j].type == JointType::Revolute;
      vel_note += (vel_note.empty() ? "" : ", ") + model.joints[j].name + " " + formatG(rms, 3) +
                  (rev ? " rad/s" : " m/s");
      std::vector<double> al = acc ? lowPass(js.qdd_log, j) : centralDifference(vl, time);
      const double arms = rmsDifference(al, a, keep);
      acc_note += (acc_note.empty() ? "" : ", ") + model.joints[j].name + " " + formatG(arms, 3) +
                  (rev ? " rad/s^2" : " m/s^2");
      v = vl;
      a = al;
    }
    for (int k = 0; k < K; ++k) {
      d.q(k, j) = qf[keep[k]];
      d.qd(k, j) = v[keep[k]];
      d.qdd(k, j) = a[keep[k]];
      d.measured(k, j) = tf[keep[k]];
    }
  }
  if (vel) {
    d.warnings.push_back("logged velocities used (" + s.velocities.path +
                         "); RMS of logged minus differentiated positions, per joint: " + vel_note);
    const std::string what = acc ? "logged accelerations used"
                                 : "accelerations differentiated from the logged velocities";
    d.warnings.push_back(
        what + "; RMS against the twice-differentiated positions, per joint: " + acc_note);
  }
}

// The log's content hash: each file read, once.
std::string logHash(const JointLogSpec& s) {
  std::string hash = fileHash(s.positions.path);
  std::vector<std::string> hashed = {s.positions.path};
  for (const LogFile* f : {&s.efforts, &s.velocities, &s.accelerations})
    if (!f->path.empty() && std::find(hashed.begin(), hashed.end(), f->path) == hashed.end()) {
      hash += "+" + fileHash(f->path);
      hashed.push_back(f->path);
    }
  return hash;
}

}  // namespace

TrajectoryData readJointLog(const JointLogSpec& s, const Model& model) {
  checkSpec(s);
  const std::vector<int> map = jointMap(s, model);
  LogTable pos = readLogFile(s.positions, s.time_column, !s.time_column.empty());
  std::vector<OtherFile> others = readOtherFiles(s);
  std::vector<std::string> warnings;
  if (pos.lines.size() < static_cast<std::size_t>(defaults::kMinLogRows)) checkMinRows(s, pos);
  const double h = s.time_column.empty()
                       ? s.sample_period_s
                       : samplePeriod(pos, s.positions.path, s.time_column, warnings);
  alignFiles(s, pos, h, others, warnings);
  const LogTable* vel = s.velocities.path.empty() ? nullptr : &others[1].table;
  const LogTable* acc = s.accelerations.path.empty() ? nullptr : &others[2].table;
  const int R = static_cast<int>(pos.lines.size());
  std::vector<double> time = pos.time;
  if (time.empty())
    for (int i = 0; i < R; ++i) time.push_back(i * h);
  if (!(s.cutoff_Hz > 0 && s.cutoff_Hz * h * s.decimate < 0.5))
    throw InputError(s.study_file, s.study_line, keyOf(s, "filter.cutoff"),
                     "the cut-off must lie below half the sample rate after decimation (" +
                         std::to_string(0.5 / (h * s.decimate)) + " Hz)");
  const int n = model.dof();
  const JointSideSamples js = jointSideSamples(s, map, n, pos, others[0].table, vel, acc);
  const int trim = trimSamples(s, h, R);
  std::vector<int> keep;
  for (int i = trim; i < R - trim; i += s.decimate) keep.push_back(i);
  if (keep.size() < 3)
    throw InputError(s.positions.path, pos.lines.back(), s.positions.columns.front(),
                     std::to_string(R) + " rows leave " + std::to_string(keep.size()) +
                         " after trimming and decimation");
  TrajectoryData d;
  d.file = s.positions.path;
  d.hash = logHash(s);
  d.qdd_given = false;
  d.currents = false;
  d.warnings = warnings;
  filteredRows(s, model, js, time, keep, h, vel != nullptr, acc != nullptr, d);
  const int K = static_cast<int>(keep.size());
  d.joint_named_channels = true;
  d.gravity_compensated.assign(n, false);
  for (const std::string& g : s.gravity_compensated) {
    d.gravity_compensated[model.jointIndex(g)] = true;
    d.warnings.push_back("joint " + g +
                         ": its controller compensates gravity, so its model effort excludes the "
                         "gravity term");
  }
  for (int k = 0; k < K; ++k) {
    d.t.push_back(time[keep[k]]);
    d.lines.push_back(pos.lines[keep[k]]);
  }
  d.friction_width_fraction =
      s.friction_width_fraction > 0 ? s.friction_width_fraction : defaults::kFrictionWidthFraction;
  d.coupling = Eigen::MatrixXd::Zero(n, n);  // in design joint order
  for (std::size_t a = 0; a < map.size(); ++a)
    for (std::size_t b = 0; b < map.size(); ++b)
      d.coupling(map[a], map[b]) =
          s.coupling(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
  d.warnings.push_back(s.positions.path + ": " + std::to_string(R) +
                       " samples, zero-phase Butterworth low-pass at " + formatG(s.cutoff_Hz, 6) +
                       " Hz (order " + std::to_string(s.filter_order) + " forward and backward), " +
                       std::to_string(K) + " rows after decimation by " +
                       std::to_string(s.decimate) + " and " + std::to_string(trim) +
                       " samples trimmed at each end");
  return d;
}

}  // namespace armstudy::calibration
