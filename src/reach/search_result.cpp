#include <string_view>

#include "common/errors.hpp"
#include "reach/reach_sweep.hpp"
#include "reach/sweep_internal.hpp"

// A finished map search's results as bytes and back (reach_sweep.hpp, packSearchResult).
namespace armstudy {

using namespace sweep_detail;

namespace {
constexpr std::string_view kResultMagic = "armstudy-search-result-2";
}  // namespace

std::string packSearchResult(const PoseSweep& s, const SweepSearchSummary& sum) {
  UnitWriter w(kResultMagic);
  w.put<std::int64_t>(s.size);
  w.put<std::int64_t>(sum.rounds);
  for (const long v : {sum.neighbour_tries, sum.neighbour_updates, sum.multistart_poses,
                       sum.multistart_tries, sum.multistart_freed, sum.box_tries, sum.box_freed})
    w.put<std::int64_t>(v);
  w.put<std::int64_t>(sum.best_rounds);
  w.put<std::int64_t>(sum.best_tries);
  w.put<std::int64_t>(sum.best_updates);
  w.put<std::uint8_t>(sum.converged ? 1 : 0);
  for (const SolveTally* t : {&sum.propagation, &sum.collision_starts, &sum.box, &sum.best})
    putTally(w, *t);
  w.put(sum.seconds);
  w.put<std::int64_t>(static_cast<std::int64_t>(sum.changed.size()));
  for (const long i : sum.changed) {
    w.put<std::int64_t>(i);
    putPose(w, s, i);
  }
  return w.bytes();
}

void unpackSearchResult(const std::string& bytes, PoseSweep& s, SweepSearchSummary& sum) {
  UnitReader rd(bytes, kResultMagic);
  ARMSTUDY_CHECK(rd.get<std::int64_t>() == s.size, "a search result fits its sweep");
  sum = SweepSearchSummary{};
  sum.rounds = static_cast<int>(rd.get<std::int64_t>());
  for (long* v : {&sum.neighbour_tries, &sum.neighbour_updates, &sum.multistart_poses,
                  &sum.multistart_tries, &sum.multistart_freed, &sum.box_tries, &sum.box_freed})
    *v = static_cast<long>(rd.get<std::int64_t>());
  sum.best_rounds = static_cast<int>(rd.get<std::int64_t>());
  sum.best_tries = static_cast<long>(rd.get<std::int64_t>());
  sum.best_updates = static_cast<long>(rd.get<std::int64_t>());
  sum.converged = rd.get<std::uint8_t>() != 0;
  for (SolveTally* t : {&sum.propagation, &sum.collision_starts, &sum.box, &sum.best})
    getTally(rd, *t);
  sum.seconds = rd.get<double>();
  const auto n = rd.get<std::int64_t>();
  ARMSTUDY_CHECK(rd.ok() && n >= 0 && n <= s.size, "a search result fits its sweep");
  sum.changed.reserve(static_cast<std::size_t>(n));
  for (std::int64_t k = 0; k < n; ++k) {
    const long i = static_cast<long>(rd.get<std::int64_t>());
    ARMSTUDY_CHECK(rd.ok() && i >= 0 && i < s.size && getPose(rd, s, i),
                   "a search result's rows arrive whole");
    sum.changed.push_back(i);
  }
  ARMSTUDY_CHECK(rd.finished(), "a search result arrives whole");
}

}  // namespace armstudy
