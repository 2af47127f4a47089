#pragma once
// The [[calibration]] stage's report (calibration/report.md): per entry its ladder, verdict,
// fitted parameters and figures, folding the figures that repeat others.
#include <string>
#include <vector>

#include "report/document.hpp"
#include "stages/calibration/calibration_stage.hpp"

namespace armstudy::calibration {

// report.md of the stage folder `stage_dir` (relative to the study's output folder) for `entries`.
report::Document stageReport(const std::string& study, const std::vector<EntrySummary>& entries,
                             const std::string& stage_dir);

// A warning when a fit's calibrated copy, compared with the same data, misses the fit's training
// RMSE by more than 1 % (the design format could not hold every fitted value; the entry's notes
// name which); "" when it reproduces the fit or there is no copy.
std::string checkRunWarning(const EntrySummary& s);

}  // namespace armstudy::calibration
