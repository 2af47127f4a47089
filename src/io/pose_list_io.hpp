#pragma once
// CSV pose lists (docs/reachability.md, "Pose lists"): the file format of tasks/task_grid.hpp's
// PoseList, read with the one CSV tokenizer (io/csv_io.hpp) and the plausible magnitudes of
// io/units.hpp.
#include <string>

#include "tasks/task_grid.hpp"

namespace armstudy {

// Parses CSV text: a header `x,y,z` or `x,y,z,alpha,beta,gamma` (any order of those names), one
// pose per row, metres and radians; blank lines and lines starting with '#' are skipped.
// Throws InputError(file_label, line, column, message) for a malformed row or header, and when
// `task_space` constrains orientation but the file has no orientation columns.
PoseList parsePoseCsv(const std::string& text, const std::string& file_label,
                      const TaskSpace& task_space);
PoseList loadPoseCsv(const std::string& path, const TaskSpace& task_space);

}  // namespace armstudy
