#pragma once
// Model versus measurement for one joint drive (issue 7, thesis chapter 4): compare the design's
// friction model with test-bed data, map where it fails, rank the candidate effects that could be
// missing, add them and refit. docs/calibration.md describes formats, statistics and outputs.
//
// The measured quantity is the motor current I; the model predicts it from the drive chain
// I = (T_l / N + T_loss(speed, T_l, theta)) / k_m (thesis eq. 4.3, 4.5). Residual = measured -
// predicted [A]. Friction-torque figures [N m] are the same residuals times k_m (thesis eq. 4.6).
#include <cstdint>
#include <string>
#include <vector>

#include "calibration/stats.hpp"
#include "common/defaults.hpp"
#include "drive/friction.hpp"
#include "model/model.hpp"

namespace armstudy::calibration {

// One drive test-bed file (CSV columns speed, load_torque, current, optional temperature; SI).
struct DriveData {
  std::string file;
  std::string hash;
  std::vector<double> speed;        // motor side [rad/s], signed
  std::vector<double> load;         // output side load torque [N m] (force [N] for prismatic)
  std::vector<double> current;      // [A]
  std::vector<double> temperature;  // [deg C]; empty when the file has no temperature column
  std::vector<int> lines;           // file line of each row
  std::vector<std::string> warnings;  // extra columns, ...
  int rows() const { return static_cast<int>(speed.size()); }
  bool hasTemperature() const { return !temperature.empty(); }
};

// Reads and checks a drive file. Rows at standstill (speed 0) are an InputError naming the line:
// the friction laws do not predict static friction.
DriveData readDriveData(const std::string& path);

// The catalogue of drive effects: SI parameters with bounds, and the residual pattern each explains.
struct EffectParameter {
  std::string key;            // key in [drive.friction]
  std::string unit_motor;     // unit for motor-side laws
  std::string unit_joint;     // unit for joint-side (prismatic) laws
  double lower = 0, upper = 0;  // fit bounds (law side, SI); +-inf when unbounded
  double typical = 0;         // magnitude `armstudy synth` hides by default (motor-side laws)
};
struct EffectInfo {
  drive::Effect effect;
  std::string name;
  std::string thesis;         // where the term comes from
  std::string pattern;        // the residual pattern it explains
  std::vector<EffectParameter> params;  // stribeck: [stribeck_torque, stribeck_velocity]
};
const std::vector<EffectInfo>& driveEffectCatalogue();
const EffectInfo& effectInfo(drive::Effect effect);

struct DriveFitOptions {
  int folds = defaults::kCvFolds;
  std::uint64_t seed = defaults::kCvSeed;
  int speed_bins = defaults::kSpeedBins;
  int load_bins = defaults::kLoadBins;
  double significance_z = defaults::kSignificanceZ;
  double min_relative_improvement = defaults::kMinRelativeImprovement;
  std::vector<drive::Effect> add;  // effects to add (in this order), significant or not
  bool auto_add = false;           // add the best significant effect until none is left
  std::string validate() const;    // "" when valid
};

struct FittedParameter {
  std::string key;
  std::string unit;
  double value = 0;
  double ci_low = 0, ci_high = 0;  // 95 % interval (linearised, inflated for correlated samples)
  bool at_bound = false;
};

// One model (a set of effects) fitted to the data.
struct ModelFit {
  std::string label;                 // "as designed", "refit harmonic_drive", "+stribeck", ...
  std::vector<drive::Effect> effects;
  drive::FrictionParams friction;    // fitted on all rows
  std::vector<FittedParameter> params;
  int n_params = 0;                  // fitted parameters (0 for the design as is)
  double train_rmse = 0;             // [A], all rows
  double heldout_rmse = 0;           // [A], k-fold cross-validation
  double region_heldout_rmse = 0;    // [A], leave-one-region-out (speed x load quadrants)
  double aic = 0, bic = 0;           // Gaussian, from the training residuals
  std::vector<double> predicted;     // [A], fit on all rows
  std::vector<double> residual;      // measured - predicted [A]
  std::vector<double> heldout_residual;  // out-of-fold residuals [A]
};

struct Candidate {
  drive::Effect effect;
  std::string status = "ok";         // ok | unidentifiable | not_applicable | too_few_rows
  ModelFit fit;                      // base + this effect (when status == ok)
  double improvement = 0;            // (heldout_base - heldout) / heldout_base
  double t_statistic = 0;            // paired held-out squared-error difference / its std. error
  bool significant = false;
  std::vector<std::string> warnings;  // identifiability
};

struct ResidualBin {
  int speed_bin = 0, load_bin = 0;
  double speed_lo = 0, speed_hi = 0, load_lo = 0, load_hi = 0;
  int n = 0;
  double n_eff = 0;
  double mean = 0;                   // mean residual [A]
  double threshold = 0;              // |mean| above this is flagged [A]
  bool flagged = false;
};

struct ResidualMap {
  std::vector<double> speed_edges, load_edges;  // signed speed [rad/s], |load|
  std::vector<ResidualBin> bins;     // speed-major; only bins with samples
  double rho = 0;                    // lag-1 autocorrelation used for n_eff
  double z = 0;                      // Bonferroni z
  int flagged() const;
};

// Comparison of one model's prediction with the data.
struct Comparison {
  ChannelStats current;              // [A]
  ChannelStats friction_torque;      // [N m] (= current residual * k_m)
  ResidualMap map;
};

struct DriveDiagnosis {
  std::string design, joint;
  std::vector<std::string> warnings;
  double noise_estimate = 0;         // [A]
  double noise_rho = 0;              // lag-1 autocorrelation of the noise proxy residuals
  ModelFit as_designed;
  Comparison as_designed_cmp;
  ModelFit base;                     // refit of the design's effects
  Comparison base_cmp;
  std::vector<Candidate> ranking;    // for `base`, best first
  bool missing_effect_found = false;
  // "missing effect: X" (the best significant candidate of the refit model), "missing effects: X, Y"
  // when --auto added several, or "no significant missing effect". The one verdict text of the
  // console, result.json and the study stage.
  std::string verdict = "no significant missing effect";
  std::vector<ModelFit> ladder;      // as designed, refit, then one per added effect
  std::vector<drive::Effect> added;
  std::vector<std::vector<Candidate>> rankings_after;  // ranking after each addition
  ModelFit final_fit;
  Comparison final_cmp;
  double rmse_before = 0, rmse_after = 0;  // held-out [A]: refit base, final model
  Model calibrated;                  // the design with the final fitted parameters (when fitted)
};

// Compare only: the design's model as is (no fitting), residual map with the noise estimate.
DriveDiagnosis compareDrive(const Model& model, const std::string& joint, const DriveData& data,
                            const DriveFitOptions& options);
// Compare, refit, rank candidates, add effects as the options ask.
DriveDiagnosis diagnoseDrive(const Model& model, const std::string& joint, const DriveData& data,
                             const DriveFitOptions& options);

// The drive of a joint; InputError (design file, drive key) when the design has none.
const Drive& requireDrive(const Model& model, const std::string& joint);

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
DriveData synthesizeDrive(const Model& model, const std::string& joint, const SynthOptions& options);
std::string driveDataToCsv(const DriveData& data);

}  // namespace armstudy::calibration
