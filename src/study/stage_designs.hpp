#pragma once
// The designs a stage evaluates and the tool axes it gives them, the same keys in every stage that
// evaluates designs (docs/study-format.md, "Designs per stage"):
//   designs = ["a", "b"]        # the study's designs this stage evaluates (default: all)
//   [<section>.tool_axis]       # per evaluated design, for this stage only
//   a = "y"                     # or "-z", or [x, y, z] in the TCP frame
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "model/model.hpp"
#include "study/study.hpp"

namespace armstudy {

namespace io {
class TableReader;
}

struct StageDesigns {
  std::vector<std::string> names;  // empty: all
  std::vector<std::pair<std::string, Eigen::Vector3d>> tool_axes;
  // The study with only the named designs (study order) and the tool axes applied.
  Study select(const Study& study) const;
  // The models of `models` this stage evaluates, in study order.
  std::vector<const Model*> evaluated(const std::vector<const Model*>& models) const;
};

// Reads `designs` and the table `tool_axis` of a stage's section `r` (`file` names the study file
// for errors); an unknown design lists the ones there are.
StageDesigns readStageDesigns(io::TableReader& r, const std::string& file,
                              const std::vector<const Model*>& models);

}  // namespace armstudy
