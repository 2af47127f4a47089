#include "stages/tracking/stage.hpp"

#include "stages/tracking/tracking_stage.hpp"

namespace armstudy {

const Stage& trackingStage() {
  static const auto stage = FunctionStage<std::vector<tracking::TrackingEntry>>::ofEntries(
      "tracking", tracking::readTrackingEntries, tracking::runTrackingStage);
  return stage;
}

}  // namespace armstudy
