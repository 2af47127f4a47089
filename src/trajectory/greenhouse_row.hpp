#pragma once
// A sweet-pepper greenhouse row sampled from the statistics of thesis Table 2.2 (Dutch greenhouse):
// row-to-row 862 +/- 50 mm [750, 1020], stem-to-stem 192 +/- 60 mm [40, 350], fruit heights with a
// standard deviation of 220 mm within [0, 1650] mm, stem-to-fruit 38 +/- 6.9 mm [15, 96].
// Each quantity is a normal distribution truncated to the table's observed min/max (rejection
// sampling). The generator is the engine's xoshiro256** (common/rng.hpp, seeded by splitmix64) with
// its own Box-Muller; no std:: distributions, whose output differs between standard libraries, so a
// seed gives the same row on every platform and compiler.
//
// Layout in the task frame W: the robot base is at the origin in the middle of the aisle, which
// runs along y; the plant row is at x = row_to_row / 2 (thesis Fig. 5.8: stems at x = 0.43 m);
// stems follow along +y from first_stem_y; fruits around their stem at a uniform angle.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "common/rng.hpp"

namespace armstudy {

struct TruncatedNormal {
  double mean = 0, sd = 0, min = 0, max = 0;  // SI units
  bool validate(std::string& error) const;    // sd >= 0, min <= mean <= max ... (see .cpp)
  // Mean and standard deviation of the truncated distribution (closed form), for checks.
  double truncatedMean() const;
  double truncatedSd() const;
};

struct GreenhouseRowOptions {
  std::uint64_t seed = 1;
  int stems = 10;
  int fruits_per_stem = 1;
  double first_stem_y_m = 0.0;
  TruncatedNormal row_to_row{0.862, 0.050, 0.750, 1.020};    // Table 2.2
  TruncatedNormal stem_to_stem{0.192, 0.060, 0.040, 0.350};  // Table 2.2
  TruncatedNormal fruit_z{1.0, 0.220, 0.0,
                          1.650};  // Table 2.2 sd/min/max; mean: assumption (study)
  TruncatedNormal stem_to_fruit{0.038, 0.0069, 0.015, 0.096};  // Table 2.2
  double fruit_angle_min_rad = 0.0;  // fruit direction around the stem, uniform in [min, max)
  double fruit_angle_max_rad = 6.283185307179586;
  bool validate(std::string& error) const;
};

struct SampledFruit {
  int stem = 0;                // index into GreenhouseRow::stems_xy
  Eigen::Vector3d p_W;         // fruit centre
  double stem_distance_m = 0;  // stem-to-fruit
  double angle_rad = 0;        // direction from the stem, in W
};

struct GreenhouseRow {
  double row_to_row_m = 0;
  double row_x_m = 0;  // x of the plant row (row_to_row / 2)
  std::vector<Eigen::Vector2d> stems_xy;
  std::vector<SampledFruit> fruits;
};

// Deterministic for a given options.seed. Precondition: options validate.
GreenhouseRow sampleGreenhouseRow(const GreenhouseRowOptions& options);

// The generator underneath, exposed for tests: uniform in [0, 1) with 53 random bits, and a
// truncated normal by rejection of standard normals (Box-Muller).
class RowRandom {
 public:
  explicit RowRandom(std::uint64_t seed);
  double uniform();
  double normal();
  double truncatedNormal(const TruncatedNormal& d);

 private:
  rng::Xoshiro256ss gen_;
  bool has_spare_ = false;
  double spare_ = 0;
};

}  // namespace armstudy
