#pragma once
// Simplified JKR adhesion (Hu section 2.3.2), used with HertzTsuji as the normal law:
//   attraction F_JKR = 4 sqrt(pi gamma E* a^3) = 4/3 x^1.5 F_c,
// a the JKR contact radius of the current overlap (delta = a^2/R* - sqrt(4 pi gamma a/E*), solved on the
// physical branch by models/jkr_relation.hpp from a cold start: for delta >= 0 the root lies far from the
// turning point S, and the monotone Newton from the upper bracket takes about 5 iterations, so no warm
// start is stored). The bond exists only while delta >= 0: no negative-overlap tail, no hysteresis, no
// history. At delta = 0 the attraction is 8/3 F_c (a = a_A); with surface_energy = 0 it vanishes.
// The Coulomb load is left as the normal law's repulsion (the compressive force the solid contact carries).
#include "models/contact_law.hpp"
#include "models/jkr_relation.hpp"

namespace cgdem::models {

struct JkrSimplified {
  static constexpr int history_size = 0;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "jkr_simplified";
  static Real interaction_range(const PairParameters&, Real, Real) { return 0; }

  KOKKOS_INLINE_FUNCTION Real operator()(const PairParameters& p, const PairState& s, NormalResult&,
                                         Real*) const {
    if (s.overlap < 0 || !(p.surface_energy > 0)) return 0;
    const jkr::Scales sc = jkr::scales(p.surface_energy, p.E_eff, s.radius_eff);
    const Real x = jkr::solve_x(s.overlap / sc.u, 0);
    return (4.0 / 3.0) * x * math::sqrt(x) * sc.F_c;
  }
};

} // namespace cgdem::models
