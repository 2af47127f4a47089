#pragma once
// The steps of `armstudy compare|fit` that the [[calibration]] study stage shares with the CLI
// (docs/calibration.md): effect names and writing a fit (report plus calibrated design copy). The
// CLI and calibration_stage.cpp both call these; measurement_kind.hpp reads the data and builds
// the problem of each kind.
#include <string>
#include <utility>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "calibration/measurement_kind.hpp"
#include "model/model.hpp"

namespace armstudy::calibration {

// A drive effect by name; InputError(file, line, key) listing the names for an unknown one.
drive::Effect parseDriveEffect(const std::string& name, const std::string& file, int line,
                               const std::string& key);

// What `fit` writes after the diagnosis (every kind): the calibrated design (calibrated_design.hpp:
// the calibrated Model, named <design>_calibrated, as design TOML) at `design_path` (default
// <out_dir>/<design>_calibrated.toml), for a URDF design also the calibrated URDF beside it (same
// name, .urdf), and the report (writeArmReport, command "fit").
struct ArmFitFiles {
  ArmReportSummary report;
  std::string calibrated_design_path;
  std::string calibrated_urdf_path;  // "" unless the design is a URDF
  std::vector<std::string> notes;    // what the design format cannot carry
};
// `lock`: ArmReportOptions::lock (false inside a study run).
// No calibrated copy (calibrated_design_path empty, the reason in notes) when the data cannot
// identify the model (ArmDiagnosis::identifiable).
ArmFitFiles writeArmFit(const ArmDiagnosis& diagnosis, const ArmProblem& problem,
                        const Model& model, const std::string& out_dir,
                        const std::string& design_path, bool lock = true,
                        const std::vector<std::pair<std::string, std::string>>& extra_files = {});
// Why no calibrated design copy is written ("" when one is).
std::string noCalibratedDesign(const ArmDiagnosis& diagnosis);

}  // namespace armstudy::calibration
