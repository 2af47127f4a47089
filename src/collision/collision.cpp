#include "collision/collision.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

Obstacle capsuleObstacle(std::string name, const Vector3d& a_W, const Vector3d& b_W,
                         double radius_m) {
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
      // Points act as zero-length segments in the kernel (length and inverse 0).
      seg_len2[slot] =
          core_L[slot].n == 2 ? (core_L[slot].p[1] - core_L[slot].p[0]).squaredNorm() : 0.0;
      seg_inv_len2[slot] =
          seg_len2[slot] > 0 ? 1.0 / seg_len2[slot] : 0.0;  // > 0 for validated lines
      boundCore(core_L[slot], radius[slot], centre_L[slot], bound_r[slot]);
      ++slot;
    }
  }
  ARMSTUDY_CHECK(slot == num_volumes,
                 "collision: a volume is attached to a body outside the chain");
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
      for (int i = 0; i < core_L[k].n; ++i)
        r = std::max(r, (core_L[k].p[i] - c).norm() + radius[k]);
    body_centre_L[b] = c;
    body_bound_r[b] = r;
  }
  for (int a = -1; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      if (!isCollisionPair(model, a, b)) continue;
      if (body_begin[a + 1] == body_begin[a + 2] || body_begin[b + 1] == body_begin[b + 2])
        continue;
      PairDistance& p = self[num_self++];
      p.link_a = a;
      p.link_b = b;
    }
  for (int i = 0; i < num_self; ++i) {
    pair_begin[i] = static_cast<int>(pair_a.size());
    const int a = self[i].link_a + 1, b = self[i].link_b + 1;
    for (int ka = body_begin[a]; ka < body_begin[a + 1]; ++ka)
      for (int kb = body_begin[b]; kb < body_begin[b + 1]; ++kb) {
        pair_a.push_back(ka);
        pair_b.push_back(kb);
        pair_general.push_back(core_L[ka].n == 3 || core_L[kb].n == 3);
      }
  }
  pair_begin[num_self] = static_cast<int>(pair_a.size());
  pair_d.resize(pair_a.size());
  pair_s.resize(pair_a.size());
  pair_t.resize(pair_a.size());
  pair_ca.resize(pair_a.size());
  pair_cb.resize(pair_a.size());
  active.resize(pair_a.size());
  near_self.resize(pair_a.size());
  near_env.resize(static_cast<std::size_t>(num_volumes) * kMaxObstacles);
  J_a.setZero(6, n);
  J_b.setZero(6, n);
}

namespace {

// Distances of the volume pairs ws.active[0..n). Points and segments go through one branch-free
// structure-of-arrays kernel (the clamped line solution of squaredDistanceSegmentSegmentFast,
// written out on plain arrays, so that the independent pairs of all body pairs overlap in the
// pipeline); near-parallel segments and triangles are then redone with the general routines.
void evaluatePairs(CollisionWorkspace& ws, int n) {
  const double kPar = defaults::kCollisionParallelSin2;
  // Plain pointers: the stores below cannot alias the inputs.
  const int* __restrict act = ws.active.data();
  const int* __restrict pa = ws.pair_a.data();
  const int* __restrict pb = ws.pair_b.data();
  const double* __restrict sx = ws.sx.data();
  const double* __restrict sy = ws.sy.data();
  const double* __restrict sz = ws.sz.data();
  const double* __restrict ux = ws.ux.data();
  const double* __restrict uy = ws.uy.data();
  const double* __restrict uz = ws.uz.data();
  const double* __restrict len2 = ws.seg_len2.data();
  const double* __restrict inv2 = ws.seg_inv_len2.data();
  const double* __restrict rad = ws.radius.data();
  double* __restrict out_d = ws.pair_d.data();
  double* __restrict out_s = ws.pair_s.data();
  double* __restrict out_t = ws.pair_t.data();
  unsigned char* __restrict general = ws.pair_general.data();
  int i0 = 0;
#if defined(__SSE2__)
  // Two pairs per step in the two lanes of an SSE2 register (same operations as the scalar loop).
  {
    const __m128d zero = _mm_setzero_pd(), one = _mm_set1_pd(1.0), tiny = _mm_set1_pd(1e-300),
                  par = _mm_set1_pd(kPar);
    auto clamp = [&](__m128d x) { return _mm_min_pd(_mm_max_pd(x, zero), one); };
    for (; i0 + 1 < n; i0 += 2) {
      const int k0 = act[i0], k1 = act[i0 + 1];
      const int A0 = pa[k0], A1 = pa[k1], B0 = pb[k0], B1 = pb[k1];
      auto gA = [&](const double* v) { return _mm_set_pd(v[A1], v[A0]); };
      auto gB = [&](const double* v) { return _mm_set_pd(v[B1], v[B0]); };
      const __m128d uxA = gA(ux), uyA = gA(uy), uzA = gA(uz), uxB = gB(ux), uyB = gB(uy),
                    uzB = gB(uz);
      const __m128d rx = _mm_sub_pd(gA(sx), gB(sx)), ry = _mm_sub_pd(gA(sy), gB(sy)),
                    rz = _mm_sub_pd(gA(sz), gB(sz));
      const __m128d a = gA(len2), e = gB(len2);
      auto dot = [](__m128d x0, __m128d y0, __m128d z0, __m128d x1, __m128d y1, __m128d z1) {
        return _mm_add_pd(_mm_add_pd(_mm_mul_pd(x0, x1), _mm_mul_pd(y0, y1)), _mm_mul_pd(z0, z1));
      };
      const __m128d b = dot(uxA, uyA, uzA, uxB, uyB, uzB);
      const __m128d c = dot(uxA, uyA, uzA, rx, ry, rz);
      const __m128d f = dot(uxB, uyB, uzB, rx, ry, rz);
      const __m128d ae = _mm_mul_pd(a, e);
      const __m128d den = _mm_sub_pd(ae, _mm_mul_pd(b, b));
      const __m128d s0 =
          clamp(_mm_div_pd(_mm_sub_pd(_mm_mul_pd(b, f), _mm_mul_pd(c, e)), _mm_max_pd(den, tiny)));
      const __m128d t = clamp(_mm_mul_pd(_mm_add_pd(_mm_mul_pd(b, s0), f), gB(inv2)));
      const __m128d sv = clamp(_mm_mul_pd(_mm_sub_pd(_mm_mul_pd(b, t), c), gA(inv2)));
      const __m128d wx = _mm_sub_pd(_mm_add_pd(rx, _mm_mul_pd(sv, uxA)), _mm_mul_pd(t, uxB));
      const __m128d wy = _mm_sub_pd(_mm_add_pd(ry, _mm_mul_pd(sv, uyA)), _mm_mul_pd(t, uyB));
      const __m128d wz = _mm_sub_pd(_mm_add_pd(rz, _mm_mul_pd(sv, uzA)), _mm_mul_pd(t, uzB));
      const __m128d d =
          _mm_sub_pd(_mm_sub_pd(_mm_sqrt_pd(dot(wx, wy, wz, wx, wy, wz)), gA(rad)), gB(rad));
      _mm_storel_pd(&out_d[k0], d);
      _mm_storeh_pd(&out_d[k1], d);
      _mm_storel_pd(&out_s[k0], sv);
      _mm_storeh_pd(&out_s[k1], sv);
      _mm_storel_pd(&out_t[k0], t);
      _mm_storeh_pd(&out_t[k1], t);
      const int near_parallel =
          _mm_movemask_pd(_mm_and_pd(_mm_and_pd(_mm_cmpgt_pd(a, zero), _mm_cmpgt_pd(e, zero)),
                                     _mm_cmpngt_pd(den, _mm_mul_pd(par, ae))));
      general[k0] |= static_cast<unsigned char>((near_parallel & 1) << 1);
      general[k1] |= static_cast<unsigned char>(near_parallel & 2);
    }
  }
#endif
  for (int i = i0; i < n; ++i) {
    const int k = act[i];
    const int A = pa[k], B = pb[k];
    const double rx = sx[A] - sx[B], ry = sy[A] - sy[B], rz = sz[A] - sz[B];
    const double a = len2[A], e = len2[B];
    const double b = ux[A] * ux[B] + uy[A] * uy[B] + uz[A] * uz[B];
    const double c = ux[A] * rx + uy[A] * ry + uz[A] * rz;
    const double f = ux[B] * rx + uy[B] * ry + uz[B] * rz;
    const double den = a * e - b * b;
    const double s0 = clampUnit((b * f - c * e) / maxNoBranch(den, 1e-300));
    const double t = clampUnit((b * s0 + f) * inv2[B]);
    const double s = clampUnit((b * t - c) * inv2[A]);
    const double wx = rx + s * ux[A] - t * ux[B], wy = ry + s * uy[A] - t * uy[B],
                 wz = rz + s * uz[A] - t * uz[B];
    out_d[k] = sqrtNonNegative(wx * wx + wy * wy + wz * wz) - rad[A] - rad[B];
    out_s[k] = s;
    out_t[k] = t;
    // Redo below: both are segments and nearly parallel (a point is exact here), or a triangle.
    general[k] |= static_cast<unsigned char>((a > 0 && e > 0 && !(den > kPar * a * e)) << 1);
  }
  for (int i = 0; i < n; ++i) {
    const int k = act[i];
    if (!general[k]) continue;
    const int A = pa[k], B = pb[k];
    out_d[k] =
        std::sqrt(squaredDistanceCores(ws.core_W[A], ws.core_W[B], ws.pair_ca[k], ws.pair_cb[k])) -
        rad[A] - rad[B];
    out_s[k] = -1;  // witnesses in pair_ca / pair_cb
    general[k] &= 1;
  }
}

// Witnesses of the evaluated volume pair k: from the kernel's segment parameters, or those of the
// general routines (triangles, near-parallel segments).
void volumePairWitnesses(const CollisionWorkspace& ws, int k, SsvDistance& w) {
  const int A = ws.pair_a[k], B = ws.pair_b[k];
  if (ws.pair_s[k] >= 0) {
    const Vector3d ca = ws.core_W[A].p[0] + ws.pair_s[k] * ws.seg_d_W[A];
    const Vector3d cb = ws.core_W[B].p[0] + ws.pair_t[k] * ws.seg_d_W[B];
    ssvDistanceFromWitnesses(ca, ws.radius[A], cb, ws.radius[B], w);
  } else {
    ssvDistanceFromWitnesses(ws.pair_ca[k], ws.radius[A], ws.pair_cb[k], ws.radius[B], w);
  }
}

// The smallest of the evaluated volume pairs [k0, k1) of one body pair, with its witnesses. With
// near_below finite, also appends every volume pair closer than it to ws.near_self.
void finishPair(CollisionWorkspace& ws, int k0, int k1, double near_below, PairDistance& out) {
  int win = k0;
  for (int k = k0 + 1; k < k1; ++k) win = ws.pair_d[k] < ws.pair_d[win] ? k : win;
  const PairDistance* win_near = nullptr;
  if (ws.pair_d[win] < near_below) {
    for (int k = k0; k < k1; ++k) {
      if (!(ws.pair_d[k] < near_below)) continue;
      PairDistance& v = ws.near_self[ws.num_near_self++];
      v.link_a = out.link_a;
      v.link_b = out.link_b;
      v.volume_a = ws.model_index[ws.pair_a[k]];
      v.volume_b = ws.model_index[ws.pair_b[k]];
      volumePairWitnesses(ws, k, v.w);
      v.distance_m = v.w.distance_m;
      v.exact = true;
      if (k == win) win_near = &v;
    }
  }
  if (win_near) {
    out.w = win_near->w;
  } else {
    volumePairWitnesses(ws, win, out.w);
  }
  out.distance_m = out.w.distance_m;
  out.exact = true;
  out.volume_a = ws.model_index[ws.pair_a[win]];
  out.volume_b = ws.model_index[ws.pair_b[win]];
}

// Environment: the exact minimum over one body's volumes [k0, k1) against one obstacle core.
// Volumes whose bounding spheres lie beyond the cutoff are skipped (their bound is kept as a lower
// bound).
void obstaclePair(CollisionWorkspace& ws, double cutoff, double near_below, int k0, int k1,
                  const Core& oc, const Vector3d& oc_centre, double oc_bound, double oc_radius,
                  int obstacle, PairDistance& out) {
  double best = std::numeric_limits<double>::infinity();
  double lower = std::numeric_limits<double>::infinity();
  int win = -1;
  Vector3d win_a = Vector3d::Zero(), win_b = Vector3d::Zero();
  for (int k = k0; k < k1; ++k) {
    const double lb = (ws.centre_W[k] - oc_centre).norm() - ws.bound_r[k] - oc_bound;
    if (lb >= cutoff) {
      lower = std::min(lower, lb);
      continue;
    }
    Vector3d ca, cb;
    const double d =
        std::sqrt(squaredDistanceCores(ws.core_W[k], oc, ca, cb)) - ws.radius[k] - oc_radius;
    if (d < near_below) {
      PairDistance& v = ws.near_env[ws.num_near_env++];
      v.link_a = out.link_a;
      v.link_b = obstacle;
      v.volume_a = ws.model_index[k];
      v.volume_b = obstacle;
      ssvDistanceFromWitnesses(ca, ws.radius[k], cb, oc_radius, v.w);
      v.distance_m = v.w.distance_m;
      v.exact = true;
    }
    if (d < best) {
      best = d;
      win = k;
      win_a = ca;
      win_b = cb;
    }
  }
  if (win >= 0 && best <= lower) {
    ssvDistanceFromWitnesses(win_a, ws.radius[win], win_b, oc_radius, out.w);
    out.distance_m = out.w.distance_m;
    out.exact = true;
    out.volume_a = ws.model_index[win];
  } else {
    out.distance_m = std::min(best, lower);
    out.exact = false;
    out.volume_a = -1;
  }
}

// Volumes into W (bounding-sphere centres only when `need_bounds`).
void placeVolumes(const Model& model, const KinematicsWorkspace& kin, bool need_bounds,
                  CollisionWorkspace& ws) {
  const int n = model.dof();
  Eigen::Matrix3d R;
  Vector3d p;
  for (int b = 0; b <= n; ++b) {
    bodyPose(model, kin, b - 1, R, p);
    if (need_bounds) ws.body_centre_W[b] = p + R * ws.body_centre_L[b];
    for (int k = ws.body_begin[b]; k < ws.body_begin[b + 1]; ++k) {
      Core& c = ws.core_W[k];
      const Core& cl = ws.core_L[k];
      c.n = cl.n;
      c.p[0] = p + R * cl.p[0];
      if (c.n == 2) {
        ws.seg_d_W[k] = R * (cl.p[1] - cl.p[0]);  // rigid: the length is fixed
        c.p[1] = c.p[0] + ws.seg_d_W[k];
      } else {
        ws.seg_d_W[k].setZero();
        for (int i = 1; i < c.n; ++i) c.p[i] = p + R * cl.p[i];
      }
      if (need_bounds) ws.centre_W[k] = p + R * ws.centre_L[k];
      ws.sx[k] = c.p[0].x();
      ws.sy[k] = c.p[0].y();
      ws.sz[k] = c.p[0].z();
      ws.ux[k] = ws.seg_d_W[k].x();
      ws.uy[k] = ws.seg_d_W[k].y();
      ws.uz[k] = ws.seg_d_W[k].z();
    }
  }
}

// Self pairs: body pairs whose bounding spheres lie beyond the cutoff get that bound; the
// volume pairs of all others are evaluated in one flat pass, then reduced per body pair.
void selfDistances(CollisionWorkspace& ws, bool need_bounds, double cutoff, double near_below) {
  int n_active = 0;
  for (int i = 0; i < ws.num_self; ++i) {
    PairDistance& pr = ws.self[i];
    const int a = pr.link_a + 1, b = pr.link_b + 1;
    pr.volume_a = pr.volume_b = -1;
    if (need_bounds) {
      const double lb = (ws.body_centre_W[a] - ws.body_centre_W[b]).norm() - ws.body_bound_r[a] -
                        ws.body_bound_r[b];
      pr.exact = false;
      pr.distance_m = lb;
      if (lb >= cutoff) continue;
    }
    pr.exact = true;  // evaluated below
    for (int k = ws.pair_begin[i]; k < ws.pair_begin[i + 1]; ++k) ws.active[n_active++] = k;
  }
  evaluatePairs(ws, n_active);
  double min_d = std::numeric_limits<double>::infinity();
  for (int i = 0; i < ws.num_self; ++i) {
    PairDistance& pr = ws.self[i];
    if (pr.exact) finishPair(ws, ws.pair_begin[i], ws.pair_begin[i + 1], near_below, pr);
    if (pr.distance_m < min_d) {
      min_d = pr.distance_m;
      ws.closest_self = i;
    }
  }
}

// Every body with volumes against every obstacle.
void environmentDistances(int n, std::span<const Obstacle> obstacles, CollisionWorkspace& ws,
                          double cutoff, double near_below) {
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
        obstaclePair(ws, cutoff, near_below, ws.body_begin[b], ws.body_begin[b + 1], oc, oc_centre,
                     oc_bound, ob.radius_m, o, pr);
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

}  // namespace

void collisionDistances(const Model& model, const KinematicsWorkspace& kin,
                        std::span<const Obstacle> obstacles, CollisionWorkspace& ws,
                        const CollisionQueryOptions& options) {
  ARMSTUDY_CHECK(static_cast<int>(obstacles.size()) <= kMaxObstacles,
                 "collision: too many obstacles");
  ARMSTUDY_CHECK(kin.n == model.dof(), "collision: kinematics workspace of another model");
  const int n = model.dof();
  const double cutoff = options.cutoff_m;
  ws.cutoff_used_m = cutoff;
  // Volume pairs closer than this are listed in near_self / near_env (finite cutoffs only).
  const double near_below = cutoff < std::numeric_limits<double>::infinity() ? cutoff : -cutoff;
  ws.num_near_self = 0;
  ws.num_near_env = 0;

  // Volumes into W (bounding-sphere centres only when something uses them).
  const bool need_bounds = cutoff < std::numeric_limits<double>::infinity() ||
                           (options.environment && !obstacles.empty());
  placeVolumes(model, kin, need_bounds, ws);
  ws.closest_self = -1;
  if (options.self) selfDistances(ws, need_bounds, cutoff, near_below);
  ws.num_env = 0;
  ws.closest_env = -1;
  if (options.environment) environmentDistances(n, obstacles, ws, cutoff, near_below);
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
