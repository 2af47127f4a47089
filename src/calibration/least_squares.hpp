#pragma once
// Bound-constrained linear least squares: min ||A x - y||^2 subject to lo <= x <= hi.
#include <Eigen/Core>

namespace armstudy::calibration {

struct LeastSquaresResult {
  Eigen::VectorXd x;
  double ssr = 0;               // sum of squared residuals at x
  bool constrained = false;     // some bound is active
  bool rank_deficient = false;  // A has (numerically) dependent columns
};

// Columns are scaled to unit norm; the unconstrained solution (column-pivoting QR) is taken when it
// lies within the bounds, otherwise NLopt SLSQP solves the bounded problem and an active-set
// polish re-solves the free variables exactly. Bounds may be +-infinity.
LeastSquaresResult boundedLeastSquares(const Eigen::MatrixXd& A, const Eigen::VectorXd& y,
                                       const Eigen::VectorXd& lo, const Eigen::VectorXd& hi);

}  // namespace armstudy::calibration
