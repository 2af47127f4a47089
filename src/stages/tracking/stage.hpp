#pragma once
// The tracking stage as the registry sees it (study/stage.hpp).
#include "study/stage.hpp"

namespace armstudy {

const Stage& trackingStage();

}  // namespace armstudy
