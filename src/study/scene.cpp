#include "study/scene.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "common/format.hpp"
#include "kinematics/kinematics.hpp"

namespace armstudy::scene {

namespace {

constexpr int kSegments = 16;  // around a sphere or a capsule
constexpr int kRings = 8;      // from pole to pole of a sphere

// Triangle surfaces of swept-sphere volumes, with one value of a point array per point.
struct MeshBuilder {
  io::PolyDataSet& poly;
  std::vector<double>& tag;
  double value = 0;

  int add(const Eigen::Vector3d& p) {
    poly.points.push_back(p);
    tag.push_back(value);
    return static_cast<int>(poly.points.size()) - 1;
  }
  void sphere(const Eigen::Vector3d& c, double r) {
    const int north = add(c + r * Eigen::Vector3d::UnitZ());
    std::vector<int> prev(kSegments, north);
    for (int i = 1; i <= kRings; ++i) {
      std::vector<int> ring(kSegments);
      if (i == kRings) {
        ring.assign(kSegments, add(c - r * Eigen::Vector3d::UnitZ()));
      } else {
        const double th = std::numbers::pi * i / kRings;
        for (int k = 0; k < kSegments; ++k) {
          const double ph = 2 * std::numbers::pi * k / kSegments;
          ring[k] = add(c + r * Eigen::Vector3d(std::sin(th) * std::cos(ph),
                                                std::sin(th) * std::sin(ph), std::cos(th)));
        }
      }
      for (int k = 0; k < kSegments; ++k) {
        const int k1 = (k + 1) % kSegments;
        if (i > 1) poly.triangles.push_back({prev[k], ring[k], prev[k1]});
        if (i < kRings) poly.triangles.push_back({prev[k1], ring[k], ring[k1]});
      }
      prev = ring;
    }
  }
  // The side of the cylinder of radius r around the segment a-b.
  void cylinder(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r) {
    const Eigen::Vector3d axis = b - a;
    if (axis.norm() <= 0 || r <= 0) return;
    const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.normalized().cross(u);
    std::vector<int> ra(kSegments), rb(kSegments);
    for (int k = 0; k < kSegments; ++k) {
      const double ph = 2 * std::numbers::pi * k / kSegments;
      const Eigen::Vector3d d = r * (std::cos(ph) * u + std::sin(ph) * v);
      ra[k] = add(a + d);
      rb[k] = add(b + d);
    }
    for (int k = 0; k < kSegments; ++k) {
      const int k1 = (k + 1) % kSegments;
      poly.triangles.push_back({ra[k], ra[k1], rb[k]});
      poly.triangles.push_back({rb[k], ra[k1], rb[k1]});
    }
  }
  // A swept-sphere volume (thesis section 3.4.4): sphere, capsule or swept triangle.
  void ssv(SsvType type, const std::array<Eigen::Vector3d, 3>& p, double r) {
    const int n = static_cast<int>(type);
    for (int i = 0; i < n; ++i) sphere(p[i], r);
    if (n == 2) cylinder(p[0], p[1], r);
    if (n < 3) return;
    for (int i = 0; i < 3; ++i) cylinder(p[i], p[(i + 1) % 3], r);
    const Eigen::Vector3d nrm = (p[1] - p[0]).cross(p[2] - p[0]).normalized() * r;
    poly.triangles.push_back({add(p[0] + nrm), add(p[1] + nrm), add(p[2] + nrm)});
    poly.triangles.push_back({add(p[0] - nrm), add(p[2] - nrm), add(p[1] - nrm)});
  }
};

}  // namespace

std::vector<Eigen::Vector3d> skeletonPoints(const Model& model,
                                            const Eigen::Ref<const Eigen::VectorXd>& q) {
  KinematicsWorkspace ws(model);
  forwardKinematics(model, ws, q);
  std::vector<Eigen::Vector3d> p{model.T_WB.translation()};
  for (int i = 0; i < model.dof(); ++i) p.push_back(ws.p_WF[i]);
  p.push_back(ws.p_WT);
  return p;
}

io::PolyDataSet robotPolyData(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q) {
  io::PolyDataSet poly;
  KinematicsWorkspace ws(model);
  forwardKinematics(model, ws, q);
  std::vector<double> part, body;
  MeshBuilder mesh{poly, body};
  const std::vector<Eigen::Vector3d> joints = skeletonPoints(model, q);
  std::vector<int> skeleton;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    mesh.value = std::clamp(static_cast<int>(i) - 1, 0, model.dof() - 1);
    skeleton.push_back(mesh.add(joints[i]));
  }
  poly.lines.push_back(skeleton);
  part.assign(poly.points.size(), 0.0);
  body.front() = -1;
  for (const CollisionVolume& v : model.collision.volumes) {
    const Eigen::Matrix3d R = v.link < 0 ? Eigen::Matrix3d(model.T_WB.linear()) : ws.R_WF[v.link];
    const Eigen::Vector3d p =
        v.link < 0 ? Eigen::Vector3d(model.T_WB.translation()) : ws.p_WF[v.link];
    std::array<Eigen::Vector3d, 3> p_W;
    for (int k = 0; k < 3; ++k) p_W[k] = p + R * v.p_L[k];
    mesh.value = v.link;
    mesh.ssv(v.type, p_W, v.radius_m);
  }
  part.resize(poly.points.size(), 1.0);
  poly.point_arrays = {{"part", io::ArrayType::UInt8, 1, part},
                       {"body", io::ArrayType::Int32, 1, body}};
  std::vector<std::string> legend{"part 0: skeleton (base origin, joint frame origins, TCP)",
                                  "part 1: collision volume surface", "body -1: base"};
  for (int i = 0; i < model.dof(); ++i)
    legend.push_back("body " + std::to_string(i) + ": link after joint " + model.joints[i].name);
  std::string qtext;
  for (int i = 0; i < model.dof(); ++i) qtext += (i ? "," : "") + formatG(q[i], 9);
  poly.field_data = io::fieldData({"position: m", "part: 1", "body: 1"}, legend);
  poly.field_data.push_back({"design", {model.name}});
  poly.field_data.push_back({"q", {qtext + " (rad, m for prismatic joints)"}});
  return poly;
}

io::PolyDataSet obstaclePolyData(const std::vector<collision::Obstacle>& obstacles) {
  io::PolyDataSet poly;
  std::vector<double> index;
  MeshBuilder mesh{poly, index};
  std::vector<std::string> legend;
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const collision::Obstacle& o = obstacles[i];
    mesh.value = static_cast<double>(i);
    mesh.ssv(o.type, o.p_W, o.radius_m);
    legend.push_back("obstacle " + std::to_string(i) + ": " + o.name + " (" + toString(o.type) +
                     ", r = " + formatG(o.radius_m, 9) + " m)");
  }
  poly.point_arrays = {{"obstacle", io::ArrayType::Int32, 1, index}};
  poly.field_data = io::fieldData({"position: m", "obstacle: 1"}, legend);
  return poly;
}

std::vector<int> evenSamples(int n, int max_steps) {
  std::vector<int> idx;
  const int k = std::min(n, max_steps);
  for (int i = 0; i < k; ++i)
    idx.push_back(k == 1 ? 0 : static_cast<int>(std::lround(double(i) * (n - 1) / (k - 1))));
  return idx;
}

std::string writeMotion(Writer& out, const std::string& rel_stem, const Model& model,
                        const std::vector<MotionStep>& steps) {
  std::vector<io::PvdStep> pvd;
  const std::string folder = std::filesystem::path(rel_stem).filename().string();
  for (std::size_t k = 0; k < steps.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "step_%03zu.vtp", k);
    io::PolyDataSet poly = robotPolyData(model, steps[k].q);
    poly.field_data.push_back({"time", {formatG(steps[k].t, 9) + " s"}});
    io::writeVtp(out.path(rel_stem + "/" + name), poly);
    out.add(rel_stem + "/" + name);
    pvd.push_back({steps[k].t, folder + "/" + name});
  }
  io::writePvd(out.path(rel_stem + ".pvd"), pvd);
  out.add(rel_stem + ".pvd");
  return rel_stem + ".pvd";
}

}  // namespace armstudy::scene
