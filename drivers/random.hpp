#pragma once
#include <cmath>
#include <cstdint>
#include <random>
#include "core/scene.hpp"

namespace cgdem {

// Random numbers from std::mt19937_64 seeded through std::seed_seq (both fully specified by the standard),
// converted by hand rather than with std::*_distribution so that a seed gives the same particles with any
// standard library. One stream per purpose so that, e.g., changing velocity_random keeps the positions.
class Rng {
public:
  enum Stream : std::uint32_t { radius = 1, position = 2, velocity = 3, inlet = 4 };
  Rng(std::uint64_t seed, Stream stream) {
    std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                      static_cast<std::uint32_t>(stream), 0x63676465u /* "cgde" */};
    eng_.seed(seq);
  }
  // A stream per event (an inlet's insertion at one step), so a restart that resumes at an event draws
  // what the uninterrupted run drew there.
  Rng(std::uint64_t seed, Stream stream, std::uint64_t event) {
    std::seed_seq seq{static_cast<std::uint32_t>(seed),   static_cast<std::uint32_t>(seed >> 32),
                      static_cast<std::uint32_t>(stream), 0x63676465u /* "cgde" */,
                      static_cast<std::uint32_t>(event),  static_cast<std::uint32_t>(event >> 32)};
    eng_.seed(seq);
  }
  double uniform() { return static_cast<double>(eng_() >> 11) * (1.0 / 9007199254740992.0); } // [0, 1)
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  double normal() {                    // Box-Muller, one value per call
    const double u1 = 1.0 - uniform(); // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
  }
  Vec3d unit_vector() {
    const double z = uniform(-1.0, 1.0);
    const double phi = uniform(0.0, 2.0 * 3.14159265358979323846);
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
  }

private:
  std::mt19937_64 eng_;
};

} // namespace cgdem
