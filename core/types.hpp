#pragma once
// Basic value types usable on host and device: Real and a small Vec3.
#include <Kokkos_Core.hpp>
#include "core/math.hpp"

namespace cgdem {

using Real = double;

// Storage precision of the per-pair contact history (the precision knob, CMake option CGDEM_FLOAT_FORCES):
// every computation stays in double, and positions, velocities and forces stay double (a micron-sized
// overlap at a millimetre coordinate needs double's 16 digits); only the history, five or so slots per
// particle, is rounded, which halves its memory traffic.
#ifdef CGDEM_FLOAT_FORCES
using ForceReal = float;
#else
using ForceReal = double;
#endif

struct Vec3 {
  Real x = 0, y = 0, z = 0;

  KOKKOS_INLINE_FUNCTION Vec3() = default;
  KOKKOS_INLINE_FUNCTION constexpr Vec3(Real x_, Real y_, Real z_) : x(x_), y(y_), z(z_) {}

  KOKKOS_INLINE_FUNCTION Real& operator[](int d) { return d == 0 ? x : (d == 1 ? y : z); }
  KOKKOS_INLINE_FUNCTION Real operator[](int d) const { return d == 0 ? x : (d == 1 ? y : z); }

  KOKKOS_INLINE_FUNCTION Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  KOKKOS_INLINE_FUNCTION Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  KOKKOS_INLINE_FUNCTION Vec3& operator*=(Real s) { x *= s; y *= s; z *= s; return *this; }
};

KOKKOS_INLINE_FUNCTION Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
KOKKOS_INLINE_FUNCTION Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
KOKKOS_INLINE_FUNCTION Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
KOKKOS_INLINE_FUNCTION Vec3 operator*(Real s, const Vec3& a) { return {s * a.x, s * a.y, s * a.z}; }
KOKKOS_INLINE_FUNCTION Vec3 operator*(const Vec3& a, Real s) { return {s * a.x, s * a.y, s * a.z}; }
KOKKOS_INLINE_FUNCTION Real dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
KOKKOS_INLINE_FUNCTION Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
KOKKOS_INLINE_FUNCTION Real norm2(const Vec3& a) { return dot(a, a); }
KOKKOS_INLINE_FUNCTION Real norm(const Vec3& a) { return math::sqrt(dot(a, a)); }

} // namespace cgdem
