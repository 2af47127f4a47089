#pragma once
// The [explore] stage as the registry sees it (study/stage.hpp).
#include "study/stage.hpp"

namespace armstudy {

const Stage& exploreStage();

}  // namespace armstudy
