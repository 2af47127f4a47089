#include "calibration/joint_log.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

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

// The columns of one log file (and its time column), every row on consecutive lines: a blank
// line inside a sampled log would shift one file against the other.
LogTable readLogFile(const LogFile& f, const std::string& time_column) {
  io::CsvSchema schema;
  schema.required = f.columns;
  if (!time_column.empty()) schema.required.push_back(time_column);
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
  if (!time_column.empty()) out.time = t.column(time_column);
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
}

// The two files hold one row per sample each, and at least kMinLogRows of them.
void checkRows(const JointLogSpec& s, const LogTable& pos, const LogTable& eff) {
  const std::size_t R = pos.lines.size();
  if (eff.lines.size() != R) {
    const bool pos_short = R < eff.lines.size();
    const LogTable& shorter = pos_short ? pos : eff;
    throw InputError(pos_short ? s.positions.path : s.efforts.path, shorter.lines.back() + 1,
                     (pos_short ? s.positions : s.efforts).columns.front(),
                     "the positions have " + std::to_string(R) + " rows and the efforts " +
                         std::to_string(eff.lines.size()) +
                         ": the two files must have one row per sample each");
  }
  if (R < static_cast<std::size_t>(defaults::kMinLogRows))
    throw InputError(s.positions.path, R ? pos.lines.back() : 1,
                     s.time_column.empty() ? s.positions.columns.front() : s.time_column,
                     "the log has " + std::to_string(R) + " row" + (R == 1 ? "" : "s") +
                         "; velocities and accelerations need at least " +
                         std::to_string(defaults::kMinLogRows));
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
  const double K = std::tan(M_PI * fc * h);
  for (int pass = 0; pass < 2; ++pass) {
    for (int k = 0; k < order / 2; ++k) {
      const double Q = 1.0 / (2 * std::cos(M_PI * (2 * k + 1) / (2.0 * order)));
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

TrajectoryData readJointLog(const JointLogSpec& s, const Model& model) {
  checkSpec(s);
  const std::vector<int> map = jointMap(s, model);
  const LogTable pos = readLogFile(s.positions, s.time_column);
  const LogTable eff = readLogFile(s.efforts, "");
  checkRows(s, pos, eff);
  const int R = static_cast<int>(pos.lines.size());
  std::vector<std::string> warnings;
  const double h = s.time_column.empty()
                       ? s.sample_period_s
                       : samplePeriod(pos, s.positions.path, s.time_column, warnings);
  std::vector<double> time = pos.time;
  if (time.empty())
    for (int i = 0; i < R; ++i) time.push_back(i * h);
  if (!(s.cutoff_Hz > 0 && s.cutoff_Hz * h * s.decimate < 0.5))
    throw InputError(s.study_file, s.study_line, keyOf(s, "filter.cutoff"),
                     "the cut-off must lie below half the sample rate after decimation (" +
                         std::to_string(0.5 / (h * s.decimate)) + " Hz)");
  const int n = model.dof();
  // Convert every sample to the joint side, in design joint order.
  Eigen::MatrixXd q(R, n), tau(R, n);
  Eigen::VectorXd qi, ti;
  for (int i = 0; i < R; ++i) {
    motorToJoint(s.coupling, pos.values.row(i).transpose(), eff.values.row(i).transpose(), qi, ti);
    for (std::size_t c = 0; c < map.size(); ++c) {
      q(i, map[c]) = qi[static_cast<Eigen::Index>(c)] + s.offsets[static_cast<Eigen::Index>(c)];
      tau(i, map[c]) = ti[static_cast<Eigen::Index>(c)];
    }
  }
  const int trim = trimSamples(s, h, R);
  std::vector<int> keep;
  for (int i = trim; i < R - trim; i += s.decimate) keep.push_back(i);
  if (keep.size() < 3)
    throw InputError(s.positions.path, pos.lines.back(), s.positions.columns.front(),
                     std::to_string(R) + " rows leave " + std::to_string(keep.size()) +
                         " after trimming and decimation");
  TrajectoryData d;
  d.file = s.positions.path;
  d.hash = fileHash(s.positions.path) + "+" + fileHash(s.efforts.path);
  d.qdd_given = false;
  d.currents = false;
  const int K = static_cast<int>(keep.size());
  d.q.resize(K, n);
  d.qd.resize(K, n);
  d.qdd.resize(K, n);
  d.measured.resize(K, n);
  for (int j = 0; j < n; ++j) {
    const std::vector<double> qf = zeroPhaseLowPass(
        std::vector<double>(q.col(j).data(), q.col(j).data() + R), h, s.cutoff_Hz, s.filter_order);
    const std::vector<double> tf =
        zeroPhaseLowPass(std::vector<double>(tau.col(j).data(), tau.col(j).data() + R), h,
                         s.cutoff_Hz, s.filter_order);
    const std::vector<double> v = centralDifference(qf, time), a = centralDifference(v, time);
    for (int k = 0; k < K; ++k) {
      d.q(k, j) = qf[keep[k]];
      d.qd(k, j) = v[keep[k]];
      d.qdd(k, j) = a[keep[k]];
      d.measured(k, j) = tf[keep[k]];
    }
  }
  d.warnings = warnings;
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
