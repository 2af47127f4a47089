#pragma once
// Deriving a variant from a design (docs/study-format.md "Variants", docs/exploration.md): table
// entries overridden by dotted keys (io/design_io.hpp setModelEntry), then the geometry that
// follows (model/geometry_follows.hpp: collision volumes and inertias of the links whose length
// changed), then validation. The one place [[variant]] entries and the explore stage derive
// designs.
#include <string>
#include <utility>
#include <vector>

#include "model/model.hpp"

namespace armstudy {

using Overrides = std::vector<std::pair<std::string, double>>;  // (entry key, SI value), in order

// Stable variant name from a base name and its overrides, e.g.
// "first_prototype_9dof+j4.x=0.35" (joint entries drop the "joint." prefix).
std::string variantName(const std::string& base, const Overrides& overrides);

// Throws InputError naming `file`, `line` and the override key when variantName(base, overrides)
// is not a plain name (common/names.hpp: letters, digits and "_-.+="), e.g. for a joint whose
// name holds quotes, spaces or '/'.
void checkVariantName(const std::string& base, const Overrides& overrides, const std::string& file,
                      int line);

// How a variant's collision volumes and inertias relate to its table (docs/study-format.md):
// Follows (default) adapts them to moved link ends (a design change); Fixed keeps the base
// design's (the variant is the same physical arm, e.g. a table entry carrying a calibration error).
enum class VariantGeometry { Follows, Fixed };

// The variant of `base` with `overrides` applied, named variantName(base.name, overrides).
// Throws InputError naming `file`, `line` and the key on an unknown key, a name that is not plain
// (checkVariantName) or an invalid result.
Model deriveVariant(const Model& base, const Overrides& overrides, const std::string& file,
                    int line, VariantGeometry geometry = VariantGeometry::Follows);

}  // namespace armstudy
