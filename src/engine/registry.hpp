#pragma once
// The registry: the one place that names the concrete stages (docs/architecture.md, "Stages").
// Their order is the order in which a study runs them and reads their sections.
#include <vector>

#include "study/stage.hpp"

namespace armstudy {

const std::vector<const Stage*>& stageRegistry();

}  // namespace armstudy
