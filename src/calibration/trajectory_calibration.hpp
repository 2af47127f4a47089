#pragma once
// Model versus measurement, kind `trajectory`: joint efforts (or motor currents) measured
// along a joint trajectory against inverse dynamics (src/dynamics RNEA) plus the drive chain
// (src/drive). Candidate effects: payload, rotor_inertia, gravity_tilt, link_mass.<joint> and the
// drive friction effects per joint <joint>.<coulomb|viscous|load_coulomb|load_viscous|stribeck|
// asymmetry>. docs/calibration.md, "Arms".
//
// Measured channel per joint j (with a [[drive]]): tau_j = N * T_a (the joint-side drive effort,
// e.g. k_m N I, including drive friction and rotor inertia) or current_j = T_a / k_m, with
// T_a = Q_j / N + T_loss(N qd_j, Q_j) + J_m N qdd_j (thesis eq. 3.27a, 4.1a, 4.5) and Q = RNEA.
// Joints without a drive: tau_j = Q_j (currents need a drive).
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "model/model.hpp"

namespace armstudy::calibration {

// CSV columns t [s], q1..qn, qd1..qdn, optional qdd1..qddn, and tau1..taun [N m | N] or
// current1..currentn [A]. Without qdd the accelerations are the Savitzky-Golay derivative of qd
// (local quadratic over 9 samples, defaults::kSavitzkyGolay*).
struct TrajectoryData {
  std::string file = "synthetic", hash;
  std::vector<double> t;
  Eigen::MatrixXd q, qd, qdd;  // rows x n
  bool qdd_given = true;
  bool currents = false;     // measured holds currents [A], else joint efforts
  Eigen::MatrixXd measured;  // rows x n
  std::vector<int> lines;
  std::vector<std::string> warnings;
  // Measured logs (joint_log.hpp): the width w of the smooth sign tanh(v / w) of joint-side and
  // coupled-motor Coulomb friction as a fraction of the peak speed v in the data (0: no joint-side
  // effects, only the drive effects of joints with a [[drive]]), and the coupling matrix R
  // (theta_m = R q, rows motors, design joint order) of motor-side logs (empty when none).
  double friction_width_fraction = 0;
  Eigen::MatrixXd coupling;
  // Per design joint: true where the joint's controller compensates gravity (the measured effort
  // excludes the gravity term, so the model's does too). Empty: none.
  std::vector<bool> gravity_compensated;
  // Measured logs with logged velocities: per design joint, the RMS of logged minus
  // differentiated velocity [rad/s | m/s] (empty when the velocities are differentiated).
  std::vector<double> velocity_difference_rms;
  // Measured logs: per design joint, the logging resolution of the unfiltered joint-side effort
  // [N m | N] (the grid its values lie on, 0 on none); empty for unfiltered data.
  std::vector<double> effort_resolution;
  bool joint_named_channels = false;  // channels labelled by joint name (measured logs)
  int rows() const { return static_cast<int>(t.size()); }
};

TrajectoryData readTrajectoryData(const std::string& path, const Model& model);
std::string trajectoryDataToCsv(const TrajectoryData& data, bool write_qdd);

std::unique_ptr<ArmProblem> makeTrajectoryProblem(const Model& model, const TrajectoryData& data);

struct TrajectorySynthOptions {
  double duration_s = 4.0;
  double rate_Hz = 50.0;
  int harmonics = 3;  // sum of sines per joint
  double max_frequency_Hz = 0.8;
  double range_fraction = 0.35;    // total amplitude as a fraction of the joint range
  double max_amplitude_rad = 1.0;  // revolute joints
  double noise = 0.05;             // effort noise [N m | N] or current noise [A]
  bool currents = false;
  bool write_qdd = true;
  std::vector<std::string> still_joints;  // joints held at their centre (tests, bad input)
  std::uint64_t seed = 1;
  std::vector<std::string> hidden;
};
TrajectoryData synthesizeTrajectory(const Model& model, const TrajectorySynthOptions& options);

// The design with the fitted trajectory effects applied (payload mass and centre, link masses, the
// payload's inertia in the last link, drive rotor inertia and friction, [model] effects, the tilt
// as base alpha/beta, the joint-side terms in Joint::dynamics); `notes`: what the Model cannot hold
// (coupled-motor terms).
Model calibratedTrajectoryModel(const Model& model, const ArmProblem& problem,
                                const EffectValues& values, std::vector<std::string>& notes);

}  // namespace armstudy::calibration
