#include "model/model.hpp"

namespace armstudy {

const char* toString(JointType t) { return t == JointType::Revolute ? "revolute" : "prismatic"; }

Eigen::Isometry3d PoseXYZABG::toIsometry() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  T.linear() = (Eigen::AngleAxisd(alpha, Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(beta, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(gamma, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  return T;
}

int Model::jointIndex(const std::string& joint_name) const {
  for (int i = 0; i < dof(); ++i)
    if (joints[i].name == joint_name) return i;
  return -1;
}

void Model::finalize() {
  for (auto& j : joints) j.T_PJ0 = j.offset.toIsometry();
  T_NT = tcp.toIsometry();
  T_WB = base.toIsometry();
}

}  // namespace armstudy
