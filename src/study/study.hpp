#pragma once
// A loaded study (docs/study-format.md): which designs (and variants derived from them) to
// evaluate, the environment, the regression settings, and the settings of each stage whose
// section the study file holds. engine/study_file.hpp reads it; engine/run.hpp runs it.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "collision/collision.hpp"
#include "model/model.hpp"
#include "study/regression.hpp"

namespace armstudy {

class Stage;

// One design as a study evaluates it: a design file as written, or a variant derived from one.
struct StudyDesign {
  Model model;            // model.name is the stable name used in every output
  std::string base_name;  // the design it derives from (== model.name for plain designs)
  std::vector<std::pair<std::string, double>> overrides;  // (entry key, SI value) applied
  // [[design]] reference_reach_m: a reach to compare the largest reach found with (a datasheet's;
  // 0 = none; variants have none).
  double reference_reach_m = 0;
};

struct InputFile {
  std::string path;
  std::string hash;
};

// A stage's settings as read from its study section (immutable once read). Each stage keeps its
// own type behind this (study/stage.hpp: SettingsOf<T>).
struct StageSettings {
  virtual ~StageSettings() = default;
};

// One stage the study runs, with its settings; in registry order.
struct StudySection {
  const Stage* stage = nullptr;
  std::shared_ptr<const StageSettings> settings;
};

struct Study {
  std::string name;
  std::string description;
  // The question the study answers (report.md and report.html open with it, above the answer).
  std::string question;
  // The study's own assumptions (values the study chooses that its results depend on: a stem
  // circle's radius, fruit heights): listed under the answer.
  std::vector<std::string> assumptions;
  std::string file;
  std::string file_hash;
  std::vector<StudyDesign> designs;  // declaration order; variants follow their sweep order
  std::vector<InputFile> inputs;     // every file read (study, designs, data), with content hashes
  // [[obstacle]] entries: environment obstacles fixed in the task frame W (plant stems, wires,
  // the platform; docs/collision.md), checked against every design's collision volumes.
  std::vector<collision::Obstacle> obstacles;
  RegressionSpec regression;           // [regression]: baseline path and tolerances
  std::vector<StudySection> sections;  // the stages whose sections are present, registry order

  // The settings a stage named `stage` read, or null when the study has no such section.
  const StageSettings* settings(const std::string& stage) const;
  std::vector<const Model*> models() const;  // &designs[i].model, study order
};

}  // namespace armstudy
