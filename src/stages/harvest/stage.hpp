#pragma once
// The harvest stage as the registry sees it (study/stage.hpp).
#include "study/stage.hpp"

namespace armstudy {

const Stage& harvestStage();

}  // namespace armstudy
