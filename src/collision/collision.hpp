#pragma once
// Self-collision and environment distances of an arm's swept-sphere-volume model (thesis section
// 3.4.4; docs/collision.md).
//
// Collision pairs are pairs of bodies (the base and the links after each joint): every pair
// except chain neighbours and the design's [[collision_allowed]] pairs. The distance of a body
// pair is the minimum over all pairs of their volumes: core distance minus both radii, negative
// when the volumes overlap. Environment obstacles (spheres, capsules, swept triangles) are given
// in the task frame W and checked against every body the same way.
//
// Usage: one CollisionWorkspace per thread, built once from the const Model (fixed-size, no heap
// after construction); per configuration run forwardKinematics, then collisionDistances.
#include <Eigen/Core>
#include <array>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "collision/distance.hpp"
#include "common/defaults.hpp"
#include "kinematics/kinematics.hpp"
#include "model/model.hpp"

namespace armstudy::collision {

inline constexpr int kMaxBodies = defaults::kMaxDof + 1;  // base + one body per joint
inline constexpr int kMaxBodyPairs = kMaxBodies * (kMaxBodies - 1) / 2;
inline constexpr int kMaxVolumes = defaults::kMaxCollisionVolumes;
inline constexpr int kMaxObstacles = defaults::kMaxObstacles;

// An environment obstacle, fixed in the task frame W (a plant stem as a capsule, a fruit or
// the Fig. 5.13 obstacle as a sphere, the platform as a swept triangle).
struct Obstacle {
  std::string name;
  SsvType type = SsvType::Point;
  std::array<Eigen::Vector3d, 3> p_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                     Eigen::Vector3d::Zero()};
  double radius_m = 0;
};
Obstacle sphereObstacle(std::string name, const Eigen::Vector3d& c_W, double radius_m);
Obstacle capsuleObstacle(std::string name, const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W,
                         double radius_m);

// The distance of one collision pair and where it is attained.
struct PairDistance {
  int link_a = -1;    // body A: joint index, -1 = base
  int link_b = -1;    // body B: joint index (self pairs) or obstacle index (environment)
  int volume_a = -1;  // model.collision.volumes index of the closest volume on A
  int volume_b = -1;  // volume index on B, or the obstacle index
  double distance_m = std::numeric_limits<double>::infinity();
  bool exact = false;  // false: the pair lies beyond the cutoff; distance_m is a lower bound
  SsvDistance w;       // witness points (core c_a/c_b, surface p_a/p_b) and normal, in W
};

struct CollisionQueryOptions {
  // Pairs whose distance is at least this may be reported by a lower bound (exact = false)
  // instead of the exact value. Infinity: every pair exact. The potential H_c needs exact
  // distances below its safety distance d_a only. A finite cutoff also lists every volume pair
  // closer than it (CollisionWorkspace::near_self / near_env): the terms of H_c.
  double cutoff_m = std::numeric_limits<double>::infinity();
  bool self = true;         // body-body pairs
  bool environment = true;  // body-obstacle pairs
};

struct CollisionWorkspace {
  explicit CollisionWorkspace(const Model& model);

  // --- fixed after construction (derived from the model) ---
  int num_volumes = 0;                         // volumes sorted by body
  std::array<int, kMaxVolumes> model_index{};  // sorted slot -> model.collision.volumes index
  std::array<Core, kMaxVolumes> core_L;        // core points in the link frame
  std::array<double, kMaxVolumes> radius{};
  std::array<Eigen::Vector3d, kMaxVolumes> centre_L;      // bounding sphere of each volume
  std::array<double, kMaxVolumes> bound_r{};              //   (radius included)
  std::array<int, kMaxBodies + 1> body_begin{};           // volumes of body b = link + 1
  std::array<Eigen::Vector3d, kMaxBodies> body_centre_L;  // bounding sphere of each body's volumes
  std::array<double, kMaxBodies> body_bound_r{};
  int num_self = 0;                              // collision pairs with volumes on both bodies
  std::array<PairDistance, kMaxBodyPairs> self;  // link_a/link_b fixed; results per query
  // Flat list of the volume pairs of the self pairs: those of self[i] are
  // [pair_begin[i], pair_begin[i + 1]). Sized once here (no allocation per query).
  std::array<int, kMaxBodyPairs + 1> pair_begin{};
  std::vector<int> pair_a, pair_b;                // volume slots
  std::vector<unsigned char> pair_general;        // 1: a triangle is involved (general routine)
  std::vector<double> pair_d, pair_s, pair_t;     // per query: SSV distance, segment parameters
  std::vector<Eigen::Vector3d> pair_ca, pair_cb;  // per query: core witnesses where pair_s < 0
  std::vector<int> active;                        // per query: pairs to evaluate (capacity: all)

  // --- per query ---
  std::array<Core, kMaxVolumes> core_W;  // core points in W
  std::array<Eigen::Vector3d, kMaxVolumes> centre_W;
  std::array<Eigen::Vector3d, kMaxVolumes> seg_d_W;  // line volumes: p1 - p0 in W (0 for points)
  std::array<double, kMaxVolumes> seg_len2{};        //   |p1 - p0|^2 and its inverse (fixed:
  std::array<double, kMaxVolumes> seg_inv_len2{};    //   set at construction; 0 for points)
  // Structure-of-arrays copy of p0 and p1 - p0 in W for the segment kernel.
  std::array<double, kMaxVolumes> sx{}, sy{}, sz{}, ux{}, uy{}, uz{};
  std::array<Eigen::Vector3d, kMaxBodies> body_centre_W;
  int num_env = 0;  // body-obstacle pairs evaluated
  std::array<PairDistance, kMaxBodies * kMaxObstacles> env;
  int closest_self = -1;  // index into self of the smallest distance
  int closest_env = -1;   // index into env of the smallest distance
  double cutoff_used_m = 0;
  // Queries with a finite cutoff only: every volume pair (SSV pair) closer than the cutoff, each
  // with its own exact distance and witnesses (PairDistance with volume_a/volume_b set and
  // exact = true). Self: the volume pairs of the body pairs in `self`, grouped by body pair in
  // the order of `self`; environment: each volume against each obstacle (volume_b, link_b = the
  // obstacle index), by obstacle, then body. Capacity fixed at construction (all volume pairs).
  int num_near_self = 0;
  std::vector<PairDistance> near_self;
  int num_near_env = 0;
  std::vector<PairDistance> near_env;
  // Jacobian scratch (6 x n) for callers; collisionPotential accumulates J^T f without it.
  Jacobian6 J_a, J_b;
};

// Transforms the volumes with the current forward kinematics (kin must be up to date) and computes
// the distance of every collision pair and every body-obstacle pair. No heap allocation.
void collisionDistances(const Model& model, const KinematicsWorkspace& kin,
                        std::span<const Obstacle> obstacles, CollisionWorkspace& ws,
                        const CollisionQueryOptions& options = {});

// Smallest self / environment distance of the last query (+infinity when there are no pairs).
double minSelfDistance(const CollisionWorkspace& ws);
double minEnvironmentDistance(const CollisionWorkspace& ws);

// Human-readable name of a pair, e.g. "j2-j5" or "j4-obstacle:sphere".
std::string pairName(const Model& model, const PairDistance& p, bool environment,
                     std::span<const Obstacle> obstacles = {});

}  // namespace armstudy::collision
