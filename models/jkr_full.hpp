#pragma once
// Full JKR normal contact (Chen eqs 8-11, 18-24; Johnson-Kendall-Roberts 1971; Thornton & Yin 1991),
// docs/physics.md 3.3:
//   F_n = 4 E* a^3/(3 R*) - sqrt(16 pi gamma E* a^3) + c_n delta_dot,   delta = a^2/R* - sqrt(4 pi gamma
//   a/E*)
// with a solved from delta on the physical branch a >= a_S in closed form, in physical units
// (jkr::solve_quartic_closed: Ferrari's solution of the quartic in sqrt(a) and two Newton steps,
// straight-line arithmetic, so that the force pass's loop over pairs vectorizes; as accurate as the bracketed
// solver jkr::solve_x, tests/test_jkr_closed_form.cpp and tests/test_cohesive_models.cpp). Hysteresis: an
// unbonded pair feels nothing until delta reaches 0 on approach, where it snaps in onto the JKR curve (F =
// -8/9 F_c at point A); a bonded pair stays bonded across the gap until delta falls below the pair's
// separation overlap (contact.jkr_separation), then separates and forgets its history:
//   delta_s       delta_S = -1.1906 u (point S, F = -5/9 F_c): JKR theory, the default;
//   pull_off      delta_C = -0.5724 u (point C, F = -F_c): LAMMPS' jkr model;
//   contact_loss  delta = 0: Hu's JKR (Hu section 2.3.2, eqs 5, 10, 11, 16, 23), one JKR contact radius in
//                 the repulsion and the attraction, no negative-overlap tail, no reach beyond touching.
// Damping (Chen eqs 20-23): c_n = eta sqrt(S_n m*), S_n = 2 E* a; tangential stiffness k_t = 8 G* a with
// c_t = eta sqrt(k_t m*). The total force is not clamped: the JKR force is attractive by nature, and the
// damper is part of it; eta = 2 sqrt(5/6) |beta| gives the input restitution exactly for this unclamped
// form in the limit of impact speeds far above the sticking velocity (setup/restitution.hpp).
// Coulomb load (Thornton & Yin): |F_n,JKR + 2 F_c| = |4/9 x^3 - 4/3 x^1.5 + 2| F_c, elastic part only.
// `stiffness` reports S_n = 2 E* a, the Hertzian stiffness of the current contact radius (the one Chen's
// damping uses), rather than the tangent dF/d(delta), which diverges at S.
// surface_energy <= 0 gives exactly HertzTsuji.
//
// Written without early returns (every quantity computed, the inactive ones selected away) for the same
// reason. History (1 Real): the bonded flag (0 or 1). The contact radius is solved afresh each step (closed
// form, no warm start) and reported through `stiffness` = 2 E* a.
#include "models/contact_law.hpp"
#include "models/jkr_relation.hpp"

namespace cgdem::models {

struct JkrFull {
  static constexpr int history_size = 1;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "jkr";

  // The widest gap a bonded pair survives: -jkr_separation_overlap u, u = (pi^2 gamma^2 R*/E*^2)^(1/3).
  // R_j <= 0 (or infinite) is a wall: R* = R_i.
  static Real interaction_range(const PairParameters& p, Real R_i, Real R_j) {
    if (p.surface_energy <= 0 || p.E_eff <= 0 || R_i <= 0 || p.jkr_separation_overlap >= 0) return 0;
    const Real R_eff = (R_j > 0) ? 1 / (1 / R_i + 1 / R_j) : R_i;
    return -p.jkr_separation_overlap * jkr::scales(p.surface_energy, p.E_eff, R_eff).u;
  }

  KOKKOS_FORCEINLINE_FUNCTION NormalResult operator()(const PairParameters& p, const PairState& s,
                                                      Real* h) const {
    // One straight-line evaluation for both cases, the JKR curve and, for a pair without surface energy,
    // Hertz-Tsuji (models/hertz_tsuji.hpp, repeated here operation for operation, so bit for bit): a branch
    // would keep the force pass's loop over pairs from vectorizing. The JKR arithmetic of a gamma = 0 pair
    // runs on meaningless numbers that the selections drop; only numbers are selected (a selection between
    // two truth values does not vectorize either).
    const bool adhesive = p.surface_energy > 0;
    const Real R = s.radius_eff;
    const Real delta = s.overlap;
    // In physical units, without the pair's natural scales (their cube root is a third of the pair's cost):
    // z = sqrt(a) solves z^4 - R* K z - R* delta = 0 with K = sqrt(4 pi gamma / E*)
    // (jkr::solve_quartic_closed).
    const Real K = math::sqrt(4 * math::pi * p.surface_energy / p.E_eff);
    // Unbonded: nothing until the surfaces touch. Bonded: separation below the separation overlap t u, tested
    // as delta^3 >= t^3 u^3 with u^3 = pi^2 gamma^2 R* / E*^2 (the cube keeps the sign and needs no root).
    const Real t = p.jkr_separation_overlap;
    const Real u3_per_R = math::pi * math::pi * p.surface_energy * p.surface_energy / (p.E_eff * p.E_eff);
    const bool was_bonded = h[0] > 0.5;
    const Real lhs = was_bonded ? delta * delta * delta : delta;
    const Real rhs = was_bonded ? (t * t * t) * u3_per_R * R : 0.0;
    const bool bonded_now = lhs >= rhs;
    const Real delta_jkr = bonded_now ? delta : 0; // an unbonded lane solves a harmless delta = 0
    const Real z = jkr::solve_quartic_closed(R * K, R * delta_jkr);
    const Real touching = delta > 0 ? delta : 0;
    const Real a = adhesive ? z * z : math::sqrt(R * touching); // contact radius
    const Real S_n = 2 * p.E_eff * a;                           // Hertz: dF/d(delta)
    // JKR: 4 E* a^3/(3 R*) - sqrt(16 pi gamma E* a^3) with a^2/R* = delta + K z and sqrt(16 pi gamma E*) = 2
    // E* K: (2/3) E* a (2 delta - K z), no division. Hertz: (2/3) S_n delta.
    const Real elastic =
        adhesive ? (2.0 / 3.0) * p.E_eff * a * (2 * delta_jkr - K * z) : (2.0 / 3.0) * S_n * delta;
    const Real damped = elastic + p.damping * math::sqrt(S_n * s.mass_eff) * s.overlap_rate;
    // Hertz-Tsuji holds the force at >= 0 and takes it as the Coulomb load; JKR uses Thornton's load.
    const Real force = adhesive ? damped : (damped < 0 ? 0.0 : damped);
    const Real F_c = 3 * math::pi * p.surface_energy * R; // pull-off force
    const Real friction_load = adhesive ? math::fabs(elastic + 2 * F_c) : force;
    const Real k_t = 8 * p.G_eff * a;
    const Real c_t = p.damping * math::sqrt(k_t * s.mass_eff);
    const Real on = adhesive ? (bonded_now ? 1.0 : 0.0) : (delta > 0 ? 1.0 : 0.0);
    NormalResult r;
    r.force = on > 0 ? force : 0.0;
    r.friction_load = on > 0 ? friction_load : 0.0;
    r.k_t = on > 0 ? k_t : 0.0;
    r.c_t = on > 0 ? c_t : 0.0;
    r.stiffness = on > 0 ? S_n : 0.0;
    r.active = on > 0.5;
    h[0] = adhesive && bonded_now ? 1.0 : 0.0;
    return r;
  }
};

} // namespace cgdem::models
