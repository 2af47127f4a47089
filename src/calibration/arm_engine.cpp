#include "calibration/arm_engine.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

#include "calibration/least_squares.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"

namespace armstudy::calibration::arm_detail {

constexpr double kProfileRelativeStep =
    1e-4;  // central-difference step of a profiled parameter, relative

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
Eigen::VectorXd solveStep(const Eigen::MatrixXd& J, const Eigen::VectorXd& r,
                          const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
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

// Fit of a set: the effects in `start` (a profiled effect whose value is NaN is profiled on its
// grid).
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
  double lo = std::log(grid[bi > 0 ? bi - 1 : 0]),
         hi = std::log(grid[std::min(grid.size() - 1, bi + 1)]);
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

double rms(const Eigen::VectorXd& r) {
  return r.size() ? std::sqrt(r.squaredNorm() / r.size()) : kNaN;
}

// Linearised held-out residuals for a partition of the rows. Returns false when a training set is
// too small.
bool heldOut(const ArmProblem& P, const Solved& s, const std::vector<int>& part, int parts,
             Eigen::VectorXd& out) {
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
  const double rho = std::clamp(
      lag1Autocorrelation(std::vector<double>(s.r.data(), s.r.data() + s.r.size())), 0.0, 0.95);
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

double r2OnBasis(const Eigen::VectorXd& col, const Eigen::MatrixXd& basis) {
  const double tot = col.squaredNorm();
  if (tot == 0) return 1.0;
  if (basis.cols() == 0) return 0.0;
  const Eigen::VectorXd coef = basis.colPivHouseholderQr().solve(col);
  return 1.0 - (col - basis * coef).squaredNorm() / tot;
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

ArmResidualMap residualMap(const ArmProblem& P, const Eigen::MatrixXd& res,
                           const std::vector<double>& sigma, double rho, const ArmFitOptions& o) {
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
    return std::clamp(static_cast<int>(std::upper_bound(e.begin(), e.end(), x) - e.begin()) - 1, 0,
                      nb - 1);
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
  for (const auto& p : protos)
    tested += static_cast<int>(p.rows.size()) >= defaults::kMinBinSamples;
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

ArmFit Engine::make(const Solved& s, const std::string& label, bool& ok) const {
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
    f.channel_region_heldout = channelStatsOf(P, unflatten(P, hr));
  }
  const double n = static_cast<double>(s.r.size());
  const double ll = n * std::log(std::max(s.ssr, 1e-300) / n);
  f.aic = ll + 2.0 * f.n_params;
  f.bic = ll + f.n_params * std::log(n);
  confidence(P, s, f);
  return f;
}

}  // namespace armstudy::calibration::arm_detail

namespace armstudy::calibration {

int ArmProblem::findEffect(const std::string& name) const {
  for (std::size_t i = 0; i < catalogue.size(); ++i)
    if (catalogue[i].name == name) return static_cast<int>(i);
  return -1;
}

std::string ArmProblem::effectNames() const {
  std::string names;
  for (const ArmEffect& c : catalogue) names += (names.empty() ? "" : ", ") + c.name;
  return names;
}

std::vector<double> savitzkyGolayDerivative(const std::vector<double>& t,
                                            const std::vector<double>& y, int m, int degree) {
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
