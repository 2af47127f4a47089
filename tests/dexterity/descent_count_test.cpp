// The descent counts of a dexterity map (MapSearchSummary, DexterityAudit::descent) against
// independent counts: a counting objective term, closed forms of a descent that cannot step, the
// starts that land on the pose solved again here, and the same map on 1 and 2 threads.
#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>

#include "dexterity/dexterity_audit.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::dexterity;
using namespace armstudy::test;

namespace {

// A term of value and gradient zero that counts its evaluations (H and its minimum unchanged).
class CountingTerm final : public ik::ObjectiveTerm {
 public:
  std::string name() const override { return "counting"; }
  double evaluate(ik::ObjectiveContext&, JointVector* grad) const override {
    ++calls;
    if (grad) grad->setZero();
    return 0.0;
  }
  mutable std::atomic<long> calls{0};
};

// A 5 x 3 grid of the first prototype's stem map (studies/stem_heatmap.toml's objective).
DexterityOptions smallMap() {
  DexterityOptions o;
  o.grid.stem_x_m = 0.225;
  o.grid.stem_y_m = 0.7;
  o.grid.radius_m = 0.15;
  o.grid.gamma_rad = {-M_PI / 2, M_PI / 2, 5};
  o.grid.z_m = {0.40, 0.70, 3};
  o.w_joint_limits = 0.1;
  o.seed_stride = 1;
  o.seed_starts = 3;
  o.audit_cells = 4;
  o.audit_starts = 3;
  return o;
}

void checkSame(const ik::DescentTally& a, const ik::DescentTally& b) {
  CHECK(a.descents == b.descents);
  CHECK(a.changed == b.changed);
  CHECK(a.iterations == b.iterations);
  CHECK(a.kernel_evaluations == b.kernel_evaluations);
  CHECK(a.objective_evaluations == b.objective_evaluations);
  CHECK(a.step_sum == b.step_sum);
  CHECK(a.last_step_sum == b.last_step_sum);
  for (int k = 0; k < 3; ++k) CHECK(a.stopped[k] == b.stopped[k]);
}

}  // namespace

TEST_CASE(
    "a descent counts its objective evaluations as a counting term does, and its kernel "
    "evaluations in closed form when it cannot step",
    "[dexterity][descent_counts]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  const DexterityOptions o = smallMap();
  // A cell of the middle row that the chained row reaches, from its plain posture.
  const DexterityMap row = computeDexterityRows(m, o, {{1, 2}}, 1);
  int ig = 0;
  while (ig < o.grid.gamma_rad.count && !row.cells[o.grid.index(ig, 1)].reachable) ++ig;
  REQUIRE(ig < o.grid.gamma_rad.count);
  const StemGrid::Cell cell = o.grid.cell(ig, 1);
  const JointVector q_plain = row.cells[o.grid.index(ig, 1)].q_plain;
  KinematicsWorkspace ws(m);
  ik::ObjectiveContext ctx(m, ws);
  ctx.u_W = cell.u_W;
  ik::WeightedObjective objective = o.buildObjective(m);
  auto counter = std::make_shared<CountingTerm>();
  objective.add(1.0, counter);
  const Eigen::VectorXd w_inv = Eigen::VectorXd::Ones(m.dof());
  const ik::NullspaceResult r =
      ik::optimiseAtPose(m, ws, ctx, cell.target, q_plain, objective, w_inv, o.nullspace);
  REQUIRE(r.iterations > 0);  // the scenario: a descent that moved
  CHECK(r.evaluations == counter->calls);
  // Every accepted step needs at least one kernel evaluation besides the start and the end.
  CHECK(r.kernel_evaluations >= r.iterations + 2);
  CHECK(r.step_sum > 0);
  CHECK(r.last_step > 0);
  CHECK(r.step_sum <= r.iterations * o.nullspace.max_step * (1 + 1e-12));
  // No iteration allowed: the start and the final pose check, nothing else.
  ik::NullspaceOptions none = o.nullspace;
  none.max_iterations = 0;
  const ik::NullspaceResult z =
      ik::optimiseAtPose(m, ws, ctx, cell.target, q_plain, objective, w_inv, none);
  CHECK(z.kernel_evaluations == 2);
  CHECK(z.iterations == 0);
  CHECK(z.step_sum == 0);
  CHECK(z.status == ik::NullspaceStatus::IterationLimit);
}

TEST_CASE(
    "a dexterity map counts one descent per seeded start and audit start that lands on the "
    "pose, and none for a search switched off",
    "[dexterity][descent_counts]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  const DexterityOptions o = smallMap();
  const DexterityMap map = computeDexterityMap(m, o, 2);
  const MapSearchSummary& s = map.search;
  // The seeded starts solved again here: each that lands on the pose descends once.
  KinematicsWorkspace ws(m);
  IkWorkspace ik_ws(m);
  ik::ObjectiveContext ctx(m, ws);
  const ik::WeightedObjective objective = o.buildObjective(m);
  long landed = 0;
  JointVector q0(m.dof());
  for (int idx = 0; idx < o.grid.size(); ++idx) {
    const StemGrid::Cell cell =
        o.grid.cell(idx % o.grid.gamma_rad.count, idx / o.grid.gamma_rad.count);
    for (int k = 0; k < o.seed_starts; ++k) {
      randomConfiguration(m, o.search_seed, static_cast<std::uint64_t>(idx), k, q0);
      CellResult c;
      landed += cellFromSeed(m, ws, ik_ws, ctx, objective, o, cell, q0, c, nullptr, false);
    }
  }
  REQUIRE(landed > 0);
  CHECK(s.multistart_tries == long(o.grid.size()) * o.seed_starts);
  CHECK(s.seed.descents == landed);
  CHECK(s.seed.stopped[static_cast<int>(ik::NullspaceStatus::NotOnPose)] == 0);
  CHECK(s.seed.stopped[0] + s.seed.stopped[1] == s.seed.descents);  // each stopped once
  CHECK(s.seed.last_step_sum <= s.seed.step_sum);
  // The chain: one descent per optimised cell, a second where the warm start led to a worse
  // optimum than the plain configuration's.
  long optimised = 0;
  for (const CellResult& c : computeDexterityRows(m, o, {{0, o.grid.z_m.count}}, 2).cells)
    optimised += c.optimised;
  REQUIRE(optimised > 0);
  CHECK(s.chain.descents >= optimised);
  CHECK(s.chain.descents <= 2 * optimised);
  CHECK(s.chain.changed == optimised);
  CHECK(s.neighbour.descents > 0);
  CHECK(s.neighbour.descents <= s.neighbour_tries);
  // A cell adopts at most one candidate per neighbour in a round; neighbour_improved counts cells.
  CHECK(s.neighbour.changed >= s.neighbour_improved);
  CHECK(s.neighbour.changed <= s.neighbour.descents);
  // The audit: one descent per start on the pose, counted by the audit's rows.
  const DexterityAudit a = auditDexterityMap(m, o, map, 2);
  long on_pose = 0;
  for (const AuditCell& r : a.rows) on_pose += r.on_pose;
  REQUIRE(on_pose > 0);
  CHECK(a.descent.descents == on_pose);
  // Each kind off: its count is zero.
  DexterityOptions off = o;
  off.seed_starts = 0;
  off.propagation_rounds = 0;
  const DexterityMap chain_only = computeDexterityMap(m, off, 2);
  CHECK(chain_only.search.seed.descents == 0);
  CHECK(chain_only.search.neighbour.descents == 0);
  CHECK(chain_only.search.chain.descents == s.chain.descents);
  off.audit_cells = 0;
  CHECK(auditDexterityMap(m, off, chain_only, 2).descent.descents == 0);
}

TEST_CASE("a dexterity map's descent counts are the same on 1 and 2 threads",
          "[dexterity][descent_counts]") {
  const Model m = loadDesign(sourcePath("designs/first_prototype_9dof.toml"));
  const DexterityOptions o = smallMap();
  const DexterityMap a = computeDexterityMap(m, o, 1), b = computeDexterityMap(m, o, 2);
  REQUIRE(a.search.neighbour.descents > 0);
  checkSame(a.search.chain, b.search.chain);
  checkSame(a.search.seed, b.search.seed);
  checkSame(a.search.neighbour, b.search.neighbour);
  checkSame(auditDexterityMap(m, o, a, 1).descent, auditDexterityMap(m, o, b, 2).descent);
}
