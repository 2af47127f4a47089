#pragma once
// The registry: the one place that names and makes the concrete stages (docs/architecture.md,
// "Stages"). Their order is the order in which a study runs them and reads their sections.
#include <string>
#include <vector>

#include "study/stage.hpp"

namespace armstudy {

const std::vector<const Stage*>& stageRegistry();
// The registered stage of that name (a programming error when there is none).
const Stage& registeredStage(const std::string& name);

}  // namespace armstudy
