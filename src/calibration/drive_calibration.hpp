#pragma once
// Model versus measurement for one joint drive (thesis chapter 4): the drive kind's data,
// its problem for the one engine of arm_calibration.hpp and its virtual
// test bed. docs/calibration.md describes formats, statistics and outputs; the fit, its
// diagnosis and its report are the engine's (diagnoseArm, writeArmReport) as for every kind.
//
// The measured quantity is the motor current I; the model predicts it from the drive chain
// I = (T_l / N + T_loss(speed, T_l, theta)) / k_m (thesis eq. 4.3, 4.5), with the friction law of
// src/drive/friction.hpp. Residual = measured - predicted [A]. Friction-torque figures [N m] are
// the same residuals times k_m (thesis eq. 4.6).
//
// The problem's catalogue: "refit" (the design's own friction terms, thesis Table 4.5's refit of
// eq. 3.30) and one instance per declared drive effect the design does not have
// (drive::effectDeclarations; those that need a temperature only when the data has a temperature
// column). Every parameter is a
// change to the design's value and reported as the absolute value (ArmParam::design); the
// Stribeck velocity is profiled on a log grid over the measured speed range.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "common/defaults.hpp"
#include "drive/friction.hpp"
#include "model/model.hpp"

namespace armstudy::calibration {

// One drive test-bed file (CSV columns speed, load_torque, current, optional temperature; SI).
struct DriveData {
  std::string file;
  std::string hash;
  std::vector<double> speed;          // motor side [rad/s], signed
  std::vector<double> load;           // output side load torque [N m] (force [N] for prismatic)
  std::vector<double> current;        // [A]
  std::vector<double> temperature;    // [deg C]; empty when the file has no temperature column
  std::vector<int> lines;             // file line of each row
  std::vector<std::string> warnings;  // extra columns, ...
  int rows() const { return static_cast<int>(speed.size()); }
  bool hasTemperature() const { return !temperature.empty(); }
};

// Reads and checks a drive file. Rows at standstill (speed 0) are an InputError naming the line:
// the friction laws do not predict static friction.
DriveData readDriveData(const std::string& path);

// The drive of a joint; InputError (design file, drive key) when the design has none.
const Drive& requireDrive(const Model& model, const std::string& joint);

// The name of the catalogue instance that refits the design's own friction terms.
inline constexpr const char* kRefitEffect = "refit";

// The drive kind's problem for the engine: one channel "current" [A]; operating variables speed,
// load (and temperature); the residual map is the speed x |load| grid (speed_bins x load_bins);
// held-out-by-region uses the four speed x load quadrants split at the medians. Its calibrated
// model has the fitted friction in the drive's [drive.friction] (law "none" when the design had
// no law) and the added effects in [model].effects.
std::unique_ptr<ArmProblem> makeDriveProblem(const Model& model, const std::string& joint,
                                             const DriveData& data,
                                             int speed_bins = defaults::kSpeedBins,
                                             int load_bins = defaults::kLoadBins);
// ---- virtual test bed ----
struct SynthOptions {
  std::vector<double> speeds_radps;  // motor speeds, both signs used; default thesis-like grid
  std::vector<double> loads;         // |load| levels [N m]; default 1.3 .. 17 N m
  int series = 2;                    // repeated test series, each in a seeded speed order
  double noise_A = 0.01;             // current noise standard deviation
  double noise_rho = 0.0;            // AR(1) correlation of successive noise samples
  double temperature_start_C = 25, temperature_end_C = 45;  // warm-up drift over the run
  std::uint64_t seed = 1;
  bool write_temperature = true;
  std::vector<std::pair<drive::Effect, std::vector<std::pair<std::string, double>>>> hidden;
};
// Test-bed rows (speed, load_torque, current, temperature) from the design's drive plus hidden
// effects (parameters not given take the catalogue's typical values).
DriveData synthesizeDrive(const Model& model, const std::string& joint,
                          const SynthOptions& options);
std::string driveDataToCsv(const DriveData& data);

}  // namespace armstudy::calibration
