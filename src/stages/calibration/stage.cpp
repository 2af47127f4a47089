#include "stages/calibration/stage.hpp"

#include "stages/calibration/calibration_stage.hpp"

namespace armstudy {

namespace {

using Entries = std::vector<calibration::CalibrationEntry>;

class CalibrationStage final : public Stage {
 public:
  std::string name() const override { return "calibration"; }
  // Data files are inputs of the study (hashed into its fingerprint and manifest).
  std::shared_ptr<const StageSettings> read(const SectionInput& in) const override {
    std::vector<std::pair<std::string, std::string>> files;
    Entries entries = calibration::readCalibrationEntries(in.top, in.study_dir, in.designs, files);
    for (const auto& [f, h] : files) in.inputs.push_back({f, h});
    if (entries.empty()) return nullptr;
    return std::make_shared<SettingsOf<Entries>>(std::move(entries));
  }
  StageResult run(const StageContext& ctx, const StageSettings& settings) const override {
    return calibration::runCalibrationStage(ctx, settingsAs<Entries>(settings));
  }
};

}  // namespace

const Stage& calibrationStage() {
  static const CalibrationStage stage;
  return stage;
}

}  // namespace armstudy
