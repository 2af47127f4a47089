#include "stages/harvest/stage.hpp"

#include "stages/harvest/harvest_stage.hpp"

namespace armstudy {

const Stage& harvestStage() {
  static const auto stage = FunctionStage<harvest::HarvestOptions>::ofTable(
      "harvest", harvest::readHarvestOptions, harvest::runHarvestStage);
  return stage;
}

}  // namespace armstudy
