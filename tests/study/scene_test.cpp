// The ParaView scene geometry (study/scene.hpp): obstacle and robot surfaces lie on their
// swept-sphere volumes (distances from collision/distance, not the mesh code), the skeleton
// follows the joint frames, time steps are spread evenly.
#include "study/scene.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "collision/distance.hpp"
#include "io/design_io.hpp"
#include "kinematics/kinematics.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;

namespace {
constexpr double kSurfaceTolerance = 1e-9;  // [m] a mesh vertex on its volume's surface

// Distance of p from the core (point, segment or triangle) of a swept-sphere volume.
double coreDistance(SsvType type, const std::array<Eigen::Vector3d, 3>& c,
                    const Eigen::Vector3d& p) {
  Eigen::Vector3d closest;
  switch (type) {
    case SsvType::Point:
      return (p - c[0]).norm();
    case SsvType::Line:
      return std::sqrt(collision::squaredDistancePointSegment(p, c[0], c[1], closest));
    case SsvType::Triangle:
      return std::sqrt(collision::squaredDistancePointTriangle(p, c[0], c[1], c[2], closest));
  }
  return NAN;
}

// A mesh vertex of a swept-sphere volume: never outside it, and on the sphere around one of its
// core points or at the radius from the core (tube and face points); the corner spheres' inner
// halves lie inside the volume.
bool onVolume(SsvType type, const std::array<Eigen::Vector3d, 3>& c, double r,
              const Eigen::Vector3d& p) {
  const double d = coreDistance(type, c, p);
  bool on = std::abs(d - r) < kSurfaceTolerance;
  for (int i = 0; i < static_cast<int>(type); ++i)
    on = on || std::abs((p - c[i]).norm() - r) < kSurfaceTolerance;
  return on && d <= r + kSurfaceTolerance;
}

const io::NamedArray& array(const io::PolyDataSet& p, const std::string& name) {
  for (const auto& a : p.point_arrays)
    if (a.name == name) return a;
  FAIL("no array " << name);
  return p.point_arrays.front();
}
}  // namespace

TEST_CASE("obstacle surfaces lie on their spheres, capsules and swept triangles", "[scene]") {
  std::vector<collision::Obstacle> obs{
      collision::sphereObstacle("fruit", Eigen::Vector3d(0.2, 0.7, 1.2), 0.045),
      collision::capsuleObstacle("stem", Eigen::Vector3d(0.225, 0.7, 0),
                                 Eigen::Vector3d(0.225, 0.7, 2), 0.012)};
  collision::Obstacle tri;
  tri.name = "platform";
  tri.type = SsvType::Triangle;
  tri.p_W = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0.2)};
  tri.radius_m = 0.02;
  obs.push_back(tri);
  const io::PolyDataSet poly = scene::obstaclePolyData(obs);
  const io::NamedArray& idx = array(poly, "obstacle");
  std::array<int, 3> count{};
  for (std::size_t k = 0; k < poly.points.size(); ++k) {
    const collision::Obstacle& o = obs[static_cast<std::size_t>(idx.values[k])];
    ++count[static_cast<std::size_t>(idx.values[k])];
    CHECK(onVolume(o.type, o.p_W, o.radius_m, poly.points[k]));
    if (o.type == SsvType::Point)
      CHECK(std::abs((poly.points[k] - o.p_W[0]).norm() - o.radius_m) < kSurfaceTolerance);
  }
  CHECK(count[0] > 0);
  CHECK(count[1] > 0);
  CHECK(count[2] > 0);
  for (const auto& t : poly.triangles)
    for (int i : t) CHECK((i >= 0 && i < static_cast<int>(poly.points.size())));
  REQUIRE(poly.field_data.size() == 3);
  CHECK(poly.field_data[0].values == std::vector<std::string>{io::kWorldMetres});
  CHECK(poly.field_data[2].values[1].find("stem") != std::string::npos);
}

TEST_CASE("the robot's skeleton follows its frames and its volumes lie on the posed SSVs",
          "[scene]") {
  const Model m = loadDesign(sourcePath("designs/final_prototype_7dof.toml"));
  REQUIRE(!m.collision.empty());
  std::mt19937_64 rng(18);
  const Eigen::VectorXd q = randomConfiguration(m, rng);
  const io::PolyDataSet poly = scene::robotPolyData(m, q);
  KinematicsWorkspace ws(m);
  forwardKinematics(m, ws, q);
  REQUIRE(poly.lines.size() == 1);
  REQUIRE(poly.lines[0].size() == static_cast<std::size_t>(m.dof() + 2));
  CHECK((poly.points[poly.lines[0][0]] - m.T_WB.translation()).norm() == 0);
  for (int i = 0; i < m.dof(); ++i)
    CHECK((poly.points[poly.lines[0][i + 1]] - ws.p_WF[i]).norm() == 0);
  CHECK((poly.points[poly.lines[0].back()] - ws.p_WT).norm() == 0);
  const io::NamedArray& part = array(poly, "part");
  const io::NamedArray& body = array(poly, "body");
  long surface = 0;
  for (std::size_t k = 0; k < poly.points.size(); ++k) {
    if (part.values[k] != 1) continue;
    ++surface;
    // The point lies on some volume of its body.
    bool on = false;
    for (const CollisionVolume& v : m.collision.volumes) {
      if (v.link != static_cast<int>(body.values[k])) continue;
      const Eigen::Matrix3d R = v.link < 0 ? Eigen::Matrix3d(m.T_WB.linear()) : ws.R_WF[v.link];
      const Eigen::Vector3d p =
          v.link < 0 ? Eigen::Vector3d(m.T_WB.translation()) : ws.p_WF[v.link];
      std::array<Eigen::Vector3d, 3> c;
      for (int j = 0; j < 3; ++j) c[j] = p + R * v.p_L[j];
      on = on || onVolume(v.type, c, v.radius_m, poly.points[k]);
    }
    CHECK(on);
  }
  CHECK(surface > 0);
}

TEST_CASE("motion steps are spread evenly with the first and the last sample", "[scene]") {
  CHECK(scene::evenSamples(0, 31).empty());
  CHECK(scene::evenSamples(1, 31) == std::vector<int>{0});
  CHECK(scene::evenSamples(5, 31) == std::vector<int>{0, 1, 2, 3, 4});
  CHECK(scene::evenSamples(101, 5) == std::vector<int>{0, 25, 50, 75, 100});
  const std::vector<int> s = scene::evenSamples(4001, 31);
  CHECK(s.size() == 31);
  CHECK(s.back() == 4000);
}
