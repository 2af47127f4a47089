#pragma once
// The calibration stage as the registry sees it (study/stage.hpp).
#include "study/stage.hpp"

namespace armstudy {

const Stage& calibrationStage();

}  // namespace armstudy
