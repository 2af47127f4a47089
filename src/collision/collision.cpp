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
      if (core_L[slot].n == 2) {
        seg_len2[slot] = (core_L[slot].p[1] - core_L[slot].p[0]).squaredNorm();  // > 0: validated
        seg_inv_len2[slot] = 1.0 / seg_len2[slot];
      }
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
      if (c.n == 2) ws.seg_d_W[k] = c.p[1] - c.p[0];  // length fixed: seg_len2 set at construction
    }
  }

  // Exact minimum over the volume pairs of two groups (volume slots [a0, a1) against [b0, b1), or
  // against one obstacle core). Pairs whose bounding spheres lie beyond the cutoff are skipped
  // (their bound is kept as a lower bound). The others are evaluated in a branch-free first pass
  // (independent kernels overlap in the pipeline), then the minimum is picked; witness points are
  // built once, for the winner. Culling against the best-so-far does not pay for these small
  // groups: it adds a data-dependent branch per pair and saves few evaluations.
  const Core* ob_core = nullptr;
  Vector3d ob_centre = Vector3d::Zero();
  double ob_bound = 0, ob_radius = 0;
  constexpr int kGroup = 64;
  std::array<double, kGroup> g_sq, g_s, g_t;
  std::array<int, kGroup> g_ka, g_kb;
  auto groupPair = [&](int a0, int a1, int b0, int b1, PairDistance& out) {
    const bool env = ob_core != nullptr;
    const bool cull = cutoff < std::numeric_limits<double>::infinity();
    double lower = std::numeric_limits<double>::infinity();  // smallest bound skipped by the cutoff
    int m = 0;
    for (int ka = a0; ka < a1; ++ka)
      for (int kb = b0; kb < b1; ++kb) {
        if (cull) {
          const double lb = (ws.centre_W[ka] - (env ? ob_centre : ws.centre_W[kb])).norm() - ws.bound_r[ka] -
                            (env ? ob_bound : ws.bound_r[kb]);
          if (lb >= cutoff) {
            lower = std::min(lower, lb);
            continue;
          }
        }
        ARMSTUDY_CHECK(m < kGroup, "collision: more than 64 volume pairs between two bodies");
        const Core& ca = ws.core_W[ka];
        const Core& cb = env ? *ob_core : ws.core_W[kb];
        double sq;
        if (!env && ca.n == 2 && cb.n == 2) {
          sq = squaredDistanceSegmentSegmentFast(ca.p[0], ws.seg_d_W[ka], ws.seg_len2[ka], ws.seg_inv_len2[ka],
                                                 cb.p[0], ws.seg_d_W[kb], ws.seg_len2[kb], ws.seg_inv_len2[kb],
                                                 g_s[m], g_t[m]);
        } else {
          Vector3d pa, pb;
          sq = squaredDistanceCores(ca, cb, pa, pb);
          g_s[m] = -1;  // marks the general path: the witnesses are recomputed for the winner
        }
        g_sq[m] = sq;
        g_ka[m] = ka;
        g_kb[m] = kb;
        ++m;
      }
    double best = std::numeric_limits<double>::infinity();
    int win = -1;
    for (int i = 0; i < m; ++i) {
      const double d = std::sqrt(g_sq[i]) - ws.radius[g_ka[i]] - (env ? ob_radius : ws.radius[g_kb[i]]);
      win = d < best ? i : win;
      best = std::min(best, d);
    }
    if (win >= 0 && best <= lower) {
      const int ka = g_ka[win], kb = g_kb[win];
      const Core& cb = env ? *ob_core : ws.core_W[kb];
      Vector3d pa, pb;
      if (g_s[win] >= 0) {
        pa = ws.core_W[ka].p[0] + g_s[win] * ws.seg_d_W[ka];
        pb = cb.p[0] + g_t[win] * ws.seg_d_W[kb];
      } else {
        squaredDistanceCores(ws.core_W[ka], cb, pa, pb);
      }
      ssvDistanceFromWitnesses(pa, ws.radius[ka], pb, env ? ob_radius : ws.radius[kb], out.w);
      out.distance_m = out.w.distance_m;
      out.exact = true;
      out.volume_a = ws.model_index[ka];
      out.volume_b = env ? -1 : ws.model_index[kb];
    } else {
      // Everything beyond the cutoff (or the best found lies beyond a skipped lower bound).
      out.distance_m = std::min(best, lower);
      out.exact = false;
      out.volume_a = out.volume_b = -1;
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
