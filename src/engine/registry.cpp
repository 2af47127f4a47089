#include "engine/registry.hpp"

#include <algorithm>

#include "common/errors.hpp"
#include "stages/calibration/calibration_stage.hpp"
#include "stages/dexterity/dexterity_io.hpp"
#include "stages/dexterity/dexterity_output.hpp"
#include "stages/explore/explore.hpp"
#include "stages/harvest/harvest_stage.hpp"
#include "stages/reach/reach_stage.hpp"
#include "stages/tracking/tracking_stage.hpp"

namespace armstudy {

namespace {

// [reach] and its pose-list files, which are inputs of the study too.
std::optional<ReachConfig> readReach(const SectionInput& in) {
  ReachConfig cfg;
  std::vector<std::pair<std::string, std::string>> files;
  readReachSection(in.top, in.study_dir, in.designs, in.obstacles, cfg, files);
  for (const auto& [f, h] : files) in.inputs.push_back({f, h});
  if (!cfg.enabled) return std::nullopt;
  return cfg;
}

}  // namespace

// Each stage is a FunctionStage made of its section reader and its run function
// (study/stage.hpp): `ofTable` for a section that is one table [name], `ofEntries` for a list of
// [[name]] entries.
const std::vector<const Stage*>& stageRegistry() {
  static const FunctionStage<ReachConfig> reach_stage("reach", readReach, runReachStage,
                                                      "reachability");
  static const auto dexterity_stage = FunctionStage<dexterity::DexterityOptions>::ofTable(
      "dexterity", dexterity::readDexterityOptions, dexterity::runDexterityStage);
  static const auto harvest_stage = FunctionStage<harvest::HarvestOptions>::ofTable(
      "harvest", harvest::readHarvestOptions, harvest::runHarvestStage);
  static const auto tracking_stage = FunctionStage<std::vector<tracking::TrackingEntry>>::ofEntries(
      "tracking", tracking::readTrackingEntries, tracking::runTrackingStage);
  static const auto calibration_stage =
      FunctionStage<std::vector<calibration::CalibrationEntry>>::ofEntries(
          "calibration", calibration::readCalibrationEntries, calibration::runCalibrationStage);
  static const auto explore_stage = FunctionStage<explore::ExploreOptions>::ofTable(
      "explore", explore::readExploreOptions, explore::runExploreStage);
  static const std::vector<const Stage*> stages = {
      &reach_stage,        // [reach]          docs/reachability.md
      &dexterity_stage,    // [dexterity]      docs/dexterity.md
      &harvest_stage,      // [harvest]        docs/dynamics.md
      &tracking_stage,     // [[tracking]]     docs/tracking.md
      &calibration_stage,  // [[calibration]]  docs/calibration.md
      &explore_stage,      // [explore]        docs/exploration.md
  };
  return stages;
}

const Stage& registeredStage(const std::string& name) {
  const auto& stages = stageRegistry();
  const auto it =
      std::find_if(stages.begin(), stages.end(), [&](const Stage* s) { return s->name() == name; });
  ARMSTUDY_CHECK(it != stages.end(), "no stage named " + name);
  return **it;
}

}  // namespace armstudy
