#pragma once
// The one place where kernels get their math functions. Kokkos 3.4 keeps them in
// Kokkos::Experimental, later versions in Kokkos::; kernels call cgdem::math::sqrt etc.
#include <Kokkos_Core.hpp>

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
