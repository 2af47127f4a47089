#include "stages/calibration/stage.hpp"

#include "stages/calibration/calibration_stage.hpp"

namespace armstudy {

const Stage& calibrationStage() {
  static const auto stage = FunctionStage<std::vector<calibration::CalibrationEntry>>::ofEntries(
      "calibration", calibration::readCalibrationEntries, calibration::runCalibrationStage);
  return stage;
}

}  // namespace armstudy
