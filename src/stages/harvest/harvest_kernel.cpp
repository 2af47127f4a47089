#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "common/errors.hpp"
#include "common/first_exception.hpp"
#include "dynamics/approach_tracking.hpp"
#include "io/approach_io.hpp"
#include "io/files.hpp"
#include "io/toml_reader.hpp"
#include "io/vtk_io.hpp"
#include "report/image.hpp"
#include "report/markdown.hpp"
#include "stages/harvest/harvest_stage.hpp"

namespace armstudy::harvest {

namespace fs = std::filesystem;
using io::TableReader;
using nlohmann::ordered_json;
// ---------------------------------------------------------------------------------------------
// Evaluation
// ---------------------------------------------------------------------------------------------

namespace {

Eigen::Matrix3d toolRotation(double beta) {
  return Eigen::AngleAxisd(beta, Eigen::Vector3d::UnitY()).toRotationMatrix();
}

// The (range, item) pairs of `ranges`, in order; every range non-empty and within [0, count).
std::vector<std::pair<std::size_t, long>> workItems(const std::vector<ItemRange>& ranges,
                                                    long count) {
  std::vector<std::pair<std::size_t, long>> items;
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    ARMSTUDY_CHECK(
        0 <= ranges[k].begin && ranges[k].begin < ranges[k].end && ranges[k].end <= count,
        "harvest work range out of bounds");
    for (long i = ranges[k].begin; i < ranges[k].end; ++i) items.emplace_back(k, i);
  }
  return items;
}

ApproachTrackingOptions trackingOptions(const HarvestOptions& o) {
  ApproachTrackingOptions t;
  t.tracking.dt = 1.0 / o.rate_Hz;
  t.tracking.stop_at_joint_limit = true;
  t.R_tool = toolRotation(o.tool_beta_rad);
  return t;
}

// Tells `done` (may be empty) that range k of `res` is complete; `failure` keeps the first
// exception.
void tellRangeDone(FirstException& failure, const RangeDone& done, std::size_t k,
                   const DesignResult& res) {
  if (done) failure.call([&] { done(k, res); });
}

// One approach: planned, tracked, through the drive chain with and without friction.
void evaluateFruit(const Model& model, const RigidBodyModel& rbm, const HarvestOptions& options,
                   const GreenhouseRow& row, const ik::WeightedObjective& objective,
                   const ApproachTrackingOptions& topt, IkWorkspace& ws, ik::ObjectiveContext& ctx,
                   DynamicsWorkspace& dws, int f, FruitResult& out) {
  const SampledFruit& fr = row.fruits[f];
  out.fruit = f;
  out.p_fruit_W = fr.p_W;
  const Eigen::Vector2d stem = row.stems_xy[fr.stem];
  ApproachProblem pb;
  pb.p_start_W =
      Eigen::Vector3d(stem.x() + options.start_offset.x(), stem.y() + options.start_offset.y(),
                      fr.p_W.z() + options.start_offset.z());
  const Eigen::Vector2d to_stem = stem - pb.p_start_W.head<2>();
  pb.cardan_start = Eigen::Vector3d(0, 0, std::atan2(to_stem.y(), to_stem.x()));
  pb.stem_xy_W = stem;
  pb.fruit_W = fr.p_W;
  pb.reference_xy_W = Eigen::Vector2d::Zero();
  const ApproachTrajectory appr = planApproach(pb, options.approach);
  if (appr.status() != ApproachStatus::Ok) {
    out.status = toString(appr.status());
    return;
  }
  const TrackedApproach tr =
      trackApproach(model, ws, ctx, appr, objective, topt, static_cast<std::uint64_t>(f));
  out.max_position_error_m = tr.max_position_error_m;
  out.max_orientation_error_rad = tr.max_orientation_error_rad;
  out.limit_joint = tr.limit_joint;
  out.limit_q = tr.limit_q;
  if (tr.status != ApproachTrackingStatus::Ok) {
    out.status = tr.status == ApproachTrackingStatus::TrackingFailed
                     ? std::string("tracking_") + ik::toString(tr.tracking_status)
                     : std::string(toString(tr.status));
    return;
  }
  out.status = "ok";
  DriveFeasibilityOptions fo;
  fo.temperature_C = options.temperature_C;
  fo.keep_profiles = true;  // friction share and plots need them (a few MB at most)
  fo.friction = true;
  out.with_friction = evaluateDriveFeasibility(model, rbm, dws, tr.trajectory, fo);
  fo.friction = false;
  out.without_friction = evaluateDriveFeasibility(model, rbm, dws, tr.trajectory, fo);
}

// One thread's workspaces.
struct ThreadWorkspaces {
  ThreadWorkspaces(const Model& model, const RigidBodyModel& rbm)
      : ik(model), ctx(model, ik.kin), dyn(rbm) {}
  IkWorkspace ik;
  ik::ObjectiveContext ctx;
  DynamicsWorkspace dyn;
};

// Calls item(ws, i) for the items i of the work's `ranges` (all of [0, count) without work) in
// parallel, each thread with workspaces of its own, handed out `chunk` items at a time; tells the
// work's `done` when a range's last item is done.
template <class Item>
void evaluateRanges(const Model& model, const RigidBodyModel& rbm, const HarvestWork* work,
                    std::vector<ItemRange> HarvestWork::*ranges, RangeDone HarvestWork::*done,
                    long count, int nthreads, int chunk, DesignResult& res, FirstException& failure,
                    const Item& item) {
  std::vector<ItemRange> all;
  if (count > 0) all.push_back({0, count});
  const std::vector<ItemRange>& todo = work ? work->*ranges : all;
  const std::vector<std::pair<std::size_t, long>> items = workItems(todo, count);
  RangeCountdown countdown(todo);
  const long n_items = static_cast<long>(items.size());
#pragma omp parallel num_threads(nthreads)
  {
    ThreadWorkspaces ws(model, rbm);
#pragma omp for schedule(dynamic, chunk)
    for (long w = 0; w < n_items; ++w) {
      const auto [k, i] = items[w];
      item(ws, i);
      if (countdown.itemDone(k)) tellRangeDone(failure, work ? work->*done : RangeDone{}, k, res);
    }
  }
}

// Evaluates the fruits of the work's ranges (all fruits without work) in parallel into res.fruits.
void evaluateFruits(const Model& model, const RigidBodyModel& rbm, const HarvestOptions& options,
                    const GreenhouseRow& row, const ik::WeightedObjective& objective,
                    const ApproachTrackingOptions& topt, int nthreads, const HarvestWork* work,
                    DesignResult& res, FirstException& failure) {
  const long nf = static_cast<long>(row.fruits.size());
  res.fruits.resize(nf);
  evaluateRanges(model, rbm, work, &HarvestWork::fruits, &HarvestWork::fruits_done, nf, nthreads, 1,
                 res, failure, [&](ThreadWorkspaces& ws, long f) {
                   evaluateFruit(model, rbm, options, row, objective, topt, ws.ik, ws.ctx, ws.dyn,
                                 static_cast<int>(f), res.fruits[f]);
                 });
}

// Solves the pose and the static holding load of the grid points of the work's ranges (all
// points without work) in parallel into res.grid.
void evaluateGrid(const Model& model, const RigidBodyModel& rbm, const HarvestOptions& options,
                  int nthreads, const HarvestWork* work, DesignResult& res,
                  FirstException& failure) {
  const HarvestGrid& g = *options.grid;
  const long nx = g.axes[0].count(), ny = g.axes[1].count(), nz = g.axes[2].count();
  const long np = nx * ny * nz;
  res.grid.resize(np);
  const Eigen::Matrix3d R_WT =
      Eigen::AngleAxisd(g.gamma_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
      toolRotation(options.tool_beta_rad);
  IkOptions iko;
  iko.classify_failures = false;
  evaluateRanges(
      model, rbm, work, &HarvestWork::grid, &HarvestWork::grid_done, np, nthreads, 8, res, failure,
      [&](ThreadWorkspaces& ws, long p) {
        const long i = p % nx, j = (p / nx) % ny, k = p / (nx * ny);
        const PoseTask target = fullPoseTask(Eigen::Vector3d(g.axes[0].value(static_cast<int>(i)),
                                                             g.axes[1].value(static_cast<int>(j)),
                                                             g.axes[2].value(static_cast<int>(k))),
                                             R_WT);
        const IkResult r = solvePose(model, ws.ik, target, iko, static_cast<std::uint64_t>(p));
        GridPointResult& gp = res.grid[p];
        gp.reachable = r.reachable();
        if (gp.reachable) gp.holding = holdingLoad(model, rbm, ws.dyn, r.q);
      });
}

}  // namespace

// Sets up the design's dynamics and tracking objective, then evaluates the fruits and the grid.
DesignResult evaluateHarvestDesign(const Model& model, const HarvestOptions& options,
                                   const GreenhouseRow& row, int threads, const HarvestWork* work) {
  ARMSTUDY_CHECK(options.validate().empty(), "harvest options must validate");
  DesignResult res;
  res.design = model.name;
  DynamicsOptions dopt;
  dopt.include_rotor_inertia = false;  // the drive chain adds J_rotor (counted once)
  const RigidBodyModel rbm = makeRigidBodyModel(model, dopt);
  ik::WeightedObjective objective;
  if (options.w_joint_limits > 0)
    objective.add(options.w_joint_limits,
                  std::make_shared<ik::JointLimitTerm>(model, defaults::kJointLimitActivation));
  if (options.w_manipulability > 0)
    objective.add(options.w_manipulability,
                  std::make_shared<ik::ManipulabilityTerm>(metrics::MeasureSpace::Translational));
  const ApproachTrackingOptions topt = trackingOptions(options);
  const int nthreads = threads > 0 ? threads : omp_get_max_threads();
  FirstException failure;
  evaluateFruits(model, rbm, options, row, objective, topt, nthreads, work, res, failure);
  failure.rethrow();
  if (options.grid) {
    evaluateGrid(model, rbm, options, nthreads, work, res, failure);
    failure.rethrow();
  }
  return res;
}

}  // namespace armstudy::harvest
