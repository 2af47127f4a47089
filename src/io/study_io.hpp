#pragma once
// Study files (docs/study-format.md): which designs (and variants derived from them) to evaluate,
// and the settings of each evaluation stage.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "calibration/calibration_stage.hpp"
#include "collision/collision.hpp"
#include "dexterity/dexterity_map.hpp"
#include "dynamics/harvest_stage.hpp"
#include "model/model.hpp"
#include "reach/reach_config.hpp"
#include "study/regression.hpp"
#include "tracking/tracking_stage.hpp"

namespace armstudy {

// One design as a study evaluates it: a design file as written, or a variant derived from one.
struct StudyDesign {
  Model model;                 // model.name is the stable name used in every output
  std::string base_name;       // the design it derives from (== model.name for plain designs)
  std::vector<std::pair<std::string, double>> overrides;  // (entry key, SI value) applied
};

struct InputFile {
  std::string path;
  std::string hash;
};

struct Study {
  std::string name;
  std::string description;
  std::string file;
  std::string file_hash;
  std::vector<StudyDesign> designs;  // declaration order; variants follow their sweep order
  std::vector<InputFile> inputs;     // every file read (study, designs), with content hashes
  // [[obstacle]] entries: environment obstacles fixed in the task frame W (plant stems, wires,
  // the platform; docs/collision.md), checked against every design's collision volumes.
  std::vector<collision::Obstacle> obstacles;
  ReachConfig reach;                 // [reach] section (reach.enabled = present)
  RegressionSpec regression;         // [regression]: baseline path and tolerances
  std::optional<dexterity::DexterityOptions> dexterity;  // [dexterity] section (docs/dexterity.md)
  std::optional<harvest::HarvestOptions> harvest;        // [harvest] section (docs/dynamics.md)
  std::vector<tracking::TrackingEntry> tracking;         // [[tracking]] entries (docs/tracking.md)
  std::vector<calibration::CalibrationEntry> calibration;  // [[calibration]] entries (docs/calibration.md)
};

// Parses and validates a study; loads every design it names and derives the variants.
// Throws InputError (file, line, key) on bad input; nothing is written.
Study loadStudy(const std::string& path);

// Stable variant name from a base name and its overrides, e.g.
// "first_prototype_9dof+j4.x=0.35" (joint entries drop the "joint." prefix).
std::string variantName(const std::string& base,
                        const std::vector<std::pair<std::string, double>>& overrides);

}  // namespace armstudy
