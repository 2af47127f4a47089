#include "stages/calibration/stage.hpp"

#include "stages/calibration/calibration_stage.hpp"

namespace armstudy {

const Stage& calibrationStage() {
  using Entries = std::vector<calibration::CalibrationEntry>;
  static const FunctionStage<Entries> stage(
      "calibration",
      [](const SectionInput& in) -> std::optional<Entries> {
        // Data files are inputs of the study (hashed into its fingerprint and manifest).
        std::vector<std::pair<std::string, std::string>> files;
        Entries entries = calibration::readCalibrationEntries(in.top, in.study_dir, in.designs, files);
        for (const auto& [f, h] : files) in.inputs.push_back({f, h});
        if (entries.empty()) return std::nullopt;
        return entries;
      },
      [](const StageContext& ctx, const Entries& e) { return calibration::runCalibrationStage(ctx, e); });
  return stage;
}

}  // namespace armstudy
