#pragma once
// Private to calibration/arm_*.cpp: the fit engine every kind of measurement shares:
// bounded Gauss-Newton fits of effect sets, held-out residuals over folds, linearised confidence
// intervals, candidate columns, residual maps.
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "calibration/arm_calibration.hpp"

namespace armstudy::calibration::arm_detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Solved {
  EffectValues v;
  Eigen::MatrixXd pred;  // native
  Eigen::VectorXd r;     // flattened weighted residual
  Eigen::MatrixXd J;     // at the solution
  double ssr = 0;
};

// The problem with every channel weighted by 1 / its noise estimate: fits, ranking and
// significance then see dimensionless residuals, so channels of different units (N, N m, A, m)
// count by their own noise, not by their unit. Forwards the prediction to the problem.
class NoiseWeighted : public ArmProblem {
 public:
  NoiseWeighted(const ArmProblem& p, const Eigen::VectorXd& w) : ArmProblem(p), inner_(p) {
    weight = w;
  }
  Eigen::MatrixXd predict(const EffectValues& values) const override {
    return inner_.predict(values);
  }
  Model calibratedModel(const Model& model, const EffectValues& values,
                        std::vector<std::string>& notes) const override {
    return inner_.calibratedModel(model, values, notes);
  }

 private:
  const ArmProblem& inner_;
};

struct Engine {
  const ArmProblem& P;  // the noise-weighted problem
  std::vector<int> folds;
  int k = 5;
  Eigen::VectorXd report_weight;  // the problem's own channel weights (fit units)
  std::vector<char> at_floor;     // per channel: at the logging resolution (no effect for it)

  ArmFit make(const Solved& s, const std::string& label, bool& ok) const;  // the fit's statistics
};

// Flattened weighted residual vector (row-major: row * C + channel), and back.
Eigen::VectorXd flatten(const ArmProblem& P, const Eigen::MatrixXd& m);
Eigen::MatrixXd unflatten(const ArmProblem& P, const Eigen::VectorXd& v);
Eigen::VectorXd packX(const EffectValues& v);
double rms(const Eigen::VectorXd& r);
// Gauss-Newton from the given start values (all parameters of v are free).
Solved gaussNewton(const ArmProblem& P, EffectValues v);
// Fit of a set: the effects in `start` (a profiled effect whose value is NaN is profiled on its
// grid).
Solved fitSet(const ArmProblem& P, const EffectValues& start);
// R^2 of a column on a basis (1: fully explained).
double r2OnBasis(const Eigen::VectorXd& col, const Eigen::MatrixXd& basis);
// Candidate columns at the current values (a profiled effect at the middle of its grid).
EffectValue zeroValue(const ArmProblem& P, int e, bool profile_nan);
Eigen::MatrixXd candidateColumns(const ArmProblem& P, const EffectValues& current, int e);
ArmResidualMap residualMap(const ArmProblem& P, const Eigen::MatrixXd& res,
                           const std::vector<double>& sigma, double rho, const ArmFitOptions& o);

// arm_checks.cpp: per channel the logging resolution (the log's, else loggingResolution of the
// measured values) and whether the design's residual is at that
// floor (warned in d); why fitted values describe no possible body ("" when they do); the
// remainders of the final fit, one per channel with a significant pattern left.
void floorOfChannels(const ArmProblem& P, const Eigen::MatrixXd& residual, ArmDiagnosis& d);
// The strongest of d.patterns in a channel above the logging resolution (null when none): a
// channel at the floor is not identifiable, so no pattern there is an effect.
const ArmPattern* strongestAboveFloor(const ArmProblem& P, const ArmDiagnosis& d);
std::string impossibility(const ArmProblem& P, const ArmFit& fit);
std::vector<ArmRemainder> remaindersOf(const ArmProblem& P, const ArmDiagnosis& d,
                                       const ArmFit& fin);

}  // namespace armstudy::calibration::arm_detail
