#pragma once
// The JKR overlap-contact radius relation of JkrFull (docs/physics.md 3):
//   delta(a) = a^2/R* - sqrt(4 pi gamma a / E*),   F(a) = 4 E* a^3/(3 R*) - sqrt(16 pi gamma E* a^3).
// In the natural scales a_c = (pi gamma R*^2/E*)^(1/3), u = a_c^2/R* = (pi^2 gamma^2 R*/E*^2)^(1/3) and
// F_c = 3 pi gamma R*, with x = a/a_c, both become parameter free:
//   delta/u = x^2 - 2 sqrt(x),   F/F_c = 4/9 x^3 - 4/3 x^1.5.
// delta(x) has its minimum at the separation point S, x_S = 2^(-2/3), delta_S/u = 2^(-4/3) - 2^(2/3);
// on the physical branch x >= x_S it is increasing and convex, so for every delta >= delta_S there is
// exactly one root there. The solver is Newton's method kept inside a bracket [lo, hi] on that branch
// (bisection whenever a Newton step would leave it): it cannot fall onto the unphysical branch x < x_S,
// and it converges next to S, where d delta/dx -> 0, as well as far up the loading branch.
#include "core/types.hpp"

namespace cgdem::models::jkr {

constexpr Real x_S = 0.62996052494743658238;  // 2^(-2/3)
constexpr Real d_S = -1.19055078897614960606; // 2^(-4/3) - 2^(2/3): delta_S / u
constexpr Real x_A = 1.58740105196819947475;  // 2^(2/3): zero overlap
constexpr Real x_C = 1.31037069710444830357;  // (3/2)^(2/3): pull-off
constexpr Real d_C = -0.57235712127666593390; // x_C^2 - 2 sqrt(x_C): delta_C / u
constexpr Real x_B = 2.08008382305190411453;  // 3^(2/3): zero force

// Natural scales of one pair (host and device).
struct Scales {
  Real a_c = 0; // (pi gamma R*^2 / E*)^(1/3)
  Real u = 0;   // a_c^2 / R*
  Real F_c = 0; // 3 pi gamma R*
};

KOKKOS_FORCEINLINE_FUNCTION Scales scales(Real gamma, Real E_eff, Real R_eff) {
  Scales s;
  s.a_c = math::cbrt_positive(math::pi * gamma * R_eff * R_eff / E_eff);
  s.u = s.a_c * s.a_c / R_eff;
  s.F_c = 3 * math::pi * gamma * R_eff;
  return s;
}

// Dimensionless overlap and force as functions of x = a / a_c.
KOKKOS_INLINE_FUNCTION Real overlap_of(Real x) {
  return x * x - 2 * math::sqrt(x);
}
KOKKOS_INLINE_FUNCTION Real force_of(Real x) {
  const Real x15 = x * math::sqrt(x);
  return (4.0 / 9.0) * x15 * x15 - (4.0 / 3.0) * x15;
}

// Root x >= x_S of x^2 - 2 sqrt(x) = d for d >= d_S (d below d_S returns x_S). `guess` <= 0 means a cold
// start (from the upper bracket, where convexity makes Newton monotone); a warm start from the previous
// step's x usually converges in 2-3 iterations. `iterations` (optional) receives the number of steps.
KOKKOS_INLINE_FUNCTION Real solve_x(Real d, Real guess, int* iterations = nullptr) {
  Real lo = x_S;
  // x = sqrt(max(d,0)) + 2 has overlap_of(x) > d for every d: (t+2)^2 - 2 sqrt(t+2) > t^2 for t >= 0.
  Real hi = math::sqrt(d > 0 ? d : 0) + 2;
  int it = 0;
  if (d <= d_S) {
    if (iterations) *iterations = 0;
    return x_S;
  }
  Real x = (guess > lo && guess < hi) ? guess : hi;
  for (; it < 100; ++it) {
    const Real sx = math::sqrt(x);
    const Real f = x * x - 2 * sx - d;
    if (f == 0) break;
    if (f > 0)
      hi = x;
    else
      lo = x;
    const Real fp = 2 * x - 1 / sx; // > 0 for x > x_S
    if (fp > 0) {
      const Real step = f / fp;
      // After a Newton step of relative size 1e-13 the quadratic convergence leaves ~1e-26 of error;
      // accepting it here also stops the round-off dithering of a converged iterate.
      if (math::fabs(step) <= 1e-13 * x) {
        x -= step;
        ++it;
        break;
      }
      const Real xn = x - step;
      x = (xn > lo && xn < hi) ? xn : 0.5 * (lo + hi); // safeguard: bisect the bracket
    } else {
      x = 0.5 * (lo + hi);
    }
    if (hi - lo <= 4e-16 * x) {
      ++it;
      break;
    }
  }
  if (iterations) *iterations = it;
  return x;
}

// The physical root z of the quartic z^4 - P z - Q = 0 (P > 0) in closed form, straight-line arithmetic (the
// force kernel's loop over contacts vectorizes with it; the bracketed solver above stays the reference).
// The JKR relation is this quartic twice over: in the natural scales y = sqrt(x) solves y^4 - 2 y - d = 0
// (P = 2, Q = d: solve_x_closed below), and in physical units z = sqrt(a) solves z^4 - R* K z - R* delta = 0,
// K = sqrt(4 pi gamma / E*) (delta R* = a^2 - K R* sqrt(a)), which JkrFull solves without the pair's natural
// scales and so without their cube root. Ferrari: for m > 0 with 8 m (Q + m^2) = P^2,
// (z^2 + m)^2 = 2 m (z + P/(4m))^2, so the physical root is z = (w + sqrt(2P/w - w^2)) / 2, w = sqrt(2m).
// The resolvent m^3 + Q m - P^2/8 = 0 has one real root while its discriminant P^4/256 + Q^3/27 is positive
// (it vanishes exactly at the separation point S, where the two real roots of the quartic meet):
// Cardano's m = A - B with A^3 = P^2/16 + s, B^3 = s - P^2/16, s = sqrt(P^4/256 + Q^3/27), so A B = Q/3 (one
// cube root only, taken as its inverse so that neither A nor B = Q/(3A) costs a division), written
// m = (P^2/8) / (A^2 + A B + B^2) (A^3 - B^3 = P^2/8) so that no difference cancels
// for large Q. Near S the sqrt(2P/w - w^2) loses half the digits; two Newton steps on the quartic restore
// them. The slope 4 z^3 - P vanishes at S (z_S = (P/4)^(1/3)): a step is taken only if z - |step| stays above
// z_S, tested as 4 (z - |step|)^3 > P (no cube root), so that round-off in the estimate next to S cannot
// throw it off the branch. Beyond S (negative discriminant) the result is a number near z_S, not a root.
KOKKOS_FORCEINLINE_FUNCTION Real solve_quartic_closed(Real P, Real Q) {
  const Real P2 = P * P;
  const Real disc = P2 * P2 * (1.0 / 256.0) + Q * Q * Q * (1.0 / 27.0);
  const Real s = math::sqrt(disc > 0 ? disc : 0);
  const Real inv_A = math::inverse_cbrt_positive(P2 * 0.0625 + s); // no division
  const Real A = (P2 * 0.0625 + s) * inv_A * inv_A;
  const Real B = Q * inv_A * (1.0 / 3.0); // A B = cbrt(s^2 - P^4/256) = cbrt(Q^3 / 27): no second cube root
  const Real m = (0.125 * P2) / (A * A + A * B + B * B);
  const Real w = math::sqrt(2 * m);
  const Real q = 2 * P / w - w * w;
  Real z = 0.5 * (w + math::sqrt(q > 0 ? q : 0));
  for (int k = 0; k < 2; ++k) {
    const Real z3 = z * z * z;
    const Real slope = 4 * z3 - P; // > 0 above z_S, -> 0 at z_S
    const Real step = (z3 * z - P * z - Q) / slope;
    const Real low = z - math::fabs(step);
    z = (slope > 0 && low > 0 && 4 * (low * low * low) > P) ? z - step : z;
  }
  return z;
}

// The root x >= x_S of x^2 - 2 sqrt(x) = d (natural scales) in closed form: y = sqrt(x) from the quartic
// y^4 - 2 y - d = 0, kept at or above y_S = 2^(-1/3). d <= d_S gives x_S.
KOKKOS_FORCEINLINE_FUNCTION Real solve_x_closed(Real d) {
  constexpr Real y_S = 0.79370052598409973738; // 2^(-1/3) = sqrt(x_S)
  Real y = solve_quartic_closed(2, d);
  y = y > y_S ? y : y_S;
  return d > d_S ? y * y : x_S;
}

// Contact radius a (physical units) for the overlap delta of a pair with scales sc; prev_a <= 0 = cold.
KOKKOS_INLINE_FUNCTION Real contact_radius(const Scales& sc, Real delta, Real prev_a,
                                           int* iterations = nullptr) {
  return sc.a_c * solve_x(delta / sc.u, prev_a > 0 ? prev_a / sc.a_c : 0, iterations);
}

} // namespace cgdem::models::jkr
