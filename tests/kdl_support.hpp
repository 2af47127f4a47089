#pragma once
// A Model written as an orocos-kdl chain, kinematic or with inertias (test and benchmark oracle
// only). Built from the Model directly (not from RigidBodyModel), so the payload merge, the inertia
// shift to the link origin and the reflected rotor inertia are checked independently.
#include <kdl/chain.hpp>

#include "model/model.hpp"

namespace armstudy::test {

inline KDL::Frame toKdl(const Eigen::Isometry3d& T) {
  const Eigen::Matrix3d R = T.linear();
  return KDL::Frame(KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0),
                                  R(2, 1), R(2, 2)),
                    KDL::Vector(T.translation().x(), T.translation().y(), T.translation().z()));
}

// The kinematic table as a KDL chain: fixed segment T_WB, per joint a fixed segment T_PJ0 and the
// joint about/along z, then the TCP.
inline KDL::Chain toKdlChain(const Model& m) {
  KDL::Chain c;
  c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(m.T_WB)));
  for (const Joint& j : m.joints) {
    c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(j.T_PJ0)));
    c.addSegment(KDL::Segment(
        KDL::Joint(j.type == JointType::Revolute ? KDL::Joint::RotZ : KDL::Joint::TransZ),
        KDL::Frame::Identity()));
  }
  c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(m.T_NT)));
  return c;
}

inline KDL::RigidBodyInertia toKdl(const LinkInertia& li) {
  if (!li.given) return KDL::RigidBodyInertia::Zero();
  const Eigen::Matrix3d& I = li.I_com_kgm2;
  return KDL::RigidBodyInertia(
      li.mass_kg, KDL::Vector(li.p_com_m.x(), li.p_com_m.y(), li.p_com_m.z()),
      KDL::RotationalInertia(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)));
}

// Fixed segment T_WB, then per joint a fixed segment T_PJ0 and the moving segment (joint about/
// along z, identity tip, link inertia in frame i, armature as KDL joint inertia), then the TCP and
// the payload as a point mass on its own segment. Gravity is passed to the solver in W.
inline KDL::Chain toKdlDynamicChain(const Model& m, bool with_payload, bool with_rotor) {
  KDL::Chain c;
  c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(m.T_WB)));
  for (int i = 0; i < m.dof(); ++i) {
    const Joint& j = m.joints[i];
    double armature = 0;
    if (with_rotor)
      for (const Drive& d : m.drives)
        if (d.joint == j.name) armature = d.gear_ratio * d.gear_ratio * d.rotor_inertia_kgm2;
    c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(j.T_PJ0)));
    const LinkInertia li = m.inertias.empty() ? LinkInertia{} : m.inertias[i];
    c.addSegment(KDL::Segment(
        KDL::Joint(j.type == JointType::Revolute ? KDL::Joint::RotZ : KDL::Joint::TransZ, 1.0, 0.0,
                   armature),
        KDL::Frame::Identity(), toKdl(li)));
  }
  c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), toKdl(m.T_NT)));
  if (with_payload && m.payload_kg > 0) {
    const Eigen::Vector3d& p = m.p_payload_com_T;
    c.addSegment(
        KDL::Segment(KDL::Joint(KDL::Joint::None), KDL::Frame::Identity(),
                     KDL::RigidBodyInertia(m.payload_kg, KDL::Vector(p.x(), p.y(), p.z()))));
  }
  return c;
}

}  // namespace armstudy::test
