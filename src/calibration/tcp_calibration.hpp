#pragma once
// Model versus measurement, kind `tcp`: measured TCP positions (optionally Cardan angles)
// at known joint positions against the design's forward kinematics. Candidate effects:
// joint_offset.<joint>, link_length.<joint>.<x|y|z>, base_offset, joint_compliance.<joint>
// (deflection = compliance * gravity torque of src/dynamics). docs/calibration.md, "Arms".
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "model/model.hpp"

namespace armstudy::calibration {

// CSV columns q1..qn, x, y, z [m] (TCP position in the design's world frame W, which is the robot
// base frame for designs without a [base] pose), optional alpha, beta, gamma [rad] (R = Rx Ry Rz).
struct TcpData {
  std::string file = "synthetic", hash;
  Eigen::MatrixXd q;     // rows x n
  Eigen::MatrixXd pose;  // rows x 3 (x, y, z) or rows x 6 (+ alpha, beta, gamma)
  std::vector<int> lines;
  std::vector<std::string> warnings;
  int rows() const { return static_cast<int>(q.rows()); }
  bool hasOrientation() const { return pose.cols() == 6; }
};

TcpData readTcpData(const std::string& path, const Model& model);
std::string tcpDataToCsv(const TcpData& data);

std::unique_ptr<ArmProblem> makeTcpProblem(const Model& model, const TcpData& data);

struct TcpSynthOptions {
  int rows = 60;
  double noise_m = 1e-4;    // position noise standard deviation per axis
  double noise_rad = 1e-4;  // angle noise (with orientation)
  bool orientation = false;
  double range_fraction = 0.6;  // joint positions uniform in this central fraction of the limits
  std::uint64_t seed = 1;
  std::vector<std::string> hidden;  // "effect" or "effect:key=value,..."
};
TcpData synthesizeTcp(const Model& model, const TcpSynthOptions& options);

// The design with the fitted tcp effects applied to its table (joint gamma / x,y,z, base pose);
// `notes` lists what the design format cannot carry (joint compliance).
Model calibratedTcpModel(const Model& model, const ArmProblem& problem, const EffectValues& values,
                         std::vector<std::string>& notes);

}  // namespace armstudy::calibration
