#include "stages/tracking/stage.hpp"

#include "stages/tracking/tracking_stage.hpp"

namespace armstudy {

const Stage& trackingStage() {
  using Entries = std::vector<tracking::TrackingEntry>;
  static const FunctionStage<Entries> stage(
      "tracking",
      [](const SectionInput& in) -> std::optional<Entries> {
        Entries entries = tracking::readTrackingEntries(in.top, in.designs, in.obstacles);
        if (entries.empty()) return std::nullopt;
        return entries;
      },
      [](const StageContext& ctx, const Entries& e) { return tracking::runTrackingStage(ctx, e); });
  return stage;
}

}  // namespace armstudy
