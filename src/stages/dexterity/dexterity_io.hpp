#pragma once
// Reading the [dexterity] section of a study file (docs/dexterity.md). Throws InputError with file,
// line and key for bad input, before any work starts.
#include <vector>

#include "dexterity/dexterity_map.hpp"
#include "study/stage.hpp"

namespace armstudy::io {
class TableReader;
}

namespace armstudy::dexterity {

// Reads and validates the section; `designs` are checked against per-design settings
// (joint_weights length, enough joints for the task). Calls finish() on every reader it creates.
DexterityOptions readDexterityOptions(io::TableReader& r, const SectionInput& in);

}  // namespace armstudy::dexterity
