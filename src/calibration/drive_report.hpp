#pragma once
// The outputs of compare/fit for a drive: the one report writer of every kind (writeArmReport,
// writeArmFit; docs/calibration.md, "Outputs"), called with the drive diagnosis' engine result.
// Kept for callers written against the drive kind's own API (the [[calibration]] stage).
#include <string>
#include <vector>

#include "calibration/drive_calibration.hpp"

namespace armstudy::calibration {

struct DriveReportOptions {
  std::string out_dir;
  std::string command;  // "compare" or "fit"
  bool write_calibrated_design = false;
  std::string calibrated_design_path;            // default <out_dir>/<design>_calibrated.toml
  bool lock = true;                              // ArmReportOptions::lock
  ShownDesign shown = ShownDesign::as_designed;  // ArmReportOptions::shown
};

struct DriveReportSummary {
  std::vector<std::string> files_written;  // relative to out_dir
  std::string json;                        // the content of result.json
  std::string calibrated_design_path;
};

DriveReportSummary writeDriveReport(const DriveDiagnosis& diagnosis, const Model& model,
                                    const DriveData& data, const DriveReportOptions& options);

}  // namespace armstudy::calibration
