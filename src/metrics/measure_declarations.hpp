#pragma once
// The declaration of every dexterity measure (DexterityMeasures, computed by computeMeasures): its
// name, its units and where the stem maps show it. Adding a measure is a member of
// DexterityMeasures that computeMeasures fills, one row in kMeasures, and its row in the measures
// table of docs/dexterity.md (tests/metrics/measure_declarations_test.cpp compares the two). From
// the row alone the measure reaches the map's checkpoint bytes, the per-cell arrays of the .vti and
// .vts (with their units in the field data), the ellipsoid glyphs and the heat-map figures.
#include <span>
#include <string>
#include <string_view>

#include "common/errors.hpp"
#include "metrics/dexterity_measures.hpp"

namespace armstudy::metrics {

struct MeasureDeclaration {
  const char* name;                  // "sigma_min": map arrays sigma_min_{plain,optimised}
  double DexterityMeasures::*value;  // the member computeMeasures fills
  const char* unit_translational;    // unit for measure_space "translational" (J_T)
  const char* unit_full;             // unit for measure_space "full" ([J_T; J_R])
  bool on_maps;     // per-cell arrays <name>_{plain,optimised} in the map's .vti and .vts
  bool normalised;  // also <name>_{plain,optimised}_normalised: divided by the best value of the
                    // map over both postures (thesis Fig. 3.6)
  bool on_glyphs;   // on the ellipsoid glyphs (.vtp) as <name>
  // A heat-map figure of the optimised value on one scale for all designs, captioned
  // "<figure_label>, optimised [<figure_unit>]" (the unit for the translational space; "mixed"
  // units for the full space as unit_full says); null: no figure.
  const char* figure_label;
  const char* figure_unit_translational;
  const char* figure_unit_full;
};

// In the order of the checkpoint bytes and of the map's arrays.
inline constexpr MeasureDeclaration kMeasures[] = {
    {"manipulability", &DexterityMeasures::manipulability,
     "m^3 (translational Jacobian, revolute joints: per rad^3)", "mixed m and rad (full Jacobian)",
     true, true, true, "manipulability", "m^3", "mixed m and rad"},
    {"transmission", &DexterityMeasures::transmission, "m/rad", "m/rad", true, false, true,
     "transmission beta along u", "m/rad", "m/rad"},
    {"condition", &DexterityMeasures::condition, "1", "1", false, false, false, nullptr, nullptr,
     nullptr},
    {"inverse_condition", &DexterityMeasures::inverse_condition, "1", "1", true, false, false,
     nullptr, nullptr, nullptr},
    {"sigma_min", &DexterityMeasures::sigma_min, "m/rad", "mixed m/rad and 1", true, false, false,
     nullptr, nullptr, nullptr},
    {"sigma_max", &DexterityMeasures::sigma_max, "m/rad", "mixed m/rad and 1", false, false, false,
     nullptr, nullptr, nullptr},
};

inline std::span<const MeasureDeclaration> measureDeclarations() { return kMeasures; }

// The declaration named `name`; a name that is not declared is a programming error.
inline const MeasureDeclaration& declaredMeasure(std::string_view name) {
  for (const MeasureDeclaration& d : kMeasures)
    if (name == d.name) return d;
  ARMSTUDY_CHECK(false, "no declared measure " + std::string(name));
  return kMeasures[0];
}

// The measure's unit in a measure space (VTK field data, docs table).
inline const char* unitIn(const MeasureDeclaration& d, MeasureSpace space) {
  return space == MeasureSpace::Translational ? d.unit_translational : d.unit_full;
}
// The unit its figure names.
inline const char* figureUnitIn(const MeasureDeclaration& d, MeasureSpace space) {
  return space == MeasureSpace::Translational ? d.figure_unit_translational : d.figure_unit_full;
}

}  // namespace armstudy::metrics
