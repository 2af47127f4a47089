#include "stages/reach/reach_units.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "collision/reach_collision.hpp"
#include "common/defaults.hpp"

namespace armstudy::reach_units {

constexpr char kUnitMagic[] = "armstudy-reach-unit-v7";

// The unit layout, both ways (study/checkpoint.hpp): the sizes and flags, then every per-pose
// array (the chains' solve counts follow).
template <class Io, class Sweep>
void sweepFields(Io& io, Sweep& s) {
  unitValue<std::int64_t>(io, s.dof);
  for (auto* v : {&s.offset, &s.size}) unitValue<std::int64_t>(io, *v);
  for (auto* flag : {&s.collision, &s.obstacles}) unitValue<std::uint8_t>(io, *flag);
  forEachPoseArray([&](auto& v) { unitField(io, v); }, s);
  unitField(io, s.pair_names);
}

std::string serializeSweep(const PoseSweep& s) {
  UnitWriter w(kUnitMagic);
  sweepFields(w, s);
  putTally(w, s.chain);
  return w.bytes();
}

bool deserializeSweep(const std::string& b, const std::string& design, PoseSweep& s) {
  UnitReader r(b, kUnitMagic);
  s = PoseSweep{};
  s.design = design;
  sweepFields(r, s);
  getTally(r, s.chain);
  if (!r.finished() || s.size < 0 || s.dof < 0) return false;
  const auto n = static_cast<std::size_t>(s.size);
  const std::size_t nc = s.collision ? n : 0, no = s.obstacles ? n : 0;
  return s.status.size() == n && s.starts.size() == n && s.position_error_m.size() == n &&
         s.orientation_error_rad.size() == n && s.manipulability.size() == n &&
         s.joint_limit_margin.size() == n && s.q.size() == n * s.dof &&
         s.q_alt.size() == n * s.dof && s.min_distance_m.size() == nc &&
         s.colliding_pair.size() == nc && s.obstacle_distance_m.size() == no;
}

namespace {

long posesOf(const TaskGrid& g) { return g.size(); }
long posesOf(const PoseList& l) { return static_cast<long>(l.poses.size()); }

// One design's sweep of a grid or pose list, as checkpoint units of `unit_poses` poses (rounded to
// whole sweep units, at least one): units saved by an interrupted run are loaded, the others
// solved in one parallel sweep and each saved as soon as it is done; the sweep is assembled from
// the units in index order. Unit ids: <prefix>/units_<first>-<end> (a range of sweep units). A
// saved unit that does not fit (place, size, design size, collision columns) is solved again.
// `batch()` is what the runner runs (alone, or with other designs' in one pool: runUnitBatches);
// `finish()` assembles the sweep afterwards.
template <class Source, class SweepRanges>
class UnitSweepJob {
 public:
  UnitSweepJob(const StageContext& ctx, const std::string& prefix, const Model& model,
               const Source& source, const SweepCollision& collision, Progress& progress,
               SweepRanges sweep_ranges)
      : prefix_(prefix),
        model_(model),
        len_(sweepUnitLength(source)),
        poses_(posesOf(source)),
        collision_(collision),
        progress_(progress),
        sweep_ranges_(std::move(sweep_ranges)) {
    if (collision.enabled())
      pair_names_ = collision::collisionPairNames(model, collision.obstacles, collision.self);
    const long unit_poses =
        ctx.options.unit_items > 0 ? ctx.options.unit_items : defaults::kReachUnitPoses;
    ranges_ = splitRange(sweepUnitCount(source), std::max(1L, unit_poses / len_));
  }
  UnitSweepJob(const UnitSweepJob&) = delete;  // the batch's functions point at this job
  UnitSweepJob& operator=(const UnitSweepJob&) = delete;

  UnitBatch batch() {
    auto load = [this](std::size_t k, const std::string& bytes) {
      PoseSweep c;
      const long first = ranges_[k].begin * len_,
                 n = std::min(poses_, ranges_[k].end * len_) - first;
      if (!(deserializeSweep(bytes, model_.name, c) && c.offset == first && c.size == n &&
            c.dof == model_.dof() && c.collision == collision_.enabled() &&
            c.obstacles == !collision_.obstacles.empty() && c.pair_names == pair_names_))
        return false;
      progress_.advance(n);
      chunks_.push_back(std::move(c));
      return true;
    };
    auto compute = [this](const std::vector<std::size_t>&, const std::vector<ItemRange>& todo,
                          const RangeDone& done) {
      solved_.clear();  // each call replaces the previous one's units (UnitBatch)
      if (todo.empty()) return;
      solved_ = sweep_ranges_(
          todo, [&](std::size_t j, const PoseSweep& c) { done(j, serializeSweep(c)); });
    };
    return rangeUnitBatch(unitIds(prefix_ + "/units_", ranges_), ranges_, load, compute);
  }

  PoseSweep finish(StageResult& sum) {
    if (solved_.empty() && !chunks_.empty()) return assembleSweep(std::move(chunks_), poses_);
    double wall = 0, t_reach = 0, t_unreach = 0;
    long nr = 0, n = 0;
    for (PoseSweep& c : solved_) {
      wall = std::max(wall, c.wall_seconds);
      t_reach += c.solve_seconds_reachable;
      t_unreach += c.solve_seconds_unreachable;
      nr += c.countReachable();
      n += c.size;
      chunks_.push_back(std::move(c));
    }
    sum.timings.push_back({prefix_ + "/wall", wall});
    sum.timings.push_back({prefix_ + "/per_reachable_pose", nr ? t_reach / nr : 0.0});
    sum.timings.push_back({prefix_ + "/per_unreachable_pose", n > nr ? t_unreach / (n - nr) : 0.0});
    return assembleSweep(std::move(chunks_), poses_);
  }

 private:
  std::string prefix_;
  const Model& model_;
  long len_, poses_;
  const SweepCollision collision_;  // a copy: ReachConfig::collisionFor returns it by value
  Progress& progress_;
  SweepRanges sweep_ranges_;
  std::vector<std::string> pair_names_;
  std::vector<ItemRange> ranges_;
  std::vector<PoseSweep> chunks_, solved_;
};

template <class Source, class SweepRanges>
std::unique_ptr<UnitSweepJob<Source, SweepRanges>> makeJob(
    const StageContext& ctx, const std::string& prefix, const Model& model, const Source& source,
    const ReachConfig& cfg, Progress& progress, SweepRanges sweep_ranges) {
  return std::make_unique<UnitSweepJob<Source, SweepRanges>>(
      ctx, prefix, model, source, cfg.collisionFor(model), progress, std::move(sweep_ranges));
}

auto gridJob(const StageContext& ctx, const std::string& prefix, const Model& model,
             const TaskGrid& g, const ReachConfig& cfg, Progress& progress) {
  return makeJob(ctx, prefix, model, g, cfg, progress,
                 [&ctx, &model, &g, &cfg, &progress](const std::vector<ItemRange>& ranges,
                                                     const SweepChunkDone& done) {
                   return sweepGridRanges(model, g, ranges, cfg.ik, ctx.threads, &progress,
                                          cfg.collisionFor(model), done);
                 });
}

}  // namespace

std::vector<PoseSweep> solveGridDesigns(const StageContext& ctx, StageResult& sum,
                                        const std::string& prefix,
                                        const std::vector<const Model*>& models, const TaskGrid& g,
                                        const ReachConfig& cfg, Progress& progress) {
  using Job = decltype(gridJob(ctx, prefix, *models.front(), g, cfg, progress));
  std::vector<Job> jobs;
  std::vector<UnitBatch> batches;
  for (const Model* m : models) {
    jobs.push_back(gridJob(ctx, prefix + "/" + m->name, *m, g, cfg, progress));
    batches.push_back(jobs.back()->batch());
  }
  sum.units_resumed += runUnitBatches(ctx.units, batches);
  std::vector<PoseSweep> out;
  for (Job& job : jobs) out.push_back(job->finish(sum));
  return out;
}

PoseSweep solvePoseList(const StageContext& ctx, StageResult& sum, const std::string& prefix,
                        const Model& model, const PoseList& l, const ReachConfig& cfg,
                        Progress& progress) {
  auto job = makeJob(ctx, prefix, model, l, cfg, progress,
                     [&](const std::vector<ItemRange>& ranges, const SweepChunkDone& done) {
                       return sweepPoseListRanges(model, l, ranges, cfg.ik, ctx.threads, &progress,
                                                  cfg.collisionFor(model), done);
                     });
  sum.units_resumed += ctx.units.run(job->batch());
  return job->finish(sum);
}

// Summary metrics of one unit for baselines and checks.
void addUnitMetrics(StudyMetrics& m, const std::string& prefix, const PoseSweep& s) {
  const long nr = s.countReachable();
  m.scalars[prefix + "/reachable_fraction"] = s.size ? double(nr) / s.size : 0.0;
  double sum_m = 0;
  std::vector<std::uint8_t> flags(s.size);
  std::vector<double> reachable_m;
  reachable_m.reserve(static_cast<std::size_t>(nr));
  for (long i = 0; i < s.size; ++i) {
    flags[i] = s.reachable(i);
    if (flags[i]) {
      sum_m += s.manipulability[i];
      reachable_m.push_back(s.manipulability[i]);
    }
  }
  m.scalars[prefix + "/manipulability_mean"] = nr ? sum_m / nr : 0.0;
  // The weakest part of the map (objectives of a design-space exploration): the lowest and the
  // 5th-percentile manipulability over the reachable poses (nearest rank: the ceil(0.05 n)-th
  // smallest), 0 when nothing is reachable.
  std::sort(reachable_m.begin(), reachable_m.end());
  const std::size_t p5 =
      reachable_m.empty() ? 0 : static_cast<std::size_t>(std::ceil(0.05 * reachable_m.size())) - 1;
  m.scalars[prefix + "/manipulability_min"] = reachable_m.empty() ? 0.0 : reachable_m.front();
  m.scalars[prefix + "/manipulability_p5"] = reachable_m.empty() ? 0.0 : reachable_m[p5];
  m.flags[prefix + "/reachable"] = flags;
}

}  // namespace armstudy::reach_units
