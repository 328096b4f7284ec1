#pragma once
// The simulation box with periodic axes: minimum-image separation and wrapping, usable in kernels.
#include <limits>
#include "core/types.hpp"

namespace cgdem {

struct Domain {
  Vec3 lo, hi, length;
  bool periodic[3] = {false, false, false};
  // Half the box on periodic axes, infinite on the others: minimum_image then needs no test of the axis
  // kind (it runs once per listed pair).
  Vec3 image_half{std::numeric_limits<Real>::infinity(), std::numeric_limits<Real>::infinity(),
                  std::numeric_limits<Real>::infinity()};

  Domain() = default;
  Domain(const Vec3& lo_, const Vec3& hi_, bool px, bool py, bool pz) : lo(lo_), hi(hi_), length(hi_ - lo_) {
    periodic[0] = px;
    periodic[1] = py;
    periodic[2] = pz;
    if (px) image_half.x = 0.5 * length.x;
    if (py) image_half.y = 0.5 * length.y;
    if (pz) image_half.z = 0.5 * length.z;
  }

  // Shortest image of a separation vector. Written per component with the same operations for d and -d,
  // so that minimum_image(-d) == -minimum_image(d) bitwise (except at exactly half a box). Spelled out per
  // axis rather than looped over a (Vec3's operator[] is a chain of selects when the loop is not unrolled):
  // it runs once per listed pair.
  KOKKOS_INLINE_FUNCTION Vec3 minimum_image(const Vec3& d) const {
    return {nearest_image(d.x, length.x, image_half.x), nearest_image(d.y, length.y, image_half.y),
            nearest_image(d.z, length.z, image_half.z)};
  }

  KOKKOS_INLINE_FUNCTION Vec3 wrap(const Vec3& x) const {
    return {wrap_axis(x.x, lo.x, hi.x, length.x, periodic[0]),
            wrap_axis(x.y, lo.y, hi.y, length.y, periodic[1]),
            wrap_axis(x.z, lo.z, hi.z, length.z, periodic[2])};
  }

  // The box shrunk by `range` from both faces of each periodic axis (the open axes whole): a particle in
  // it sees every partner closer than `range` at that partner's stored position, so their separation
  // needs no minimum image (stored positions are wrapped into [lo, hi); range < half the box).
  struct Interior {
    Vec3 lo, hi;
    KOKKOS_INLINE_FUNCTION bool contains(const Vec3& x) const {
      return x.x >= lo.x && x.x < hi.x && x.y >= lo.y && x.y < hi.y && x.z >= lo.z && x.z < hi.z;
    }
  };
  Interior interior(Real range) const {
    const Real inf = std::numeric_limits<Real>::infinity();
    Interior box{{-inf, -inf, -inf}, {inf, inf, inf}};
    if (periodic[0]) box.lo.x = lo.x + range, box.hi.x = hi.x - range;
    if (periodic[1]) box.lo.y = lo.y + range, box.hi.y = hi.y - range;
    if (periodic[2]) box.lo.z = lo.z + range, box.hi.z = hi.z - range;
    return box;
  }

private:
  KOKKOS_INLINE_FUNCTION static Real nearest_image(Real d, Real length, Real half) {
    if (d > half) return d - length;
    if (d < -half) return d + length;
    return d;
  }

  KOKKOS_INLINE_FUNCTION static Real wrap_axis(Real x, Real lo, Real hi, Real length, bool periodic) {
    if (!periodic) return x;
    if (x >= hi) return x - length;
    if (x < lo) return x + length;
    return x;
  }
};

} // namespace cgdem
