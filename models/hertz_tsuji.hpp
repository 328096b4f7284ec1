#pragma once
// Hertz normal contact with Tsuji damping (Hu eqs 5-15, physics.md 1):
//   F_n = 4/3 E* sqrt(R*) delta^1.5 + c_n delta_dot,  c_n = 2 sqrt(5/3) |beta| sqrt(m* E*) (R* delta)^(1/4)
// and the Mindlin tangential stiffness 8 G* a with c_t = 4 sqrt(5/3) |beta| sqrt(m* G*) (R* delta)^(1/4).
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
    const Real k_n = 2 * p.E_eff * a;                     // dF/d(delta)
    // sqrt(m* E*) (R* delta)^(1/4) = sqrt(m* k_n / 2): one root instead of two; likewise with 8 G* a.
    const Real c_n = 2 * 1.2909944487358056 * -p.beta * math::sqrt(0.5 * s.mass_eff * k_n);
    const Real elastic = (2.0 / 3.0) * k_n * s.overlap;
    r.force = elastic + c_n * s.overlap_rate;
    // A damper must not pull the surfaces together at the end of a contact (physics.md sign note).
    if (r.force < 0) r.force = 0;
    r.friction_load = r.force;
    r.k_t = 8 * p.G_eff * a;
    r.c_t = 4 * 1.2909944487358056 * -p.beta * math::sqrt(0.125 * s.mass_eff * r.k_t);
    r.stiffness = k_n;
    r.active = true;
    return r;
  }
};

} // namespace cgdem::models
