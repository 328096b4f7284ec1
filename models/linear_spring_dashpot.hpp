#pragma once
// Linear spring-dashpot (Cundall-Strack): F_n = k_n delta + c_n delta_dot, c_n = eta sqrt(m* k_n) with
// eta = 2 |beta| (setup/restitution.hpp), so the restitution equals the input exactly and
// t_c = pi / sqrt(k_n/m* - (c_n / 2m*)^2).
// Tangential stiffness k_t (2/7 k_n when the scene leaves it out) with the same damping ratio.
#include "models/contact_law.hpp"
#include "models/material_parameters.hpp"

namespace cgdem::models {

struct LinearSpringDashpot {
  static constexpr int history_size = 0;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "linear";
  static Real interaction_range(const PairParameters&, Real, Real) { return 0; }

  // Host side: materials.<name>.spring: {normal, tangential}, each material's spring in series.
  static constexpr bool spring_like = true;
  static Real spring_stiffness(const PairParameters& p) { return p.k_n; }
  static constexpr const char* material_block = "spring";
  static constexpr const char* material_example = "spring: {normal: <N/m>, tangential: <N/m>}";
  static constexpr MaterialParameter material_parameters[] = {
      {"normal", &PairParameters::k_n, Mix::series, Scales::stiffness, false, 0, 0, kUnbounded, false, false,
       false, "give the normal spring stiffness in N/m"},
      {"tangential", &PairParameters::k_t, Mix::series, Scales::stiffness, false, 0, 0, kUnbounded, true,
       false, false, "give the tangential stiffness >= 0 in N/m"},
  };
  static const char* material_missing(const MaterialSpec& m) {
    return m.law_parameter("spring.normal", 0) > 0 ? nullptr : "spring.normal";
  }
  // k_t = 2/7 k_n when the materials leave it out.
  static void finish_pair(PairParameters& p) {
    if (p.k_t <= 0) p.k_t = 2.0 / 7.0 * p.k_n;
  }

  KOKKOS_INLINE_FUNCTION NormalResult operator()(const PairParameters& p, const PairState& s, Real*) const {
    NormalResult r;
    if (s.overlap <= 0) return r;
    const Real c_n = p.damping * math::sqrt(s.mass_eff * p.k_n);
    // No clamping here: the linear model's restitution is exact only with the full dashpot force.
    r.force = p.k_n * s.overlap + c_n * s.overlap_rate;
    r.friction_load = math::fabs(r.force);
    r.k_t = p.k_t;
    r.c_t = p.damping * math::sqrt(s.mass_eff * p.k_t);
    r.stiffness = p.k_n;
    r.active = true;
    return r;
  }
};

} // namespace cgdem::models
