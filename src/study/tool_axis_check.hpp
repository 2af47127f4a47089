#pragma once
// The check of the stages that point a design's tool axis at their targets (the spraying task of
// [reach], the stem task of [dexterity]).
#include <string>
#include <vector>

#include "study/stage_designs.hpp"

namespace armstudy {

// Refuses a design that leaves its tool axis open (notes::kToolAxisOpen: a URDF arm whose TCP is
// off its last joint's axis) and gets none from the stage (`d`'s tool_axis table): InputError at
// `line` of the study `file`, key `section`, with the candidates.
void requireToolAxes(const StageDesigns& d, const std::vector<const Model*>& evaluated,
                     const std::string& file, int line, const std::string& section);

}  // namespace armstudy
