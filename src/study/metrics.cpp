#include "study/metrics.hpp"

#include "common/errors.hpp"

namespace armstudy {

void StudyMetrics::merge(const StudyMetrics& o) {
  for (const auto& [k, v] : o.scalars)
    ARMSTUDY_CHECK(scalars.emplace(k, v).second, "duplicate metric name " + k);
  for (const auto& [k, v] : o.flags)
    ARMSTUDY_CHECK(flags.emplace(k, v).second, "duplicate flag metric name " + k);
}

std::vector<std::string> metricsOutside(const StudyMetrics& metrics, const std::string& stage) {
  const std::string prefix = stage + "/";
  std::vector<std::string> out;
  for (const auto& [k, v] : metrics.scalars)
    if (k.rfind(prefix, 0) != 0) out.push_back(k);
  for (const auto& [k, v] : metrics.flags)
    if (k.rfind(prefix, 0) != 0) out.push_back(k);
  return out;
}

}  // namespace armstudy
