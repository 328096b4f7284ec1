#pragma once
// The simulation box with periodic axes: minimum-image separation and wrapping, usable in kernels.
#include "core/types.hpp"

namespace cgdem {

struct Domain {
  Vec3 lo, hi, length;
  bool periodic[3] = {false, false, false};

  Domain() = default;
  Domain(const Vec3& lo_, const Vec3& hi_, bool px, bool py, bool pz) : lo(lo_), hi(hi_), length(hi_ - lo_) {
    periodic[0] = px;
    periodic[1] = py;
    periodic[2] = pz;
  }

  // Shortest image of a separation vector. Written per component with the same operations for d and -d,
  // so that minimum_image(-d) == -minimum_image(d) bitwise (except at exactly half a box).
  KOKKOS_INLINE_FUNCTION Vec3 minimum_image(Vec3 d) const {
    for (int a = 0; a < 3; ++a) {
      if (!periodic[a]) continue;
      const Real half = 0.5 * length[a];
      if (d[a] > half) d[a] -= length[a];
      else if (d[a] < -half) d[a] += length[a];
    }
    return d;
  }

  KOKKOS_INLINE_FUNCTION Vec3 wrap(Vec3 x) const {
    for (int a = 0; a < 3; ++a) {
      if (!periodic[a]) continue;
      if (x[a] >= hi[a]) x[a] -= length[a];
      else if (x[a] < lo[a]) x[a] += length[a];
    }
    return x;
  }
};

} // namespace cgdem
