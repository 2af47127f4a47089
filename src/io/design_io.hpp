#pragma once
// Design files (docs/design-format.md): one TOML file per candidate design holding the kinematic
// parameter table of thesis section 3.2 plus limits, TCP offset and optional sections.
#include <string>

#include "io/units.hpp"
#include "model/model.hpp"

namespace armstudy {

// Parses, validates and finalizes a design. Throws InputError (file, line, key) on bad input.
Model loadDesign(const std::string& path);

// Same from text (for tests and generated designs); `file_label` names it in messages.
Model parseDesign(const std::string& text, const std::string& file_label);

namespace io {
class TableReader;
}
// The tool axis at `key` (docs/design-format.md): "x", "y", "z" with an optional sign, or
// [x, y, z] (normalised), in the TCP frame; `fallback` when absent. InputError otherwise.
Eigen::Vector3d readToolAxis(io::TableReader& r, const std::string& key,
                             const Eigen::Vector3d& fallback);

// "" when `name` may name a design (it names files: letters, digits, '_', '-' and '.'), else
// the reason.
std::string designNameError(const std::string& name);

// Validates an assembled model (limits ordered and finite, unique names, ...). Used after a
// variant overrides entries. Throws InputError naming `file` and the offending key.
void validateModel(const Model& model, const std::string& file);

// Sets one table entry addressed by a dotted key, as study variants do:
//   joint.<name>.<x|y|z|alpha|beta|gamma|min|max|max_velocity>, tcp.<x..gamma>, base.<x..gamma>,
//   payload.mass. `value_si` is already in SI. Returns false with a message for an unknown key or
//   a value that is not finite or beyond the plausible magnitude of the entry's dimension.
bool setModelEntry(Model& model, const std::string& key, double value_si, std::string& error);
// The current value (SI) of an entry key; false with a message for an unknown key.
bool modelEntryValue(const Model& model, const std::string& key, double& value_si,
                     std::string& error);
// The physical dimension of an entry key (for unit checking of override values).
bool modelEntryDimension(const Model& model, const std::string& key, Dimension& dimension_out,
                         std::string& error);

}  // namespace armstudy
