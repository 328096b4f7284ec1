#pragma once
// DMT adhesion (Derjaguin-Muller-Toporov), docs/physics.md 3.4, used with HertzTsuji as the normal law:
// a constant attraction 2 pi W R* = 4 pi gamma R* (W = 2 gamma) while the surfaces touch (delta >= 0),
// nothing across a gap, no hysteresis, no history. The pull-off force is the attraction at delta = 0,
// 4 pi gamma R* = 4/3 of the JKR F_c.
// The Coulomb load is left as the normal law's (Hertz) repulsion: in DMT the contact area is the
// Hertzian one of that repulsion, which already carries the adhesive pull.
#include "models/contact_law.hpp"

namespace cgdem::models {

struct Dmt {
  static constexpr int history_size = 0;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "dmt";
  static Real interaction_range(const PairParameters&, Real, Real) { return 0; }

  KOKKOS_INLINE_FUNCTION Real operator()(const PairParameters& p, const PairState& s, NormalResult&,
                                         Real*) const {
    if (s.overlap < 0 || !(p.surface_energy > 0)) return 0;
    return 4 * math::pi * p.surface_energy * s.radius_eff;
  }
};

} // namespace cgdem::models
