// The [[tracking]] entries' runs in the study's 3-D view (tracking_stage.hpp trackingViewClouds).
#include <cmath>

#include "common/format.hpp"
#include "stages/tracking/tracking_stage.hpp"
#include "study/scene.hpp"

namespace armstudy::tracking {

namespace {

constexpr double kPathPointSize = 0.005;  // [m] drawn size of a path sample

report::ViewCloud runCloud(const Model& model, const TrackingEntry& e, const RunResult& r,
                           const std::string& run) {
  const bool obstacles = !e.obstacles.empty();
  report::ViewCloud c;
  c.name = e.name + " " + run + ": TCP path";
  c.value_quantity = obstacles ? "distance to the obstacles" : "self-collision distance";
  c.value_unit = "mm";
  c.point_size_m = kPathPointSize;
  c.status_names = {"clear", "in contact (volumes overlap)"};
  int closest = -1;
  for (std::size_t k = 0; k < r.samples.size(); ++k) {
    const RunSample& s = r.samples[k];
    const double d = obstacles ? s.obstacle_distance_m : s.self_distance_m;
    c.p_W.push_back({s.p_WT.x(), s.p_WT.y(), s.p_WT.z()});
    c.status.push_back(s.obstacle_distance_m < 0 || s.self_distance_m < 0 ? 1 : 0);
    c.value.push_back(std::isfinite(d) ? 1e3 * d : NAN);
    if (std::isfinite(d) && (closest < 0 || 1e3 * d < c.value[closest]))
      closest = static_cast<int>(k);
  }
  if (closest >= 0) {
    const RunSample& s = r.samples[closest];
    for (const Eigen::Vector3d& x : scene::skeletonPoints(model, s.q))
      c.arm_W.push_back({x.x(), x.y(), x.z()});
    c.arm_caption = "arm: " + model.name +
                    " at the run's closest approach (t = " + formatG(s.t, 4) +
                    " s: " + formatG(c.value[closest], 3) + " mm).";
  }
  return c;
}

}  // namespace

std::vector<report::ViewCloud> trackingViewClouds(const Model& model, const TrackingEntry& e,
                                                  const EntryResult& er) {
  return {runCloud(model, e, er.plain, "without H_c"), runCloud(model, e, er.with_hc, "with H_c")};
}

}  // namespace armstudy::tracking
