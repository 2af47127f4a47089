#include "calibration/least_squares.hpp"

#include <Eigen/QR>
#include <cmath>
#include <limits>
#include <nlopt.hpp>

#include "common/defaults.hpp"

namespace armstudy::calibration {
namespace {

struct Problem {
  const Eigen::MatrixXd* A;
  const Eigen::VectorXd* y;
};

double objective(unsigned n, const double* z, double* grad, void* data) {
  const auto* p = static_cast<const Problem*>(data);
  const Eigen::Map<const Eigen::VectorXd> zv(z, n);
  const Eigen::VectorXd r = (*p->A) * zv - *p->y;
  if (grad) Eigen::Map<Eigen::VectorXd>(grad, n) = 2.0 * p->A->transpose() * r;
  return r.squaredNorm();
}

bool inside(const Eigen::VectorXd& x, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  for (int i = 0; i < x.size(); ++i)
    if (!(x[i] >= lo[i] && x[i] <= hi[i])) return false;
  return true;
}

}  // namespace

LeastSquaresResult boundedLeastSquares(const Eigen::MatrixXd& A, const Eigen::VectorXd& y,
                                       const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  const int p = static_cast<int>(A.cols());
  LeastSquaresResult res;
  res.x = Eigen::VectorXd::Zero(p);
  if (p == 0) {
    res.ssr = y.squaredNorm();
    return res;
  }
  Eigen::VectorXd scale(p);
  for (int j = 0; j < p; ++j) {
    const double nrm = A.col(j).norm();
    scale[j] = nrm > 0 ? nrm : 1.0;
  }
  const Eigen::MatrixXd As = A * scale.cwiseInverse().asDiagonal();
  const Eigen::VectorXd los = lo.cwiseProduct(scale), his = hi.cwiseProduct(scale);

  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(As);
  qr.setThreshold(defaults::kLeastSquaresRankTolerance);
  res.rank_deficient = qr.rank() < p;
  Eigen::VectorXd z = qr.solve(y);
  if (!inside(z, los, his)) {
    res.constrained = true;
    Eigen::VectorXd z0 = z.cwiseMax(los).cwiseMin(his);
    Problem prob{&As, &y};
    nlopt::opt opt(nlopt::LD_SLSQP, static_cast<unsigned>(p));
    std::vector<double> lb(los.data(), los.data() + p), ub(his.data(), his.data() + p);
    opt.set_lower_bounds(lb);
    opt.set_upper_bounds(ub);
    opt.set_min_objective(objective, &prob);
    opt.set_xtol_rel(1e-14);
    opt.set_ftol_rel(1e-16);
    opt.set_maxeval(defaults::kLeastSquaresMaxEval);
    std::vector<double> zz(z0.data(), z0.data() + p);
    double f = 0;
    try {
      opt.optimize(zz, f);
    } catch (const std::exception&) {
      // SLSQP may stop on round-off; the point it reached is still feasible and is polished below.
    }
    z = Eigen::Map<Eigen::VectorXd>(zz.data(), p).cwiseMax(los).cwiseMin(his);
    // Active-set polish: re-solve the free variables exactly with the active ones at their bounds.
    const double tol = 1e-9;
    std::vector<int> free_idx;
    Eigen::VectorXd fixed = Eigen::VectorXd::Zero(p);
    for (int j = 0; j < p; ++j) {
      const bool at_lo = std::isfinite(los[j]) && z[j] <= los[j] + tol * (1 + std::abs(los[j]));
      const bool at_hi = std::isfinite(his[j]) && z[j] >= his[j] - tol * (1 + std::abs(his[j]));
      if (at_lo || at_hi)
        fixed[j] = at_lo ? los[j] : his[j];
      else
        free_idx.push_back(j);
    }
    if (!free_idx.empty()) {
      Eigen::MatrixXd Af(As.rows(), free_idx.size());
      for (std::size_t k = 0; k < free_idx.size(); ++k) Af.col(k) = As.col(free_idx[k]);
      const Eigen::VectorXd rhs = y - As * fixed;
      const Eigen::VectorXd zf = Af.colPivHouseholderQr().solve(rhs);
      Eigen::VectorXd cand = fixed;
      for (std::size_t k = 0; k < free_idx.size(); ++k) cand[free_idx[k]] = zf[k];
      if (inside(cand, los, his) && (As * cand - y).squaredNorm() <= (As * z - y).squaredNorm())
        z = cand;
    }
  }
  res.x = z.cwiseQuotient(scale);
  res.ssr = (A * res.x - y).squaredNorm();
  return res;
}

}  // namespace armstudy::calibration
