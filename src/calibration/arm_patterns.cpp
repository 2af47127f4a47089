#include "calibration/arm_patterns.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

#include "common/angles.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"

namespace armstudy::calibration {

namespace {

// An operating variable: its samples per row and how the search treats it.
struct Var {
  std::string name, unit;
  std::vector<double> x;
  bool position = false, sign = false;
  int channel = -1;  // a per-channel variable (the load) applies to that channel only
};

struct Bin {
  double lo, hi;
  std::vector<int> rows;
};

// The variables to search against: the problem's, the sign of each joint speed, time (or row
// order), and each channel's load.
std::vector<Var> operatingVariables(const ArmProblem& P, const Eigen::MatrixXd& predicted) {
  const int R = P.rows(), C = P.channels();
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
  return vars;
}

// Equal-width bins of v over its range (two for a sign), with the rows (of R) in each.
std::vector<Bin> binsOf(const Var& v, int R) {
  std::vector<Bin> bins;
  const auto [mn, mx] = std::minmax_element(v.x.begin(), v.x.end());
  if (!(*mx > *mn)) return bins;
  const int nb = v.sign ? 2 : defaults::kUnexplainedBins;
  for (int b = 0; b < nb; ++b)
    bins.push_back({*mn + (*mx - *mn) * b / nb, *mn + (*mx - *mn) * (b + 1) / nb, {}});
  for (int i = 0; i < R; ++i)
    bins[std::clamp(static_cast<int>((v.x[i] - *mn) / (*mx - *mn) * nb), 0, nb - 1)].rows.push_back(
        i);
  return bins;
}

// The periodogram's angular frequencies for a joint position v over R rows (none otherwise).
std::vector<double> frequencies(const Var& v, int R) {
  std::vector<double> w;
  if (!v.position) return w;
  const auto [mn, mx] = std::minmax_element(v.x.begin(), v.x.end());
  const double range = *mx - *mn;
  if (!(range > 0)) return w;
  const int kmax = defaults::kPeriodogramOversampling * R / defaults::kPeriodogramRowsPerCycle;
  for (int k = defaults::kPeriodogramOversampling / 2; k <= kmax; ++k)
    w.push_back(kFullTurn_rad * k / (range * defaults::kPeriodogramOversampling));
  return w;
}

// One search: the normalised residuals and the thresholds shared by every test.
struct PatternSearch {
  const ArmProblem& P;
  const std::vector<double>& sigma;
  double rho;
  int R, C;
  std::vector<Var> vars;
  double inflate = 1;
  Eigen::MatrixXd e;       // residuals normalised by the channels' noise
  std::vector<double> ss;  // their sums of squares per channel
  double z_bin = 0, chi_freq = 0;

  PatternSearch(const ArmProblem& p, const Eigen::MatrixXd& residual,
                const Eigen::MatrixXd& predicted, const std::vector<double>& s, double r)
      : P(p),
        sigma(s),
        rho(r),
        R(p.rows()),
        C(p.channels()),
        vars(operatingVariables(p, predicted)) {
    inflate = (1 + std::clamp(rho, 0.0, 0.95)) / (1 - std::clamp(rho, 0.0, 0.95));
    // Normalised residuals and their sums of squares per channel.
    e.resize(R, C);
    ss.assign(C, 0.0);
    for (int c = 0; c < C; ++c)
      for (int i = 0; i < R; ++i) {
        e(i, c) = sigma[c] > 0 ? residual(i, c) / sigma[c] : 0.0;
        ss[c] += e(i, c) * e(i, c);
      }
    thresholds();
  }

  // Count the tests of both families first (Bonferroni), then their thresholds.
  void thresholds() {
    long bin_tests = 0, freq_tests = 0;
    for (int c = 0; c < C; ++c)
      for (const Var& v : vars) {
        if (v.channel >= 0 && v.channel != c) continue;
        for (const Bin& b : binsOf(v, R))
          bin_tests += static_cast<int>(b.rows.size()) >= defaults::kMinBinSamples;
        freq_tests += static_cast<long>(frequencies(v, R).size());
      }
    const double alpha = defaults::kBinFalseAlarm / 2;
    z_bin = normalQuantile(1.0 - alpha / (2.0 * std::max(1L, bin_tests)));
    chi_freq = -2.0 * std::log(alpha / std::max(1L, freq_tests));  // chi^2(2) tail exp(-x/2)
  }

  // A pattern of channel c against v, of `kind`, significant above `threshold`.
  ArmPattern pattern(int c, const Var& v, PatternKind kind, double threshold) const {
    ArmPattern p;
    p.channel = P.channel_names[c];
    p.variable = v.name;
    p.unit = v.unit;
    p.kind = kind;
    p.threshold = threshold;
    return p;
  }

  // Binned means of channel c against v: the largest standardised bin mean.
  void binnedMeans(int c, const Var& v, std::vector<ArmPattern>& out) const {
    const std::vector<Bin> bins = binsOf(v, R);
    if (bins.empty()) return;
    ArmPattern p = pattern(c, v, PatternKind::binned_means, z_bin);
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
    p.description = "binned means of " + p.channel + " against " + v.name + ": largest " +
                    formatG(p.peak_mean, 3) + " " + P.channel_units[c] + " for " + v.name +
                    " in [" + formatG(p.peak_lo, 3) + ", " + formatG(p.peak_hi, 3) + "] " + v.unit +
                    " (" + formatG(p.statistic, 3) + " standard errors, threshold " +
                    formatG(z_bin, 3) + ")";
    out.push_back(p);
  }

  // Periodogram of channel c against a joint position v: the best centred sine fit.
  // Periodograms of every channel against a joint position v: per channel the best centred sine
  // fit (empty `found[c]` when none). The sines and their 2x2 normal matrix are shared by the
  // channels.
  void periodograms(const Var& v, std::vector<std::vector<ArmPattern>>& found) const {
    found.assign(C, {});
    const std::vector<double> ws = frequencies(v, R);
    if (ws.empty()) return;
    std::vector<double> best(C, -1.0), period(C, 0.0), amplitude(C, 0.0);
    // The grid is uniform (w_k = w_0 + k dw): sin and cos of w_k x advance by a rotation through dw
    // x, re-seeded exactly every kReseed steps so rounding cannot drift.
    constexpr std::size_t kReseed = 32;
    const Eigen::Map<const Eigen::VectorXd> x(v.x.data(), R);
    const double dw = ws.size() > 1 ? ws[1] - ws[0] : 0.0;
    const Eigen::ArrayXd cd = (dw * x.array()).cos(), sd = (dw * x.array()).sin();
    Eigen::ArrayXd sn(R), cs(R);
    const Eigen::MatrixXd ec = e.rowwise() - e.colwise().mean();  // centred residuals, R x C
    for (std::size_t k = 0; k < ws.size(); ++k) {
      const double w = ws[k];
      if (k % kReseed == 0) {
        sn = (w * x.array()).sin();
        cs = (w * x.array()).cos();
      } else {
        const Eigen::ArrayXd s0 = sn;
        sn = s0 * cd + cs * sd;
        cs = cs * cd - s0 * sd;
      }
      const Eigen::VectorXd fs = (sn - sn.mean()).matrix(), fc = (cs - cs.mean()).matrix();
      Eigen::Matrix2d A;
      A(0, 0) = fs.squaredNorm();
      A(1, 1) = fc.squaredNorm();
      A(0, 1) = A(1, 0) = fs.dot(fc);
      if (std::abs(A.determinant()) <= 1e-12 * A.squaredNorm()) continue;
      const auto ldlt = A.ldlt();
      const Eigen::VectorXd bs = ec.transpose() * fs, bc = ec.transpose() * fc;
      for (int c = 0; c < C; ++c) {
        if (v.channel >= 0 && v.channel != c) continue;
        const Eigen::Vector2d b(bs[c], bc[c]);
        const Eigen::Vector2d ab = ldlt.solve(b);
        const double red = ab.dot(b);  // SSR reduction of the centred sine fit
        if (red > best[c]) {
          best[c] = red;
          period[c] = kFullTurn_rad / w;
          amplitude[c] = ab.norm() * sigma[c];
        }
      }
    }
    for (int c = 0; c < C; ++c) {
      if (best[c] < 0 || !(sigma[c] > 0) || !(ss[c] > 0)) continue;
      ArmPattern p = pattern(c, v, PatternKind::periodic, chi_freq);
      p.period = period[c];
      p.amplitude = amplitude[c];
      p.statistic = best[c] / inflate;
      p.explained = best[c] / ss[c];
      p.sum_squares = best[c];
      p.significant = p.statistic > chi_freq;
      p.description =
          "periodic in " + v.name + ": period " + formatG(p.period, 3) + " " + v.unit +
          (v.unit == "rad" ? " (" + formatG(kFullTurn_rad / p.period, 3) + " per revolution)"
                           : std::string()) +
          ", amplitude " + formatG(p.amplitude, 3) + " " + P.channel_units[c] + " (chi^2 " +
          formatG(p.statistic, 3) + ", threshold " + formatG(chi_freq, 3) + ")";
      found[c].push_back(p);
    }
  }
};

}  // namespace

const char* toString(PatternKind kind) {
  return kind == PatternKind::periodic ? "periodic" : "binned_means";
}

// The unexplained-effect search on a model's residuals (native units): every channel,
// normalised by its noise, against every operating variable (joint positions and speeds, the
// speed's sign, the channel's load, time or row order): binned means and, against joint
// positions, a periodogram (least-squares sine fit over a frequency grid). Under the noise alone a
// standardised bin mean is N(0, 1) and a sine fit's SSR reduction chi^2(2) (both inflated for
// AR(1) residuals); the 5 % family-wise false-alarm rate is split between the two families and
// Bonferroni-corrected over all their tests.
std::vector<ArmPattern> searchPatterns(const ArmProblem& P, const Eigen::MatrixXd& residual,
                                       const Eigen::MatrixXd& predicted,
                                       const std::vector<double>& sigma, double rho) {
  const PatternSearch S(P, residual, predicted, sigma, rho);
  std::vector<ArmPattern> out;
  std::vector<std::vector<std::vector<ArmPattern>>> periodic(S.vars.size());  // [variable][channel]
  for (std::size_t k = 0; k < S.vars.size(); ++k) S.periodograms(S.vars[k], periodic[k]);
  for (int c = 0; c < S.C; ++c) {
    if (!(sigma[c] > 0) || !(S.ss[c] > 0)) continue;
    for (std::size_t k = 0; k < S.vars.size(); ++k) {
      const Var& v = S.vars[k];
      if (v.channel >= 0 && v.channel != c) continue;
      S.binnedMeans(c, v, out);
      out.insert(out.end(), periodic[k][c].begin(), periodic[k][c].end());
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const ArmPattern& a, const ArmPattern& b) {
    if (a.significant != b.significant) return a.significant;
    return a.explained > b.explained;
  });
  return out;
}

// A significant candidate must explain what is visibly there: when the residuals of the
// current model show significant patterns, its fit has to remove at least kPatternExplainedDrop of
// the strongest one (or make it insignificant). A candidate that lowers the error without removing
// the strongest pattern is fitting part of an effect outside the catalogue (e.g.
// rotor_inertia, linear in qdd, absorbing a slice of a position-periodic ripple of a joint that
// moves sinusoidally); it is then not called significant and is moved behind the ones that are.
// When the strongest pattern is still significant in the residuals of the most flexible model
// (every candidate at once, `saturated`), no combination of catalogue effects explains it: a
// candidate then has to make it insignificant, a partial absorption never counts (a slow ripple,
// nearly linear in the position over the motion, is absorbed by rotor_inertia to 89 %).
constexpr double kPatternExplainedDrop =
    0.5;  // share of a pattern's sum of squares a candidate must remove
constexpr double kHalvedMeanSquare =
    0.25;  // held-out mean square of the channel left by a candidate that halves its RMSE

// What a candidate lowers in the pattern's channel beyond the pattern's own shape (its bin means or
// its sine), in squared noise units, deflated for AR(1)-correlated residuals: the channel's sum of
// squares outside the pattern's shape, ||(1 - P_N) e||^2 = ||e||^2 - (the pattern's sum of
// squares), before minus after. A candidate that only absorbs a slice of the pattern (rotor_inertia
// on a slow ripple) gains nothing there; a separate effect in the same channel (the friction of a
// coupled motor beside a pattern at low speed) does.
double gainBeyondPattern(const ArmPattern& before, const std::vector<ArmPattern>& after, int pc,
                         const ArmFit& current, const ArmFit& fit, double sigma, double rho) {
  double left = 0;  // the pattern's sum of squares in the candidate's residuals
  for (const ArmPattern& x : after)
    if (x.channel == before.channel && x.variable == before.variable && x.kind == before.kind)
      left = x.sum_squares;
  const double s2 = sigma * sigma;
  const double outside_before = current.residual.col(pc).squaredNorm() / s2 - before.sum_squares,
               outside_after = fit.residual.col(pc).squaredNorm() / s2 - left;
  const double r = std::clamp(rho, 0.0, 0.95);
  return (outside_before - outside_after) * (1 - r) / (1 + r);
}

void confirmCandidates(const ArmProblem& P, std::vector<ArmCandidate>& ranking,
                       const ArmFit& current, const std::vector<double>& sigma, double rho,
                       const std::vector<ArmPattern>& saturated, double significance_z) {
  const std::vector<ArmPattern> before =
      searchPatterns(P, current.residual, current.predicted, sigma, rho);
  // The strongest significant pattern (largest explained sum of squares in noise units).
  std::vector<const ArmPattern*> seen;
  for (const ArmPattern& p : before)
    if (p.significant && (seen.empty() || p.sum_squares > seen.front()->sum_squares))
      seen.assign(1, &p);
  if (seen.empty()) return;
  bool outside = false;  // the catalogue as a whole leaves it significant
  for (const ArmPattern& x : saturated)
    if (x.significant && x.channel == seen.front()->channel &&
        x.variable == seen.front()->variable && x.kind == seen.front()->kind)
      outside = true;
  const double drop = outside ? 1.0 : kPatternExplainedDrop;
  // A pattern does not hold back a candidate that does not touch its channel (the friction of
  // another joint), nor, when no combination of catalogue effects explains the pattern, one whose
  // held-out gain lies mostly in the other channels; one that gains mostly in the pattern's
  // channel must explain it (or halve a channel's error, below).
  int pc = -1;
  for (int c = 0; c < P.channels(); ++c)
    if (P.channel_names[c] == seen.front()->channel) pc = c;
  auto elsewhere = [&](const ArmCandidate& c) {
    if (pc < 0 || current.heldout_residual.rows() != c.fit.heldout_residual.rows()) return false;
    // A candidate that does not change the pattern channel's prediction cannot explain it.
    const double scale = current.predicted.col(pc).cwiseAbs().maxCoeff();
    if ((c.fit.predicted.col(pc) - current.predicted.col(pc)).cwiseAbs().maxCoeff() <=
        1e-12 * (1 + scale))
      return true;
    if (!outside) return false;
    double in = 0, out = 0;
    for (int i = 0; i < P.rows(); ++i)
      for (int k = 0; k < P.channels(); ++k) {
        const double g = (std::pow(current.heldout_residual(i, k), 2) -
                          std::pow(c.fit.heldout_residual(i, k), 2)) /
                         (sigma[k] * sigma[k]);
        (k == pc ? in : out) += g;
      }
    return out > in;
  };
  // The selection rule (docs/calibration.md "Selection rule"): a candidate whose fit halves the
  // held-out RMSE of a channel is a physical effect of that channel even when a
  // pattern remains (friction of a joint whose fastest moves leave a small remainder); what it
  // leaves is reported as a remainder, never as "no catalogue effect explains it". Its value is
  // physically possible: impossible candidates are refused before (status "impossible").
  auto halves = [&](const ArmCandidate& c) {
    if (current.heldout_residual.rows() != c.fit.heldout_residual.rows()) return false;
    for (int k = 0; k < P.channels(); ++k) {
      const double b = current.heldout_residual.col(k).squaredNorm(),
                   a = c.fit.heldout_residual.col(k).squaredNorm();
      if (b > 0 && a <= kHalvedMeanSquare * b) return true;
    }
    return false;
  };
  std::vector<std::string> demoted;
  for (ArmCandidate& c : ranking) {
    if (!c.significant || elsewhere(c)) continue;
    if (halves(c)) {
      c.warnings.push_back(
          "halves the held-out error of a channel and leaves the strongest "
          "residual pattern (" +
          seen.front()->description + "): the rest is reported as a remainder");
      continue;
    }
    const std::vector<ArmPattern> after =
        searchPatterns(P, c.fit.residual, c.fit.predicted, sigma, rho);
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
    // A pattern no combination of catalogue effects explains holds back only what it explains
    // (waiting for its own effect does not help: there is none): a candidate that lowers the
    // channel's residual beyond the pattern's shape by more than significance_z^2 per fitted
    // parameter (chi^2; the z-test for one) is an effect of its own, and the pattern is reported.
    const int added_params = std::max(1, c.fit.n_params - current.n_params);
    const double beyond = outside && pc >= 0 ? gainBeyondPattern(*seen.front(), after, pc, current,
                                                                 c.fit, sigma[pc], rho)
                                             : 0.0;
    if (beyond > significance_z * significance_z * added_params) {
      c.warnings.push_back("leaves the strongest residual pattern (" + seen.front()->description +
                           ") but lowers its channel beyond the pattern's shape (chi^2 " +
                           formatG(beyond, 3) + "): an effect of its own; the pattern is reported");
      continue;
    }
    c.significant = false;
    c.warnings.push_back("lowers the error but leaves the strongest residual pattern in place (" +
                         seen.front()->description + "): it does not explain it");
    demoted.push_back(c.name);
  }
  if (demoted.empty()) return;
  // The demoted ones go right behind the last candidate that is still significant.
  std::vector<ArmCandidate> keep, moved;
  for (ArmCandidate& c : ranking)
    (std::find(demoted.begin(), demoted.end(), c.name) != demoted.end() ? moved : keep)
        .push_back(std::move(c));
  std::size_t pos = 0;
  for (std::size_t k = 0; k < keep.size(); ++k)
    if (keep[k].significant) pos = k + 1;
  keep.insert(keep.begin() + static_cast<long>(pos), moved.begin(), moved.end());
  ranking = std::move(keep);
}

std::string candidateVerdictName(const ArmCandidate& c) {
  std::string others;
  for (const auto& o2 : c.indistinguishable) others += (others.empty() ? "" : ", ") + o2;
  return others.empty() ? c.name
                        : c.name + " (cannot be told apart from " + others + " with this data)";
}

}  // namespace armstudy::calibration
