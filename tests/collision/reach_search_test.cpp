// Reach statuses describe the design, not the sweep's path. On a part of the thesis
// Fig. 3.8 grid (6-DoF first prototype, spraying task, self-collision checked), the searched
// sweep is compared with (a) the grid swept in the other direction, (b) this file's own
// many-start search (std::mt19937_64 starts, no warm starts, no neighbours) on every pose the map
// calls self_collision, (c) itself with 1 and 2 threads; the built-in audit is compared with (b).
#include <catch2/catch.hpp>
#include <cstring>
#include <random>

#include "collision/collision.hpp"
#include "io/design_io.hpp"
#include "reach/reach_audit.hpp"
#include "stages/reach/reach_config.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace {
constexpr int kBruteStarts = 500;          // the independent search's starts per pose
constexpr double kMaxAuditMissed = 0.02;   // reachable poses 500 random starts do not find
constexpr double kMaxContradicted = 0.01;  // at most 1 % of self_collision verdicts

// Close to the base, where the sweep alone called poses self_collision that have collision-free
// solutions: x -0.36..0.24 m (3 cm), y 0.30..0.50 m (2 cm), z 1.2 m, gamma +-40 deg: 21 x 11 x 2
// = 462 poses.
TaskGrid fig38Part() {
  TaskGrid g;
  g.name = "fig3_8_part";
  g.task_space = TaskSpace::spraying();
  g.axes = {AxisRange{-0.36, 0.24, 0.03}, AxisRange{0.30, 0.50, 0.02}, AxisRange{1.2, 1.2, 1.0}};
  const double deg = M_PI / 180;
  g.orientations = {{0, 0, -40 * deg}, {0, 0, 40 * deg}};
  return g;
}

PoseSweep searched(const Model& m, const TaskGrid& g, const IkOptions& o, int threads) {
  const SweepCollision sc{true, {}};
  PoseSweep s = sweepGrid(m, g, o, threads, nullptr, sc);
  searchGridSweep(m, g, o, threads, sc, SweepSearch{}, s);
  return s;
}

// True when one of kBruteStarts uniform random starts reaches pose i collision-free.
bool bruteForceClear(const Model& m, const TaskGrid& g, const IkOptions& o, long i,
                     std::mt19937_64& rng) {
  IkWorkspace ws(m);
  collision::CollisionWorkspace cws(m);
  IkOptions one = o;
  one.max_starts = 1;
  one.classify_failures = false;
  const PoseTask t = taskTarget(g.task_space, g.pose(i));
  for (int k = 0; k < kBruteStarts; ++k) {
    const JointVector q0 = test::randomConfiguration(m, rng);
    const IkResult r = solvePose(m, ws, t, one, 0, &q0);
    if (!r.reachable()) continue;
    forwardKinematics(m, ws.kin, r.q);
    collision::collisionDistances(m, ws.kin, {}, cws);
    if (collision::minSelfDistance(cws) > 0) return true;
  }
  return false;
}

// Two sweeps of the same grid hold the same rows, bit for bit.
void checkSameRows(const PoseSweep& a, const PoseSweep& b) {
  REQUIRE(a.size == b.size);
  CHECK(a.status == b.status);
  CHECK(a.starts == b.starts);
  CHECK(std::memcmp(a.q.data(), b.q.data(), b.q.size() * sizeof(double)) == 0);
  CHECK(std::memcmp(a.manipulability.data(), b.manipulability.data(), b.size * sizeof(double)) ==
        0);
  CHECK(std::memcmp(a.min_distance_m.data(), b.min_distance_m.data(), b.size * sizeof(double)) ==
        0);
  CHECK(a.colliding_pair == b.colliding_pair);
}
}  // namespace

TEST_CASE(
    "reach statuses do not depend on the sweep direction and are the same for 1 and 2 threads",
    "[reach][map_search][determinism]") {
  const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  const TaskGrid g = fig38Part();
  IkOptions up = ReachConfig::studyDefaults(), down = up;
  down.sweep_descending = true;
  const PoseSweep a = searched(m, g, up, 2), b = searched(m, g, down, 2), c = searched(m, g, up, 1);
  long differ = 0, in_collision = 0;
  for (long i = 0; i < a.size; ++i) {
    differ += a.status[i] != b.status[i];
    in_collision += a.status[i] == static_cast<std::uint8_t>(ReachStatus::SelfCollision);
  }
  INFO("statuses differing between the directions: " << differ << " of " << a.size
                                                     << ", self_collision " << in_collision);
  REQUIRE(in_collision > 0);  // the part has poses reachable only in collision
  // Every line is chained both ways and each pose keeps the better result by a symmetric rule, so
  // the whole result (statuses, solutions, quantities) is the same in either direction.
  CHECK(differ == 0);
  CHECK(std::memcmp(b.q.data(), a.q.data(), a.q.size() * sizeof(double)) == 0);
  CHECK(b.manipulability == a.manipulability);
  CHECK(b.starts == a.starts);
  // With one chain per line (the sweep before this rule) the directions disagree here even after
  // the map search: the comparison can fail.
  IkOptions one_up = up, one_down = down;
  one_up.sweep_both_directions = one_down.sweep_both_directions = false;
  const PoseSweep ou = searched(m, g, one_up, 2), od = searched(m, g, one_down, 2);
  CHECK(ou.status != od.status);
  CHECK(c.status == a.status);
  CHECK(c.starts == a.starts);
  CHECK(std::memcmp(c.q.data(), a.q.data(), a.q.size() * sizeof(double)) == 0);
}

TEST_CASE(
    "self_collision verdicts are rarely contradicted by a 500-start search, the audit finds the "
    "same",
    "[reach][map_search][audit][oracle]") {
  const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  const TaskGrid g = fig38Part();
  const IkOptions o = ReachConfig::studyDefaults();
  const PoseSweep s = searched(m, g, o, 2);
  std::mt19937_64 rng(12);
  long verdicts = 0, contradicted = 0;
  std::vector<long> clear(s.size, -1);  // brute force on the self_collision poses
  for (long i = 0; i < s.size; ++i) {
    if (s.status[i] != static_cast<std::uint8_t>(ReachStatus::SelfCollision)) continue;
    ++verdicts;
    clear[i] = bruteForceClear(m, g, o, i, rng) ? 1 : 0;
    contradicted += clear[i];
  }
  REQUIRE(verdicts > 0);
  INFO(contradicted << " of " << verdicts << " self_collision verdicts contradicted");
  CHECK(double(contradicted) <= kMaxContradicted * double(verdicts));
  // The built-in audit over every pose: its self_collision count is the map's, and it contradicts
  // no more than the brute force does (+1: two random searches at the edge of a tiny free region).
  const ReachAudit au =
      auditGridSweep(m, g, o, SweepCollision{true, {}}, s, static_cast<int>(s.size), kBruteStarts,
                     defaults::kAuditSeed, 2);
  const int sc = static_cast<int>(ReachStatus::SelfCollision);
  CHECK(au.by_status[sc] == verdicts);
  CHECK(std::abs(au.contradicted[sc] - contradicted) <= 1);
  // Reachable poses where the audit's random starts found no clear solution (a free region too
  // small for random starts): rare, and at each the map's own solution is the witness, re-checked
  // here: on the pose within the tolerances and clear of every self-collision pair.
  CHECK(double(au.audit_missed) <= kMaxAuditMissed * double(au.by_status[0]));
  IkWorkspace ws(m);
  collision::CollisionWorkspace cws(m);
  for (const ReachAuditPose& row : au.rows) {
    if (!(row.map_status == ReachStatus::Reachable && row.solutions == 0)) continue;
    const JointVector q =
        Eigen::Map<const JointVector>(&s.q[static_cast<std::size_t>(row.index) * s.dof], s.dof);
    const IkResult e = evaluateSolution(m, ws, taskTarget(g.task_space, g.pose(row.index)), o, q,
                                        ReachStatus::OutOfReach);
    CHECK(e.reachable());
    forwardKinematics(m, ws.kin, q);
    collision::collisionDistances(m, ws.kin, {}, cws);
    CHECK(collision::minSelfDistance(cws) > 0);
  }
  // Without the map search (the sweep alone) the same oracle finds wrong verdicts: the test can
  // fail.
  const PoseSweep raw = sweepGrid(m, g, o, 2, nullptr, SweepCollision{true, {}});
  const ReachAudit au_raw =
      auditGridSweep(m, g, o, SweepCollision{true, {}}, raw, static_cast<int>(raw.size),
                     kBruteStarts, defaults::kAuditSeed, 2);
  INFO("sweep alone: " << au_raw.contradicted[sc] << " of " << au_raw.by_status[sc]
                       << " contradicted");
  CHECK(au_raw.contradicted[sc] > au.contradicted[sc]);
}

TEST_CASE(
    "pose lists: poses in collision get the seeded starts, freed poses are verified collision-free",
    "[reach][map_search]") {
  const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  const TaskGrid g = fig38Part();
  PoseList list;
  list.name = "fig3_8_part_as_list";
  list.task_space = g.task_space;
  for (long i = 0; i < g.size(); ++i) list.poses.push_back(g.pose(i));
  const IkOptions o = ReachConfig::studyDefaults();
  const SweepCollision sc{true, {}};
  const PoseSweep raw = sweepPoseList(m, list, o, 2, nullptr, sc);
  auto searchedList = [&](int threads) {
    PoseSweep s = sweepPoseList(m, list, o, threads, nullptr, sc);
    const SweepSearchSummary sum = searchPoseListSweep(m, list, o, threads, sc, SweepSearch{}, s);
    CHECK(sum.multistart_poses > 0);
    return s;
  };
  const PoseSweep a = searchedList(2), b = searchedList(1);
  CHECK(a.status == b.status);
  CHECK(std::memcmp(a.q.data(), b.q.data(), a.q.size() * sizeof(double)) == 0);
  IkWorkspace ws(m);
  collision::CollisionWorkspace cws(m);
  long freed = 0, lost = 0;
  const auto sc_status = static_cast<std::uint8_t>(ReachStatus::SelfCollision);
  for (long i = 0; i < a.size; ++i) {
    lost += raw.reachable(i) && !a.reachable(i);  // the search never loses a solution
    if (raw.status[i] != sc_status || !a.reachable(i)) continue;
    ++freed;
    JointVector q(m.dof());
    for (int k = 0; k < m.dof(); ++k) q[k] = a.q[static_cast<std::size_t>(i) * m.dof() + k];
    forwardKinematics(m, ws.kin, q);
    collision::collisionDistances(m, ws.kin, {}, cws);
    CHECK(collision::minSelfDistance(cws) > 0);
    CHECK(collision::minSelfDistance(cws) == a.min_distance_m[i]);
    const IkResult e = evaluateSolution(m, ws, taskTarget(list.task_space, list.poses[i]), o, q,
                                        ReachStatus::OutOfReach);
    CHECK(e.reachable());
  }
  CHECK(lost == 0);
  INFO("poses freed by the seeded starts: " << freed);
  CHECK(freed > 0);
}

TEST_CASE("a search's packed result turns the sweep it started from into the searched sweep",
          "[reach][map_search][distributed]") {
  // What a rank that did not run a design's search applies (study/interleave.hpp, rank groups).
  const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml"));
  const TaskGrid g = fig38Part();
  const IkOptions o = ReachConfig::studyDefaults();
  const SweepCollision sc{true, {}};
  const PoseSweep before = sweepGrid(m, g, o, 2, nullptr, sc);
  PoseSweep s = before;
  const SweepSearchSummary sum = searchGridSweep(m, g, o, 2, sc, SweepSearch{}, s);
  REQUIRE(!sum.changed.empty());
  REQUIRE(static_cast<long>(sum.changed.size()) < s.size);  // only the changed rows travel
  // Every row outside `changed` is the sweep's.
  std::vector<char> in(s.size, 0);
  for (const long i : sum.changed) in[i] = 1;
  for (long i = 0; i < s.size; ++i)
    if (!in[i]) {
      CHECK(s.status[i] == before.status[i]);
      CHECK(s.starts[i] == before.starts[i]);
    }
  PoseSweep other = before;
  SweepSearchSummary got;
  unpackSearchResult(packSearchResult(s, sum), other, got);
  checkSameRows(other, s);
  CHECK(got.rounds == sum.rounds);
  CHECK(got.neighbour_updates == sum.neighbour_updates);
  CHECK(got.multistart_freed == sum.multistart_freed);
  CHECK(got.best_updates == sum.best_updates);
  CHECK(got.converged == sum.converged);
  CHECK(got.changed == sum.changed);
}

TEST_CASE("a search's steps over their active sets give the map of steps over every pose",
          "[reach][map_search][oracle]") {
  // The search's steps visit only the poses next to a change (active sets); the oracle
  // visits every pose its phase may change in every step (SweepSearch::every_pose_each_step). The
  // two must give the same map, bit for bit, and the same counts: on the 6-DoF arm with
  // self-collision (propagation, multi-starts, the box round) and on the 7-DoF arm (long
  // best-manipulability rounds), 1 and 2 threads.
  for (const char* design :
       {"designs/first_prototype_6dof.toml", "designs/final_prototype_7dof.toml"}) {
    const Model m = loadDesign(test::sourcePath(design));
    const TaskGrid g = fig38Part();
    const IkOptions o = ReachConfig::studyDefaults();
    const SweepCollision sc{true, {}};
    const PoseSweep before = sweepGrid(m, g, o, 2, nullptr, sc);
    PoseSweep fast = before, full = before;
    const SweepSearchSummary a = searchGridSweep(m, g, o, 2, sc, SweepSearch{}, fast);
    SweepSearch every;
    every.every_pose_each_step = true;
    const SweepSearchSummary b = searchGridSweep(m, g, o, 1, sc, every, full);
    INFO(design << ": " << a.rounds << " propagation rounds, " << a.best_rounds << " best rounds, "
                << a.best_updates << " best updates, " << a.changed.size() << " rows changed");
    REQUIRE(a.changed.size() > 0);
    if (m.dof() > 6) CHECK(a.best_rounds > 2);  // the comparison covers later rounds' active sets
    checkSameRows(full, fast);
    CHECK(b.rounds == a.rounds);
    CHECK(b.neighbour_tries == a.neighbour_tries);
    CHECK(b.neighbour_updates == a.neighbour_updates);
    CHECK(b.multistart_freed == a.multistart_freed);
    CHECK(b.box_tries == a.box_tries);
    CHECK(b.best_rounds == a.best_rounds);
    CHECK(b.best_tries == a.best_tries);
    CHECK(b.best_updates == a.best_updates);
    CHECK(b.changed == a.changed);
  }
}
