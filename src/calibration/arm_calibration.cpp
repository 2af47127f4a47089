#include "calibration/arm_calibration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

#include "calibration/least_squares.hpp"
#include "common/errors.hpp"

namespace armstudy::calibration {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kProfileRelativeStep = 1e-4;  // central-difference step of a profiled parameter, relative

// Flattened weighted residual vector (row-major: row * C + channel).
Eigen::VectorXd flatten(const ArmProblem& P, const Eigen::MatrixXd& m) {
  Eigen::VectorXd v(m.size());
  for (int i = 0; i < P.rows(); ++i)
    for (int c = 0; c < P.channels(); ++c) v[i * P.channels() + c] = m(i, c) * P.weight[c];
  return v;
}

Eigen::MatrixXd unflatten(const ArmProblem& P, const Eigen::VectorXd& v) {
  Eigen::MatrixXd m(P.rows(), P.channels());
  for (int i = 0; i < P.rows(); ++i)
    for (int c = 0; c < P.channels(); ++c) m(i, c) = v[i * P.channels() + c] / P.weight[c];
  return m;
}

int countParams(const ArmProblem& P, const EffectValues& v) {
  int p = 0;
  for (const auto& e : v) p += static_cast<int>(P.catalogue[e.effect].params.size());
  return p;
}

Eigen::VectorXd packX(const EffectValues& v) {
  int n = 0;
  for (const auto& e : v) n += static_cast<int>(e.x.size());
  Eigen::VectorXd x(n);
  int k = 0;
  for (const auto& e : v) {
    x.segment(k, e.x.size()) = e.x;
    k += static_cast<int>(e.x.size());
  }
  return x;
}

void unpackX(EffectValues& v, const Eigen::VectorXd& x) {
  int k = 0;
  for (auto& e : v) {
    e.x = x.segment(k, e.x.size());
    k += static_cast<int>(e.x.size());
  }
}

const ArmParam& paramAt(const ArmProblem& P, const EffectValues& v, int j) {
  for (const auto& e : v) {
    const auto& ps = P.catalogue[e.effect].params;
    if (j < static_cast<int>(ps.size())) return ps[j];
    j -= static_cast<int>(ps.size());
  }
  ARMSTUDY_CHECK(false, "parameter index in range");
  return P.catalogue[0].params[0];
}

// d prediction / d parameters (flattened, weighted) by central differences; columns of the
// parameters from index `first` on.
Eigen::MatrixXd jacobian(const ArmProblem& P, const EffectValues& v, int first = 0) {
  const Eigen::VectorXd x = packX(v);
  Eigen::MatrixXd J(P.rows() * P.channels(), x.size() - first);
  for (int j = first; j < x.size(); ++j) {
    const double h = paramAt(P, v, j).step;
    EffectValues vp = v, vm = v;
    Eigen::VectorXd xp = x, xm = x;
    xp[j] += h;
    xm[j] -= h;
    unpackX(vp, xp);
    unpackX(vm, xm);
    J.col(j - first) = (flatten(P, P.predict(vp)) - flatten(P, P.predict(vm))) / (2 * h);
  }
  return J;
}

struct Solved {
  EffectValues v;
  Eigen::MatrixXd pred;  // native
  Eigen::VectorXd r;     // flattened weighted residual
  Eigen::MatrixXd J;     // at the solution
  double ssr = 0;
};

void bounds(const ArmProblem& P, const EffectValues& v, Eigen::VectorXd& lo, Eigen::VectorXd& hi) {
  const Eigen::VectorXd x = packX(v);
  lo.resize(x.size());
  hi.resize(x.size());
  for (int j = 0; j < x.size(); ++j) {
    lo[j] = paramAt(P, v, j).lower - x[j];
    hi[j] = paramAt(P, v, j).upper - x[j];
  }
}

// Bounded solve that leaves parameters with all-zero columns untouched.
Eigen::VectorXd solveStep(const Eigen::MatrixXd& J, const Eigen::VectorXd& r, const Eigen::VectorXd& lo,
                          const Eigen::VectorXd& hi) {
  std::vector<int> live;
  for (int j = 0; j < J.cols(); ++j)
    if (J.col(j).norm() > 0) live.push_back(j);
  Eigen::VectorXd d = Eigen::VectorXd::Zero(J.cols());
  if (live.empty()) return d;
  Eigen::MatrixXd A(J.rows(), live.size());
  Eigen::VectorXd l(live.size()), h(live.size());
  for (std::size_t k = 0; k < live.size(); ++k) {
    A.col(k) = J.col(live[k]);
    l[k] = std::min(0.0, lo[live[k]]);
    h[k] = std::max(0.0, hi[live[k]]);
  }
  const LeastSquaresResult ls = boundedLeastSquares(A, r, l, h);
  for (std::size_t k = 0; k < live.size(); ++k) d[live[k]] = ls.x[k];
  return d;
}

// Gauss-Newton from the given start values (all parameters of v are free).
Solved gaussNewton(const ArmProblem& P, EffectValues v) {
  const Eigen::VectorXd y = flatten(P, P.measured);
  Solved s;
  s.v = v;
  s.pred = P.predict(v);
  s.r = y - flatten(P, s.pred);
  s.ssr = s.r.squaredNorm();
  if (packX(v).size() == 0) return s;
  s.J = jacobian(P, v);
  for (int it = 0; it < defaults::kGaussNewtonIterations; ++it) {
    Eigen::VectorXd lo, hi;
    bounds(P, s.v, lo, hi);
    const Eigen::VectorXd d = solveStep(s.J, s.r, lo, hi);
    const double predicted_ssr = (s.r - s.J * d).squaredNorm();
    EffectValues nv = s.v;
    unpackX(nv, packX(s.v) + d);
    const Eigen::MatrixXd pred = P.predict(nv);
    const Eigen::VectorXd r = y - flatten(P, pred);
    const double ssr = r.squaredNorm();
    if (ssr > s.ssr) break;  // no progress: keep the current point
    const bool linear = std::abs(ssr - predicted_ssr) <= 1e-6 * ssr + 1e-300;
    s.v = nv;
    s.pred = pred;
    s.r = r;
    const double gain = s.ssr - ssr;
    s.ssr = ssr;
    if (linear) break;  // the model is linear over the step: J still holds
    s.J = jacobian(P, s.v);
    if (gain <= 1e-12 * ssr) break;
  }
  return s;
}

// Fit of a set: the effects in `start` (a profiled effect whose value is NaN is profiled on its grid).
Solved fitSet(const ArmProblem& P, const EffectValues& start) {
  int prof = -1;
  for (std::size_t k = 0; k < start.size(); ++k)
    if (std::isnan(start[k].profile)) prof = static_cast<int>(k);
  if (prof < 0) return gaussNewton(P, start);
  const std::vector<double>& grid = P.catalogue[start[prof].effect].profile_grid;
  auto at = [&](double g) {
    EffectValues v = start;
    v[prof].profile = g;
    return gaussNewton(P, v);
  };
  Solved best;
  best.ssr = kInf;
  std::size_t bi = 0;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    Solved s = at(grid[k]);
    if (s.ssr < best.ssr) {
      best = std::move(s);
      bi = k;
    }
  }
  // Golden-section refinement in log space between the neighbours of the best grid point.
  double lo = std::log(grid[bi > 0 ? bi - 1 : 0]), hi = std::log(grid[std::min(grid.size() - 1, bi + 1)]);
  if (hi <= lo) return best;
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo);
  Solved f1 = at(std::exp(x1)), f2 = at(std::exp(x2));
  for (int it = 0; it < defaults::kArmProfileRefineIterations; ++it) {
    if (f1.ssr < f2.ssr) {
      hi = x2;
      x2 = x1;
      f2 = std::move(f1);
      x1 = hi - phi * (hi - lo);
      f1 = at(std::exp(x1));
    } else {
      lo = x1;
      x1 = x2;
      f1 = std::move(f2);
      x2 = lo + phi * (hi - lo);
      f2 = at(std::exp(x2));
    }
  }
  if (f1.ssr < best.ssr) best = std::move(f1);
  if (f2.ssr < best.ssr) best = std::move(f2);
  return best;
}

double rms(const Eigen::VectorXd& r) { return r.size() ? std::sqrt(r.squaredNorm() / r.size()) : kNaN; }

// Linearised held-out residuals for a partition of the rows. Returns false when a training set is
// too small.
bool heldOut(const ArmProblem& P, const Solved& s, const std::vector<int>& part, int parts, Eigen::VectorXd& out) {
  const int C = P.channels(), p = static_cast<int>(packX(s.v).size());
  out = s.r;
  if (p == 0) return true;
  Eigen::VectorXd lo, hi;
  bounds(P, s.v, lo, hi);
  for (int k = 0; k < parts; ++k) {
    std::vector<int> train, test;
    for (int i = 0; i < P.rows(); ++i) (part[i] == k ? test : train).push_back(i);
    if (test.empty()) continue;
    if (static_cast<int>(train.size()) * C < p + defaults::kMinResidualDof) return false;
    Eigen::MatrixXd Jt(train.size() * C, p);
    Eigen::VectorXd rt(train.size() * C);
    for (std::size_t a = 0; a < train.size(); ++a)
      for (int c = 0; c < C; ++c) {
        Jt.row(a * C + c) = s.J.row(train[a] * C + c);
        rt[a * C + c] = s.r[train[a] * C + c];
      }
    const Eigen::VectorXd d = solveStep(Jt, rt, lo, hi);
    for (int i : test)
      for (int c = 0; c < C; ++c) out[i * C + c] = s.r[i * C + c] - s.J.row(i * C + c).dot(d);
  }
  return true;
}

std::vector<ChannelStats> channelStatsOf(const ArmProblem& P, const Eigen::MatrixXd& m) {
  std::vector<ChannelStats> out;
  for (int c = 0; c < P.channels(); ++c) {
    std::vector<double> col(m.rows());
    for (int i = 0; i < m.rows(); ++i) col[i] = m(i, c);
    out.push_back(channelStats(col));
  }
  return out;
}

// d prediction / d profiled parameter (flattened, weighted) of every effect with one, by central
// differences with a relative step: the profiled parameters' columns of the linearised covariance.
Eigen::MatrixXd profileJacobian(const ArmProblem& P, const EffectValues& v) {
  std::vector<int> which;
  for (std::size_t k = 0; k < v.size(); ++k)
    if (P.catalogue[v[k].effect].hasProfile()) which.push_back(static_cast<int>(k));
  Eigen::MatrixXd J(P.rows() * P.channels(), which.size());
  for (std::size_t c = 0; c < which.size(); ++c) {
    const double h = kProfileRelativeStep * std::abs(v[which[c]].profile);
    EffectValues vp = v, vm = v;
    vp[which[c]].profile += h;
    vm[which[c]].profile -= h;
    J.col(c) = (flatten(P, P.predict(vp)) - flatten(P, P.predict(vm))) / (2 * h);
  }
  return J;
}

// Linearised 95 % intervals: sigma^2 (J^T J)^-1 over the fitted and the profiled parameters,
// inflated by (1 + rho) / (1 - rho) for AR(1)-correlated residuals.
void confidence(const ArmProblem& P, const Solved& s, ArmFit& f) {
  const int p = static_cast<int>(packX(s.v).size());
  const Eigen::VectorXd x = packX(s.v);
  const Eigen::MatrixXd Jp = profileJacobian(P, s.v);
  const int q = p + static_cast<int>(Jp.cols());
  Eigen::MatrixXd J(s.r.size(), q);
  if (p > 0) J.leftCols(p) = s.J;
  J.rightCols(Jp.cols()) = Jp;
  const int dof = static_cast<int>(s.r.size()) - q;
  const double rho = std::clamp(lag1Autocorrelation(std::vector<double>(s.r.data(), s.r.data() + s.r.size())), 0.0, 0.95);
  const double s2 = dof > 0 ? s.ssr / dof * (1 + rho) / (1 - rho) : kInf;
  Eigen::VectorXd sd = Eigen::VectorXd::Constant(q, kInf);
  if (q > 0) {
    Eigen::VectorXd scale(q);
    for (int j = 0; j < q; ++j) scale[j] = J.col(j).norm() > 0 ? J.col(j).norm() : 1.0;
    const Eigen::MatrixXd Js = J * scale.cwiseInverse().asDiagonal();
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(Js, Eigen::ComputeThinV);
    const Eigen::VectorXd sv = svd.singularValues();
    if (sv.size() == q && sv[q - 1] > 1e-10 * sv[0]) {
      const Eigen::MatrixXd V = svd.matrixV();
      const Eigen::MatrixXd cov = V * sv.cwiseInverse().cwiseAbs2().asDiagonal() * V.transpose();
      for (int j = 0; j < q; ++j) sd[j] = std::sqrt(s2 * cov(j, j)) / scale[j];
    }
  }
  f.params.clear();
  int j = 0, k = p;
  for (const auto& e : s.v) {
    const ArmEffect& info = P.catalogue[e.effect];
    for (const auto& ap : info.params) {
      FittedParameter fp;
      fp.key = info.name + "." + ap.key;
      fp.unit = ap.unit;
      fp.value = ap.design + x[j];
      fp.ci_low = fp.value - defaults::kConfidenceZ * sd[j];
      fp.ci_high = fp.value + defaults::kConfidenceZ * sd[j];
      fp.at_bound = x[j] <= ap.lower || x[j] >= ap.upper;
      f.params.push_back(fp);
      ++j;
    }
    if (info.hasProfile()) {
      FittedParameter fp;
      fp.key = info.name + "." + info.profile.key;
      fp.unit = info.profile.unit;
      fp.value = e.profile;
      fp.ci_low = e.profile - defaults::kConfidenceZ * sd[k];
      fp.ci_high = e.profile + defaults::kConfidenceZ * sd[k];
      fp.at_bound = e.profile <= info.profile_grid.front() || e.profile >= info.profile_grid.back();
      f.params.push_back(fp);
      ++k;
    }
  }
}

// RMS of a native residual matrix in fit units (the problem's own channel weights).
double rmsFitUnits(const Eigen::MatrixXd& m, const Eigen::VectorXd& w) {
  if (m.size() == 0) return kNaN;
  return std::sqrt((m * w.asDiagonal()).squaredNorm() / static_cast<double>(m.size()));
}

// The problem with every channel weighted by 1 / its noise estimate (issue 13): fits, ranking and
// significance then see dimensionless residuals, so channels of different units (N, N m, A, m)
// count by their own noise, not by their unit. Forwards the prediction to the problem.
class NoiseWeighted : public ArmProblem {
 public:
  NoiseWeighted(const ArmProblem& p, const Eigen::VectorXd& w) : ArmProblem(p), inner_(p) { weight = w; }
  Eigen::MatrixXd predict(const EffectValues& values) const override { return inner_.predict(values); }

 private:
  const ArmProblem& inner_;
};

struct Engine {
  const ArmProblem& P;  // the noise-weighted problem
  std::vector<int> folds;
  int k = 5;
  Eigen::VectorXd report_weight;  // the problem's own channel weights (fit units)

  ArmFit make(const Solved& s, const std::string& label, bool& ok) const {
    ArmFit f;
    f.label = label;
    f.values = s.v;
    for (const auto& e : s.v) f.effects.push_back(P.catalogue[e.effect].name);
    f.n_params = countParams(P, s.v);
    for (const auto& e : s.v) f.n_params += P.catalogue[e.effect].hasProfile();
    f.predicted = s.pred;
    f.residual = unflatten(P, s.r);
    f.train_score = rms(s.r);
    f.train_rmse = rmsFitUnits(f.residual, report_weight);
    f.channel_train = channelStatsOf(P, f.residual);
    Eigen::VectorXd ho, hr;
    ok = heldOut(P, s, folds, k, ho);
    if (!ok) return f;
    f.heldout_residual = unflatten(P, ho);
    f.heldout_score = rms(ho);
    f.heldout_rmse = rmsFitUnits(f.heldout_residual, report_weight);
    f.channel_heldout = channelStatsOf(P, f.heldout_residual);
    f.region_heldout_score = kNaN;
    f.region_heldout_rmse = kNaN;
    if (P.region_count > 1 && heldOut(P, s, P.regions, P.region_count, hr)) {
      f.region_heldout_score = rms(hr);
      f.region_heldout_rmse = rmsFitUnits(unflatten(P, hr), report_weight);
    }
    const double n = static_cast<double>(s.r.size());
    const double ll = n * std::log(std::max(s.ssr, 1e-300) / n);
    f.aic = ll + 2.0 * f.n_params;
    f.bic = ll + f.n_params * std::log(n);
    confidence(P, s, f);
    return f;
  }
};

double r2OnBasis(const Eigen::VectorXd& col, const Eigen::MatrixXd& basis) {
  const double tot = col.squaredNorm();
  if (tot == 0) return 1.0;
  if (basis.cols() == 0) return 0.0;
  const Eigen::VectorXd coef = basis.colPivHouseholderQr().solve(col);
  return 1.0 - (col - basis * coef).squaredNorm() / tot;
}

std::string fmt(double v) {
  char b[48];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

// Candidate columns at the current values (a profiled effect at the middle of its grid).
EffectValue zeroValue(const ArmProblem& P, int e, bool profile_nan) {
  EffectValue v;
  v.effect = e;
  v.x = Eigen::VectorXd::Zero(P.catalogue[e].params.size());
  const auto& g = P.catalogue[e].profile_grid;
  v.profile = g.empty() ? 0.0 : (profile_nan ? kNaN : g[g.size() / 2]);
  return v;
}

Eigen::MatrixXd candidateColumns(const ArmProblem& P, const EffectValues& current, int e) {
  EffectValues v = current;
  v.push_back(zeroValue(P, e, false));
  return jacobian(P, v, static_cast<int>(packX(current).size()));
}

ArmResidualMap residualMap(const ArmProblem& P, const Eigen::MatrixXd& res, const std::vector<double>& sigma,
                           double rho, const ArmFitOptions& o) {
  ArmResidualMap map;
  map.rho = rho;
  const int C = P.channels();
  struct Proto {
    ArmBin bin;
    std::vector<int> rows;
  };
  std::vector<Proto> protos;
  auto edgesOf = [](double a, double b, int nb) {
    if (b <= a) b = a + 1e-12;
    std::vector<double> e(nb + 1);
    for (int i = 0; i <= nb; ++i) e[i] = a + (b - a) * i / nb;
    return e;
  };
  auto binOf = [](const std::vector<double>& e, double x) {
    const int nb = static_cast<int>(e.size()) - 1;
    return std::clamp(static_cast<int>(std::upper_bound(e.begin(), e.end(), x) - e.begin()) - 1, 0, nb - 1);
  };
  for (const BinVariable& var : P.variables) {
    if (!P.bin_variables) break;
    const auto [mn, mx] = std::minmax_element(var.values.begin(), var.values.end());
    if (*mx - *mn <= 0) continue;  // constant variable: nothing to bin
    const auto e = edgesOf(*mn, *mx, o.variable_bins);
    std::vector<Proto> local(o.variable_bins);
    for (int b = 0; b < o.variable_bins; ++b) {
      local[b].bin.space = "joint";
      local[b].bin.variable = var.name;
      local[b].bin.index = {b, 0, 0};
      local[b].bin.lo = {e[b], 0, 0};
      local[b].bin.hi = {e[b + 1], 0, 0};
    }
    for (int i = 0; i < P.rows(); ++i) local[binOf(e, var.values[i])].rows.push_back(i);
    for (auto& l : local)
      if (!l.rows.empty()) protos.push_back(std::move(l));
  }
  if (!P.workspace.empty()) {
    const int nb = o.workspace_bins;
    std::array<std::vector<double>, 3> e;
    for (int a = 0; a < 3; ++a) {
      double mn = kInf, mx = -kInf;
      for (const auto& p : P.workspace) {
        mn = std::min(mn, p[a]);
        mx = std::max(mx, p[a]);
      }
      e[a] = edgesOf(mn, mx, nb);
      map.ws_dims[a] = nb;
      map.ws_origin[a] = e[a][0];
      map.ws_cell[a] = e[a][1] - e[a][0];
    }
    std::map<int, Proto> cells;
    for (int i = 0; i < P.rows(); ++i) {
      std::array<int, 3> id;
      for (int a = 0; a < 3; ++a) id[a] = binOf(e[a], P.workspace[i][a]);
      Proto& pr = cells[(id[2] * nb + id[1]) * nb + id[0]];
      pr.bin.space = "workspace";
      pr.bin.variable = "x,y,z";
      pr.bin.index = id;
      for (int a = 0; a < 3; ++a) {
        pr.bin.lo[a] = e[a][id[a]];
        pr.bin.hi[a] = e[a][id[a] + 1];
      }
      pr.rows.push_back(i);
    }
    for (auto& [key, pr] : cells) protos.push_back(std::move(pr));
  }
  if (P.grid.size() == 2) {  // the 2-D grid map, first axis major; only cells with rows
    std::array<std::vector<double>, 2> e;
    for (int a = 0; a < 2; ++a) {
      const auto [mn, mx] = std::minmax_element(P.grid[a].values.begin(), P.grid[a].values.end());
      e[a] = edgesOf(*mn, *mx, P.grid_bins[a]);
    }
    std::map<int, Proto> cells;
    for (int i = 0; i < P.rows(); ++i) {
      const int i0 = binOf(e[0], P.grid[0].values[i]), i1 = binOf(e[1], P.grid[1].values[i]);
      Proto& pr = cells[i0 * P.grid_bins[1] + i1];
      pr.bin.space = "grid";
      pr.bin.variable = P.grid[0].name + "," + P.grid[1].name;
      pr.bin.index = {i0, i1, 0};
      pr.bin.lo = {e[0][i0], e[1][i1], 0};
      pr.bin.hi = {e[0][i0 + 1], e[1][i1 + 1], 0};
      pr.rows.push_back(i);
    }
    for (auto& [key, pr] : cells) protos.push_back(std::move(pr));
  }
  int tested = 0;
  for (const auto& p : protos) tested += static_cast<int>(p.rows.size()) >= defaults::kMinBinSamples;
  map.z = normalQuantile(1.0 - defaults::kBinFalseAlarm / (2.0 * std::max(1, tested * C)));
  for (auto& pr : protos) {
    ArmBin& b = pr.bin;
    b.n = static_cast<int>(pr.rows.size());
    b.n_eff = effectiveSampleSize(b.n, rho);
    for (int c = 0; c < C; ++c) {
      double m = 0;
      for (int i : pr.rows) m += res(i, c);
      m /= b.n;
      b.mean.push_back(m);
      b.threshold.push_back(map.z * sigma[c] / std::sqrt(b.n_eff));
      if (b.n >= defaults::kMinBinSamples && std::abs(m) > b.threshold.back()) b.flagged = true;
    }
    map.bins.push_back(b);
  }
  return map;
}

}  // namespace

int ArmProblem::findEffect(const std::string& name) const {
  for (std::size_t i = 0; i < catalogue.size(); ++i)
    if (catalogue[i].name == name) return static_cast<int>(i);
  return -1;
}

int ArmResidualMap::flagged() const {
  int n = 0;
  for (const auto& b : bins) n += b.flagged;
  return n;
}

std::string ArmFitOptions::validate() const {
  if (folds < 2) return "folds must be at least 2";
  if (variable_bins < 1 || workspace_bins < 1) return "bin counts must be positive";
  if (!(significance_z > 0)) return "significance z must be positive";
  if (!(min_relative_improvement >= 0 && min_relative_improvement < 1))
    return "minimum relative improvement must lie in [0, 1)";
  return "";
}

SetFit fitEffects(const ArmProblem& problem, const EffectValues& start) {
  const Solved s = fitSet(problem, start);
  return {s.v, s.ssr};
}

const EffectValue* findValue(const EffectValues& values, int effect) {
  for (const auto& v : values)
    if (v.effect == effect) return &v;
  return nullptr;
}

namespace {

// Per-channel residual weights 1 / sigma_c (native units), guarded against a zero noise estimate.
Eigen::VectorXd noiseWeights(const ArmProblem& P, const std::vector<double>& sigma) {
  double smax = 0;
  for (int c = 0; c < P.channels(); ++c) smax = std::max(smax, sigma[c] * P.weight[c]);
  if (!(smax > 0) || !std::isfinite(smax)) return P.weight;  // no noise seen: keep the fit units
  Eigen::VectorXd w(P.channels());
  for (int c = 0; c < P.channels(); ++c) w[c] = 1.0 / std::max(sigma[c], 1e-9 * smax / P.weight[c]);
  return w;
}

// Residuals (flattened) of one linearised step of the most flexible model: the design plus every
// candidate at once, dependent columns dropped by a rank-revealing QR. Returns the rank; `leverage`
// gets the diagonal of the hat matrix (how much of each residual's degree of freedom the fit
// used), so that each channel's noise is estimated with its own degrees of freedom.
int saturatedResidual(const Eigen::MatrixXd& all, const Eigen::VectorXd& r0, Eigen::VectorXd& sat_r,
                      Eigen::VectorXd& leverage) {
  sat_r = r0;
  leverage = Eigen::VectorXd::Zero(r0.size());
  if (all.cols() == 0) return 0;
  Eigen::VectorXd sc(all.cols());
  for (int j = 0; j < all.cols(); ++j) sc[j] = all.col(j).norm() > 0 ? 1.0 / all.col(j).norm() : 0.0;
  const Eigen::MatrixXd As = all * sc.asDiagonal();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(As);
  qr.setThreshold(1e-9);
  sat_r = r0 - As * qr.solve(r0);
  const int rank = static_cast<int>(qr.rank());
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(r0.size(), rank);
  leverage = Q.rowwise().squaredNorm();
  return rank;
}

}  // namespace

ArmDiagnosis compareArm(const ArmProblem& P, const ArmFitOptions& o) {
  if (const std::string err = o.validate(); !err.empty()) throw InputError("", 0, "options", err);
  const int min_rows = std::max(2 * o.folds, defaults::kMinResidualDof + 1);
  if (P.rows() < min_rows)
    throw InputError(P.file, 0, 2 * o.folds >= min_rows ? "folds" : "",
                     std::to_string(P.rows()) + " rows are too few to compare and cross-validate with " +
                         std::to_string(o.folds) + " folds (need at least " + std::to_string(min_rows) +
                         (2 * o.folds >= min_rows ? ", two per fold; use fewer folds)" : ")"));
  ArmDiagnosis d;
  d.kind = P.kind;
  d.design = P.design;
  d.file = P.file;
  d.warnings = P.warnings;
  const int C = P.channels();

  // Noise: one linearised step of the most flexible model (every candidate at once); residual
  // standard deviation with its dof. First in fit units (the overall noise estimate), then again
  // with every channel weighted by its first estimate (so a noisy channel does not leak into the
  // others through shared parameters): the per-channel noise that weights all fits below.
  const Eigen::MatrixXd pred0 = P.predict({});
  const Eigen::VectorXd r0 = flatten(P, P.measured - pred0);
  Eigen::MatrixXd all(r0.size(), 0);
  for (std::size_t e = 0; e < P.catalogue.size(); ++e) {
    const Eigen::MatrixXd cols = candidateColumns(P, {}, static_cast<int>(e));
    Eigen::MatrixXd next(r0.size(), all.cols() + cols.cols());
    next << all, cols;
    all = next;
  }
  Eigen::VectorXd sat_r, lev;
  const int rank = saturatedResidual(all, r0, sat_r, lev);
  const int dof = static_cast<int>(r0.size()) - rank;
  const bool enough = dof >= defaults::kMinResidualDof && dof >= static_cast<int>(r0.size()) / 4;
  // Per channel: sqrt(SS_c / (rows - sum of the channel's leverages)), the channel's own dof.
  auto channelNoise = [&](const Eigen::MatrixXd& sat, const Eigen::VectorXd& leverage) {
    std::vector<double> out;
    for (int c = 0; c < C; ++c) {
      double ss = 0, used = 0;
      for (int i = 0; i < P.rows(); ++i) {
        ss += sat(i, c) * sat(i, c);
        used += enough ? leverage[i * C + c] : 0.0;
      }
      out.push_back(std::sqrt(ss / std::max(1.0, P.rows() - used)));
    }
    return out;
  };
  if (enough) {
    d.noise_estimate = std::sqrt(sat_r.squaredNorm() / dof);
  } else {
    d.noise_estimate = rms(r0);
    d.warnings.push_back("too few rows for the noise estimate (" + std::to_string(rank) +
                         " independent candidate parameters); the RMSE of the design is used instead");
  }
  Eigen::MatrixXd sat = unflatten(P, enough ? sat_r : r0);
  std::vector<double> sigma = channelNoise(sat, lev);
  if (enough && C > 1) {
    const Eigen::VectorXd w = noiseWeights(P, sigma);
    Eigen::VectorXd rs(r0.size());
    for (int i = 0; i < P.rows(); ++i)
      for (int c = 0; c < C; ++c) rs[i * C + c] = w[c] / P.weight[c];
    Eigen::VectorXd sat_w, lev_w;
    saturatedResidual(rs.asDiagonal() * all, rs.asDiagonal() * r0, sat_w, lev_w);
    sat_w = sat_w.cwiseQuotient(rs);
    sat = unflatten(P, sat_w);
    sigma = channelNoise(sat, lev_w);
  }
  d.channel_noise = sigma;
  if (enough) d.saturated_residual = sat;
  double rho_sum = 0;
  for (int c = 0; c < C; ++c) {
    std::vector<double> col(P.rows());
    for (int i = 0; i < P.rows(); ++i) col[i] = sat(i, c);
    rho_sum += lag1Autocorrelation(col);
  }
  d.noise_rho = rho_sum / C;

  const NoiseWeighted W(P, noiseWeights(P, d.channel_noise));
  Engine eng{W, foldAssignment(P.rows(), o.folds, o.seed), o.folds, P.weight};
  bool ok = false;
  d.as_designed = eng.make(gaussNewton(W, {}), "as designed", ok);
  ARMSTUDY_CHECK(ok, "no parameters to fit");
  d.as_designed_map = residualMap(P, d.as_designed.residual, d.channel_noise, d.noise_rho, o);
  d.ladder.push_back(d.as_designed);
  d.final_fit = d.as_designed;
  d.final_map = d.as_designed_map;
  d.rmse_before = d.rmse_after = d.as_designed.heldout_rmse;
  return d;
}

namespace {

std::vector<ArmCandidate> rank(const ArmProblem& P, const Engine& eng, const EffectValues& current,
                               const ArmFit& base, const Solved& base_solved, double noise_rho, const ArmFitOptions& o) {
  std::vector<ArmCandidate> out;
  const int N = P.rows() * P.channels();
  const Eigen::MatrixXd basis = base_solved.J.cols() > 0 ? base_solved.J : Eigen::MatrixXd(N, 0);
  std::map<int, Eigen::MatrixXd> resid_cols;
  for (std::size_t ei = 0; ei < P.catalogue.size(); ++ei) {
    const int e = static_cast<int>(ei);
    if (findValue(current, e)) continue;
    const ArmEffect& info = P.catalogue[e];
    ArmCandidate cand;
    cand.effect = e;
    cand.name = info.name;
    const Eigen::MatrixXd cols = candidateColumns(P, current, e);
    bool dead = true;
    for (int j = 0; j < cols.cols(); ++j) {
      const double r2 = r2OnBasis(cols.col(j), basis);
      if (cols.col(j).norm() == 0) {
        cand.warnings.push_back("parameter '" + info.params[j].key +
                                "' has no effect on the predicted channels with this data (an operating variable it "
                                "needs is constant or zero)");
        continue;
      }
      if (r2 > defaults::kCollinearR2)
        cand.warnings.push_back("parameter '" + info.params[j].key + "' cannot be told apart from the terms already in "
                                "the model (R^2 = " + fmt(r2) + ") with this data");
      if (r2 <= defaults::kUnidentifiableR2) dead = false;
    }
    if (dead) {
      cand.status = "unidentifiable";
      out.push_back(cand);
      continue;
    }
    Eigen::MatrixXd rc = cols;
    if (basis.cols() > 0) rc = cols - basis * basis.colPivHouseholderQr().solve(cols);
    resid_cols[e] = rc;
    const int p = static_cast<int>(packX(current).size() + info.params.size());
    if (N * (o.folds - 1) / o.folds < p + defaults::kMinResidualDof) {
      cand.status = "too_few_rows";
      cand.warnings.push_back("too few rows to fit and cross-validate " + std::to_string(p) + " parameters");
      out.push_back(cand);
      continue;
    }
    EffectValues v = current;
    v.push_back(zeroValue(P, e, true));
    bool ok = false;
    cand.fit = eng.make(fitSet(P, v), "+" + info.name, ok);
    if (!ok) {
      cand.status = "too_few_rows";
      cand.warnings.push_back("too few rows to fit and cross-validate " + std::to_string(p) + " parameters");
      out.push_back(cand);
      continue;
    }
    cand.improvement = (base.heldout_score - cand.fit.heldout_score) / base.heldout_score;
    // Paired held-out squared-error differences per row (all channels of a row together, each
    // weighted by 1 / its noise: P is the noise-weighted problem).
    std::vector<double> dd(P.rows());
    for (int i = 0; i < P.rows(); ++i) {
      double s = 0;
      for (int c = 0; c < P.channels(); ++c) {
        const double a = base.heldout_residual(i, c) * P.weight[c], b = cand.fit.heldout_residual(i, c) * P.weight[c];
        s += a * a - b * b;
      }
      dd[i] = s;
    }
    const double md = mean(dd);
    double var = 0;
    for (double x : dd) var += (x - md) * (x - md);
    var /= std::max(1, P.rows() - 1);
    const double neff = effectiveSampleSize(P.rows(), noise_rho);
    cand.t_statistic = var > 0 ? md / std::sqrt(var / neff) : (md > 0 ? kInf : 0.0);
    cand.significant = cand.t_statistic > o.significance_z && cand.improvement >= o.min_relative_improvement;
    out.push_back(cand);
  }
  // Candidates that cannot be told apart from each other: a parameter column of one lies in the
  // span of another candidate's columns (after removing what the model already explains).
  for (auto& a : out) {
    if (!resid_cols.count(a.effect)) continue;
    const Eigen::MatrixXd& A = resid_cols[a.effect];
    for (const auto& b : out) {
      if (a.effect == b.effect || !resid_cols.count(b.effect)) continue;
      const Eigen::MatrixXd& B = resid_cols[b.effect];
      bool warned = false, all_in = true;
      for (int j = 0; j < A.cols(); ++j) {
        if (A.col(j).norm() == 0) continue;
        const double r2 = r2OnBasis(A.col(j), B);
        if (r2 <= defaults::kCollinearR2) {
          all_in = false;
          continue;
        }
        if (!warned) {
          a.warnings.push_back("parameter '" + P.catalogue[a.effect].params[j].key +
                               "' cannot be told apart from the candidate '" + b.name + "' (R^2 = " + fmt(r2) +
                               ") with this data");
          a.indistinguishable.push_back(b.name);
          warned = true;
        }
      }
      if (all_in) a.contained_in.push_back(b.name);
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const ArmCandidate& a, const ArmCandidate& b) {
    const bool ao = a.status == "ok", bo = b.status == "ok";
    if (ao != bo) return ao;
    if (!ao) return false;
    return a.fit.heldout_score < b.fit.heldout_score;
  });
  // Parsimony: a candidate whose columns all lie in the span of a better-ranked one and that
  // scores about as well (held-out RMSE within kParsimonyTolerance) is the simpler explanation of
  // the same pattern; it moves ahead of it (e.g. the offset of a vertical joint vs base_offset).
  for (std::size_t i = 1; i < out.size(); ++i) {
    if (out[i].status != "ok") continue;
    std::size_t k = i;
    while (k > 0) {
      const ArmCandidate& b = out[k - 1];
      const ArmCandidate& a = out[k];
      const bool inside = std::find(a.contained_in.begin(), a.contained_in.end(), b.name) != a.contained_in.end();
      if (!inside || a.fit.n_params >= b.fit.n_params ||
          a.fit.heldout_score > b.fit.heldout_score * (1 + defaults::kParsimonyTolerance))
        break;
      std::swap(out[k - 1], out[k]);
      --k;
    }
  }
  return out;
}

}  // namespace

namespace {

std::string fmt3(double v) {
  char b[48];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

// The unexplained-effect search (issue 13) on a model's residuals (native units): every channel,
// normalised by its noise, against every operating variable (joint positions and speeds, the
// speed's sign, the channel's load, time or row order): binned means and, against joint
// positions, a periodogram (least-squares sine fit over a frequency grid). Under the noise alone a
// standardised bin mean is N(0, 1) and a sine fit's SSR reduction chi^2(2) (both inflated for
// AR(1) residuals); the 5 % family-wise false-alarm rate is split between the two families and
// Bonferroni-corrected over all their tests.
std::vector<ArmPattern> searchPatterns(const ArmProblem& P, const Eigen::MatrixXd& residual, const Eigen::MatrixXd& predicted,
                                       const std::vector<double>& sigma, double rho) {
  const int R = P.rows(), C = P.channels();
  struct Var {
    std::string name, unit;
    std::vector<double> x;
    bool position = false, sign = false;
    int channel = -1;  // a per-channel variable (the load) applies to that channel only
  };
  std::vector<Var> vars;
  for (const BinVariable& v : P.variables) {
    vars.push_back({v.name, v.unit, v.values, v.position, false, -1});
    if (v.name.rfind("qd", 0) == 0 && v.name.rfind("qdd", 0) != 0) {
      Var sg{"sign(" + v.name + ")", "-", {}, false, true, -1};
      for (double x : v.values) sg.x.push_back(x < 0 ? -1.0 : 1.0);
      vars.push_back(sg);
    }
  }
  {
    Var t{P.time.empty() ? "row" : "t", P.time.empty() ? "-" : "s", P.time, false, false, -1};
    if (t.x.empty())
      for (int i = 0; i < R; ++i) t.x.push_back(i);
    vars.push_back(t);
  }
  if (!P.load_name.empty())
    for (int c = 0; c < C; ++c) {
      Var l{P.load_name, P.channel_units[c], {}, false, false, c};
      for (int i = 0; i < R; ++i) l.x.push_back(predicted(i, c));
      vars.push_back(l);
    }
  const double inflate = (1 + std::clamp(rho, 0.0, 0.95)) / (1 - std::clamp(rho, 0.0, 0.95));
  // Normalised residuals and their sums of squares per channel.
  Eigen::MatrixXd e(R, C);
  std::vector<double> ss(C, 0.0);
  for (int c = 0; c < C; ++c)
    for (int i = 0; i < R; ++i) {
      e(i, c) = sigma[c] > 0 ? residual(i, c) / sigma[c] : 0.0;
      ss[c] += e(i, c) * e(i, c);
    }
  struct Bin {
    double lo, hi;
    std::vector<int> rows;
  };
  auto binsOf = [&](const Var& v) {
    std::vector<Bin> bins;
    const auto [mn, mx] = std::minmax_element(v.x.begin(), v.x.end());
    if (!(*mx > *mn)) return bins;
    const int nb = v.sign ? 2 : defaults::kUnexplainedBins;
    for (int b = 0; b < nb; ++b) bins.push_back({*mn + (*mx - *mn) * b / nb, *mn + (*mx - *mn) * (b + 1) / nb, {}});
    for (int i = 0; i < R; ++i)
      bins[std::clamp(static_cast<int>((v.x[i] - *mn) / (*mx - *mn) * nb), 0, nb - 1)].rows.push_back(i);
    return bins;
  };
  auto frequencies = [&](const Var& v) {
    std::vector<double> w;
    if (!v.position) return w;
    const auto [mn, mx] = std::minmax_element(v.x.begin(), v.x.end());
    const double range = *mx - *mn;
    if (!(range > 0)) return w;
    const int kmax = defaults::kPeriodogramOversampling * R / defaults::kPeriodogramRowsPerCycle;
    for (int k = defaults::kPeriodogramOversampling / 2; k <= kmax; ++k)
      w.push_back(2 * M_PI * k / (range * defaults::kPeriodogramOversampling));
    return w;
  };
  // Count the tests of both families first (Bonferroni).
  long bin_tests = 0, freq_tests = 0;
  for (int c = 0; c < C; ++c)
    for (const Var& v : vars) {
      if (v.channel >= 0 && v.channel != c) continue;
      for (const Bin& b : binsOf(v)) bin_tests += static_cast<int>(b.rows.size()) >= defaults::kMinBinSamples;
      freq_tests += static_cast<long>(frequencies(v).size());
    }
  const double alpha = defaults::kBinFalseAlarm / 2;
  const double z_bin = normalQuantile(1.0 - alpha / (2.0 * std::max(1L, bin_tests)));
  const double chi_freq = -2.0 * std::log(alpha / std::max(1L, freq_tests));  // chi^2(2) tail exp(-x/2)
  std::vector<ArmPattern> out;
  for (int c = 0; c < C; ++c) {
    if (!(sigma[c] > 0) || !(ss[c] > 0)) continue;
    for (const Var& v : vars) {
      if (v.channel >= 0 && v.channel != c) continue;
      // Binned means.
      const std::vector<Bin> bins = binsOf(v);
      if (!bins.empty()) {
        ArmPattern p;
        p.channel = P.channel_names[c];
        p.variable = v.name;
        p.unit = v.unit;
        p.kind = "binned_means";
        p.threshold = z_bin;
        double explained = 0;
        for (const Bin& b : bins) {
          const int n = static_cast<int>(b.rows.size());
          if (n == 0) continue;
          double m = 0;
          for (int i : b.rows) m += e(i, c);
          m /= n;
          explained += n * m * m;
          if (n < defaults::kMinBinSamples) continue;
          const double z = std::abs(m) * std::sqrt(effectiveSampleSize(n, rho));
          if (z > p.statistic) {
            p.statistic = z;
            p.peak_mean = m * sigma[c];
            p.peak_lo = b.lo;
            p.peak_hi = b.hi;
          }
        }
        p.explained = explained / ss[c];
        p.sum_squares = explained;
        p.significant = p.statistic > z_bin;
        p.description = "binned means of " + p.channel + " against " + v.name + ": largest " + fmt3(p.peak_mean) + " " +
                        P.channel_units[c] + " for " + v.name + " in [" + fmt3(p.peak_lo) + ", " + fmt3(p.peak_hi) + "] " +
                        v.unit + " (" + fmt3(p.statistic) + " standard errors, threshold " + fmt3(z_bin) + ")";
        out.push_back(p);
      }
      // Periodogram against a joint position.
      const std::vector<double> ws = frequencies(v);
      if (!ws.empty()) {
        ArmPattern p;
        p.channel = P.channel_names[c];
        p.variable = v.name;
        p.unit = v.unit;
        p.kind = "periodic";
        p.threshold = chi_freq;
        double best = -1;
        for (double w : ws) {
          double ms = 0, mc = 0, me = 0;
          for (int i = 0; i < R; ++i) {
            ms += std::sin(w * v.x[i]);
            mc += std::cos(w * v.x[i]);
            me += e(i, c);
          }
          ms /= R;
          mc /= R;
          me /= R;
          Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
          Eigen::Vector2d b = Eigen::Vector2d::Zero();
          for (int i = 0; i < R; ++i) {
            const Eigen::Vector2d f(std::sin(w * v.x[i]) - ms, std::cos(w * v.x[i]) - mc);
            A += f * f.transpose();
            b += f * (e(i, c) - me);
          }
          if (std::abs(A.determinant()) <= 1e-12 * A.squaredNorm()) continue;
          const Eigen::Vector2d ab = A.ldlt().solve(b);
          const double red = ab.dot(b);  // SSR reduction of the centred sine fit
          if (red > best) {
            best = red;
            p.period = 2 * M_PI / w;
            p.amplitude = ab.norm() * sigma[c];
          }
        }
        if (best >= 0) {
          p.statistic = best / inflate;
          p.explained = best / ss[c];
          p.sum_squares = best;
          p.significant = p.statistic > chi_freq;
          p.description = "periodic in " + v.name + ": period " + fmt3(p.period) + " " + v.unit +
                          (v.unit == "rad" ? " (" + fmt3(2 * M_PI / p.period) + " per revolution)" : std::string()) +
                          ", amplitude " + fmt3(p.amplitude) + " " + P.channel_units[c] + " (chi^2 " + fmt3(p.statistic) +
                          ", threshold " + fmt3(chi_freq) + ")";
          out.push_back(p);
        }
      }
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const ArmPattern& a, const ArmPattern& b) {
    if (a.significant != b.significant) return a.significant;
    return a.explained > b.explained;
  });
  return out;
}

// A significant candidate must explain what is visibly there (issue 13): when the residuals of the
// current model show significant patterns, its fit has to remove at least kPatternExplainedDrop of
// the strongest one (or make it insignificant). A candidate that lowers the error without removing
// the strongest pattern is fitting part of an effect outside the catalogue (e.g.
// rotor_inertia, linear in qdd, absorbing a slice of a position-periodic ripple of a joint that
// moves sinusoidally); it is then not called significant and is moved behind the ones that are.
// When the strongest pattern is still significant in the residuals of the most flexible model
// (every candidate at once, `saturated`), no combination of catalogue effects explains it: a
// candidate then has to make it insignificant, a partial absorption never counts (a slow ripple,
// nearly linear in the position over the motion, is absorbed by rotor_inertia to 89 %).
constexpr double kPatternExplainedDrop = 0.5;  // share of a pattern's sum of squares a candidate must remove

void confirmCandidates(const ArmProblem& P, std::vector<ArmCandidate>& ranking, const ArmFit& current,
                       const std::vector<double>& sigma, double rho, const std::vector<ArmPattern>& saturated) {
  const std::vector<ArmPattern> before = searchPatterns(P, current.residual, current.predicted, sigma, rho);
  // The strongest significant pattern (largest explained sum of squares in noise units).
  std::vector<const ArmPattern*> seen;
  for (const ArmPattern& p : before)
    if (p.significant && (seen.empty() || p.sum_squares > seen.front()->sum_squares)) seen.assign(1, &p);
  if (seen.empty()) return;
  bool outside = false;  // the catalogue as a whole leaves it significant
  for (const ArmPattern& x : saturated)
    if (x.significant && x.channel == seen.front()->channel && x.variable == seen.front()->variable &&
        x.kind == seen.front()->kind)
      outside = true;
  const double drop = outside ? 1.0 : kPatternExplainedDrop;
  std::vector<std::string> demoted;
  for (ArmCandidate& c : ranking) {
    if (!c.significant) continue;
    const std::vector<ArmPattern> after = searchPatterns(P, c.fit.residual, c.fit.predicted, sigma, rho);
    bool explains = false;
    for (const ArmPattern* b : seen) {
      const ArmPattern* a = nullptr;
      for (const ArmPattern& x : after)
        if (x.channel == b->channel && x.variable == b->variable && x.kind == b->kind) a = &x;
      if (!a || !a->significant || (drop < 1 && a->sum_squares <= (1 - drop) * b->sum_squares)) {
        explains = true;
        break;
      }
    }
    if (explains) continue;
    c.significant = false;
    c.warnings.push_back("lowers the error but leaves the strongest residual pattern in place (" +
                         seen.front()->description + "): it does not explain it");
    demoted.push_back(c.name);
  }
  if (demoted.empty()) return;
  // The demoted ones go right behind the last candidate that is still significant.
  std::vector<ArmCandidate> keep, moved;
  for (ArmCandidate& c : ranking)
    (std::find(demoted.begin(), demoted.end(), c.name) != demoted.end() ? moved : keep).push_back(std::move(c));
  std::size_t pos = 0;
  for (std::size_t k = 0; k < keep.size(); ++k)
    if (keep[k].significant) pos = k + 1;
  keep.insert(keep.begin() + static_cast<long>(pos), moved.begin(), moved.end());
  ranking = std::move(keep);
}

std::string candidateVerdictName(const ArmCandidate& c) {
  std::string others;
  for (const auto& o2 : c.indistinguishable) others += (others.empty() ? "" : ", ") + o2;
  return others.empty() ? c.name : c.name + " (cannot be told apart from " + others + " with this data)";
}

}  // namespace

ArmDiagnosis diagnoseArm(const ArmProblem& P0, const ArmFitOptions& o) {
  ArmDiagnosis d = compareArm(P0, o);
  const NoiseWeighted P(P0, noiseWeights(P0, d.channel_noise));
  Engine eng{P, foldAssignment(P.rows(), o.folds, o.seed), o.folds, P0.weight};
  EffectValues current;
  Solved cur_solved = gaussNewton(P, {});
  ArmFit cur = d.as_designed;
  std::vector<ArmCandidate> ranking;
  std::vector<std::string> auto_added;
  auto addEffect = [&](int e, bool warn_status) {
    const std::string& name = P.catalogue[e].name;
    if (findValue(current, e)) {
      d.warnings.push_back("effect '" + name + "' is already in the model");
      return false;
    }
    if (warn_status)
      for (const auto& c : ranking)
        if (c.effect == e && c.status != "ok")
          d.warnings.push_back("adding '" + name + "' although it is " + c.status);
    EffectValues v = current;
    v.push_back(zeroValue(P, e, true));
    const Solved s = fitSet(P, v);
    bool ok = false;
    ArmFit f = eng.make(s, "+" + name, ok);
    if (!ok) {
      d.warnings.push_back("cannot add '" + name + "': too few rows");
      return false;
    }
    current = s.v;
    cur_solved = s;
    cur = f;
    d.added.push_back(name);
    d.ladder.push_back(f);
    return true;
  };
  for (const std::string& name : o.add) {
    const int e = P.findEffect(name);
    if (e < 0) {
      std::string names;
      for (const auto& c : P.catalogue) names += (names.empty() ? "" : ", ") + c.name;
      throw InputError("", 0, "--add", "unknown effect '" + name + "' for this design and data (candidates: " + names + ")");
    }
    addEffect(e, false);
  }
  // Patterns the most flexible model leaves: what no combination of catalogue effects explains.
  const std::vector<ArmPattern> saturated =
      d.saturated_residual.size() ? searchPatterns(P, d.saturated_residual, d.as_designed.predicted, d.channel_noise, d.noise_rho)
                                  : std::vector<ArmPattern>{};
  ranking = rank(P, eng, current, cur, cur_solved, d.noise_rho, o);
  confirmCandidates(P, ranking, cur, d.channel_noise, d.noise_rho, saturated);
  d.ranking = ranking;
  d.missing_effect_found = !ranking.empty() && ranking.front().significant;
  std::vector<std::string> named;
  if (d.missing_effect_found) named.push_back(candidateVerdictName(ranking.front()));
  if (o.auto_add)
    for (bool first = true; !ranking.empty() && ranking.front().significant; first = false) {
      const std::string name = candidateVerdictName(ranking.front());
      if (!addEffect(ranking.front().effect, true)) break;
      if (!first) named.push_back(name);  // the first one is named above
      ranking = rank(P, eng, current, cur, cur_solved, d.noise_rho, o);
      confirmCandidates(P, ranking, cur, d.channel_noise, d.noise_rho, saturated);
    }
  d.final_fit = cur;
  d.final_map = residualMap(P, cur.residual, d.channel_noise, d.noise_rho, o);
  // What the catalogue leaves: patterns in the final residuals. They are an unexplained effect when
  // no significant candidate is left for the final model (otherwise the candidate comes first).
  d.patterns = searchPatterns(P, cur.residual, cur.predicted, d.channel_noise, d.noise_rho);
  const bool candidate_left = !ranking.empty() && ranking.front().significant;
  d.unexplained_found = !candidate_left && !d.patterns.empty() && d.patterns.front().significant;
  std::string verdict;
  if (!named.empty()) {
    verdict = (named.size() > 1 ? "missing effects: " : "missing effect: ");
    for (std::size_t k = 0; k < named.size(); ++k) verdict += (k ? ", " : "") + named[k];
  }
  if (d.unexplained_found) {
    const ArmPattern& p = d.patterns.front();
    const std::string u = "unexplained effect in channel " + p.channel + " against " + p.variable + " (" + p.description +
                          "): no catalogue effect explains it";
    verdict = verdict.empty() ? u : verdict + "; then " + u;
  }
  d.verdict = verdict.empty() ? "no significant missing effect" : verdict;
  d.rmse_before = d.as_designed.heldout_rmse;
  d.rmse_after = cur.heldout_rmse;
  return d;
}

EffectValue parseHiddenEffect(const ArmProblem& P, const std::string& spec) {
  const auto colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  const int e = P.findEffect(name);
  if (e < 0) {
    std::string names;
    for (const auto& c : P.catalogue) names += (names.empty() ? "" : ", ") + c.name;
    throw InputError("", 0, "--hide", "unknown effect '" + name + "' for this design (candidates: " + names + ")");
  }
  const ArmEffect& info = P.catalogue[e];
  EffectValue v;
  v.effect = e;
  v.x.resize(info.params.size());
  for (std::size_t j = 0; j < info.params.size(); ++j) v.x[j] = info.params[j].typical;
  v.profile = info.hasProfile() ? info.profile.typical : 0.0;
  if (colon == std::string::npos) return v;
  std::stringstream ss(spec.substr(colon + 1));
  for (std::string item; std::getline(ss, item, ',');) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw InputError("", 0, "--hide", "expected key=value in '" + item + "'");
    const std::string key = item.substr(0, eq);
    double val = 0;
    try {
      std::size_t pos = 0;
      val = std::stod(item.substr(eq + 1), &pos);
      if (pos != item.size() - eq - 1 || !std::isfinite(val)) throw std::invalid_argument("x");
    } catch (const std::exception&) {
      throw InputError("", 0, "--hide", "'" + item.substr(eq + 1) + "' is not a number");
    }
    bool found = false;
    for (std::size_t j = 0; j < info.params.size(); ++j)
      if (info.params[j].key == key) {
        v.x[j] = val;
        found = true;
      }
    if (info.hasProfile() && info.profile.key == key) {
      if (!(val > 0)) throw InputError("", 0, "--hide", key + " must be positive");
      v.profile = val;
      found = true;
    }
    if (!found) throw InputError("", 0, "--hide", "parameter '" + key + "' does not belong to the effect '" + name + "'");
  }
  return v;
}

std::vector<double> savitzkyGolayDerivative(const std::vector<double>& t, const std::vector<double>& y, int m,
                                            int degree) {
  const int n = static_cast<int>(t.size());
  ARMSTUDY_CHECK(n == static_cast<int>(y.size()), "same length");
  const int w = std::min(2 * m + 1, n);
  const int deg = std::min(degree, w - 1);
  std::vector<double> out(n, 0.0);
  for (int i = 0; i < n; ++i) {
    const int start = std::clamp(i - m, 0, n - w);
    Eigen::MatrixXd A(w, deg + 1);
    Eigen::VectorXd b(w);
    for (int k = 0; k < w; ++k) {
      const double dt = t[start + k] - t[i];
      double pw = 1;
      for (int p = 0; p <= deg; ++p) {
        A(k, p) = pw;
        pw *= dt;
      }
      b[k] = y[start + k];
    }
    const Eigen::VectorXd c = A.colPivHouseholderQr().solve(b);
    out[i] = deg >= 1 ? c[1] : 0.0;  // derivative of the local polynomial at t_i
  }
  return out;
}

}  // namespace armstudy::calibration
