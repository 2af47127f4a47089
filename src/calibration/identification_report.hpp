#pragma once
// The identification report of a trajectory fit on measured logs (docs/calibration.md, "Bring your
// own robot's logs"): the error ladder per joint held out by time block, the order in which each
// joint's effects were added, the fitted values next to another identification's values, how the
// Coulomb and viscous coefficients move when the width of the friction law's smooth sign varies
// over a factor 10, and the residuals before and after on one scale.
#include <string>
#include <utility>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "calibration/trajectory_calibration.hpp"
#include "model/model.hpp"

namespace armstudy::calibration {

struct IdentificationInput {
  std::string reference_source;
  std::vector<std::pair<std::string, double>> reference;  // effect instance -> value (SI)
  std::vector<double> width_factors = {0.316, 0.562, 1.0, 1.78, 3.16};  // x the rule's width
};

struct IdentificationReport {
  std::string markdown;  // identification.md
  std::string svg;       // residuals_before_after.svg
  std::vector<std::pair<std::string, double>>
      metrics;  // name -> value (per-joint ladder, fits, sweep)
  // The answer in the user's terms, one sentence per joint (by name: the effect named first, the
  // held-out error before -> after and the factor, the remainder), then the fitted values next to
  // the reference's.
  std::vector<std::string> answer;
};

IdentificationReport identificationReport(const ArmDiagnosis& d, const ArmProblem& P,
                                          const Model& model, const TrajectoryData& data,
                                          const IdentificationInput& in);

}  // namespace armstudy::calibration
