#pragma once
// Small statistics used by the model-versus-measurement loop (docs/calibration.md).
#include <cstdint>
#include <vector>

namespace armstudy::calibration {

// RMSE, mean (bias) and largest absolute value of a residual channel.
struct ChannelStats {
  int n = 0;
  double rmse = 0;
  double bias = 0;
  double max_abs = 0;
};
ChannelStats channelStats(const std::vector<double>& residual);

double mean(const std::vector<double>& x);
// Lag-1 autocorrelation of a sequence in the order given (the measurement order), in [-1, 1];
// 0 for fewer than 3 values or a constant sequence.
double lag1Autocorrelation(const std::vector<double>& x);
// Effective number of independent samples of n AR(1)-correlated samples with lag-1
// autocorrelation rho: n (1 - rho) / (1 + rho); rho is clamped to [0, 0.95], result to [1, n].
double effectiveSampleSize(int n, double rho);
// Inverse of the standard normal CDF (p in (0, 1)).
double normalQuantile(double p);

// The logging resolution of a channel: the step of the grid its values lie on (all but 1 % of them
// within 1e-6 steps of a multiple of the smallest nonzero difference between sorted values,
// counted from the smallest value); 0 when there is none (filtered or continuous data).
double loggingResolution(std::vector<double> values);

// Deterministic fold of each of n rows for k-fold cross-validation: a seeded permutation cut into
// k nearly equal parts (splitmix64, identical on every platform and thread count).
std::vector<int> foldAssignment(int n, int k, std::uint64_t seed);

}  // namespace armstudy::calibration
