#pragma once
// The [reach] stage as the registry sees it (study/stage.hpp).
#include "study/stage.hpp"

namespace armstudy {

const Stage& reachStage();

}  // namespace armstudy
