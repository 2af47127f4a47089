// The whole tree's masses (io/urdf_internal.hpp): the links off the chain that ride on a chain
// link, and the inertials of one body merged about their common COM.
#include <Eigen/Geometry>
#include <algorithm>
#include <string>
#include <vector>

#include "common/format.hpp"
#include "io/urdf_internal.hpp"

namespace armstudy::urdf_detail {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;

double heldPosition(const urdf::Joint& j) {
  if (j.type != urdf::Joint::REVOLUTE && j.type != urdf::Joint::PRISMATIC) return 0;
  if (!j.limits || !(j.limits->lower <= j.limits->upper)) return 0;
  return std::clamp(0.0, j.limits->lower, j.limits->upper);
}

// The joint's motion at q: a turn about or a shift along its axis (fixed, floating, planar: none).
Isometry3d jointMotion(const urdf::Joint& j, double q) {
  Isometry3d M = Isometry3d::Identity();
  Vector3d a(j.axis.x, j.axis.y, j.axis.z);
  if (!(a.norm() > 1e-12)) return M;
  a.normalize();
  if (j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::CONTINUOUS)
    M.linear() = Eigen::AngleAxisd(q, a).toRotationMatrix();
  else if (j.type == urdf::Joint::PRISMATIC)
    M.translation() = q * a;
  return M;
}

std::vector<OffChainLink> offChainLinks(const urdf::ModelInterface& robot,
                                        const std::set<std::string>& on_chain) {
  std::vector<OffChainLink> out;
  for (const auto& [name, link] : robot.links_) {
    if (on_chain.count(name)) continue;
    // Up the parent joints to the chain; links that never reach it are not below the base.
    OffChainLink o;
    o.link = link;
    Isometry3d T = Isometry3d::Identity();  // chain link frame -> this link's frame, built upwards
    urdf::LinkConstSharedPtr l = link;
    while (l && l->parent_joint && !on_chain.count(l->name)) {
      const urdf::Joint& j = *l->parent_joint;
      const double q = heldPosition(j);
      T = toIso(j.parent_to_joint_origin_transform) * jointMotion(j, q) * T;
      if (j.type != urdf::Joint::FIXED) {
        o.held.insert(o.held.begin(), "'" + j.name + "' at " + formatG(q, 6));
      }
      l = robot.getLink(j.parent_link_name);
    }
    if (!l || !on_chain.count(l->name)) continue;
    o.chain_link = l->name;
    o.T_CL = T;
    out.push_back(o);
  }
  return out;
}

// Inertials of the links of one body, merged into one rigid body about its COM, in frame F.
LinkInertia mergeInertials(const std::vector<LinkInBody>& links) {
  LinkInertia out;
  double mass = 0;
  Vector3d mc = Vector3d::Zero();
  struct Part {
    double m;
    Vector3d c;
    Matrix3d I;
  };
  std::vector<Part> parts;
  for (const auto& lb : links) {
    const auto& in = lb.link->inertial;
    if (!in) continue;
    out.given = true;
    const Isometry3d T = lb.T_FL * toIso(in->origin);  // inertial frame in F
    Matrix3d I;
    I << in->ixx, in->ixy, in->ixz, in->ixy, in->iyy, in->iyz, in->ixz, in->iyz, in->izz;
    const Matrix3d R = T.linear();
    parts.push_back({in->mass, T.translation(), R * I * R.transpose()});
    mass += in->mass;
    mc += in->mass * T.translation();
  }
  if (!out.given) return out;
  out.mass_kg = mass;
  out.p_com_m = mass > 0 ? Vector3d(mc / mass) : parts.front().c;
  Matrix3d I = Matrix3d::Zero();
  for (const Part& p : parts) {  // parallel-axis theorem to the common COM
    const Vector3d d = p.c - out.p_com_m;
    I += p.I + p.m * (d.squaredNorm() * Matrix3d::Identity() - d * d.transpose());
  }
  out.I_com_kgm2 = I;
  return out;
}

}  // namespace armstudy::urdf_detail
