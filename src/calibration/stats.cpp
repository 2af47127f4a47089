#include "calibration/stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "common/errors.hpp"
#include "common/rng.hpp"

namespace armstudy::calibration {

ChannelStats channelStats(const std::vector<double>& r) {
  ChannelStats s;
  s.n = static_cast<int>(r.size());
  if (r.empty()) return s;
  double sq = 0, sum = 0;
  for (double v : r) {
    sq += v * v;
    sum += v;
    s.max_abs = std::max(s.max_abs, std::abs(v));
  }
  s.rmse = std::sqrt(sq / r.size());
  s.bias = sum / r.size();
  return s;
}

double mean(const std::vector<double>& x) {
  return x.empty() ? 0.0 : std::accumulate(x.begin(), x.end(), 0.0) / x.size();
}

double lag1Autocorrelation(const std::vector<double>& x) {
  if (x.size() < 3) return 0.0;
  const double m = mean(x);
  double num = 0, den = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    den += (x[i] - m) * (x[i] - m);
    if (i > 0) num += (x[i] - m) * (x[i - 1] - m);
  }
  return den > 0 ? num / den : 0.0;
}

double effectiveSampleSize(int n, double rho) {
  const double r = std::clamp(rho, 0.0, 0.95);
  return std::clamp(n * (1.0 - r) / (1.0 + r), std::min(1.0, double(n)), double(n));
}

double normalQuantile(double p) {
  ARMSTUDY_CHECK(p > 0 && p < 1, "normalQuantile needs p in (0, 1)");
  // Bisection on the CDF 0.5 erfc(-x / sqrt 2): monotone, 200 halvings reach double precision.
  double lo = -40, hi = 40;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

std::vector<int> foldAssignment(int n, int k, std::uint64_t seed) {
  ARMSTUDY_CHECK(k >= 2 && n >= k, "k-fold needs 2 <= k <= n");
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::uint64_t state = seed;
  for (int i = n - 1; i > 0; --i)
    std::swap(perm[i], perm[rng::splitmix64Next(state) % static_cast<std::uint64_t>(i + 1)]);
  std::vector<int> fold(n);
  for (int j = 0; j < n; ++j) fold[perm[j]] = static_cast<int>(static_cast<long long>(j) * k / n);
  return fold;
}

namespace {
constexpr double kOffGridShare = 0.01;  // values allowed off the resolution grid
}  // namespace

// The logging resolution of one channel: the step of the grid its values lie on (all but
// kOffGridShare of them within 1e-6 steps of a multiple of the smallest nonzero difference between
// sorted values, counted from the smallest value); 0 when there is none (filtered or continuous
// data).
double loggingResolution(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  if (x.size() < 2 || !(x.back() > x.front())) return 0.0;
  const double range = x.back() - x.front();
  double q = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < x.size(); ++i)
    if (x[i] - x[i - 1] > 1e-9 * range) q = std::min(q, x[i] - x[i - 1]);
  if (!std::isfinite(q) || range / q > 1e6) return 0.0;
  std::size_t off = 0;
  for (double y : x) {
    const double k = (y - x.front()) / q;
    off += std::abs(k - std::round(k)) > 1e-6 * std::max(1.0, k) + 1e-6;
  }
  return off <= kOffGridShare * x.size() ? q : 0.0;
}

}  // namespace armstudy::calibration
