#pragma once
// Writing the results of compare/fit for a drive (docs/calibration.md, "Outputs"):
//   result.json            machine-readable result (kind, rmse, noise_estimate, ranking, regions, ...)
//   residuals.csv          per row: operating point, measured, predicted, residuals
//   plots/*.svg            measured vs predicted, residual vs speed/load/temperature, residual maps
//   history.csv            one row per model per run, appended (the "error ladder")
//   error_ladder.svg       drawn from the whole history
//   <design>_calibrated.toml  (fit) the design with the fitted friction parameters and effects
#include <string>
#include <vector>

#include "calibration/drive_calibration.hpp"

namespace armstudy::calibration {

struct DriveReportOptions {
  std::string out_dir;
  std::string command;              // "compare" or "fit"
  bool write_calibrated_design = false;
  std::string calibrated_design_path;  // default <out_dir>/<design>_calibrated.toml
};

struct DriveReportSummary {
  std::vector<std::string> files_written;  // relative to out_dir
  std::string json;                        // the content of result.json
  std::string calibrated_design_path;
};

DriveReportSummary writeDriveReport(const DriveDiagnosis& diagnosis, const Model& model,
                                    const DriveData& data, const DriveReportOptions& options);

// TOML text of `calibrated`'s design file: the original file (model.file) with the drive's
// [drive.friction] table, [model].effects and the design name replaced. Re-parsed before it is
// returned (a round trip through the design reader).
std::string calibratedDesignToml(const Model& original, const Model& calibrated, const std::string& joint,
                                 const std::string& note);

}  // namespace armstudy::calibration
