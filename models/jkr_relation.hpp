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

// The same root in closed form, straight-line arithmetic (the force kernel's loop over contacts vectorizes
// with it; the bracketed solver above stays the reference). With y = sqrt(x) the relation is the quartic
// y^4 - 2 y - d = 0. Ferrari: for m > 0 with 2 m (d + m^2) = 1, (y^2 + m)^2 = 2 m (y + 1/(2m))^2, so the
// physical root is y = (w + sqrt(4/w - w^2)) / 2, w = sqrt(2m). The resolvent m^3 + d m - 1/2 = 0 has one
// real root for d > d_S (its discriminant 1/16 + d^3/27 vanishes exactly at d_S): Cardano's m = A - B with
// A^3 = 1/4 + s, B^3 = s - 1/4, s = sqrt(1/16 + d^3/27), so A B = d/3 (one cube root only), written
// m = (1/2) / (A^2 + A B + B^2) (A^3 - B^3 = 1/2) so that no difference cancels for large d. Near S the
// sqrt(4/w - w^2) loses half the digits; two Newton steps on the quartic restore them (a step is taken only
// if it stays above y_S, where the slope vanishes). d <= d_S gives x_S.
KOKKOS_FORCEINLINE_FUNCTION Real solve_x_closed(Real d) {
  const Real disc = 0.0625 + d * d * d * (1.0 / 27.0);
  const Real s = math::sqrt(disc > 0 ? disc : 0);
  const Real A = math::cbrt_positive(0.25 + s);
  const Real B = d / (3 * A); // A B = cbrt(s^2 - 1/16) = cbrt(d^3 / 27): no second cube root
  const Real m = 0.5 / (A * A + A * B + B * B);
  const Real w = math::sqrt(2 * m);
  const Real q = 4 / w - w * w;
  Real y = 0.5 * (w + math::sqrt(q > 0 ? q : 0));
  constexpr Real y_S = 0.79370052598409973738; // 2^(-1/3) = sqrt(x_S)
  for (int k = 0; k < 2; ++k) {
    const Real y3 = y * y * y;
    const Real slope = 4 * y3 - 2; // > 0 above y_S, -> 0 at y_S
    const Real step = (y3 * y - 2 * y - d) / slope;
    // Next to S the slope vanishes: a step longer than the distance to y_S (round-off in the estimate) is
    // not taken.
    y = (slope > 0 && math::fabs(step) < y - y_S) ? y - step : y;
  }
  y = y > y_S ? y : y_S;
  return d > d_S ? y * y : x_S;
}

// Contact radius a (physical units) for the overlap delta of a pair with scales sc; prev_a <= 0 = cold.
KOKKOS_INLINE_FUNCTION Real contact_radius(const Scales& sc, Real delta, Real prev_a,
                                           int* iterations = nullptr) {
  return sc.a_c * solve_x(delta / sc.u, prev_a > 0 ? prev_a / sc.a_c : 0, iterations);
}

} // namespace cgdem::models::jkr
