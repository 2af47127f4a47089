// Self-collision distance benchmark (docs/performance.md, "## Self-collision distance" and
// "## Collision potential H_c").
//
// 1. Full self-collision evaluation of the shipped models per configuration: forward kinematics
//    + every collision pair's exact distance (and, for the null-space IK use, with the cutoff at
//    the safety distance d_a plus the H_c gradient; at d_a = 0.1 m also the superseded
//    one-term-per-body-pair H_c on the same query, and the mean number of terms of each).
// 2. The same capsule/sphere pairs in FCL 0.7 (specialised capsule-capsule, sphere-capsule and
//    sphere-sphere routines): narrow phase only, on identical world-frame pairs, distances
//    compared pair by pair; then per configuration including FCL's transform updates.
// Best of several repetitions (the machine is shared); times are per configuration or per pair.
#include <fcl/fcl.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <memory>
#include <random>
#include <vector>

#include "collision/collision.hpp"
#include "collision/potential.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::collision;

namespace {

constexpr int kConfigurations = 10000;
constexpr int kRepetitions = 15;

std::vector<Eigen::VectorXd> configurations(const Model& m, int count) {
  std::mt19937_64 rng(42);
  std::vector<Eigen::VectorXd> qs;
  for (int s = 0; s < count; ++s) {
    Eigen::VectorXd q(m.dof());
    for (int i = 0; i < m.dof(); ++i)
      q[i] = std::uniform_real_distribution<double>(m.joints[i].limits.q_min,
                                                    m.joints[i].limits.q_max)(rng);
    qs.push_back(q);
  }
  return qs;
}

// Per-item time of f(begin, end) over [0, items): the work is cut into chunks of ~1000 items,
// each chunk timed on the thread's CPU clock (time spent descheduled on the shared machine does
// not count), and the fastest of kRepetitions runs of each chunk is kept.
template <class F>
double bestNs(int items, F&& f) {
  const int chunk = std::max(1, std::min(items, 1000));
  double total = 0;
  for (int b = 0; b < items; b += chunk) {
    const int e = std::min(items, b + chunk);
    double best = 1e300;
    for (int r = 0; r < kRepetitions; ++r) {
      timespec t0, t1;
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
      f(b, e);
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
      best = std::min(best, (t1.tv_sec - t0.tv_sec) * 1e9 + (t1.tv_nsec - t0.tv_nsec));
    }
    total += best;
  }
  return total / items;
}

volatile double g_sink = 0;

// H_c as it was before SSV pairs (one term per body pair: its closest volume pair), for the
// before/after row: eq. (5.53) over ws.self / ws.env with the witness-point gradient.
double bodyPairPotential(const Model& m, const KinematicsWorkspace& kin, CollisionWorkspace& ws,
                         const CollisionPotentialOptions& o, Eigen::VectorXd& grad) {
  grad.setZero();
  double H = 0;
  auto add = [&](const PairDistance& p, bool environment) {
    if (!p.exact || p.distance_m >= o.safety_distance_m) return;
    double dH = 0;
    H += pairPotential(p.distance_m, o, &dH);
    if (p.w.n.isZero()) return;
    pointJacobian(m, kin, p.link_a, p.w.c_a, ws.J_a);
    grad.noalias() -= dH * (ws.J_a.topRows<3>().transpose() * p.w.n);
    if (!environment) {
      pointJacobian(m, kin, p.link_b, p.w.c_b, ws.J_b);
      grad.noalias() += dH * (ws.J_b.topRows<3>().transpose() * p.w.n);
    }
  };
  for (int i = 0; i < ws.num_self; ++i) add(ws.self[i], false);
  for (int i = 0; i < ws.num_env; ++i) add(ws.env[i], true);
  return H;
}

// The model restricted to point and line SSVs (FCL spheres and capsules).
Model capsulesOnly(const Model& m) {
  Model c = m;
  c.collision.volumes.clear();
  for (const auto& v : m.collision.volumes)
    if (v.type != SsvType::Triangle) c.collision.volumes.push_back(v);
  return c;
}

struct FclVolume {
  std::shared_ptr<fcl::CollisionGeometryd> geom;
  fcl::Transform3d T_LG;  // geometry pose in its link frame
  int link;
};

FclVolume toFcl(const CollisionVolume& v) {
  FclVolume f;
  f.link = v.link;
  f.T_LG.setIdentity();
  if (v.type == SsvType::Point) {
    f.geom = std::make_shared<fcl::Sphered>(v.radius_m);
    f.T_LG.translation() = v.p_L[0];
  } else {
    const Eigen::Vector3d d = v.p_L[1] - v.p_L[0];
    f.geom = std::make_shared<fcl::Capsuled>(v.radius_m, d.norm());
    f.T_LG.translation() = 0.5 * (v.p_L[0] + v.p_L[1]);
    f.T_LG.linear() =
        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), d).toRotationMatrix();
  }
  return f;
}

fcl::Transform3d linkPose(const Model& m, const KinematicsWorkspace& kin, int link) {
  fcl::Transform3d T;
  T.setIdentity();
  if (link < 0) return fcl::Transform3d(m.T_WB.matrix());
  T.linear() = kin.R_WF[link];
  T.translation() = kin.p_WF[link];
  return T;
}

void benchModel(const char* path) {
  const Model full = loadDesign(path);
  const Model m = capsulesOnly(full);
  const auto qs = configurations(full, kConfigurations);
  KinematicsWorkspace kin(full);
  CollisionWorkspace ws_full(full), ws(m);
  int full_pairs = 0, cap_pairs = 0;
  for (int i = 0; i < ws_full.num_self; ++i) {
    const int a = ws_full.self[i].link_a, b = ws_full.self[i].link_b;
    for (const auto& va : full.collision.volumes)
      for (const auto& vb : full.collision.volumes) {
        if (va.link != a || vb.link != b) continue;
        ++full_pairs;
        cap_pairs += (va.type != SsvType::Triangle && vb.type != SsvType::Triangle) ? 1 : 0;
      }
  }
  std::printf("\n%s: %d SSVs (%d triangles), %d collision pairs of bodies, %d SSV pairs\n",
              full.name.c_str(), ws_full.num_volumes, ws_full.num_volumes - ws.num_volumes,
              ws_full.num_self, full_pairs);

  // --- 1. full model, per configuration ---
  const double t_fk = bestNs(kConfigurations, [&](int b, int e) {
    for (int s = b; s < e; ++s) {
      const auto& q = qs[s];
      forwardKinematics(full, kin, q);
      g_sink = g_sink + kin.p_WT.x();
    }
  });
  const double t_exact = bestNs(kConfigurations, [&](int b, int e) {
    for (int s = b; s < e; ++s) {
      const auto& q = qs[s];
      forwardKinematics(full, kin, q);
      collisionDistances(full, kin, {}, ws_full);
      g_sink = g_sink + minSelfDistance(ws_full);
    }
  });
  CollisionPotentialOptions po;
  CollisionQueryOptions qo;
  qo.cutoff_m = po.safety_distance_m;
  Eigen::VectorXd grad(full.dof());
  const double t_cut = bestNs(kConfigurations, [&](int b, int e) {
    for (int s = b; s < e; ++s) {
      const auto& q = qs[s];
      forwardKinematics(full, kin, q);
      collisionDistances(full, kin, {}, ws_full, qo);
      g_sink = g_sink + collisionPotential(full, kin, ws_full, po, grad);
    }
  });
  // H_c at d_a = 0.1 m: the query with that cutoff alone, then with the body-pair minimum
  // formulation (before) and with collisionPotential's sum over SSV pairs (after).
  CollisionPotentialOptions po1;
  po1.safety_distance_m = 0.1;
  CollisionQueryOptions qo1;
  qo1.cutoff_m = po1.safety_distance_m;
  const double t_q1 = bestNs(kConfigurations, [&](int b, int e) {
    for (int s = b; s < e; ++s) {
      forwardKinematics(full, kin, qs[s]);
      collisionDistances(full, kin, {}, ws_full, qo1);
      g_sink = g_sink + minSelfDistance(ws_full);
    }
  });
  const double t_body = bestNs(kConfigurations, [&](int b, int e) {
    for (int s = b; s < e; ++s) {
      forwardKinematics(full, kin, qs[s]);
      collisionDistances(full, kin, {}, ws_full, qo1);
      g_sink = g_sink + bodyPairPotential(full, kin, ws_full, po1, grad);
    }
  });
  const double t_ssv = bestNs(kConfigurations, [&](int b, int e) {
    for (int s = b; s < e; ++s) {
      forwardKinematics(full, kin, qs[s]);
      collisionDistances(full, kin, {}, ws_full, qo1);
      g_sink = g_sink + collisionPotential(full, kin, ws_full, po1, grad);
    }
  });
  long body_terms = 0, ssv_terms = 0;
  double max_h_diff = 0;
  for (const auto& q : qs) {
    forwardKinematics(full, kin, q);
    collisionDistances(full, kin, {}, ws_full, qo1);
    for (int i = 0; i < ws_full.num_self; ++i)
      body_terms += ws_full.self[i].exact && ws_full.self[i].distance_m < po1.safety_distance_m;
    for (int i = 0; i < ws_full.num_near_self; ++i)
      ssv_terms += ws_full.near_self[i].distance_m < po1.safety_distance_m;
    Eigen::VectorXd g_old(full.dof());
    max_h_diff = std::max(max_h_diff, collisionPotential(full, kin, ws_full, po1, grad) -
                                          bodyPairPotential(full, kin, ws_full, po1, g_old));
  }
  std::printf("  %-62s %9.0f ns\n", "forward kinematics alone", t_fk);
  std::printf("  %-62s %9.0f ns\n", "FK + exact distance of every collision pair (all SSVs)",
              t_exact);
  std::printf("  %-62s %9.0f ns\n", "FK + distances below d_a = 0.05 m + H_c and its gradient",
              t_cut);
  std::printf("  %-62s %9.0f ns\n", "FK + distances with cutoff d_a = 0.1 m (no potential)", t_q1);
  std::printf("  %-62s %9.0f ns\n", "  + H_c and gradient, one term per body pair (before)",
              t_body);
  std::printf("  %-62s %9.0f ns\n", "  + H_c and gradient, collisionPotential", t_ssv);
  std::printf(
      "  mean terms below d_a = 0.1 m per configuration: %.2f body pairs, %.2f SSV pairs"
      " (largest H_c(SSV pairs) - H_c(body pairs) %.3f)\n",
      static_cast<double>(body_terms) / kConfigurations,
      static_cast<double>(ssv_terms) / kConfigurations, max_h_diff);

  // --- 2. FCL on the same capsule/sphere pairs ---
  std::vector<FclVolume> fv;
  for (const auto& v : m.collision.volumes) fv.push_back(toFcl(v));
  std::vector<std::array<int, 2>> pairs;  // volume index pairs of the checked body pairs
  for (int i = 0; i < ws.num_self; ++i)
    for (int a = 0; a < static_cast<int>(fv.size()); ++a)
      for (int b = 0; b < static_cast<int>(fv.size()); ++b)
        if (fv[a].link == ws.self[i].link_a && fv[b].link == ws.self[i].link_b)
          pairs.push_back({a, b});
  std::printf("  capsule/sphere subset: %d volumes, %zu SSV pairs\n", ws.num_volumes, pairs.size());

  // Narrow phase on identical world-frame pairs from a subset of the configurations.
  const int nq = 300;  // ~30k pairs: the working set stays in cache
  std::vector<Core> cores_a, cores_b;
  std::vector<double> ra, rb;
  std::vector<fcl::Transform3d> Ta, Tb;
  for (int s = 0; s < nq; ++s) {
    forwardKinematics(m, kin, qs[s]);
    for (const auto& p : pairs) {
      for (int side = 0; side < 2; ++side) {
        const CollisionVolume& v = m.collision.volumes[p[side]];
        const fcl::Transform3d T = linkPose(m, kin, v.link);
        Core c;
        c.n = static_cast<int>(v.type);
        for (int k = 0; k < c.n; ++k) c.p[k] = T * v.p_L[k];
        (side ? cores_b : cores_a).push_back(c);
        (side ? rb : ra).push_back(v.radius_m);
        (side ? Tb : Ta).push_back(T * fv[p[side]].T_LG);
      }
    }
  }
  const int np = static_cast<int>(cores_a.size());
  std::vector<double> d_arm(np), d_fcl(np);
  SsvDistance w;
  const double t_pair_arm = bestNs(np, [&](int b, int e) {
    for (int i = b; i < e; ++i) {
      ssvDistance(cores_a[i], ra[i], cores_b[i], rb[i], w);
      d_arm[i] = w.distance_m;
    }
  });
  fcl::DistanceRequestd req;
  req.enable_nearest_points = true;  // armstudy always returns witness points
  std::vector<const fcl::CollisionGeometryd*> ga(np), gb(np);
  for (int s = 0, i = 0; s < nq; ++s)
    for (const auto& p : pairs) {
      ga[i] = fv[p[0]].geom.get();
      gb[i] = fv[p[1]].geom.get();
      ++i;
    }
  const double t_pair_fcl = bestNs(np, [&](int b, int e) {
    for (int i = b; i < e; ++i) {
      fcl::DistanceResultd res;
      fcl::distance(ga[i], Ta[i], gb[i], Tb[i], req, res);
      d_fcl[i] = res.min_distance;
    }
  });
  double max_diff = 0;
  int compared = 0, overlapping = 0;
  for (int i = 0; i < np; ++i) {
    if (d_arm[i] > 0) {
      max_diff = std::max(max_diff, std::abs(d_arm[i] - d_fcl[i]));
      ++compared;
    } else {
      ++overlapping;  // FCL without signed distance reports overlap differently
    }
  }
  std::printf("  %-62s %9.1f ns\n", "narrow phase per SSV pair, armstudy (with witness points)",
              t_pair_arm);
  std::printf("  %-62s %9.1f ns\n", "narrow phase per SSV pair, FCL 0.7 (with nearest points)",
              t_pair_fcl);
  std::printf("  %-62s %9.1fx\n", "ratio FCL / armstudy", t_pair_fcl / t_pair_arm);
  std::printf(
      "  distances compared on %d separated pairs: max |armstudy - FCL| = %.2e m (%d overlapping "
      "pairs skipped)\n",
      compared, max_diff, overlapping);

  // Per configuration, capsule/sphere subset: FCL updates poses and checks every SSV pair.
  std::vector<fcl::CollisionObjectd> objs;
  for (const auto& f : fv) objs.emplace_back(f.geom);
  const double t_cfg_fcl = bestNs(kConfigurations, [&](int b, int e) {
    for (int s = b; s < e; ++s) {
      const auto& q = qs[s];
      forwardKinematics(m, kin, q);
      for (std::size_t k = 0; k < fv.size(); ++k)
        objs[k].setTransform(linkPose(m, kin, fv[k].link) * fv[k].T_LG);
      double best = 1e300;
      for (const auto& p : pairs) {
        fcl::DistanceRequestd r;
        fcl::DistanceResultd res;
        fcl::distance(&objs[p[0]], &objs[p[1]], r, res);
        best = std::min(best, res.min_distance);
      }
      g_sink = g_sink + best;
    }
  });
  const double t_cfg_arm = bestNs(kConfigurations, [&](int b, int e) {
    for (int s = b; s < e; ++s) {
      const auto& q = qs[s];
      forwardKinematics(m, kin, q);
      collisionDistances(m, kin, {}, ws);
      g_sink = g_sink + minSelfDistance(ws);
    }
  });
  std::printf("  %-62s %9.0f ns\n", "per configuration (capsules/spheres), armstudy FK + all pairs",
              t_cfg_arm);
  std::printf("  %-62s %9.0f ns\n", "per configuration (capsules/spheres), FK + FCL all pairs",
              t_cfg_fcl);
  std::printf("  %-62s %9.1fx\n", "ratio FCL / armstudy", t_cfg_fcl / t_cfg_arm);
}

}  // namespace

int main() {
  std::printf(
      "armstudy self-collision distance benchmark (%d configurations, best of %d per chunk, thread "
      "CPU time)\n",
      kConfigurations, kRepetitions);
  benchModel(armstudy::test::sourcePath("designs/final_prototype_9dof.toml").c_str());
  benchModel(armstudy::test::sourcePath("designs/first_prototype_9dof.toml").c_str());
  return 0;
}
