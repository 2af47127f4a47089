#pragma once
// Summary metrics of a run: what a baseline records and `armstudy check` compares. A metric's name
// is "<stage>/<subject>/.../<quantity>": the stage's name first (Stage::name; the engine refuses a
// metric outside it, checkStageMetrics), then what it describes (a grid and a design, a design, a
// calibration or tracking entry), then the quantity. Small and text-friendly by design.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace armstudy {

struct StudyMetrics {
  std::map<std::string, double> scalars;  // e.g. reach/<grid>/<design>/reachable_fraction
  std::map<std::string, std::vector<std::uint8_t>> flags;  // per-pose booleans, e.g. .../reachable
  void merge(const StudyMetrics& other);                   // ARMSTUDY_CHECKs that names are unique
};

// The names of `metrics` that do not begin with "<stage>/" (empty: all do).
std::vector<std::string> metricsOutside(const StudyMetrics& metrics, const std::string& stage);

}  // namespace armstudy
