#pragma once
// The one place where kernels get their math functions. Kokkos 3.4 keeps them in
// Kokkos::Experimental, later versions in Kokkos::; kernels call cgdem::math::sqrt etc.
#include <Kokkos_Core.hpp>
#include <cstdint>
#include <cstring>

namespace cgdem::math {

#if KOKKOS_VERSION >= 30700
namespace km = Kokkos;
#else
namespace km = Kokkos::Experimental;
#endif

KOKKOS_INLINE_FUNCTION double sqrt(double x) { return km::sqrt(x); }
KOKKOS_INLINE_FUNCTION double cbrt(double x) { return km::cbrt(x); }
KOKKOS_INLINE_FUNCTION double pow(double x, double y) { return km::pow(x, y); }
KOKKOS_INLINE_FUNCTION double fabs(double x) { return km::fabs(x); }
KOKKOS_INLINE_FUNCTION double log(double x) { return km::log(x); }
KOKKOS_INLINE_FUNCTION double exp(double x) { return km::exp(x); }
KOKKOS_INLINE_FUNCTION double cos(double x) { return km::cos(x); }
KOKKOS_INLINE_FUNCTION double sin(double x) { return km::sin(x); }
KOKKOS_INLINE_FUNCTION bool isfinite(double x) { return km::isfinite(x); }
KOKKOS_INLINE_FUNCTION double fmin(double a, double b) { return a < b ? a : b; }
KOKKOS_INLINE_FUNCTION double fmax(double a, double b) { return a > b ? a : b; }

constexpr double pi = 3.14159265358979323846;

// Cube root of x > 0 in straight-line arithmetic, so that a loop over contacts calling it vectorizes (a
// call to the library's cbrt does not): a first guess from the bits (the exponent divided by three, about
// 6 % off), then three Halley steps y <- y [(y^3 + 2x) / (2 y^3 + x)], each cubing the relative error
// (6e-2 -> 2e-4 -> 1e-11 -> round-off). Within 3 ulp of cbrt(x) (tests/test_jkr_closed_form.cpp); x = 0
// gives a number below 1e-100 instead of 0.
KOKKOS_INLINE_FUNCTION double cbrt_positive(double x) {
  std::int64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  bits = static_cast<std::int64_t>(static_cast<double>(bits) * (1.0 / 3.0)) + 0x2A9F7893782DA1CELL;
  double y;
  std::memcpy(&y, &bits, sizeof y);
  for (int k = 0; k < 3; ++k) {
    const double y3 = y * y * y;
    y *= (y3 + 2 * x) / (2 * y3 + x);
  }
  return y;
}

// x^(-1/3) for x > 0 in straight-line arithmetic without a division (a lane of the force pass waits longest
// on its divisions): a first guess from the bits (minus the exponent over three, within 3.5 %), then four
// Newton steps y <- y (4 - x y^3) / 3, each taking the relative error e to about -2 e^2
// (3.4e-2 -> 2.4e-3 -> 1.1e-5 -> 2.5e-10 -> round-off). Within a few ulp of 1/cbrt(x)
// (tests/test_jkr_closed_form.cpp).
KOKKOS_INLINE_FUNCTION double inverse_cbrt_positive(double x) {
  std::int64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  bits = 0x553EF00000000000LL - static_cast<std::int64_t>(static_cast<double>(bits) * (1.0 / 3.0));
  double y;
  std::memcpy(&y, &bits, sizeof y);
  for (int k = 0; k < 4; ++k)
    y *= (4 - x * (y * y * y)) * (1.0 / 3.0);
  return y;
}

// A hint that `address` will be read soon: on the host, a cache-line prefetch; on a GPU, nothing (its
// thousands of threads in flight hide the latency that a CPU core has to be told about).
KOKKOS_INLINE_FUNCTION void prefetch(const void* address) {
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
  (void)address;
#else
  __builtin_prefetch(address);
#endif
}

} // namespace cgdem::math
