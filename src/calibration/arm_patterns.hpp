#pragma once
// Private to calibration/arm_*.cpp: the unexplained-effect search: patterns left in a
// model's residuals against every operating variable, and the check that a significant catalogue
// candidate explains what is visibly there.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "calibration/arm_calibration.hpp"

namespace armstudy::calibration {

// Patterns of the residual (native units) of every channel against every variable, ranked; `sigma`
// the channels' noise, `rho` the residuals' lag-1 correlation.
std::vector<ArmPattern> searchPatterns(const ArmProblem& P, const Eigen::MatrixXd& residual,
                                       const Eigen::MatrixXd& predicted,
                                       const std::vector<double>& sigma, double rho);
// Demotes significant candidates that do not remove the strongest pattern (`saturated`: the
// patterns left by every candidate at once) and gain nothing beyond its shape (`significance_z`
// of the ranking).
void confirmCandidates(const ArmProblem& P, std::vector<ArmCandidate>& ranking,
                       const ArmFit& current, const std::vector<double>& sigma, double rho,
                       const std::vector<ArmPattern>& saturated, double significance_z);
std::string candidateVerdictName(const ArmCandidate& c);

}  // namespace armstudy::calibration
