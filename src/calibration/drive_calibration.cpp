#include "calibration/drive_calibration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "calibration/least_squares.hpp"
#include "common/errors.hpp"
#include "common/rng.hpp"
#include "drive/drive_chain.hpp"
#include "io/csv_io.hpp"
#include "io/files.hpp"

namespace armstudy::calibration {

using drive::Effect;
using drive::FrictionParams;
using EffectSet = std::array<bool, drive::kEffectCount>;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
int idx(Effect e) { return static_cast<int>(e); }
double sgn(double v) { return (v > 0) - (v < 0); }

std::string effectList(const EffectSet& on) {
  std::string s;
  for (Effect e : drive::kAllEffects)
    if (on[idx(e)]) { s += s.empty() ? "" : "+"; s += std::string(drive::toString(e)); }
  return s.empty() ? "(none)" : s;
}

std::vector<Effect> toList(const EffectSet& on) {
  std::vector<Effect> v;
  for (Effect e : drive::kAllEffects)
    if (on[idx(e)]) v.push_back(e);
  return v;
}

// Everything the fits need, per row, in law-side units (docs/calibration.md).
struct Context {
  const Drive* drive = nullptr;
  double km = 1, N = 1, side = 1;  // side: law-side loss -> motor-side torque
  bool joint_side = false;
  double theta_ref = 20;
  bool has_temperature = false;
  int n = 0;
  std::vector<double> v, absL, s, theta, y, load_term;
  double v_lo = 1, v_hi = 1;  // Stribeck velocity profiling range (law side)
};

Context makeContext(const Drive& d, const FrictionParams& fp, const DriveData& data) {
  Context c;
  c.drive = &d;
  c.km = d.torque_constant_NmpA;
  c.N = d.gear_ratio;
  c.joint_side = fp.joint_side;
  c.side = fp.joint_side ? 1.0 / d.gear_ratio : 1.0;
  c.theta_ref = fp.reference_temperature_C;
  c.has_temperature = data.hasTemperature();
  c.n = data.rows();
  double vmin = kInf, vmax = 0;
  for (int i = 0; i < c.n; ++i) {
    const double v = data.speed[i] * c.side;
    c.v.push_back(v);
    c.s.push_back(sgn(v));
    c.absL.push_back(std::abs(data.load[i]));
    c.theta.push_back(c.has_temperature ? data.temperature[i] : c.theta_ref);
    c.load_term.push_back(data.load[i] / c.N);
    c.y.push_back(c.km * data.current[i] - c.load_term.back());  // measured loss, motor side [N m]
    vmin = std::min(vmin, std::abs(v));
    vmax = std::max(vmax, std::abs(v));
  }
  // The Stribeck velocity is identifiable only inside the measured speed range.
  c.v_lo = 0.5 * vmin;
  c.v_hi = vmax;
  return c;
}

double stribeckShape(double v, double vS) {
  const double x = v / vS;
  return 1.0 / (1.0 + x * x);
}

// Regressor of one linear parameter for row i (motor side).
double column(const Context& c, const EffectSet& on, Effect e, int i, double vS) {
  const double st = on[idx(Effect::Stribeck)] ? stribeckShape(c.v[i], vS) : 0.0;
  double val = 0;
  switch (e) {
    case Effect::Coulomb: val = c.s[i] * (1.0 - st); break;                    // eq. (3.33) T_f0
    case Effect::Viscous: val = c.v[i]; break;
    case Effect::LoadCoulomb: val = c.absL[i] * c.s[i]; break;
    case Effect::LoadViscous: val = c.absL[i] * c.v[i]; break;
    case Effect::Stribeck: val = c.s[i] * st; break;                           // eq. (3.33) T_fS
    case Effect::Asymmetry: val = c.s[i] * c.s[i]; break;
    case Effect::Temperature: val = (c.theta[i] - c.theta_ref) * c.s[i]; break;
    case Effect::TemperatureViscous: val = (c.theta[i] - c.theta_ref) * c.v[i]; break;
  }
  return val * c.side;
}

Eigen::MatrixXd designMatrix(const Context& c, const EffectSet& on, const std::vector<int>& rows, double vS) {
  const std::vector<Effect> eff = toList(on);
  Eigen::MatrixXd A(rows.size(), eff.size());
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t j = 0; j < eff.size(); ++j) A(r, j) = column(c, on, eff[j], rows[r], vS);
  return A;
}

struct RawFit {
  Eigen::VectorXd x;  // linear parameters in kAllEffects order of the switched-on effects
  double vS = 1;
  double ssr = 0;
  bool rank_deficient = false;
};

RawFit solveAt(const Context& c, const EffectSet& on, const std::vector<int>& rows, double vS) {
  const std::vector<Effect> eff = toList(on);
  Eigen::VectorXd lo(eff.size()), hi(eff.size());
  for (std::size_t j = 0; j < eff.size(); ++j) {
    lo[j] = effectInfo(eff[j]).params[0].lower;
    hi[j] = effectInfo(eff[j]).params[0].upper;
  }
  Eigen::VectorXd y(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) y[r] = c.y[rows[r]];
  const LeastSquaresResult ls = boundedLeastSquares(designMatrix(c, on, rows, vS), y, lo, hi);
  return {ls.x, vS, ls.ssr, ls.rank_deficient};
}

// Fits the effect set on the rows; the Stribeck velocity is profiled (log grid, then golden
// section between the neighbours of the best grid point).
RawFit fitRows(const Context& c, const EffectSet& on, const std::vector<int>& rows) {
  if (!on[idx(Effect::Stribeck)]) return solveAt(c, on, rows, 1.0);
  const int G = defaults::kStribeckGridPoints;
  const double a = std::log(c.v_lo), b = std::log(c.v_hi);
  std::vector<RawFit> grid;
  int best = 0;
  for (int g = 0; g < G; ++g) {
    grid.push_back(solveAt(c, on, rows, std::exp(a + (b - a) * g / (G - 1))));
    if (grid[g].ssr < grid[best].ssr) best = g;
  }
  double lo = a + (b - a) * std::max(0, best - 1) / (G - 1);
  double hi = a + (b - a) * std::min(G - 1, best + 1) / (G - 1);
  RawFit bestFit = grid[best];
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo);
  RawFit f1 = solveAt(c, on, rows, std::exp(x1)), f2 = solveAt(c, on, rows, std::exp(x2));
  for (int it = 0; it < defaults::kStribeckRefineIterations; ++it) {
    if (f1.ssr < f2.ssr) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - phi * (hi - lo);
      f1 = solveAt(c, on, rows, std::exp(x1));
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + phi * (hi - lo);
      f2 = solveAt(c, on, rows, std::exp(x2));
    }
  }
  for (const RawFit* f : {&f1, &f2})
    if (f->ssr < bestFit.ssr) bestFit = *f;
  return bestFit;
}

double predictLoss(const Context& c, const EffectSet& on, const RawFit& f, int i) {
  double t = 0;
  int j = 0;
  for (Effect e : drive::kAllEffects)
    if (on[idx(e)]) t += f.x[j++] * column(c, on, e, i, f.vS);
  return t;
}

double currentFromLoss(const Context& c, int i, double loss) { return (c.load_term[i] + loss) / c.km; }

FrictionParams toFrictionParams(const Context& c, const FrictionParams& base, const EffectSet& on,
                                const RawFit& f) {
  FrictionParams p = base;
  p.on = on;
  int j = 0;
  for (Effect e : drive::kAllEffects) {
    if (!on[idx(e)]) continue;
    const double x = f.x[j++];
    switch (e) {
      case Effect::Coulomb: p.coulomb = x; break;
      case Effect::Viscous: p.viscous = x; break;
      case Effect::LoadCoulomb: p.load_coulomb = x; break;
      case Effect::LoadViscous: p.load_viscous = x; break;
      case Effect::Stribeck:
        p.stribeck_torque = x;
        p.stribeck_velocity = f.vS;
        break;
      case Effect::Asymmetry: p.asymmetry = x; break;
      case Effect::Temperature: p.temperature_coefficient = x; break;
      case Effect::TemperatureViscous: p.temperature_viscous_coefficient = x; break;
    }
  }
  if (!on[idx(Effect::Coulomb)]) p.coulomb = 0;
  p.reference_temperature_C = c.theta_ref;
  return p;
}

std::vector<int> allRows(int n) {
  std::vector<int> r(n);
  std::iota(r.begin(), r.end(), 0);
  return r;
}

int countParams(const EffectSet& on) {
  int p = 0;
  for (Effect e : drive::kAllEffects)
    if (on[idx(e)]) p += static_cast<int>(effectInfo(e).params.size());
  return p;
}

// Region of a row for held-out-by-region: speed x load quadrants split at the medians.
std::vector<int> regionsOf(const Context& c) {
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  std::vector<double> av(c.n);
  for (int i = 0; i < c.n; ++i) av[i] = std::abs(c.v[i]);
  const double mv = median(av), ml = median(c.absL);
  std::vector<int> reg(c.n);
  for (int i = 0; i < c.n; ++i) reg[i] = (av[i] > mv ? 2 : 0) + (c.absL[i] > ml ? 1 : 0);
  return reg;
}

// Out-of-sample residuals [A] for a partition of the rows (fold or region ids). Returns false when
// a training set is too small for the parameters.
bool heldOut(const Context& c, const EffectSet& on, const std::vector<int>& part, int parts,
             std::vector<double>& out) {
  out.assign(c.n, std::numeric_limits<double>::quiet_NaN());
  const int p = countParams(on);
  for (int k = 0; k < parts; ++k) {
    std::vector<int> train, test;
    for (int i = 0; i < c.n; ++i) (part[i] == k ? test : train).push_back(i);
    if (test.empty()) continue;
    if (static_cast<int>(train.size()) < p + defaults::kMinResidualDof) return false;
    const RawFit f = fitRows(c, on, train);
    for (int i : test) out[i] = (c.y[i] - predictLoss(c, on, f, i)) / c.km;
  }
  return true;
}

double rmsOf(const std::vector<double>& r) {
  double s = 0;
  int n = 0;
  for (double v : r)
    if (std::isfinite(v)) {
      s += v * v;
      ++n;
    }
  return n ? std::sqrt(s / n) : std::numeric_limits<double>::quiet_NaN();
}

void informationCriteria(ModelFit& m) {
  const int n = static_cast<int>(m.residual.size());
  double ssr = 0;
  for (double r : m.residual) ssr += r * r;
  const double ll = n * std::log(std::max(ssr, 1e-300) / n);
  m.aic = ll + 2.0 * m.n_params;
  m.bic = ll + m.n_params * std::log(static_cast<double>(n));
}

// Linearised 95 % intervals: sigma^2 (J^T J)^-1, inflated by (1 + rho) / (1 - rho) for AR(1)
// correlated residuals; J includes d prediction / d v_S for the profiled Stribeck velocity.
void confidenceIntervals(const Context& c, const EffectSet& on, const RawFit& f, ModelFit& m) {
  const std::vector<Effect> eff = toList(on);
  const bool st = on[idx(Effect::Stribeck)];
  const int p = static_cast<int>(eff.size()) + (st ? 1 : 0);
  Eigen::MatrixXd J(c.n, p);
  const std::vector<int> rows = allRows(c.n);
  J.leftCols(eff.size()) = designMatrix(c, on, rows, f.vS);
  Eigen::VectorXd values(p);
  for (std::size_t j = 0; j < eff.size(); ++j) values[j] = f.x[j];
  if (st) {
    int jc = -1, js = -1;
    for (std::size_t j = 0; j < eff.size(); ++j) {
      if (eff[j] == Effect::Coulomb) jc = static_cast<int>(j);
      if (eff[j] == Effect::Stribeck) js = static_cast<int>(j);
    }
    const double dT = f.x[js] - (jc >= 0 ? f.x[jc] : 0.0);
    for (int i = 0; i < c.n; ++i) {
      const double x = c.v[i] / f.vS;
      const double den = 1.0 + x * x;
      J(i, p - 1) = c.side * dT * c.s[i] * 2.0 * x * x / (f.vS * den * den);
    }
    values[p - 1] = f.vS;
  }
  const int dof = c.n - p;
  double ssr = 0;
  for (double r : m.residual) ssr += r * r * c.km * c.km;
  const double rho = std::clamp(lag1Autocorrelation(m.residual), 0.0, 0.95);
  const double s2 = dof > 0 ? ssr / dof * (1.0 + rho) / (1.0 - rho) : kInf;
  Eigen::VectorXd scale(p);
  for (int j = 0; j < p; ++j) scale[j] = J.col(j).norm() > 0 ? J.col(j).norm() : 1.0;
  const Eigen::MatrixXd Js = J * scale.cwiseInverse().asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Js, Eigen::ComputeFullV);
  const Eigen::VectorXd sv = svd.singularValues();
  const bool singular = sv.size() == 0 || sv[sv.size() - 1] < 1e-10 * sv[0];
  Eigen::VectorXd sd = Eigen::VectorXd::Constant(p, kInf);
  if (!singular) {
    const Eigen::MatrixXd V = svd.matrixV();
    const Eigen::MatrixXd covs = V * sv.cwiseInverse().cwiseAbs2().asDiagonal() * V.transpose();
    for (int j = 0; j < p; ++j) sd[j] = std::sqrt(s2 * covs(j, j)) / scale[j];
  }
  m.params.clear();
  int j = 0;
  for (Effect e : eff) {
    const EffectParameter& ep = effectInfo(e).params[0];
    FittedParameter fp;
    fp.key = ep.key;
    fp.unit = c.joint_side ? ep.unit_joint : ep.unit_motor;
    fp.value = values[j];
    fp.ci_low = values[j] - defaults::kConfidenceZ * sd[j];
    fp.ci_high = values[j] + defaults::kConfidenceZ * sd[j];
    fp.at_bound = (std::isfinite(ep.lower) && values[j] <= ep.lower) ||
                  (std::isfinite(ep.upper) && values[j] >= ep.upper);
    m.params.push_back(fp);
    ++j;
  }
  if (st) {
    const EffectParameter& ep = effectInfo(Effect::Stribeck).params[1];
    FittedParameter fp;
    fp.key = ep.key;
    fp.unit = c.joint_side ? ep.unit_joint : ep.unit_motor;
    fp.value = f.vS;
    fp.ci_low = f.vS - defaults::kConfidenceZ * sd[p - 1];
    fp.ci_high = f.vS + defaults::kConfidenceZ * sd[p - 1];
    fp.at_bound = f.vS <= c.v_lo * (1 + 1e-9) || f.vS >= c.v_hi * (1 - 1e-9);
    m.params.push_back(fp);
  }
}

struct Fitter {
  const Context& c;
  const FrictionParams& design_params;
  std::vector<int> folds, regions;
  int k = 5;

  ModelFit fit(const EffectSet& on, const std::string& label, bool& ok) const {
    ModelFit m;
    m.label = label;
    m.effects = toList(on);
    m.n_params = countParams(on);
    ok = c.n >= m.n_params + defaults::kMinResidualDof;
    if (!ok) return m;
    const RawFit f = fitRows(c, on, allRows(c.n));
    m.friction = toFrictionParams(c, design_params, on, f);
    for (int i = 0; i < c.n; ++i) {
      const double loss = predictLoss(c, on, f, i);
      m.predicted.push_back(currentFromLoss(c, i, loss));
      m.residual.push_back((c.y[i] - loss) / c.km);
    }
    m.train_rmse = rmsOf(m.residual);
    ok = heldOut(c, on, folds, k, m.heldout_residual);
    if (!ok) return m;
    m.heldout_rmse = rmsOf(m.heldout_residual);
    std::vector<double> reg;
    m.region_heldout_rmse = heldOut(c, on, regions, 4, reg) ? rmsOf(reg) : std::numeric_limits<double>::quiet_NaN();
    informationCriteria(m);
    confidenceIntervals(c, on, f, m);
    return m;
  }
};

// Regressor columns of one effect's increment for identifiability checks (all rows).
Eigen::VectorXd incrementColumn(const Context& c, Effect e, double vS) {
  EffectSet on{};
  on[idx(e)] = true;
  Eigen::VectorXd col(c.n);
  for (int i = 0; i < c.n; ++i) col[i] = column(c, on, e, i, vS);
  return col;
}

double r2OnBasis(const Eigen::VectorXd& col, const Eigen::MatrixXd& basis) {
  const double tot = col.squaredNorm();
  if (tot == 0) return 1.0;
  if (basis.cols() == 0) return 0.0;
  const Eigen::VectorXd coef = basis.colPivHouseholderQr().solve(col);
  return 1.0 - (col - basis * coef).squaredNorm() / tot;
}

ResidualMap residualMap(const DriveData& data, const std::vector<double>& residual, double sigma, double rho,
                        const DriveFitOptions& o) {
  ResidualMap map;
  map.rho = rho;
  const auto [smin, smax] = std::minmax_element(data.speed.begin(), data.speed.end());
  double lmin = kInf, lmax = 0;
  for (double l : data.load) {
    lmin = std::min(lmin, std::abs(l));
    lmax = std::max(lmax, std::abs(l));
  }
  auto edges = [](double a, double b, int nb) {
    std::vector<double> e(nb + 1);
    if (b <= a) b = a + 1e-12;
    for (int i = 0; i <= nb; ++i) e[i] = a + (b - a) * i / nb;
    return e;
  };
  map.speed_edges = edges(*smin, *smax, o.speed_bins);
  map.load_edges = edges(lmin, lmax, o.load_bins);
  auto binOf = [](const std::vector<double>& e, double x) {
    const int nb = static_cast<int>(e.size()) - 1;
    int b = static_cast<int>(std::upper_bound(e.begin(), e.end(), x) - e.begin()) - 1;
    return std::clamp(b, 0, nb - 1);
  };
  const int nb = o.speed_bins * o.load_bins;
  std::vector<std::vector<double>> members(nb);
  for (int i = 0; i < data.rows(); ++i)
    members[binOf(map.speed_edges, data.speed[i]) * o.load_bins + binOf(map.load_edges, std::abs(data.load[i]))]
        .push_back(residual[i]);
  int tested = 0;
  for (const auto& m : members) tested += static_cast<int>(m.size()) >= defaults::kMinBinSamples;
  map.z = normalQuantile(1.0 - defaults::kBinFalseAlarm / (2.0 * std::max(1, tested)));
  for (int b = 0; b < nb; ++b) {
    if (members[b].empty()) continue;
    ResidualBin bin;
    bin.speed_bin = b / o.load_bins;
    bin.load_bin = b % o.load_bins;
    bin.speed_lo = map.speed_edges[bin.speed_bin];
    bin.speed_hi = map.speed_edges[bin.speed_bin + 1];
    bin.load_lo = map.load_edges[bin.load_bin];
    bin.load_hi = map.load_edges[bin.load_bin + 1];
    bin.n = static_cast<int>(members[b].size());
    bin.n_eff = effectiveSampleSize(bin.n, rho);
    bin.mean = mean(members[b]);
    bin.threshold = map.z * sigma / std::sqrt(bin.n_eff);
    bin.flagged = bin.n >= defaults::kMinBinSamples && std::abs(bin.mean) > bin.threshold;
    map.bins.push_back(bin);
  }
  return map;
}

Comparison compareFit(const DriveData& data, const ModelFit& m, double km, double sigma, double rho,
                      const DriveFitOptions& o) {
  Comparison cmp;
  cmp.current = channelStats(m.residual);
  std::vector<double> torque(m.residual.size());
  for (std::size_t i = 0; i < torque.size(); ++i) torque[i] = m.residual[i] * km;
  cmp.friction_torque = channelStats(torque);
  cmp.map = residualMap(data, m.residual, sigma, rho, o);
  return cmp;
}

EffectSet setOf(const FrictionParams& p) { return p.on; }

}  // namespace

int ResidualMap::flagged() const {
  int n = 0;
  for (const auto& b : bins) n += b.flagged;
  return n;
}

std::string DriveFitOptions::validate() const {
  if (folds < 2) return "folds must be at least 2";
  if (speed_bins < 1 || load_bins < 1) return "bin counts must be positive";
  if (!(significance_z > 0)) return "significance z must be positive";
  if (!(min_relative_improvement >= 0 && min_relative_improvement < 1))
    return "minimum relative improvement must lie in [0, 1)";
  return "";
}

const std::vector<EffectInfo>& driveEffectCatalogue() {
  static const std::vector<EffectInfo> cat = {
      {Effect::Coulomb, "coulomb", "eq. (3.30) T_f0",
       "a step at zero speed: residual of constant magnitude, sign of the speed, independent of load",
       {{"coulomb", "N m", "N", 0, kInf, 0.08}}},
      {Effect::Viscous, "viscous", "eq. (3.30) b",
       "a straight line through the origin in speed, independent of load",
       {{"viscous", "N m s/rad", "N s/m", 0, kInf, 1.5e-4}}},
      {Effect::LoadCoulomb, "load_coulomb", "eq. (3.30) mu",
       "grows with |load|, sign of the speed, the same at every speed",
       {{"load_coulomb", "-", "-", 0, kInf, 4e-3}}},
      {Effect::LoadViscous, "load_viscous", "eq. (3.30) gamma",
       "fan of lines through the origin in speed whose slope grows with |load|",
       {{"load_viscous", "s/rad", "s/m", 0, kInf, 7e-6}}},
      {Effect::Stribeck, "stribeck", "eq. (3.33) T_fS, phi_S",
       "a bend at low speed: residual largest near standstill, fading above the Stribeck velocity",
       {{"stribeck_torque", "N m", "N", 0, kInf, 0.04}, {"stribeck_velocity", "rad/s", "m/s", 0, kInf, 60}}},
      {Effect::Asymmetry, "asymmetry", "direction-dependent friction (not in the thesis laws)",
       "an offset of the same sign in both directions: friction larger one way than the other",
       {{"asymmetry", "N m", "N", -kInf, kInf, 0.02}}},
      {Effect::Temperature, "temperature", "temperature dependence (thesis section 4.4.1, 4.6.2)",
       "residual drifts with temperature, sign of the speed",
       {{"temperature_coefficient", "N m/K", "N/K", -kInf, kInf, -2e-3}}},
      {Effect::TemperatureViscous, "temperature_viscous",
       "temperature dependence of the viscous term (lubricant viscosity; thesis section 4.4.1)",
       "a fan of lines through the origin in speed whose slope drifts with temperature",
       {{"temperature_viscous_coefficient", "N m s/(rad K)", "N s/(m K)", -kInf, kInf, -3e-6}}},
  };
  return cat;
}

const EffectInfo& effectInfo(Effect e) { return driveEffectCatalogue()[idx(e)]; }

const Drive& requireDrive(const Model& model, const std::string& joint) {
  std::string names;
  for (const Drive& d : model.drives) {
    if (d.joint == joint) return d;
    names += names.empty() ? "" : ", "; names += d.joint;
  }
  throw InputError(model.file, 0, "drive",
                   "design '" + model.name + "' has no [[drive]] for joint '" + joint + "'" +
                       (names.empty() ? " (it has no drives)" : " (drives: " + names + ")"));
}

DriveData readDriveData(const std::string& path) {
  const io::CsvTable t = io::readCsv(path, {{"speed", "load_torque", "current"}, {"temperature"}});
  DriveData d;
  d.file = path;
  d.hash = fileHash(path);
  d.speed = t.column("speed");
  d.load = t.column("load_torque");
  d.current = t.column("current");
  if (t.has("temperature")) d.temperature = t.column("temperature");
  d.lines = t.row_lines;
  for (const std::string& x : t.extra_columns)
    d.warnings.push_back(path + ": extra column '" + x + "' is not used");
  for (int i = 0; i < d.rows(); ++i)
    if (d.speed[i] == 0)
      throw InputError(path, d.lines[i], "speed",
                       "standstill row (speed 0): the friction laws do not predict static friction; "
                       "remove the row");
  return d;
}

DriveDiagnosis compareDrive(const Model& model, const std::string& joint, const DriveData& data,
                            const DriveFitOptions& o) {
  const std::string err = o.validate();
  if (!err.empty()) throw InputError("", 0, "options", err);
  const Drive& d = requireDrive(model, joint);
  const FrictionParams fp = drive::frictionParams(model, d);
  DriveDiagnosis r;
  r.design = model.name;
  r.joint = joint;
  r.warnings = data.warnings;
  const Context c = makeContext(d, fp, data);
  if (c.n < 2 * o.folds)
    throw InputError(data.file, 0, "folds",
                     std::to_string(o.folds) + "-fold cross-validation needs at least " + std::to_string(2 * o.folds) +
                         " data rows (two per fold), the data has " + std::to_string(c.n) + "; use fewer folds");
  if ((fp.has(Effect::Temperature) || fp.has(Effect::TemperatureViscous)) && !c.has_temperature)
    r.warnings.push_back("the design has a temperature term but the data has no temperature column; "
                         "evaluated at the reference temperature");

  // The design as is (nothing fitted).
  ModelFit& a = r.as_designed;
  a.label = "as designed (" + std::string(drive::toString(fp.law)) +
            (drive::extraEffects(model, joint).empty() ? "" : " + effects") + ")";
  a.effects = toList(fp.on);
  a.friction = fp;
  for (int i = 0; i < c.n; ++i) {
    const double I = drive::testBedCurrent(d, fp, data.speed[i], data.load[i], c.theta[i]);
    a.predicted.push_back(I);
    a.residual.push_back(data.current[i] - I);
  }
  a.heldout_residual = a.residual;
  a.train_rmse = a.heldout_rmse = a.region_heldout_rmse = rmsOf(a.residual);
  informationCriteria(a);

  // Noise estimate: the most flexible identifiable model (design effects plus every applicable
  // candidate) fitted to all rows; its residual standard deviation and lag-1 autocorrelation.
  EffectSet sat{};
  for (Effect e : drive::kAllEffects) {
    if (drive::isTemperatureEffect(e)) {
      if (!c.has_temperature) continue;
      const auto [tmin, tmax] = std::minmax_element(c.theta.begin(), c.theta.end());
      if (*tmax - *tmin <= 0) continue;
    }
    sat[idx(e)] = true;
  }
  const int p = countParams(sat);
  if (c.n >= p + defaults::kMinResidualDof) {
    const RawFit f = fitRows(c, sat, allRows(c.n));
    std::vector<double> res(c.n);
    for (int i = 0; i < c.n; ++i) res[i] = (c.y[i] - predictLoss(c, sat, f, i)) / c.km;
    double ss = 0;
    for (double v : res) ss += v * v;
    r.noise_estimate = std::sqrt(ss / (c.n - p));
    r.noise_rho = lag1Autocorrelation(res);
  } else {
    r.noise_estimate = a.train_rmse;
    r.warnings.push_back("too few rows for the noise estimate; the RMSE of the design is used instead");
  }
  r.as_designed_cmp = compareFit(data, a, c.km, r.noise_estimate, r.noise_rho, o);
  r.ladder.push_back(a);
  r.final_fit = a;
  r.final_cmp = r.as_designed_cmp;
  r.rmse_before = r.rmse_after = a.heldout_rmse;
  r.calibrated = model;
  return r;
}

namespace {

std::vector<Candidate> rankCandidates(const Context& c, const Fitter& fitter, const EffectSet& base_on,
                                      const ModelFit& base, double noise_rho, const DriveFitOptions& o) {
  std::vector<Candidate> out;
  const std::vector<int> rows = allRows(c.n);
  const double vS_mid = std::sqrt(c.v_lo * c.v_hi);
  // Base columns for identifiability (the increments of the present effects).
  std::vector<Effect> base_eff = toList(base_on);
  Eigen::MatrixXd basis(c.n, base_eff.size());
  for (std::size_t j = 0; j < base_eff.size(); ++j)
    basis.col(j) = incrementColumn(c, base_eff[j], base.friction.stribeck_velocity);
  std::map<int, Eigen::VectorXd> resid_cols;  // candidate columns with the base part removed
  for (Effect e : drive::kAllEffects) {
    if (base_on[idx(e)]) continue;
    Candidate cand;
    cand.effect = e;
    if (drive::isTemperatureEffect(e)) {
      if (!c.has_temperature) {
        cand.status = "not_applicable";
        cand.warnings.push_back("the data has no temperature column");
        out.push_back(cand);
        continue;
      }
      const auto [tmin, tmax] = std::minmax_element(c.theta.begin(), c.theta.end());
      const double span = *tmax - *tmin;
      if (span <= 0) {
        cand.status = "unidentifiable";
        cand.warnings.push_back("temperature is constant in the data: the temperature effect cannot be identified");
        out.push_back(cand);
        continue;
      }
      if (span < defaults::kMinTemperatureSpan_K)
        cand.warnings.push_back("temperature varies by only " + std::to_string(span) +
                                " K in the data: the temperature effect is weakly identifiable");
    }
    const Eigen::VectorXd col = incrementColumn(c, e, vS_mid);
    const double r2 = r2OnBasis(col, basis);
    if (r2 > defaults::kCollinearR2) {
      // Name the most similar present term.
      std::string like;
      double best = -1;
      for (std::size_t j = 0; j < base_eff.size(); ++j) {
        const double nb = basis.col(j).norm() * col.norm();
        const double cs = nb > 0 ? std::abs(basis.col(j).dot(col)) / nb : 0;
        if (cs > best) {
          best = cs;
          like = drive::toString(base_eff[j]);
        }
      }
      cand.warnings.push_back(std::string("cannot be told apart from the present term(s) (R^2 = ") +
                              std::to_string(r2) + (like.empty() ? "" : ", most like '" + like + "'") +
                              ") with this data");
      if (r2 > defaults::kUnidentifiableR2) {
        cand.status = "unidentifiable";
        out.push_back(cand);
        continue;
      }
    }
    if (basis.cols() > 0) {
      const Eigen::VectorXd coef = basis.colPivHouseholderQr().solve(col);
      resid_cols[idx(e)] = col - basis * coef;
    } else {
      resid_cols[idx(e)] = col;
    }
    EffectSet on = base_on;
    on[idx(e)] = true;
    bool ok = false;
    cand.fit = fitter.fit(on, "+" + std::string(drive::toString(e)), ok);
    if (!ok) {
      cand.status = "too_few_rows";
      cand.warnings.push_back("too few rows to fit " + std::to_string(cand.fit.n_params) + " parameters");
      out.push_back(cand);
      continue;
    }
    cand.improvement = (base.heldout_rmse - cand.fit.heldout_rmse) / base.heldout_rmse;
    std::vector<double> dd(c.n);
    for (int i = 0; i < c.n; ++i)
      dd[i] = base.heldout_residual[i] * base.heldout_residual[i] -
              cand.fit.heldout_residual[i] * cand.fit.heldout_residual[i];
    const double md = mean(dd);
    double var = 0;
    for (double v : dd) var += (v - md) * (v - md);
    var /= std::max(1, c.n - 1);
    // Correlated samples: n_eff from the lag-1 autocorrelation of the noise (the residuals of the
    // most flexible model), not of dd itself, whose correlation is the systematic error under test.
    const double neff = effectiveSampleSize(c.n, noise_rho);
    cand.t_statistic = var > 0 ? md / std::sqrt(var / neff) : (md > 0 ? kInf : 0.0);
    cand.significant = cand.t_statistic > o.significance_z && cand.improvement >= o.min_relative_improvement;
    out.push_back(cand);
  }
  // Candidates that cannot be told apart from each other with this data.
  for (auto& a : out)
    for (const auto& b : out) {
      if (a.effect == b.effect || !resid_cols.count(idx(a.effect)) || !resid_cols.count(idx(b.effect))) continue;
      const Eigen::VectorXd& x = resid_cols[idx(a.effect)];
      const Eigen::VectorXd& y = resid_cols[idx(b.effect)];
      const double nn = x.norm() * y.norm();
      if (nn > 0 && std::pow(x.dot(y) / nn, 2) > defaults::kCollinearR2)
        a.warnings.push_back(std::string("cannot be told apart from the candidate '") +
                             drive::toString(b.effect) + "' with this data");
    }
  std::stable_sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) {
    const bool ao = a.status == "ok", bo = b.status == "ok";
    if (ao != bo) return ao;
    if (!ao) return false;
    return a.fit.heldout_rmse < b.fit.heldout_rmse;
  });
  return out;
}

}  // namespace

DriveDiagnosis diagnoseDrive(const Model& model, const std::string& joint, const DriveData& data,
                             const DriveFitOptions& o) {
  DriveDiagnosis r = compareDrive(model, joint, data, o);
  const Drive& d = requireDrive(model, joint);
  const FrictionParams fp = drive::frictionParams(model, d);
  const Context c = makeContext(d, fp, data);
  EffectSet on = setOf(fp);
  const int p = countParams(on);
  const int need = (p + defaults::kMinResidualDof) * o.folds / (o.folds - 1) + 1;
  if (c.n < need)
    throw InputError(data.file, 0, "",
                     std::to_string(c.n) + " rows are too few to fit and cross-validate the " +
                         std::to_string(p) + " parameters of the design's friction model (need at least " +
                         std::to_string(need) + ")");
  Fitter fitter{c, fp, foldAssignment(c.n, o.folds, o.seed), regionsOf(c), o.folds};
  bool ok = false;
  r.base = fitter.fit(on, "refit " + effectList(on), ok);
  ARMSTUDY_CHECK(ok, "row count was checked above");
  r.base_cmp = compareFit(data, r.base, c.km, r.noise_estimate, r.noise_rho, o);
  r.ladder.push_back(r.base);
  r.ranking = rankCandidates(c, fitter, on, r.base, r.noise_rho, o);
  r.missing_effect_found = !r.ranking.empty() && r.ranking.front().significant;
  ModelFit current = r.base;
  std::vector<Candidate> ranking = r.ranking;
  auto addEffect = [&](Effect e) {
    if (on[idx(e)]) {
      r.warnings.push_back(std::string("effect '") + drive::toString(e) + "' is already in the model");
      return;
    }
    for (const Candidate& cnd : ranking)
      if (cnd.effect == e && cnd.status != "ok")
        r.warnings.push_back(std::string("adding '") + drive::toString(e) + "' although it is " + cnd.status);
    EffectSet next = on;
    next[idx(e)] = true;
    bool fit_ok = false;
    ModelFit m = fitter.fit(next, "+" + std::string(drive::toString(e)), fit_ok);
    if (!fit_ok) {
      r.warnings.push_back(std::string("cannot add '") + drive::toString(e) + "': too few rows");
      return;
    }
    on = next;
    current = m;
    r.added.push_back(e);
    r.ladder.push_back(m);
    ranking = rankCandidates(c, fitter, on, current, r.noise_rho, o);
    r.rankings_after.push_back(ranking);
  };
  for (Effect e : o.add) addEffect(e);
  std::vector<Effect> named;
  if (r.missing_effect_found) named.push_back(r.ranking.front().effect);
  if (o.auto_add)
    while (!ranking.empty() && ranking.front().significant) {
      const std::size_t before = r.added.size();
      const Effect e = ranking.front().effect;
      addEffect(e);
      if (r.added.size() == before) break;
      if (std::find(named.begin(), named.end(), e) == named.end()) named.push_back(e);
    }
  if (!named.empty()) {
    r.verdict = named.size() > 1 ? "missing effects: " : "missing effect: ";
    for (std::size_t k = 0; k < named.size(); ++k) r.verdict += (k ? ", " : "") + std::string(drive::toString(named[k]));
  }
  r.final_fit = current;
  r.final_cmp = compareFit(data, current, c.km, r.noise_estimate, r.noise_rho, o);
  r.rmse_before = r.base.heldout_rmse;
  r.rmse_after = current.heldout_rmse;

  // The calibrated design: the final fitted parameters in the drive, added effects listed.
  Model cal = model;
  Drive* cd = nullptr;
  for (Drive& x : cal.drives)
    if (x.joint == joint) cd = &x;
  ARMSTUDY_CHECK(cd != nullptr, "drive exists");
  const FrictionParams& f = current.friction;
  std::map<std::string, double> fr;
  if (f.has(Effect::Coulomb)) fr["coulomb"] = f.coulomb;
  if (f.has(Effect::Viscous)) fr["viscous"] = f.viscous;
  if (f.has(Effect::LoadCoulomb)) fr["load_coulomb"] = f.load_coulomb;
  if (f.has(Effect::LoadViscous)) fr["load_viscous"] = f.load_viscous;
  if (f.has(Effect::Stribeck)) {
    fr["stribeck_torque"] = f.stribeck_torque;
    fr["stribeck_velocity"] = f.stribeck_velocity;
  }
  if (f.has(Effect::Asymmetry)) fr["asymmetry"] = f.asymmetry;
  if (f.has(Effect::Temperature)) {
    fr["temperature_coefficient"] = f.temperature_coefficient;
    fr["reference_temperature"] = f.reference_temperature_C;
  }
  if (f.has(Effect::TemperatureViscous)) {
    fr["temperature_viscous_coefficient"] = f.temperature_viscous_coefficient;
    fr["reference_temperature"] = f.reference_temperature_C;
  }
  cd->friction = fr;
  if (cd->friction_law.empty()) cd->friction_law = "none";
  for (Effect e : r.added) cal.effects.push_back(joint + "." + drive::toString(e));
  r.calibrated = cal;
  return r;
}

// ---------------- virtual test bed ----------------

namespace {

void setParam(FrictionParams& p, const std::string& key, double v) {
  if (key == "coulomb") p.coulomb = v;
  else if (key == "viscous") p.viscous = v;
  else if (key == "load_coulomb") p.load_coulomb = v;
  else if (key == "load_viscous") p.load_viscous = v;
  else if (key == "stribeck_torque") p.stribeck_torque = v;
  else if (key == "stribeck_velocity") p.stribeck_velocity = v;
  else if (key == "asymmetry") p.asymmetry = v;
  else if (key == "temperature_coefficient") p.temperature_coefficient = v;
  else if (key == "temperature_viscous_coefficient") p.temperature_viscous_coefficient = v;
  else if (key == "reference_temperature") p.reference_temperature_C = v;
  else throw InputError("", 0, key, "unknown friction parameter '" + key + "'");
}

}  // namespace

DriveData synthesizeDrive(const Model& model, const std::string& joint, const SynthOptions& o) {
  const Drive& d = requireDrive(model, joint);
  FrictionParams truth = drive::frictionParams(model, d);
  for (const auto& [e, overrides] : o.hidden) {
    const EffectInfo& info = effectInfo(e);
    if (!truth.has(e))
      for (const auto& ep : info.params) setParam(truth, ep.key, ep.typical);
    truth.on[idx(e)] = true;
    for (const auto& [k, v] : overrides) {
      bool belongs = k == "reference_temperature" && drive::isTemperatureEffect(e);
      for (const auto& ep : info.params) belongs = belongs || ep.key == k;
      if (!belongs)
        throw InputError("", 0, k, "parameter '" + k + "' does not belong to the effect '" + info.name + "'");
      setParam(truth, k, v);
    }
  }
  if (truth.has(Effect::Stribeck) && !(truth.stribeck_velocity > 0))
    throw InputError("", 0, "stribeck_velocity", "Stribeck velocity must be positive");
  std::vector<double> speeds = o.speeds_radps;
  if (speeds.empty())
    for (double rpm : {100, 250, 500, 1000, 1500, 2000, 2500, 3000, 3500}) speeds.push_back(rpm * M_PI / 30.0);
  std::vector<double> loads = o.loads;
  if (loads.empty()) loads = {1.3, 4.0, 6.5, 9.0, 11.7, 14.5, 17.0};
  std::vector<double> levels;
  for (double s : speeds) {
    if (!(s > 0)) throw InputError("", 0, "speeds", "speed levels must be positive (both directions are run)");
    levels.push_back(s);
    levels.push_back(-s);
  }
  for (double l : loads)
    if (!(l >= 0)) throw InputError("", 0, "loads", "load levels must not be negative");
  if (o.series < 1) throw InputError("", 0, "series", "at least one test series");
  if (!(o.noise_A >= 0) || !(o.noise_rho >= 0 && o.noise_rho < 1))
    throw InputError("", 0, "noise", "noise must be >= 0 and its correlation in [0, 1)");
  rng::SplitMix64 rng{o.seed};
  DriveData out;
  out.file = "synthetic";
  const int total = o.series * static_cast<int>(levels.size() * loads.size());
  double e_prev = 0;
  int row = 0;
  for (int s = 0; s < o.series; ++s) {
    std::vector<double> order = levels;
    for (int i = static_cast<int>(order.size()) - 1; i > 0; --i)
      std::swap(order[i], order[rng.next() % static_cast<std::uint64_t>(i + 1)]);
    for (double v : order)
      for (double l : loads) {
        // Warm-up: the housing temperature approaches its end value over the run.
        const double t = total > 1 ? double(row) / (total - 1) : 0.0;
        const double theta = o.temperature_end_C - (o.temperature_end_C - o.temperature_start_C) * std::exp(-3.0 * t);
        const double load = v > 0 ? l : -l;  // the load opposes the motion
        const double e = o.noise_rho * e_prev + std::sqrt(1 - o.noise_rho * o.noise_rho) * o.noise_A * rng.normal();
        e_prev = e;
        out.speed.push_back(v);
        out.load.push_back(load);
        out.current.push_back(drive::testBedCurrent(d, truth, v, load, theta) + e);
        if (o.write_temperature) out.temperature.push_back(theta);
        out.lines.push_back(row + 2);
        ++row;
      }
  }
  return out;
}

std::string driveDataToCsv(const DriveData& d) {
  std::vector<std::string> h = {"speed", "load_torque", "current"};
  std::vector<std::vector<double>> cols = {d.speed, d.load, d.current};
  if (d.hasTemperature()) {
    h.push_back("temperature");
    cols.push_back(d.temperature);
  }
  return io::formatCsv(h, cols);
}

}  // namespace armstudy::calibration
