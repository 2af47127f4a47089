#include "engine/registry.hpp"

#include "stages/calibration/stage.hpp"
#include "stages/dexterity/stage.hpp"
#include "stages/explore/stage.hpp"
#include "stages/harvest/stage.hpp"
#include "stages/reach/stage.hpp"
#include "stages/tracking/stage.hpp"

namespace armstudy {

const std::vector<const Stage*>& stageRegistry() {
  static const std::vector<const Stage*> stages = {
      &reachStage(),        // [reach]          docs/reachability.md
      &dexterityStage(),    // [dexterity]      docs/dexterity.md
      &harvestStage(),      // [harvest]        docs/dynamics.md
      &trackingStage(),     // [[tracking]]     docs/tracking.md
      &calibrationStage(),  // [[calibration]]  docs/calibration.md
      &exploreStage(),      // [explore]        docs/exploration.md
  };
  return stages;
}

}  // namespace armstudy
