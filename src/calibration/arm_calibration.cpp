#include "calibration/arm_calibration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

#include "calibration/arm_engine.hpp"
#include "calibration/arm_patterns.hpp"
#include "calibration/least_squares.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"
#include "common/join.hpp"

namespace armstudy::calibration {

using namespace arm_detail;

int ArmResidualMap::flagged() const {
  int n = 0;
  for (const auto& b : bins) n += b.flagged;
  return n;
}

std::string CvSettings::validate(bool bins_ok) const {
  if (folds < 2) return "folds must be at least 2";
  if (!bins_ok) return "bin counts must be within 1.." + std::to_string(defaults::kMaxResidualBins);
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
  for (int j = 0; j < all.cols(); ++j)
    sc[j] = all.col(j).norm() > 0 ? 1.0 / all.col(j).norm() : 0.0;
  const Eigen::MatrixXd As = all * sc.asDiagonal();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(As);
  qr.setThreshold(1e-9);
  sat_r = r0 - As * qr.solve(r0);
  const int rank = static_cast<int>(qr.rank());
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(r0.size(), rank);
  leverage = Q.rowwise().squaredNorm();
  return rank;
}

// Why the data cannot identify the model ("" when they can): every row the same operating point
// (each operating variable constant), or the kind's own reasons (a joint that never moves).
std::string identifiability(const ArmProblem& P) {
  std::vector<std::string> why = P.unidentifiable;
  bool one_point = !P.variables.empty();
  std::string point;
  for (const BinVariable& v : P.variables) {
    for (double x : v.values) one_point = one_point && x == v.values.front();
    if (!v.values.empty())
      point += (point.empty() ? "" : ", ") + v.name + " = " + formatG(v.values.front(), 4) + " " +
               v.unit;
  }
  if (one_point)
    why.insert(why.begin(), "all " + std::to_string(P.rows()) +
                                " rows are the same operating point (" + point +
                                "): such data cannot tell any effect from another");
  return join(why, "; ");
}

}  // namespace

ArmDiagnosis compareArm(const ArmProblem& P, const ArmFitOptions& o) {
  if (const std::string err = o.validate(); !err.empty()) throw InputError("", 0, "options", err);
  const int min_rows = std::max(2 * o.folds, defaults::kMinResidualDof + 1);
  if (P.rows() < min_rows)
    throw InputError(
        P.file, 0, 2 * o.folds >= min_rows ? "folds" : "",
        std::to_string(P.rows()) + " rows are too few to compare and cross-validate with " +
            std::to_string(o.folds) + " folds (need at least " + std::to_string(min_rows) +
            (2 * o.folds >= min_rows ? ", two per fold; use fewer folds)" : ")"));
  ArmDiagnosis d;
  d.kind = P.kind;
  d.design = P.design;
  d.file = P.file;
  d.warnings = P.warnings;
  d.identifiable = identifiability(P);
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
    d.warnings.push_back(
        "too few rows for the noise estimate (" + std::to_string(rank) +
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
  floorOfChannels(P, P.measured - pred0, d);
  if (enough) d.saturated_residual = sat;
  double rho_sum = 0;
  for (int c = 0; c < C; ++c) {
    std::vector<double> col(P.rows());
    for (int i = 0; i < P.rows(); ++i) col[i] = sat(i, c);
    rho_sum += lag1Autocorrelation(col);
  }
  d.noise_rho = rho_sum / C;

  const NoiseWeighted W(P, noiseWeights(P, d.channel_noise));
  Engine eng{W, foldAssignment(P.rows(), o.folds, o.seed), o.folds, P.weight, {}};
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

// Whether a candidate's columns add anything to the model's basis; warns on the columns that
// have no effect or cannot be told apart from the basis.
bool identifiable(const ArmProblem& P, const EffectValues& current, const Eigen::MatrixXd& cols,
                  const Eigen::MatrixXd& basis, const ArmEffect& info, ArmCandidate& cand) {
  // The effects of the model a column cannot be told apart from (each one's own columns explain
  // it to R^2 > kCollinearR2): named, so the pair is reported before either value is trusted.
  auto partners = [&](const Eigen::VectorXd& col) {
    std::vector<std::string> out;
    int k0 = 0;
    for (const EffectValue& v : current) {
      const int n = static_cast<int>(v.x.size());
      if (k0 + n <= basis.cols() && n > 0 &&
          r2OnBasis(col, basis.middleCols(k0, n)) > defaults::kCollinearR2)
        out.push_back(P.catalogue[v.effect].name);
      k0 += n;
    }
    return out;
  };
  bool dead = true;
  for (int j = 0; j < cols.cols(); ++j) {
    const double r2 = r2OnBasis(cols.col(j), basis);
    if (cols.col(j).norm() == 0) {
      cand.warnings.push_back(
          "parameter '" + info.params[j].key +
          "' has no effect on the predicted channels with this data (an operating variable it "
          "needs is constant or zero)");
      continue;
    }
    if (r2 > defaults::kCollinearR2) {
      const std::vector<std::string> who = partners(cols.col(j));
      std::string names;
      for (const std::string& w : who) {
        names += (names.empty() ? "" : ", ") + w;
        if (std::find(cand.indistinguishable.begin(), cand.indistinguishable.end(), w) ==
            cand.indistinguishable.end())
          cand.indistinguishable.push_back(w);
      }
      cand.warnings.push_back("parameter '" + info.params[j].key + "' cannot be told apart from " +
                              (names.empty() ? std::string("the terms already in the model")
                                             : "'" + names + "' already in the model") +
                              " (R^2 = " + formatG(r2, 4) + ") with this data");
    }
    if (r2 <= defaults::kUnidentifiableR2) dead = false;
  }
  return !dead;
}

// The t statistic of the paired held-out squared-error differences per row (all channels of a
// row together, each weighted by 1 / its noise: P is the noise-weighted problem).
double pairedTStatistic(const ArmProblem& P, const ArmFit& base, const ArmFit& fit,
                        double noise_rho) {
  std::vector<double> dd(P.rows());
  for (int i = 0; i < P.rows(); ++i) {
    double s = 0;
    for (int c = 0; c < P.channels(); ++c) {
      const double a = base.heldout_residual(i, c) * P.weight[c],
                   b = fit.heldout_residual(i, c) * P.weight[c];
      s += a * a - b * b;
    }
    dd[i] = s;
  }
  const double md = mean(dd);
  double var = 0;
  for (double x : dd) var += (x - md) * (x - md);
  var /= std::max(1, P.rows() - 1);
  const double neff = effectiveSampleSize(P.rows(), noise_rho);
  return var > 0 ? md / std::sqrt(var / neff) : (md > 0 ? kInf : 0.0);
}

// Relative held-out improvement (noise-weighted RMS) in the channels whose prediction the candidate
// changes: an effect of one joint is judged on that joint's channel, not diluted by channels it
// cannot touch (whose residuals may hold patterns no candidate explains).
double touchedImprovement(const ArmProblem& P, const ArmFit& base, const ArmFit& fit) {
  double b = 0, f = 0;
  for (int c = 0; c < P.channels(); ++c) {
    const double scale =
        base.predicted.col(c).cwiseAbs().maxCoeff() + fit.predicted.col(c).cwiseAbs().maxCoeff();
    if ((fit.predicted.col(c) - base.predicted.col(c)).cwiseAbs().maxCoeff() <= 1e-12 * (1 + scale))
      continue;
    const double w = P.weight[c] * P.weight[c];
    b += base.heldout_residual.col(c).squaredNorm() * w;
    f += fit.heldout_residual.col(c).squaredNorm() * w;
  }
  return b > 0 ? (std::sqrt(b) - std::sqrt(f)) / std::sqrt(b) : 0.0;
}

// Catalogue effect e added to the current model: identifiability, fit, improvement and
// significance; its columns outside the basis go into resid_cols when identifiable.
ArmCandidate scoreCandidate(const ArmProblem& P, const Engine& eng, const EffectValues& current,
                            const ArmFit& base, const Eigen::MatrixXd& basis, int e,
                            double noise_rho, const ArmFitOptions& o,
                            std::map<int, Eigen::MatrixXd>& resid_cols) {
  const int N = P.rows() * P.channels();
  const ArmEffect& info = P.catalogue[e];
  ArmCandidate cand;
  cand.effect = e;
  cand.name = info.name;
  const Eigen::MatrixXd cols = candidateColumns(P, current, e);
  if (!identifiable(P, current, cols, basis, info, cand)) {
    cand.status = "unidentifiable";
    return cand;
  }
  if (!eng.at_floor.empty()) {  // every channel it touches at the logging resolution: not fitted
    bool live = false;
    std::string where;
    for (int c = 0; c < P.channels(); ++c) {
      bool touched = false;
      for (int i = 0; i < P.rows() && !touched; ++i)
        touched = cols.row(i * P.channels() + c).cwiseAbs().maxCoeff() > 0;
      if (!touched) continue;
      if (eng.at_floor[c])
        where += (where.empty() ? "" : ", ") + P.channel_names[c];
      else
        live = true;
    }
    if (!live && !where.empty()) {
      cand.status = "at_floor";
      cand.warnings.push_back("not identifiable from these logs: " + where +
                              " at the logging resolution");
      return cand;
    }
  }
  Eigen::MatrixXd rc = cols;
  if (basis.cols() > 0) rc = cols - basis * basis.colPivHouseholderQr().solve(cols);
  resid_cols[e] = rc;
  const int p = static_cast<int>(packX(current).size() + info.params.size());
  if (N * (o.folds - 1) / o.folds < p + defaults::kMinResidualDof) {
    cand.status = "too_few_rows";
    cand.warnings.push_back("too few rows to fit and cross-validate " + std::to_string(p) +
                            " parameters");
    return cand;
  }
  EffectValues v = current;
  v.push_back(zeroValue(P, e, true));
  bool ok = false;
  cand.fit = eng.make(fitSet(P, v), "+" + info.name, ok);
  if (!ok) {
    cand.status = "too_few_rows";
    cand.warnings.push_back("too few rows to fit and cross-validate " + std::to_string(p) +
                            " parameters");
    return cand;
  }
  if (const std::string why = impossibility(P, cand.fit); !why.empty()) {
    cand.status = "impossible";
    cand.warnings.push_back("refused: " + why);
    return cand;
  }
  cand.improvement = touchedImprovement(P, base, cand.fit);
  cand.t_statistic = pairedTStatistic(P, base, cand.fit, noise_rho);
  cand.significant =
      cand.t_statistic > o.significance_z && cand.improvement >= o.min_relative_improvement;
  return cand;
}

// Candidates that cannot be told apart from each other: a parameter column of one lies in the
// span of another candidate's columns (after removing what the model already explains).
void markIndistinguishable(const ArmProblem& P, std::vector<ArmCandidate>& out,
                           std::map<int, Eigen::MatrixXd>& resid_cols) {
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
                               "' cannot be told apart from the candidate '" + b.name +
                               "' (R^2 = " + formatG(r2, 4) + ") with this data");
          a.indistinguishable.push_back(b.name);
          warned = true;
        }
      }
      if (all_in) a.contained_in.push_back(b.name);
    }
  }
}

// Fitted candidates first, by held-out score; then the parsimony moves.
void sortCandidates(std::vector<ArmCandidate>& out) {
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
      const bool inside =
          std::find(a.contained_in.begin(), a.contained_in.end(), b.name) != a.contained_in.end();
      if (!inside || a.fit.n_params >= b.fit.n_params ||
          a.fit.heldout_score > b.fit.heldout_score * (1 + defaults::kParsimonyTolerance))
        break;
      std::swap(out[k - 1], out[k]);
      --k;
    }
  }
}

// Every catalogue effect not yet in the model, scored against `base`, then ranked.
std::vector<ArmCandidate> rank(const ArmProblem& P, const Engine& eng, const EffectValues& current,
                               const ArmFit& base, const Solved& base_solved, double noise_rho,
                               const ArmFitOptions& o) {
  std::vector<ArmCandidate> out;
  const int N = P.rows() * P.channels();
  const Eigen::MatrixXd basis = base_solved.J.cols() > 0 ? base_solved.J : Eigen::MatrixXd(N, 0);
  std::map<int, Eigen::MatrixXd> resid_cols;
  for (std::size_t ei = 0; ei < P.catalogue.size(); ++ei) {
    const int e = static_cast<int>(ei);
    if (findValue(current, e)) continue;
    out.push_back(scoreCandidate(P, eng, current, base, basis, e, noise_rho, o, resid_cols));
  }
  markIndistinguishable(P, out, resid_cols);
  sortCandidates(out);
  return out;
}

// A candidate that scores best but is not significant (many parameters fitting part of a pattern
// no catalogue effect explains) does not hide the significant ones behind it.
void significantFirst(std::vector<ArmCandidate>& ranking) {
  std::stable_partition(ranking.begin(), ranking.end(),
                        [](const ArmCandidate& c) { return c.significant; });
}

}  // namespace

ArmDiagnosis diagnoseArm(const ArmProblem& P0, const ArmFitOptions& o) {
  ArmDiagnosis d = compareArm(P0, o);
  const bool identifiable =
      d.identifiable.empty();  // otherwise ranked (statuses shown), nothing added
  const NoiseWeighted P(P0, noiseWeights(P0, d.channel_noise));
  Engine eng{P, foldAssignment(P.rows(), o.folds, o.seed), o.folds, P0.weight, d.channel_at_floor};
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
  std::vector<std::string> to_add = P0.added_first;
  to_add.insert(to_add.end(), o.add.begin(), o.add.end());
  for (std::size_t k = 0; identifiable && k < to_add.size(); ++k) {
    const std::string& name = to_add[k];
    const int e = P.findEffect(name);
    if (e < 0) {
      throw InputError("", 0, "--add",
                       "unknown effect '" + name +
                           "' for this design and data (candidates: " + P.effectNames() + ")");
    }
    // Without the effects every fit adds first there is no model to rank from.
    if (!addEffect(e, false) && k < P0.added_first.size())
      throw InputError(P0.file, 0, "",
                       std::to_string(P0.rows()) +
                           " rows are too few to fit and cross-validate the " +
                           std::to_string(P.catalogue[e].params.size()) + " parameters of '" +
                           name + "' (" + P.catalogue[e].pattern + "), which every fit adds first");
  }
  // Patterns the most flexible model leaves: what no combination of catalogue effects explains.
  const std::vector<ArmPattern> saturated =
      d.saturated_residual.size() ? searchPatterns(P, d.saturated_residual, d.as_designed.predicted,
                                                   d.channel_noise, d.noise_rho)
                                  : std::vector<ArmPattern>{};
  ranking = rank(P, eng, current, cur, cur_solved, d.noise_rho, o);
  confirmCandidates(P, ranking, cur, d.channel_noise, d.noise_rho, saturated, o.significance_z);
  significantFirst(ranking);
  d.ranking = ranking;
  d.missing_effect_found = !ranking.empty() && ranking.front().significant;
  std::vector<std::string> named;
  if (d.missing_effect_found) named.push_back(candidateVerdictName(ranking.front()));
  if (o.auto_add && identifiable)
    for (bool first = true; !ranking.empty() && ranking.front().significant; first = false) {
      const std::string name = candidateVerdictName(ranking.front());
      if (!addEffect(ranking.front().effect, true)) break;
      if (!first) named.push_back(name);  // the first one is named above
      ranking = rank(P, eng, current, cur, cur_solved, d.noise_rho, o);
      confirmCandidates(P, ranking, cur, d.channel_noise, d.noise_rho, saturated, o.significance_z);
      significantFirst(ranking);
    }
  d.final_fit = cur;
  d.final_map = residualMap(P, cur.residual, d.channel_noise, d.noise_rho, o);
  // What the catalogue leaves: patterns in the final residuals. They are an unexplained effect when
  // no significant candidate is left for the final model (otherwise the candidate comes first).
  d.patterns = searchPatterns(P, cur.residual, cur.predicted, d.channel_noise, d.noise_rho);
  const ArmPattern* strongest = strongestAboveFloor(P, d);
  const bool candidate_left = !ranking.empty() && ranking.front().significant;
  d.unexplained_found = !candidate_left && strongest && strongest->significant;
  d.remainders = remaindersOf(P, d, cur);
  for (const ArmRemainder& r : d.remainders) d.warnings.push_back(r.text());
  std::string verdict;
  if (!named.empty()) {
    verdict = (named.size() > 1 ? "missing effects: " : "missing effect: ");
    for (std::size_t k = 0; k < named.size(); ++k) verdict += (k ? ", " : "") + named[k];
  }
  if (d.unexplained_found) {
    const ArmPattern& p = *strongest;
    bool halved = false;  // catalogue effects halved the channel's error: a remainder of them
    for (const ArmRemainder& r : d.remainders)
      halved = halved || (r.channel == p.channel && r.explained_by_catalogue);
    const std::string u =
        halved ? "a remainder in channel " + p.channel + " against " + p.variable + " (" +
                     p.description + ") after the catalogue effects halved its error"
               : "unexplained effect in channel " + p.channel + " against " + p.variable + " (" +
                     p.description + "): no catalogue effect explains it";
    verdict = verdict.empty() ? u : verdict + "; then " + u;
  }
  d.verdict = verdict.empty() ? "no significant missing effect" : verdict;
  if (!identifiable) d.verdict = "not identifiable: " + d.identifiable;
  d.rmse_before = d.as_designed.heldout_rmse;
  d.rmse_after = cur.heldout_rmse;
  return d;
}

EffectValue parseHiddenEffect(const ArmProblem& P, const std::string& spec) {
  const auto colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  const int e = P.findEffect(name);
  if (e < 0) {
    throw InputError(
        "", 0, "--hide",
        "unknown effect '" + name + "' for this design (candidates: " + P.effectNames() + ")");
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
    if (eq == std::string::npos)
      throw InputError("", 0, "--hide", "expected key=value in '" + item + "'");
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
    if (!found)
      throw InputError("", 0, "--hide",
                       "parameter '" + key + "' does not belong to the effect '" + name + "'");
  }
  return v;
}

}  // namespace armstudy::calibration
