#pragma once
// The calibrated design of a fit (docs/calibration.md, "Outputs"): the design's Model with the
// fitted values applied by the problem's kind (ArmProblem::calibratedModel), written by the
// design writers: a design TOML (designToToml: every value at full round-trip precision) and, for
// a URDF design, a calibrated URDF (exportUrdf: the joints' `<dynamics damping friction>`, the
// inertials, the base pose) whose header comment names the fitted values URDF cannot hold.
#include <string>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "model/model.hpp"

namespace armstudy::calibration {

struct CalibratedDesign {
  Model model;       // named <design>_calibrated
  std::string toml;  // the design TOML text (read back into `model`'s values)
  std::string urdf;  // the calibrated URDF text for a URDF design; "" otherwise
  // Fitted values the calibrated URDF cannot hold (the TOML holds them), one phrase each.
  std::vector<std::string> urdf_cannot_hold;
};

// The first line of every calibrated design TOML (shownDesign recognises a calibrated copy by it).
inline constexpr const char* kCalibratedDesignHeader = "# Calibrated copy of design '";

// `notes` gets what the Model cannot hold (from the kind) and, for a URDF design, what URDF
// cannot hold.
CalibratedDesign calibratedDesign(const Model& design, const ArmProblem& problem,
                                  const EffectValues& values, std::vector<std::string>& notes);

// Whether a design comes from a URDF file (by its file name).
bool isUrdfDesign(const Model& design);

}  // namespace armstudy::calibration
