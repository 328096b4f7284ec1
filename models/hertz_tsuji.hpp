#pragma once
// Hertz normal contact with Tsuji-form damping (Hu eqs 5-15, docs/physics.md 3.1):
//   F_n = 4/3 E* sqrt(R*) delta^1.5 + c_n delta_dot,  c_n = eta sqrt(m* k_n),  k_n = 2 E* a,  a = sqrt(R*
//   delta)
// held at F_n >= 0, and the Mindlin tangential stiffness k_t = 8 G* a with c_t = eta sqrt(m* k_t). eta is the
// pair's damping coefficient (setup/restitution.hpp: solved for this clamped form, or Tsuji's 2 sqrt(5/6)
// |beta| with contact.damping: beta_formula).
#include "models/contact_law.hpp"

namespace cgdem::models {

struct HertzTsuji {
  static constexpr int history_size = 0;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "hertz";
  static Real interaction_range(const PairParameters&, Real, Real) { return 0; }

  KOKKOS_INLINE_FUNCTION NormalResult operator()(const PairParameters& p, const PairState& s, Real*) const {
    NormalResult r;
    if (s.overlap <= 0) return r;
    const Real a = math::sqrt(s.radius_eff * s.overlap); // contact radius
    const Real k_n = 2 * p.E_eff * a;                    // dF/d(delta)
    const Real c_n = p.damping * math::sqrt(s.mass_eff * k_n);
    const Real elastic = (2.0 / 3.0) * k_n * s.overlap;
    r.force = elastic + c_n * s.overlap_rate;
    // A damper must not pull the surfaces together at the end of a contact (docs/physics.md 2).
    if (r.force < 0) r.force = 0;
    r.friction_load = r.force;
    r.k_t = 8 * p.G_eff * a;
    r.c_t = p.damping * math::sqrt(s.mass_eff * r.k_t);
    r.stiffness = k_n;
    r.active = true;
    return r;
  }
};

} // namespace cgdem::models
