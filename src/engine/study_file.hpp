#pragma once
// Study files (docs/study-format.md): which designs (and variants derived from them) to evaluate,
// the environment, and the sections of the stages (each read by its stage, found in the registry).
#include <string>
#include <utility>
#include <vector>

#include "study/study.hpp"

namespace armstudy {

// Parses and validates a study; loads every design it names and derives the variants.
// Throws InputError (file, line, key) on bad input; nothing is written.
Study loadStudy(const std::string& path);

// Stable variant name from a base name and its overrides, e.g.
// "first_prototype_9dof+j4.x=0.35" (joint entries drop the "joint." prefix).
std::string variantName(const std::string& base,
                        const std::vector<std::pair<std::string, double>>& overrides);

}  // namespace armstudy
