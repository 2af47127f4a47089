#include "trajectory/greenhouse_row.hpp"

#include <cmath>
#include <numbers>

#include "common/errors.hpp"

namespace armstudy {
namespace {

double phi(double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi); }
double Phi(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }

}  // namespace

RowRandom::RowRandom(std::uint64_t seed) : gen_(seed) {}

double RowRandom::uniform() { return gen_.uniform(); }

double RowRandom::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u1 = uniform();
  while (u1 <= 0.0) u1 = uniform();
  const double u2 = uniform();
  const double r = std::sqrt(-2.0 * std::log(u1));
  spare_ = r * std::sin(2.0 * std::numbers::pi * u2);
  has_spare_ = true;
  return r * std::cos(2.0 * std::numbers::pi * u2);
}

double RowRandom::truncatedNormal(const TruncatedNormal& d) {
  if (d.sd == 0) return d.mean;
  for (;;) {
    const double x = d.mean + d.sd * normal();
    if (x >= d.min && x <= d.max) return x;
  }
}

bool TruncatedNormal::validate(std::string& error) const {
  if (!(std::isfinite(mean) && std::isfinite(sd) && std::isfinite(min) && std::isfinite(max))) {
    error = "values must be finite";
    return false;
  }
  if (sd < 0) {
    error = "standard deviation must not be negative";
    return false;
  }
  if (!(min <= mean && mean <= max)) {
    error = "need min <= mean <= max";
    return false;
  }
  // Rejection sampling must accept often enough: at least 1 % of the mass inside [min, max].
  if (sd > 0 && Phi((max - mean) / sd) - Phi((min - mean) / sd) < 0.01) {
    error = "[min, max] holds less than 1 % of the distribution";
    return false;
  }
  return true;
}

double TruncatedNormal::truncatedMean() const {
  if (sd == 0) return mean;
  const double a = (min - mean) / sd, b = (max - mean) / sd, Z = Phi(b) - Phi(a);
  return mean + sd * (phi(a) - phi(b)) / Z;
}

double TruncatedNormal::truncatedSd() const {
  if (sd == 0) return 0;
  const double a = (min - mean) / sd, b = (max - mean) / sd, Z = Phi(b) - Phi(a);
  const double m = (phi(a) - phi(b)) / Z;
  return sd * std::sqrt(1.0 + (a * phi(a) - b * phi(b)) / Z - m * m);
}

bool GreenhouseRowOptions::validate(std::string& error) const {
  if (stems < 1) return error = "need at least one stem", false;
  if (fruits_per_stem < 1) return error = "need at least one fruit per stem", false;
  if (!std::isfinite(first_stem_y_m)) return error = "first stem y must be finite", false;
  for (const auto* d : {&row_to_row, &stem_to_stem, &fruit_z, &stem_to_fruit})
    if (!d->validate(error)) return false;
  if (row_to_row.min <= 0 || stem_to_stem.min < 0 || stem_to_fruit.min < 0)
    return error = "distances must not be negative", false;
  if (!(fruit_angle_min_rad < fruit_angle_max_rad) || !std::isfinite(fruit_angle_max_rad) ||
      !std::isfinite(fruit_angle_min_rad))
    return error = "fruit angle range is empty", false;
  return true;
}

GreenhouseRow sampleGreenhouseRow(const GreenhouseRowOptions& o) {
  std::string err;
  ARMSTUDY_CHECK(o.validate(err), "greenhouse row options: " + err);
  RowRandom rng(o.seed);
  GreenhouseRow row;
  row.row_to_row_m = rng.truncatedNormal(o.row_to_row);
  row.row_x_m = 0.5 * row.row_to_row_m;
  double y = o.first_stem_y_m;
  for (int k = 0; k < o.stems; ++k) {
    if (k > 0) y += rng.truncatedNormal(o.stem_to_stem);
    row.stems_xy.emplace_back(row.row_x_m, y);
  }
  for (int k = 0; k < o.stems; ++k)
    for (int f = 0; f < o.fruits_per_stem; ++f) {
      SampledFruit fr;
      fr.stem = k;
      fr.stem_distance_m = rng.truncatedNormal(o.stem_to_fruit);
      fr.angle_rad =
          o.fruit_angle_min_rad + (o.fruit_angle_max_rad - o.fruit_angle_min_rad) * rng.uniform();
      const double z = rng.truncatedNormal(o.fruit_z);
      fr.p_W =
          Eigen::Vector3d(row.stems_xy[k].x() + fr.stem_distance_m * std::cos(fr.angle_rad),
                          row.stems_xy[k].y() + fr.stem_distance_m * std::sin(fr.angle_rad), z);
      row.fruits.push_back(fr);
    }
  return row;
}

}  // namespace armstudy
