#pragma once
// The one random-number generator of the engine: seeded, platform independent (no std::
// distributions, whose output differs between standard libraries), the same on any thread.
//   splitmix64 (Steele, Lea, Flood; Vigna's constants): a counter hash and a sequential stream.
//   xoshiro256** (Blackman and Vigna), seeded by splitmix64, for long streams.
// Doubles take the top 53 bits to [0, 1); normals are Box-Muller.
#include <cmath>
#include <cstdint>
#include <numbers>

namespace armstudy::rng {

inline constexpr std::uint64_t kSplitMixIncrement = 0x9E3779B97F4A7C15ull;

// The splitmix64 output function (the mixer applied to an already advanced state).
constexpr std::uint64_t splitmix64Mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Counter-based use: the splitmix64 output for state x (advance by one increment, then mix).
constexpr std::uint64_t splitmix64(std::uint64_t x) {
  return splitmix64Mix(x + kSplitMixIncrement);
}

// Sequential use: advances `state` and returns the next output.
inline std::uint64_t splitmix64Next(std::uint64_t& state) {
  return splitmix64Mix(state += kSplitMixIncrement);
}

// Top 53 bits of x as a double in [0, 1).
constexpr double unitDouble(std::uint64_t x) { return static_cast<double>(x >> 11) * 0x1.0p-53; }

// A sequential splitmix64 stream with uniform and Box-Muller normal draws.
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() { return splitmix64Next(state); }
  double uniform() { return unitDouble(next()); }  // [0, 1)
  double normal() {
    double u1 = uniform();
    while (u1 <= 0) u1 = uniform();
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
};

// xoshiro256** with its four state words seeded from a splitmix64 stream.
class Xoshiro256ss {
 public:
  explicit Xoshiro256ss(std::uint64_t seed) {
    for (auto& s : state_) s = splitmix64Next(seed);
  }
  std::uint64_t next() {
    const std::uint64_t result = rotl(state_[1] * 5, 7) * 9;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = rotl(state_[3], 45);
    return result;
  }
  double uniform() { return unitDouble(next()); }  // [0, 1)

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t state_[4];
};

}  // namespace armstudy::rng
