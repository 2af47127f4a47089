#include "reach/reach_audit.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <numeric>
#include <optional>
#include <string_view>

#include "common/errors.hpp"
#include "kinematics/kernel_count.hpp"
#include "study/shared_loop.hpp"

namespace armstudy {

namespace {
constexpr std::string_view kAuditMagic = "armstudy-audit-rows-2";
}  // namespace

int ReachAudit::contradictedTotal() const {
  return std::accumulate(contradicted.begin(), contradicted.end(), 0);
}

ReachAudit auditGridSweep(const Model& model, const TaskGrid& grid, const IkOptions& options,
                          const SweepCollision& collision, const PoseSweep& sweep, int poses,
                          int starts, std::uint64_t seed, int threads, const UnitRunner* runner) {
  const auto t0 = std::chrono::steady_clock::now();
  ARMSTUDY_CHECK(sweep.offset == 0 && sweep.size == grid.size(),
                 "the audit needs the whole sweep of the grid");
  ReachAudit a;
  a.starts = starts;
  a.seed = seed;
  const std::vector<long> idx = drawIndices(grid.size(), poses, seed);
  a.poses = static_cast<int>(idx.size());
  a.rows.resize(idx.size());
  IkOptions one = options;
  one.max_starts = 1;
  one.classify_failures = false;
  const int nt = threads > 0 ? threads : omp_get_max_threads();
  // The audited poses, shared among the processes of a distributed run (each audits the poses of
  // its chunks; the rows travel).
  SharedLoop loop;
  loop.items = static_cast<long>(idx.size());
  loop.id = "audit/" + sweep.design;
  loop.chunk = 1;  // each pose is `starts` searches: hundreds of times a search step's pose
  loop.compute = [&](const std::vector<SharedLoop::Chunk>& mine) {
    const std::vector<long> items = SharedLoop::itemsOf(mine);
    const long n = static_cast<long>(items.size());
#pragma omp parallel num_threads(nt)
    {
      IkWorkspace ws(model);
      std::optional<collision::CollisionWorkspace> cws;
      if (collision.enabled()) cws.emplace(model);
      collision::CollisionQueryOptions query;
      query.self = collision.self;
      query.environment = !collision.obstacles.empty();
      JointVector q0(model.dof());
#pragma omp for schedule(dynamic, 1)
      for (long m = 0; m < n; ++m) {
        const long t = items[m];
        const long i = idx[t];
        ReachAuditPose& row = a.rows[t];
        row.index = i;
        row.map_status = static_cast<ReachStatus>(sweep.status[i]);
        row.manipulability_map = sweep.reachable(i) ? sweep.manipulability[i] : 0.0;
        const PoseTask target = taskTarget(grid.task_space, grid.pose(i));
        row.tally = SolveTally{};
        for (int k = 0; k < starts; ++k) {
          randomConfiguration(model, seed, static_cast<std::uint64_t>(i), k, q0);
          const long kernels = kernelEvaluationsOnThisThread();
          const IkResult r = solvePose(model, ws, target, one, static_cast<std::uint64_t>(i), &q0);
          ReachStatus ended = r.status;
          if (r.reachable() && cws) {
            forwardKinematics(model, ws.kin, r.q);
            collision::collisionDistances(model, ws.kin, collision.obstacles, *cws, query);
            const double ds = collision.self ? collision::minSelfDistance(*cws) : INFINITY;
            const double de = collision::minEnvironmentDistance(*cws);
            if (!(std::min(ds, de) > 0))
              ended = ds <= de ? ReachStatus::SelfCollision : ReachStatus::ObstacleCollision;
          }
          ++row.tally.descents;
          row.tally.iterations += r.iterations;
          row.tally.kernel_evaluations += kernelEvaluationsOnThisThread() - kernels;
          ++row.tally.ended[static_cast<int>(ended)];
          if (ended != ReachStatus::Reachable) continue;
          ++row.solutions;
          row.manipulability_best = std::max(row.manipulability_best, r.manipulability);
          if (!sweep.reachable(i)) break;  // one solution contradicts the status
        }
      }
    }
  };
  loop.pack = [&](std::size_t, const ItemRange& r) {
    UnitWriter w(kAuditMagic);
    for (long t = r.begin; t < r.end; ++t) {
      w.put<std::int64_t>(a.rows[t].index);
      w.put(a.rows[t].map_status);
      w.put<std::int32_t>(a.rows[t].solutions);
      w.put(a.rows[t].manipulability_map);
      w.put(a.rows[t].manipulability_best);
      putTally(w, a.rows[t].tally);
    }
    return w.bytes();
  };
  loop.unpack = [&](std::size_t, const ItemRange& r, const std::string& bytes) {
    UnitReader rd(bytes, kAuditMagic);
    for (long t = r.begin; t < r.end; ++t) {
      a.rows[t].index = static_cast<long>(rd.get<std::int64_t>());
      a.rows[t].map_status = rd.get<ReachStatus>();
      a.rows[t].solutions = rd.get<std::int32_t>();
      a.rows[t].manipulability_map = rd.get<double>();
      a.rows[t].manipulability_best = rd.get<double>();
      getTally(rd, a.rows[t].tally);
    }
    ARMSTUDY_CHECK(rd.finished(), "the audit's rows arrive whole");
  };
  runSharedLoop(runner, loop);
  for (const ReachAuditPose& r : a.rows) {
    a.descents.add(r.tally);
    const int s = static_cast<int>(r.map_status);
    ++a.by_status[s];
    if (r.map_status != ReachStatus::Reachable && r.solutions > 0) ++a.contradicted[s];
    if (r.map_status == ReachStatus::Reachable && r.solutions == 0) ++a.audit_missed;
    if (r.map_status == ReachStatus::Reachable && r.solutions > 0) {
      ++a.manipulability_compared;
      a.manipulability_within_5pct += r.manipulability_map >= 0.95 * r.manipulability_best ? 1 : 0;
    }
  }
  a.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return a;
}

}  // namespace armstudy
