#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <set>

#include "calibration/drive_calibration.hpp"
#include "calibration/trajectory_calibration.hpp"
#include "common/angles.hpp"
#include "common/errors.hpp"
#include "common/rng.hpp"
#include "drive/drive_chain.hpp"
#include "dynamics/dynamics.hpp"
#include "io/csv_io.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "kinematics/kinematics.hpp"
namespace armstudy::calibration {

TrajectoryData readTrajectoryData(const std::string& path, const Model& model) {
  const int n = model.dof();
  io::CsvSchema schema;
  schema.required.push_back("t");
  for (const char* p : {"q", "qd"})
    for (int j = 1; j <= n; ++j) schema.required.push_back(p + std::to_string(j));
  for (const char* p : {"qdd", "tau", "current"})
    for (int j = 1; j <= n; ++j) schema.optional.push_back(p + std::to_string(j));
  const io::CsvTable t = io::readCsv(path, schema);
  TrajectoryData d;
  d.file = path;
  d.hash = fileHash(path);
  d.warnings = t.extraColumnWarnings("(q|qd|qdd|tau|current)([0-9]+)", model.name, n);
  auto group = [&](const std::string& p) {
    int c = 0;
    std::string missing;
    for (int j = 1; j <= n; ++j) {
      if (t.has(p + std::to_string(j)))
        ++c;
      else if (missing.empty())
        missing = p + std::to_string(j);
    }
    if (c != 0 && c != n)
      throw InputError(path, 1, missing,
                       "missing column '" + missing + "' (give " + p + "1.." + p +
                           std::to_string(n) + " for all joints or none)");
    return c == n;
  };
  const bool has_qdd = group("qdd"), has_tau = group("tau"), has_cur = group("current");
  if (has_tau && has_cur)
    throw InputError(path, 1, "current1", "give either tau1..taun or current1..currentn, not both");
  if (!has_tau && !has_cur)
    throw InputError(
        path, 1, "tau1",
        "missing column 'tau1' (or 'current1'): the measured joint efforts or motor currents");
  d.t = t.column("t");
  d.lines = t.row_lines;
  const int R = t.rows();
  d.q.resize(R, n);
  d.qd.resize(R, n);
  d.qdd.resize(R, n);
  d.measured.resize(R, n);
  d.currents = has_cur;
  d.qdd_given = has_qdd;
  for (int j = 0; j < n; ++j) {
    const std::string s = std::to_string(j + 1);
    for (int i = 0; i < R; ++i) {
      d.q(i, j) = t.column("q" + s)[i];
      d.qd(i, j) = t.column("qd" + s)[i];
      d.measured(i, j) = t.column((has_cur ? "current" : "tau") + s)[i];
      if (has_qdd) d.qdd(i, j) = t.column("qdd" + s)[i];
    }
  }
  for (int i = 1; i < R; ++i)
    if (!(d.t[i] > d.t[i - 1]))
      throw InputError(path, d.lines[i], "t", "time must increase strictly from row to row");
  if (!has_qdd) {
    const int w = 2 * defaults::kSavitzkyGolayHalfWindow + 1;
    if (R < w)
      throw InputError(path, 0, "qdd1",
                       "no qdd columns and only " + std::to_string(R) +
                           " rows: differentiating qd needs at least " + std::to_string(w));
    double hmin = std::numeric_limits<double>::infinity(), hmax = 0;
    for (int i = 1; i < R; ++i) {
      hmin = std::min(hmin, d.t[i] - d.t[i - 1]);
      hmax = std::max(hmax, d.t[i] - d.t[i - 1]);
    }
    if (hmax > hmin * (1 + defaults::kUniformSamplingTolerance))
      d.warnings.push_back(path + ": time steps are not uniform (" + std::to_string(hmin) + " .. " +
                           std::to_string(hmax) +
                           " s); the Savitzky-Golay fit uses the actual times");
    for (int j = 0; j < n; ++j) {
      const std::vector<double> qd(d.qd.col(j).data(), d.qd.col(j).data() + R);
      const auto a = savitzkyGolayDerivative(d.t, qd, defaults::kSavitzkyGolayHalfWindow,
                                             defaults::kSavitzkyGolayDegree);
      for (int i = 0; i < R; ++i) d.qdd(i, j) = a[i];
    }
    d.warnings.push_back(path +
                         ": no qdd columns; accelerations are the Savitzky-Golay derivative of qd "
                         "(local quadratic, " +
                         std::to_string(2 * defaults::kSavitzkyGolayHalfWindow + 1) + " samples)");
  }
  return d;
}

std::string trajectoryDataToCsv(const TrajectoryData& d, bool write_qdd) {
  std::vector<std::string> h = {"t"};
  std::vector<std::vector<double>> cols = {d.t};
  const int n = static_cast<int>(d.q.cols());
  auto put = [&](const std::string& p, const Eigen::MatrixXd& m) {
    for (int j = 0; j < n; ++j) {
      h.push_back(p + std::to_string(j + 1));
      const Eigen::VectorXd c = m.col(j);
      cols.emplace_back(c.data(), c.data() + c.size());
    }
  };
  put("q", d.q);
  put("qd", d.qd);
  if (write_qdd) put("qdd", d.qdd);
  put(d.currents ? "current" : "tau", d.measured);
  return io::formatCsv(h, cols);
}

TrajectoryData synthesizeTrajectory(const Model& model, const TrajectorySynthOptions& o) {
  if (!(o.duration_s > 0) || !(o.rate_Hz > 0))
    throw InputError("", 0, "duration", "duration and rate must be positive");
  if (!(o.duration_s * o.rate_Hz <= defaults::kMaxTrajectorySamples))
    throw InputError("", 0, "duration", "duration x rate exceeds 1e6 samples");
  if (!(o.noise >= 0)) throw InputError("", 0, "noise", "noise must not be negative");
  if (o.harmonics < 1) throw InputError("", 0, "harmonics", "at least one harmonic");
  const int n = model.dof();
  std::set<int> still;
  for (const auto& s : o.still_joints) {
    const int j = model.jointIndex(s);
    if (j < 0)
      throw InputError("", 0, "still", "design '" + model.name + "' has no joint '" + s + "'");
    still.insert(j);
  }
  rng::SplitMix64 rng{o.seed};
  const int R = static_cast<int>(std::floor(o.duration_s * o.rate_Hz)) + 1;
  TrajectoryData d;
  d.currents = o.currents;
  d.q.resize(R, n);
  d.qd.resize(R, n);
  d.qdd.resize(R, n);
  d.measured = Eigen::MatrixXd::Zero(R, n);
  for (int i = 0; i < R; ++i) {
    d.t.push_back(i / o.rate_Hz);
    d.lines.push_back(i + 2);
  }
  // Smooth random joint motion: a sum of sines around the middle of the joint range.
  for (int j = 0; j < n; ++j) {
    const JointLimits& l = model.joints[j].limits;
    const double c = 0.5 * (l.q_min + l.q_max);
    double amp = o.range_fraction * 0.5 * (l.q_max - l.q_min);
    if (model.joints[j].type == JointType::Revolute) amp = std::min(amp, o.max_amplitude_rad);
    if (still.count(j)) amp = 0;
    std::vector<double> a(o.harmonics), w(o.harmonics), ph(o.harmonics);
    double sum = 0;
    for (int k = 0; k < o.harmonics; ++k) {
      a[k] = 0.3 + rng.uniform();
      sum += a[k];
      w[k] = kFullTurn_rad * o.max_frequency_Hz * (0.25 + 0.75 * rng.uniform());
      ph[k] = kFullTurn_rad * rng.uniform();
    }
    for (int k = 0; k < o.harmonics; ++k) a[k] *= amp / sum;
    for (int i = 0; i < R; ++i) {
      double q = c, qd = 0, qdd = 0;
      for (int k = 0; k < o.harmonics; ++k) {
        const double x = w[k] * d.t[i] + ph[k];
        q += a[k] * std::sin(x);
        qd += a[k] * w[k] * std::cos(x);
        qdd -= a[k] * w[k] * w[k] * std::sin(x);
      }
      d.q(i, j) = q;
      d.qd(i, j) = qd;
      d.qdd(i, j) = qdd;
    }
  }
  const auto P = makeTrajectoryProblem(model, d);
  EffectValues hidden;
  for (const auto& h : o.hidden) hidden.push_back(parseHiddenEffect(*P, h));
  d.measured = P->predict(hidden);
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < n; ++j) d.measured(i, j) += o.noise * rng.normal();
  d.qdd_given = o.write_qdd;
  return d;
}

}  // namespace armstudy::calibration
