#include "study/tool_axis_check.hpp"

#include <algorithm>

#include "common/errors.hpp"
#include "model/model_notes.hpp"

namespace armstudy {

void requireToolAxes(const StageDesigns& d, const std::vector<const Model*>& evaluated,
                     const std::string& file, int line, const std::string& section) {
  for (const Model* m : evaluated) {
    const std::string open = notes::toolAxisOpen(*m);
    if (open.empty()) continue;
    const bool given = std::find_if(d.tool_axes.begin(), d.tool_axes.end(), [&](const auto& t) {
                         return t.first == m->name;
                       }) != d.tool_axes.end();
    if (!given)
      throw InputError(file, line, section,
                       "this stage points the tool axis at its targets, and " + open +
                           " (for this stage only: [" + section + ".tool_axis] " + m->name +
                           " = \"" + "<axis>\")");
  }
}

}  // namespace armstudy
