#pragma once
// The [dexterity] stage as the registry sees it (study/stage.hpp).
#include "study/stage.hpp"

namespace armstudy {

const Stage& dexterityStage();

}  // namespace armstudy
