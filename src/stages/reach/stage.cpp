#include "stages/reach/stage.hpp"

#include "stages/reach/reach_stage.hpp"

namespace armstudy {

namespace {

class ReachStage final : public Stage {
 public:
  std::string name() const override { return "reach"; }
  std::string timingName() const override { return "reachability"; }
  std::shared_ptr<const StageSettings> read(const SectionInput& in) const override {
    ReachConfig cfg;
    std::vector<std::pair<std::string, std::string>> files;
    readReachSection(in.top, in.study_dir, in.designs, in.obstacles, cfg, files);
    for (const auto& [f, h] : files) in.inputs.push_back({f, h});
    if (!cfg.enabled) return nullptr;
    return std::make_shared<SettingsOf<ReachConfig>>(std::move(cfg));
  }
  StageResult run(const StageContext& ctx, const StageSettings& settings) const override {
    return runReachStage(ctx, settingsAs<ReachConfig>(settings));
  }
};

}  // namespace

const Stage& reachStage() {
  static const ReachStage stage;
  return stage;
}

}  // namespace armstudy
