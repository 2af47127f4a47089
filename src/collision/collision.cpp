#include "collision/collision.hpp"

#include <algorithm>
#include <cmath>

#include "collision/collision_model.hpp"
#include "common/errors.hpp"

namespace armstudy::collision {

using Eigen::Vector3d;

Obstacle sphereObstacle(std::string name, const Vector3d& c_W, double radius_m) {
  Obstacle o;
  o.name = std::move(name);
  o.type = SsvType::Point;
  o.p_W[0] = c_W;
  o.radius_m = radius_m;
  return o;
}

Obstacle capsuleObstacle(std::string name, const Vector3d& a_W, const Vector3d& b_W, double radius_m) {
  Obstacle o;
  o.name = std::move(name);
  o.type = SsvType::Line;
  o.p_W[0] = a_W;
  o.p_W[1] = b_W;
  o.radius_m = radius_m;
  return o;
}

namespace {

// Bounding sphere of a core (centroid of its points; radius to the farthest point plus r).
void boundCore(const Core& c, double r, Vector3d& centre, double& bound) {
  centre.setZero();
  for (int i = 0; i < c.n; ++i) centre += c.p[i];
  centre /= c.n;
  double far = 0;
  for (int i = 0; i < c.n; ++i) far = std::max(far, (c.p[i] - centre).norm());
  bound = far + r;
}

inline void bodyPose(const Model& model, const KinematicsWorkspace& kin, int link,
                     Eigen::Matrix3d& R, Vector3d& p) {
  if (link < 0) {
    R = model.T_WB.linear();
    p = model.T_WB.translation();
  } else {
    R = kin.R_WF[link];
    p = kin.p_WF[link];
  }
}

}  // namespace

CollisionWorkspace::CollisionWorkspace(const Model& model) {
  const int n = model.dof();
  ARMSTUDY_CHECK(n + 1 <= kMaxBodies, "collision: too many joints");
  const auto& vols = model.collision.volumes;
  ARMSTUDY_CHECK(static_cast<int>(vols.size()) <= kMaxVolumes, "collision: too many volumes");
  num_volumes = static_cast<int>(vols.size());
  // Sort volume slots by body (stable: model order within a body).
  int slot = 0;
  for (int b = 0; b <= n; ++b) {
    body_begin[b] = slot;
    for (int i = 0; i < num_volumes; ++i) {
      if (vols[i].link + 1 != b) continue;
      ARMSTUDY_CHECK(volumeGeometryProblem(vols[i].type, vols[i].p_L, vols[i].radius_m).empty(),
                     "collision: invalid volume reached the workspace");
      model_index[slot] = i;
      core_L[slot].n = static_cast<int>(vols[i].type);
      for (int k = 0; k < 3; ++k) core_L[slot].p[k] = vols[i].p_L[k];
      radius[slot] = vols[i].radius_m;
      boundCore(core_L[slot], radius[slot], centre_L[slot], bound_r[slot]);
      ++slot;
    }
  }
  ARMSTUDY_CHECK(slot == num_volumes, "collision: a volume is attached to a body outside the chain");
  for (int b = n + 1; b <= kMaxBodies; ++b) body_begin[b] = slot;
  for (int b = 0; b <= n; ++b) {
    body_centre_L[b].setZero();
    body_bound_r[b] = 0;
    const int k0 = body_begin[b], k1 = body_begin[b + 1];
    if (k0 == k1) continue;
    Vector3d c = Vector3d::Zero();
    int count = 0;
    for (int k = k0; k < k1; ++k)
      for (int i = 0; i < core_L[k].n; ++i, ++count) c += core_L[k].p[i];
    c /= count;
    double r = 0;
    for (int k = k0; k < k1; ++k)
      for (int i = 0; i < core_L[k].n; ++i) r = std::max(r, (core_L[k].p[i] - c).norm() + radius[k]);
    body_centre_L[b] = c;
    body_bound_r[b] = r;
  }
  for (int a = -1; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      if (!isCollisionPair(model, a, b)) continue;
      if (body_begin[a + 1] == body_begin[a + 2] || body_begin[b + 1] == body_begin[b + 2]) continue;
      PairDistance& p = self[num_self++];
      p.link_a = a;
      p.link_b = b;
    }
  J_a.setZero(6, n);
  J_b.setZero(6, n);
}

void collisionDistances(const Model& model, const KinematicsWorkspace& kin,
                        std::span<const Obstacle> obstacles, CollisionWorkspace& ws,
                        const CollisionQueryOptions& options) {
  ARMSTUDY_CHECK(static_cast<int>(obstacles.size()) <= kMaxObstacles, "collision: too many obstacles");
  ARMSTUDY_CHECK(kin.n == model.dof(), "collision: kinematics workspace of another model");
  const int n = model.dof();
  const double cutoff = options.cutoff_m;
  ws.cutoff_used_m = cutoff;

  // Volumes and body bounds into W.
  Eigen::Matrix3d R;
  Vector3d p;
  for (int b = 0; b <= n; ++b) {
    bodyPose(model, kin, b - 1, R, p);
    ws.body_centre_W[b] = p + R * ws.body_centre_L[b];
    for (int k = ws.body_begin[b]; k < ws.body_begin[b + 1]; ++k) {
      Core& c = ws.core_W[k];
      c.n = ws.core_L[k].n;
      for (int i = 0; i < c.n; ++i) c.p[i] = p + R * ws.core_L[k].p[i];
      ws.centre_W[k] = p + R * ws.centre_L[k];
    }
  }

  // Exact minimum over the volume pairs of two groups (volume slots [a0, a1) against [b0, b1), or
  // against one obstacle core). Bounding spheres give lower bounds; the pair with the smallest
  // bound is evaluated first, then every pair whose bound cannot beat the best so far (or lies
  // beyond the cutoff) is skipped. Witness points are built once, for the winning pair.
  const Core* ob_core = nullptr;
  Vector3d ob_centre = Vector3d::Zero();
  double ob_bound = 0, ob_radius = 0;
  auto groupPair = [&](int a0, int a1, int b0, int b1, PairDistance& out) {
    const bool env = ob_core != nullptr;
    auto coreB = [&](int kb) -> const Core& { return env ? *ob_core : ws.core_W[kb]; };
    auto lowerBound = [&](int ka, int kb) {
      const Vector3d& cb = env ? ob_centre : ws.centre_W[kb];
      return (ws.centre_W[ka] - cb).norm() - ws.bound_r[ka] - (env ? ob_bound : ws.bound_r[kb]);
    };
    int first_a = a0, first_b = b0;
    double first_lb = std::numeric_limits<double>::infinity();
    for (int ka = a0; ka < a1; ++ka)
      for (int kb = b0; kb < b1; ++kb) {
        const double lb = lowerBound(ka, kb);
        if (lb < first_lb) {
          first_lb = lb;
          first_a = ka;
          first_b = kb;
        }
      }
    double best = std::numeric_limits<double>::infinity();
    double lower = std::numeric_limits<double>::infinity();  // smallest bound skipped by the cutoff
    int win_a = -1, win_b = -1;
    Vector3d ca, cb;
    auto evaluate = [&](int ka, int kb) {
      const double d = std::sqrt(squaredDistanceCores(ws.core_W[ka], coreB(kb), ca, cb)) - ws.radius[ka] -
                       (env ? ob_radius : ws.radius[kb]);
      if (d < best) {
        best = d;
        win_a = ka;
        win_b = kb;
      }
    };
    if (first_lb < cutoff)
      evaluate(first_a, first_b);
    else
      lower = first_lb;
    for (int ka = a0; ka < a1; ++ka)
      for (int kb = b0; kb < b1; ++kb) {
        if (ka == first_a && kb == first_b) continue;
        const double lb = lowerBound(ka, kb);
        if (lb >= best) continue;
        if (lb >= cutoff) {
          lower = std::min(lower, lb);
          continue;
        }
        evaluate(ka, kb);
      }
    if (win_a >= 0 && best <= lower) {
      ssvDistance(ws.core_W[win_a], ws.radius[win_a], coreB(win_b), env ? ob_radius : ws.radius[win_b], out.w);
      out.distance_m = out.w.distance_m;
      out.exact = true;
      out.volume_a = ws.model_index[win_a];
      out.volume_b = env ? -1 : ws.model_index[win_b];
    } else {
      // Everything beyond the cutoff (or the best found lies beyond a skipped lower bound).
      out.distance_m = std::min(best, lower);
      out.exact = false;
    }
  };

  ws.closest_self = -1;
  if (options.self) {
    double min_d = std::numeric_limits<double>::infinity();
    for (int i = 0; i < ws.num_self; ++i) {
      PairDistance& pr = ws.self[i];
      const int a = pr.link_a + 1, b = pr.link_b + 1;
      pr.volume_a = pr.volume_b = -1;
      const double lb = (ws.body_centre_W[a] - ws.body_centre_W[b]).norm() - ws.body_bound_r[a] -
                        ws.body_bound_r[b];
      if (lb >= cutoff) {
        pr.distance_m = lb;
        pr.exact = false;
      } else {
        groupPair(ws.body_begin[a], ws.body_begin[a + 1], ws.body_begin[b], ws.body_begin[b + 1], pr);
      }
      if (pr.distance_m < min_d) {
        min_d = pr.distance_m;
        ws.closest_self = i;
      }
    }
  }

  ws.num_env = 0;
  ws.closest_env = -1;
  if (options.environment) {
    ob_core = nullptr;
    double min_d = std::numeric_limits<double>::infinity();
    for (int o = 0; o < static_cast<int>(obstacles.size()); ++o) {
      const Obstacle& ob = obstacles[o];
      Core oc;
      oc.n = static_cast<int>(ob.type);
      for (int i = 0; i < 3; ++i) oc.p[i] = ob.p_W[i];
      Vector3d oc_centre;
      double oc_bound;
      boundCore(oc, ob.radius_m, oc_centre, oc_bound);
      for (int b = 0; b <= n; ++b) {
        if (ws.body_begin[b] == ws.body_begin[b + 1]) continue;
        PairDistance& pr = ws.env[ws.num_env];
        pr.link_a = b - 1;
        pr.link_b = o;
        pr.volume_a = pr.volume_b = -1;
        const double lb = (ws.body_centre_W[b] - oc_centre).norm() - ws.body_bound_r[b] - oc_bound;
        if (lb >= cutoff) {
          pr.distance_m = lb;
          pr.exact = false;
        } else {
          ob_core = &oc;
          ob_centre = oc_centre;
          ob_bound = oc_bound;
          ob_radius = ob.radius_m;
          groupPair(ws.body_begin[b], ws.body_begin[b + 1], 0, 1, pr);
          pr.volume_b = o;
        }
        if (pr.distance_m < min_d) {
          min_d = pr.distance_m;
          ws.closest_env = ws.num_env;
        }
        ++ws.num_env;
      }
    }
  }
}

double minSelfDistance(const CollisionWorkspace& ws) {
  return ws.closest_self < 0 ? std::numeric_limits<double>::infinity()
                             : ws.self[ws.closest_self].distance_m;
}

double minEnvironmentDistance(const CollisionWorkspace& ws) {
  return ws.closest_env < 0 ? std::numeric_limits<double>::infinity()
                            : ws.env[ws.closest_env].distance_m;
}

std::string pairName(const Model& model, const PairDistance& p, bool environment,
                     std::span<const Obstacle> obstacles) {
  std::string a = bodyName(model, p.link_a);
  if (environment) {
    std::string o = p.link_b >= 0 && p.link_b < static_cast<int>(obstacles.size()) &&
                            !obstacles[p.link_b].name.empty()
                        ? obstacles[p.link_b].name
                        : std::to_string(p.link_b);
    return a + "-obstacle:" + o;
  }
  return a + "-" + bodyName(model, p.link_b);
}

}  // namespace armstudy::collision
