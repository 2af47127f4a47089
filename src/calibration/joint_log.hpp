#pragma once
// Measured joint data of a real arm (docs/calibration.md, "Bring your own robot's logs"): logged
// positions and efforts (separate CSV files allowed), motor side or joint side, turned into the
// joint-side TrajectoryData of the trajectory kind. Nothing here knows a particular robot: files,
// columns, units, ratios, the coupling matrix and offsets all come from the study's
// [calibration.measured] table (docs/study-format.md).
//
// Motor side to joint side: with the coupling matrix R (motor positions theta_m = R q, R = diag of
// the reduction ratios plus the coupling entries), q = R^-1 theta_m + offset and tau = R^T tau_m
// (power balance: tau^T qd = tau_m^T theta_m_dot).
//
// Current logs: efforts in A become motor torques kt_j i_j (torque constant per logged column, sign
// included) before the motor-to-joint step; a joint-side current log gives tau_j = r_j kt_j i_j.
//
// Velocity and acceleration: both channels (positions and efforts) go through the same zero-phase
// low-pass (a Butterworth filter of even order run forward and backward, so no delay and gain
// |H(f)|^2, 1/2 at the cut-off), then qd and qdd are central differences of the filtered position,
// the samples are decimated (every k-th) and `trim` is cut from both ends, where the filter and the
// differences see the border. A time column may jitter (warned; differences use the actual times);
// a step over twice the median one is a gap, an input error. Logged velocities (and accelerations)
// go through the same conversion and filter and replace the differences (accelerations without a
// log: differences of the logged velocity); the RMS of logged minus differentiated is reported.
//
// Time columns: every file with one (its own `time_column`, else the log's when the file has that
// column) is checked against the positions' time: its own gaps, its rate (median step) and, row by
// row, its offset (more than half a step apart). With `resample`, each such file is interpolated
// linearly onto the positions' times instead (positions rows outside every file's span dropped).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "calibration/trajectory_calibration.hpp"
#include "model/model.hpp"

namespace armstudy::calibration {

// One CSV file of a log: its path and the columns (header names) in the order of `joints`.
struct LogFile {
  std::string path;  // empty: the file is not logged (velocities, accelerations)
  std::vector<std::string> columns;
  double scale = 1.0;       // file unit -> SI
  std::string time_column;  // this file's own time column (empty: JointLogSpec::time_column)
};

struct JointLogSpec {
  std::string study_file;  // where the spec was written (errors about settings name it)
  int study_line = 0;
  std::string study_key;            // key path of the spec's table (errors: <study_key>.<key>)
  std::vector<std::string> joints;  // design joint names, one per logged column
  LogFile positions, efforts;
  LogFile velocities, accelerations;  // optional (path empty): same side and coupling as positions
  std::string time_column;            // in the positions file; empty: sample_period_s
  bool resample = false;              // interpolate the other files onto the positions' times
  // Efforts logged as motor current [A]: the torque constant per logged column [N m/A or N/A],
  // sign included, never 0 (empty: the efforts are torques or forces), and for a joint-side log
  // the reduction ratio per column (tau = ratio x kt x current; empty: 1).
  std::vector<double> torque_constants, effort_ratios;
  // Joints whose controller compensates gravity: their logged effort excludes the gravity term.
  std::vector<std::string> gravity_compensated;
  double sample_period_s = 0;
  bool motor_side = false;
  Eigen::MatrixXd coupling;  // R (joints x joints), theta_m = R q; identity for joint side
  Eigen::VectorXd offsets;   // added to the joint positions [rad | m]
  double cutoff_Hz = 0;      // zero-phase low-pass cut-off
  int filter_order = 2;      // per pass, even
  int decimate = 1;          // keep every k-th sample after filtering
  double trim_s = 0;         // cut from both ends after filtering
  double friction_width_fraction = 0;  // smooth sign width / the joint's peak speed (0: default)
};

// Reads both files, converts, filters, differentiates, decimates, trims. Bad input (lengths that
// differ, time not increasing, NaN or empty cells, an unknown column or joint, a singular coupling
// matrix) is an InputError naming the file, line and column.
TrajectoryData readJointLog(const JointLogSpec& spec, const Model& model);

// Zero-phase Butterworth low-pass (order `order` per pass, even) at cut-off fc [Hz] for samples
// every h seconds: forward, then backward; odd reflections at both ends start the filter.
std::vector<double> zeroPhaseLowPass(const std::vector<double>& x, double h, double fc, int order);

// Central differences (one-sided at the two ends) of samples every h seconds, or at times t.
std::vector<double> centralDifference(const std::vector<double>& x, double h);
std::vector<double> centralDifference(const std::vector<double>& x, const std::vector<double>& t);

// Motor side to joint side for one sample: q = R^-1 theta_m, tau = R^T tau_m.
void motorToJoint(const Eigen::MatrixXd& R, const Eigen::VectorXd& theta_m,
                  const Eigen::VectorXd& tau_m, Eigen::VectorXd& q, Eigen::VectorXd& tau);

}  // namespace armstudy::calibration
