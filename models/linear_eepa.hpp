#pragma once
// Linear elasto-plastic adhesive normal contact: EEPA with n = 1 (Thakur; Thakur, Morrissey, Sun, Chen &
// Ooi 2014), docs/physics.md 3.6. With f0 <= 0 the constant pull-off and delta_p the plastic overlap
// (history):
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
#include "models/material_parameters.hpp"

namespace cgdem::models {

struct LinearEepa {
  static constexpr int history_size = 1;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "eepa";
  static Real interaction_range(const PairParameters&, Real, Real) { return 0; }

  // Host side: materials.<name>.eepa: {k1, k2, k_adh, f0}, per contact (Thakur's values are a pair's):
  // stiffnesses as two half-contacts in series, the pull-off as a geometric mean like a surface energy.
  static constexpr bool spring_like = true;
  static Real spring_stiffness(const PairParameters& p) {
    return p.eepa_k1 > p.eepa_k2 ? p.eepa_k1 : p.eepa_k2;
  }
  static constexpr const char* material_block = "eepa";
  static constexpr const char* material_example = "eepa: {k1: <N/m>, k2: <N/m>, k_adh: <N/m>, f0: <N>}";
  static constexpr MaterialParameter material_parameters[] = {
      {"k1", &PairParameters::eepa_k1, Mix::harmonic_mean, Scales::stiffness, false, 0, 0, kUnbounded, false,
       false, false, "give the loading stiffness k1 in N/m"},
      {"k2", &PairParameters::eepa_k2, Mix::harmonic_mean, Scales::stiffness, false, 0, 0, kUnbounded, false,
       false, false, "give the unloading stiffness k2 in N/m"},
      {"k_adh", &PairParameters::eepa_k_adh, Mix::harmonic_mean, Scales::stiffness, true, 0, 0, kUnbounded,
       true, false, false, "give the adhesive stiffness k_adh >= 0 in N/m"},
      {"f0", &PairParameters::eepa_f0, Mix::geometric_mean, Scales::pull_off, true, 0, -kUnbounded, 0, false,
       true, false, "f0 is the constant pull-off force and must be <= 0 (N)"},
  };
  static const char* material_missing(const MaterialSpec& m) {
    return m.law_parameter("eepa.k1", 0) > 0 && m.law_parameter("eepa.k2", 0) > 0 ? nullptr
                                                                                  : "eepa.k1 and eepa.k2";
  }
  // A problem between the keys (the key it names, what is wrong, the fix), or none.
  static MaterialProblem material_problem(const MaterialSpec& m) {
    const auto k1 = m.law_parameters.find("eepa.k1"), k2 = m.law_parameters.find("eepa.k2");
    if (k1 == m.law_parameters.end() || k2 == m.law_parameters.end() || k2->second >= k1->second) return {};
    return {"k2", "k2 = " + short_number(k2->second) + " is below k1 = " + short_number(k1->second),
            "the unloading stiffness k2 must be at least the loading stiffness k1"};
  }

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
