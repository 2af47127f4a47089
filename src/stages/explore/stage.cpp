#include "stages/explore/stage.hpp"

#include "stages/explore/explore.hpp"

namespace armstudy {

const Stage& exploreStage() {
  static const auto stage = FunctionStage<explore::ExploreOptions>::ofTable(
      "explore", explore::readExploreOptions, explore::runExploreStage);
  return stage;
}

}  // namespace armstudy
