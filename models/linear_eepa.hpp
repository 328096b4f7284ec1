#pragma once
// Linear elasto-plastic adhesive normal contact: EEPA with n = 1 (Thakur; Thakur, Morrissey, Sun, Chen &
// Ooi 2014), docs/physics.md 3.6. With f0 <= 0 the constant pull-off and delta_p the plastic overlap (history):
//   virgin loading     f_hys = f0 + k1 delta              when k2 (delta - delta_p) >= k1 delta;
//                                                          here delta_p = delta (1 - k1/k2) is updated
//   unloading/reloading f_hys = f0 + k2 (delta - delta_p)  when k1 delta > k2 (delta - delta_p) > -k_adh
//   delta adhesive branch    f_hys = f0 - k_adh delta           when -k_adh delta >= k2 (delta - delta_p)
// i.e. f_hys - f0 = max(-k_adh delta, min(k1 delta, k2 (delta - delta_p))), continuous in delta; delta_p
// only grows (on virgin loading), so unloading and reloading below the largest overlap so far run along
// the same k2 line, and the adhesive branch is followed reversibly below the crossing point
// k2 delta_p/(k2 + k_adh). The force acts while delta > 0 (at delta -> 0 on the adhesive branch it tends
// to f0) and is zero on separation, where the history is reset.
//   F_n = f_hys + c_n delta_dot, c_n = eta sqrt(m* k1), eta = 2 |beta| (= sqrt(4 m* k1)/sqrt(1 + (pi/ln
//   e)^2)), not clamped. k_t = 2/7 k1, c_t = eta sqrt(m* k_t); Coulomb load |f_hys + k_adh delta - f0|.
// `stiffness` reports k1, the law's reference stiffness (the branch slope would be negative on the
// adhesive branch). k2 < k1 (e.g. left unset) is taken as k2 = k1: elastic, no plastic overlap.
//
// History (1 Real): [0] plastic overlap delta_p.
#include "models/contact_law.hpp"

namespace cgdem::models {

struct LinearEepa {
  static constexpr int history_size = 1;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "eepa";
  static Real interaction_range(const PairParameters&, Real, Real) { return 0; }

  KOKKOS_INLINE_FUNCTION NormalResult operator()(const PairParameters& p, const PairState& s, Real* h) const {
    NormalResult r;
    const Real delta = s.overlap;
    if (!(delta > 0)) {
      h[0] = 0;
      return r;
    }
    const Real k1 = p.eepa_k1;
    const Real k2 = p.eepa_k2 > k1 ? p.eepa_k2 : k1;
    const Real k_adh = p.eepa_k_adh;
    Real delta_p = h[0];
    const Real loading = k1 * delta;
    Real f = k2 * (delta - delta_p); // unloading / reloading line
    if (f >= loading) {
      // Virgin loading: the plastic overlap follows the largest overlap.
      f = loading;
      delta_p = k2 > 0 ? delta * (1 - k1 / k2) : 0;
    } else if (-k_adh * delta >= f) {
      f = -k_adh * delta; // adhesive branch
    }
    h[0] = delta_p;
    const Real f_hys = p.eepa_f0 + f;
    r.force = f_hys + p.damping * math::sqrt(s.mass_eff * k1) * s.overlap_rate;
    r.friction_load = math::fabs(f + k_adh * delta);
    r.k_t = (2.0 / 7.0) * k1;
    r.c_t = p.damping * math::sqrt(s.mass_eff * r.k_t);
    r.stiffness = k1;
    r.active = true;
    return r;
  }
};

} // namespace cgdem::models
