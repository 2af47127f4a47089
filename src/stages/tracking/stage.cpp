#include "stages/tracking/stage.hpp"

#include "stages/tracking/tracking_stage.hpp"

namespace armstudy {

namespace {

using Entries = std::vector<tracking::TrackingEntry>;

class TrackingStage final : public Stage {
 public:
  std::string name() const override { return "tracking"; }
  std::shared_ptr<const StageSettings> read(const SectionInput& in) const override {
    Entries entries = tracking::readTrackingEntries(in.top, in.designs, in.obstacles);
    if (entries.empty()) return nullptr;
    return std::make_shared<SettingsOf<Entries>>(std::move(entries));
  }
  StageResult run(const StageContext& ctx, const StageSettings& settings) const override {
    return tracking::runTrackingStage(ctx, settingsAs<Entries>(settings));
  }
};

}  // namespace

const Stage& trackingStage() {
  static const TrackingStage stage;
  return stage;
}

}  // namespace armstudy
