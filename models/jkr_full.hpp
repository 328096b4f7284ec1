#pragma once
// Full JKR normal contact (Chen eqs 8-11, 18-24; Johnson-Kendall-Roberts 1971; Thornton & Yin 1991),
// docs/physics.md 3.3:
//   F_n = 4 E* a^3/(3 R*) - sqrt(16 pi gamma E* a^3) + c_n delta_dot,   delta = a^2/R* - sqrt(4 pi gamma
//   a/E*)
// with a solved from delta on the physical branch a >= a_S by safeguarded Newton (models/jkr_relation.hpp),
// warm-started from the previous step's a.
// Hysteresis: an unbonded pair feels nothing until delta reaches 0 on approach, where it snaps in onto the
// JKR curve (F = -8/9 F_c at point A); a bonded pair stays bonded across the gap until delta falls below
// the pair's separation overlap (contact.jkr_separation), then separates and forgets its history:
//   delta_s       delta_S = -1.1906 u (point S, F = -5/9 F_c): JKR theory, the default;
//   pull_off      delta_C = -0.5724 u (point C, F = -F_c): LAMMPS' jkr model;
//   contact_loss  delta = 0: Hu's JKR (Hu section 2.3.2, eqs 5, 10, 11, 16, 23), one JKR contact radius in
//                 the repulsion and the attraction, no negative-overlap tail, no reach beyond touching.
// Damping (Chen eqs 20-23): c_n = eta sqrt(S_n m*), S_n = 2 E* a; tangential stiffness k_t = 8 G* a with
// c_t = eta sqrt(k_t m*). The total force is not clamped: the JKR force is attractive by nature, and the
// damper is part of it; eta = 2 sqrt(5/6) |beta| gives the input restitution exactly for this unclamped
// form in the limit of impact speeds far above the sticking velocity (core/restitution.hpp).
// Coulomb load (Thornton & Yin): |F_n,JKR + 2 F_c| = |4/9 x^3 - 4/3 x^1.5 + 2| F_c, elastic part only.
// `stiffness` reports S_n = 2 E* a, the Hertzian stiffness of the current contact radius (the one Chen's
// damping uses), rather than the tangent dF/d(delta), which diverges at S.
// surface_energy <= 0 gives exactly HertzTsuji.
//
// History (2 Reals): [0] bonded flag (0 or 1), [1] contact radius a of the previous step (warm start).
#include "models/contact_law.hpp"
#include "models/hertz_tsuji.hpp"
#include "models/jkr_relation.hpp"

namespace cgdem::models {

struct JkrFull {
  static constexpr int history_size = 2;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "jkr";

  // The widest gap a bonded pair survives: -jkr_separation_overlap u, u = (pi^2 gamma^2 R*/E*^2)^(1/3).
  // R_j <= 0 (or infinite) is a wall: R* = R_i.
  static Real interaction_range(const PairParameters& p, Real R_i, Real R_j) {
    if (p.surface_energy <= 0 || p.E_eff <= 0 || R_i <= 0 || p.jkr_separation_overlap >= 0) return 0;
    const Real R_eff = (R_j > 0) ? 1 / (1 / R_i + 1 / R_j) : R_i;
    return -p.jkr_separation_overlap * jkr::scales(p.surface_energy, p.E_eff, R_eff).u;
  }

  KOKKOS_INLINE_FUNCTION NormalResult operator()(const PairParameters& p, const PairState& s, Real* h) const {
    if (!(p.surface_energy > 0)) {
      h[0] = 0;
      h[1] = 0;
      return HertzTsuji{}(p, s, h);
    }
    NormalResult r;
    const jkr::Scales sc = jkr::scales(p.surface_energy, p.E_eff, s.radius_eff);
    const Real d = s.overlap / sc.u;
    const bool bonded = h[0] > 0.5;
    // Unbonded: nothing until the surfaces touch. Bonded: separation below the separation overlap.
    if ((!bonded && s.overlap < 0) || (bonded && d < p.jkr_separation_overlap)) {
      h[0] = 0;
      h[1] = 0;
      return r;
    }
    const Real x = jkr::solve_x(d, bonded ? h[1] / sc.a_c : 0);
    const Real a = x * sc.a_c;
    h[0] = 1;
    h[1] = a;

    const Real x15 = x * math::sqrt(x);
    const Real elastic = sc.F_c * ((4.0 / 9.0) * x15 * x15 - (4.0 / 3.0) * x15);
    const Real S_n = 2 * p.E_eff * a;
    r.force = elastic + p.damping * math::sqrt(S_n * s.mass_eff) * s.overlap_rate;
    r.friction_load = math::fabs(elastic + 2 * sc.F_c);
    r.k_t = 8 * p.G_eff * a;
    r.c_t = p.damping * math::sqrt(r.k_t * s.mass_eff);
    r.stiffness = S_n;
    r.active = true;
    return r;
  }
};

} // namespace cgdem::models
