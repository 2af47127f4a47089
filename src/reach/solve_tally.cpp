#include "reach/reach_sweep.hpp"

// The counts of a reach map's pose solves (reach_sweep.hpp, SolveTally).
namespace armstudy {

namespace {
// The integer counts of `from` added to `to` (their step sums depend on the order of addition).
void addCounts(ik::DescentTally& to, const ik::DescentTally& from) {
  to.descents += from.descents;
  to.changed += from.changed;
  to.iterations += from.iterations;
  to.objective_evaluations += from.objective_evaluations;
  to.kernel_evaluations += from.kernel_evaluations;
  for (int k = 0; k < 3; ++k) to.stopped[k] += from.stopped[k];
}
}  // namespace

void SolveTally::add(const SolveTally& o) {
  descents += o.descents;
  changed += o.changed;
  iterations += o.iterations;
  kernel_evaluations += o.kernel_evaluations;
  for (int k = 0; k < kReachStatusCount; ++k) ended[k] += o.ended[k];
  addCounts(escape, o.escape);
}

void SolveTally::addEscape(const ik::DescentTally& descents) { addCounts(escape, descents); }

void putTally(UnitWriter& w, const SolveTally& t) {
  for (const long v : {t.descents, t.changed, t.iterations, t.kernel_evaluations})
    w.put<std::int64_t>(v);
  for (const long v : t.ended) w.put<std::int64_t>(v);
  const ik::DescentTally& e = t.escape;
  for (const long v : {e.descents, e.changed, e.iterations, e.objective_evaluations,
                       e.kernel_evaluations, e.stopped[0], e.stopped[1], e.stopped[2]})
    w.put<std::int64_t>(v);
}

void getTally(UnitReader& r, SolveTally& t) {
  for (long* v : {&t.descents, &t.changed, &t.iterations, &t.kernel_evaluations})
    *v = static_cast<long>(r.get<std::int64_t>());
  for (long& v : t.ended) v = static_cast<long>(r.get<std::int64_t>());
  ik::DescentTally& e = t.escape;
  for (long* v : {&e.descents, &e.changed, &e.iterations, &e.objective_evaluations,
                  &e.kernel_evaluations, &e.stopped[0], &e.stopped[1], &e.stopped[2]})
    *v = static_cast<long>(r.get<std::int64_t>());
}

}  // namespace armstudy
