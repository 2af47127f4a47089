// The descent counts of a reach map (SolveTally: PoseSweep::chain, the phases of
// SweepSearchSummary, ReachAudit::descents) against independent counts: the tries each search
// phase counts where it makes them, the kernel evaluations counted around whole calls on one
// thread, the audit's starts per pose in closed form, and the same map on 1 and 2 threads, in two
// units and through the bytes that carry the counts between processes.
#include <catch2/catch.hpp>
#include <numeric>

#include "io/design_io.hpp"
#include "kinematics/kernel_count.hpp"
#include "reach/reach_audit.hpp"
#include "stages/reach/reach_config.hpp"
#include "stages/reach/reach_units.hpp"
#include "test_support.hpp"

using namespace armstudy;

namespace {

constexpr int kAuditPoses = 12;  // poses the audit draws
constexpr int kAuditStarts = 4;  // random starts per audited pose
const SweepCollision kSelf{true, {}};

// Close to the base of the 6-DoF first prototype on the thesis Fig. 3.8 row, where poses are
// reached only in self-collision (tests/collision/reach_search_test.cpp's part, coarser): x
// -0.36..0.24 m (6 cm), y 0.30..0.50 m (4 cm), z 1.2 m, gamma +-40 deg: 11 x 6 x 2 = 132 poses.
TaskGrid basePart() {
  TaskGrid g;
  g.name = "fig3_8_base_part";
  g.task_space = TaskSpace::spraying();
  g.axes = {AxisRange{-0.36, 0.24, 0.06}, AxisRange{0.30, 0.50, 0.04}, AxisRange{1.2, 1.2, 1.0}};
  const double deg = M_PI / 180;
  g.orientations = {{0, 0, -40 * deg}, {0, 0, 40 * deg}};
  return g;
}

long endedTotal(const SolveTally& t) { return std::accumulate(t.ended.begin(), t.ended.end(), 0L); }

void checkSame(const SolveTally& a, const SolveTally& b) {
  CHECK(a.descents == b.descents);
  CHECK(a.changed == b.changed);
  CHECK(a.iterations == b.iterations);
  CHECK(a.kernel_evaluations == b.kernel_evaluations);
  CHECK(a.ended == b.ended);
  CHECK(a.escape.descents == b.escape.descents);
  CHECK(a.escape.changed == b.escape.changed);
  CHECK(a.escape.iterations == b.escape.iterations);
  CHECK(a.escape.objective_evaluations == b.escape.objective_evaluations);
  CHECK(a.escape.kernel_evaluations == b.escape.kernel_evaluations);
  for (int k = 0; k < 3; ++k) CHECK(a.escape.stopped[k] == b.escape.stopped[k]);
}

void checkSame(const SweepSearchSummary& a, const SweepSearchSummary& b) {
  checkSame(a.propagation, b.propagation);
  checkSame(a.collision_starts, b.collision_starts);
  checkSame(a.box, b.box);
  checkSame(a.best, b.best);
}

}  // namespace

TEST_CASE(
    "a reach map counts one descent per try of each search phase and per audit start, and the "
    "kernel evaluations a count around the whole call finds",
    "[reach][descent_counts]") {
  const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  const TaskGrid g = basePart();
  const IkOptions o = ReachConfig::studyDefaults();
  // The chains, on this thread alone.
  const long k0 = kernelEvaluationsOnThisThread();
  PoseSweep s = sweepGrid(m, g, o, 1, nullptr, kSelf);
  const long chain_kernels = kernelEvaluationsOnThisThread() - k0;
  const SolveTally& chain = s.chain;
  REQUIRE(chain.escape.descents > 0);  // the scenario: solutions in collision, escapes tried
  CHECK(chain.kernel_evaluations == chain_kernels);
  CHECK(chain.descents >= 2 * g.size());  // each pose in both chains, some retried backwards
  CHECK(chain.changed == g.size());
  CHECK(endedTotal(chain) == chain.descents);
  CHECK(chain.escape.stopped[0] + chain.escape.stopped[1] + chain.escape.stopped[2] ==
        chain.escape.descents);
  CHECK(chain.escape.changed <= chain.escape.descents);
  CHECK(chain.escape.kernel_evaluations < chain.kernel_evaluations);
  // The search: each phase's descents are the tries the phase counts itself, its changed rows the
  // poses it updated.
  const long k1 = kernelEvaluationsOnThisThread();
  const SweepSearchSummary ss = searchGridSweep(m, g, o, 1, kSelf, SweepSearch{}, s);
  const long search_kernels = kernelEvaluationsOnThisThread() - k1;
  REQUIRE(ss.neighbour_tries > 0);
  REQUIRE(ss.multistart_tries > 0);
  REQUIRE(ss.best_tries > 0);
  CHECK(ss.propagation.descents == ss.neighbour_tries);
  CHECK(ss.propagation.changed == ss.neighbour_updates);
  CHECK(ss.collision_starts.descents == ss.multistart_tries);
  CHECK(ss.collision_starts.changed == ss.multistart_freed);
  CHECK(ss.box.descents == ss.box_tries);
  CHECK(ss.box.changed == ss.box_freed);
  CHECK(ss.best.descents == ss.best_tries);
  CHECK(ss.best.changed == ss.best_updates);
  long kernels = 0;
  for (const SolveTally* t : {&ss.propagation, &ss.collision_starts, &ss.box, &ss.best}) {
    kernels += t->kernel_evaluations;
    CHECK(endedTotal(*t) == t->descents);
  }
  CHECK(kernels == search_kernels);
  // The audit: every start of a pose it does not contradict is one descent, and each start that
  // ends reachable is one of the row's solutions.
  const long k2 = kernelEvaluationsOnThisThread();
  const ReachAudit a = auditGridSweep(m, g, o, kSelf, s, kAuditPoses, kAuditStarts, 7, 1);
  CHECK(a.descents.kernel_evaluations == kernelEvaluationsOnThisThread() - k2);
  long exact = 0, contradicted = 0;
  for (const ReachAuditPose& row : a.rows) {
    const bool stopped_early = row.map_status != ReachStatus::Reachable && row.solutions > 0;
    contradicted += stopped_early;
    if (!stopped_early) {
      CHECK(row.tally.descents == kAuditStarts);
      exact += kAuditStarts;
    }
    CHECK(row.tally.ended[0] == row.solutions);
  }
  CHECK(a.descents.descents >= exact + contradicted);
  CHECK(a.descents.descents <= exact + contradicted * kAuditStarts);
  CHECK(a.descents.changed == 0);
}

TEST_CASE("a reach search switched off counts no descents of its phases",
          "[reach][descent_counts]") {
  const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  const TaskGrid g = basePart();
  const IkOptions o = ReachConfig::studyDefaults();
  PoseSweep s = sweepGrid(m, g, o, 2, nullptr, kSelf);
  const SolveTally chain = s.chain;
  SweepSearch off;
  off.propagation_rounds = 0;
  off.collision_starts = 0;
  off.best_manipulability = false;
  const SweepSearchSummary ss = searchGridSweep(m, g, o, 2, kSelf, off, s);
  CHECK(ss.propagation.descents == 0);
  CHECK(ss.collision_starts.descents == 0);
  CHECK(ss.best.descents == 0);
  CHECK(ss.box.descents == ss.box_tries);  // the box round runs whenever collisions are checked
  checkSame(s.chain, chain);               // the search does not count into the chains
  CHECK(auditGridSweep(m, g, o, kSelf, s, 0, kAuditStarts, 7, 2).descents.descents == 0);
}

TEST_CASE(
    "a reach map's descent counts are the same on 1 and 2 threads, in two units and through their "
    "bytes",
    "[reach][descent_counts]") {
  const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  const TaskGrid g = basePart();
  const IkOptions o = ReachConfig::studyDefaults();
  PoseSweep a = sweepGrid(m, g, o, 1, nullptr, kSelf), b = sweepGrid(m, g, o, 2, nullptr, kSelf);
  REQUIRE(a.chain.escape.descents > 0);
  checkSame(a.chain, b.chain);
  // Two units (two ranges of lines) assembled, and each unit through its checkpoint bytes.
  const long units = sweepUnitCount(g);
  std::vector<PoseSweep> chunks =
      sweepGridRanges(m, g, {{0, units / 2}, {units / 2, units}}, o, 2, nullptr, kSelf);
  for (PoseSweep& c : chunks) {
    PoseSweep back;
    REQUIRE(reach_units::deserializeSweep(reach_units::serializeSweep(c), c.design, back));
    checkSame(back.chain, c.chain);
    c = std::move(back);
  }
  checkSame(assembleSweep(std::move(chunks), g.size()).chain, a.chain);
  const SweepSearchSummary sa = searchGridSweep(m, g, o, 1, kSelf, SweepSearch{}, a),
                           sb = searchGridSweep(m, g, o, 2, kSelf, SweepSearch{}, b);
  REQUIRE(sa.propagation.descents > 0);
  checkSame(sa, sb);
  // A search's result as the bytes a rank group sends.
  PoseSweep c = sweepGrid(m, g, o, 2, nullptr, kSelf);
  SweepSearchSummary sc;
  unpackSearchResult(packSearchResult(a, sa), c, sc);
  checkSame(sc, sa);
  checkSame(auditGridSweep(m, g, o, kSelf, a, kAuditPoses, kAuditStarts, 7, 1).descents,
            auditGridSweep(m, g, o, kSelf, b, kAuditPoses, kAuditStarts, 7, 2).descents);
}
