#include "study/metrics.hpp"

#include "common/errors.hpp"

namespace armstudy {

void StudyMetrics::merge(const StudyMetrics& o) {
  for (const auto& [k, v] : o.scalars)
    ARMSTUDY_CHECK(scalars.emplace(k, v).second, "duplicate metric name " + k);
  for (const auto& [k, v] : o.flags)
    ARMSTUDY_CHECK(flags.emplace(k, v).second, "duplicate flag metric name " + k);
}

}  // namespace armstudy
