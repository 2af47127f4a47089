#pragma once
// Summary metrics of a run: what a baseline records and `armstudy check` compares. Each stage
// adds its own under a "<stage>/<design>/<...>" name. Small and text-friendly by design.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace armstudy {

struct StudyMetrics {
  std::map<std::string, double> scalars;  // e.g. reach/<design>/<grid>/reachable_fraction
  std::map<std::string, std::vector<std::uint8_t>> flags;  // per-pose booleans, e.g. .../reachable
  void merge(const StudyMetrics& other);                   // ARMSTUDY_CHECKs that names are unique
};

}  // namespace armstudy
