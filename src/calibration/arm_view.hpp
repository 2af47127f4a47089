#pragma once
// Where in the workspace a model fails: the residuals of an arm fit (tcp and trajectory kinds) at
// the TCP position of each data row, as maps of the study's 3-D view (report/view3d.hpp).
#include <string>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "model/model.hpp"
#include "report/view3d.hpp"

namespace armstudy::calibration {

// The maps of entry `entry` (the design before the fit, and after it when effects were added): one
// per model and channel, or one per model for TCP data (the length of the position error, mm; the
// orientation channels, when measured, are in the report's figures).
// Each point is a data row's TCP position, its value the residual's magnitude, its status whether
// the row's workspace cell is flagged; the arm stands at the row of the largest residual. None
// when the data have no workspace positions (the drive kind).
std::vector<report::ViewCloud> residualViewClouds(const ArmDiagnosis& d, const ArmProblem& P,
                                                  const Model& model, const std::string& entry);

}  // namespace armstudy::calibration
