#pragma once
// Study files (docs/study-format.md): which designs (and variants derived from them) to evaluate,
// the environment, and the sections of the stages (each read by its stage, found in the registry).
#include <string>
#include <utility>
#include <vector>

#include "io/variant.hpp"
#include "study/study.hpp"

namespace armstudy {

// Parses and validates a study; loads every design it names and derives the variants.
// Throws InputError (file, line, key) on bad input; nothing is written.
Study loadStudy(const std::string& path);
// The same from study text: `path` names it in messages and the manifest, relative paths in it
// (designs, data, baselines) resolve against `folder`.
Study loadStudyText(const std::string& text, const std::string& path, const std::string& folder);

// variantName and deriveVariant: io/variant.hpp.

}  // namespace armstudy
