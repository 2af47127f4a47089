#pragma once
// Reading the approach-planner settings from a study file (docs/dynamics.md, "[approach]").
//
//   [approach]
//   entry_radius = "100 mm"   # r_e (length)
//   s_a = 0.1                 # tuning parameters of eq. (5.18)
//   s_e = 0.8
//   duration = 2.0            # T [s], > 0
//   exp_scale = "1 m"         # optional, L of eq. (5.17)
//   alpha_goal = 0            # optional goal Cardan angles (angle), default 0
//   beta_goal = 0
//   gamma_offset = 0          # optional offset of the goal gamma from the approach heading
//
// Bad values are InputError with file, line and key.
#include <string>

#include "trajectory/approach_planner.hpp"

namespace armstudy {
namespace io {
class TableReader;
}

// Reads the keys of an [approach] table; unknown keys are left for the caller's finish().
ApproachPlannerOptions readApproachOptions(io::TableReader& r);

// Parses a TOML document and reads its [approach] table (strict: unknown keys are errors).
ApproachPlannerOptions parseApproachOptions(const std::string& toml_text,
                                            const std::string& file_label);

}  // namespace armstudy
