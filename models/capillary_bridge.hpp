#pragma once
// Liquid bridge, Rabinovich-Lambert (Hu eqs 19-21, 37, 42), docs/physics.md 3:
//   F_cap = 4 pi R* sigma cos(theta) / (1 + 1/(sqrt(1 + V/(pi R* S^2)) - 1))
// evaluated here in the cancellation-free form 4 pi R* sigma cos(theta) q/(q + 1 + sqrt(1 + q)),
// q = V/(pi R* S^2), which is the same expression multiplied through by (sqrt(1+q) + 1)/(sqrt(1+q) + 1).
// S = -delta is the surface separation, clamped below at S_min (min_separation), so an overlapping pair
// feels the S_min force. The bridge forms when the surfaces touch (delta >= 0) and ruptures when
// S > S_rup = (1 + 0.5 theta) V^(1/3) (a bridge exactly S_rup long still holds); a pair that approaches
// without having touched feels nothing.
// V = liquid_volume if > 0, else liquid_fraction (V_i + V_j) (Hu eq 42: 0.083 x 0.05; a wall has V_j = 0).
// The Coulomb load is left as the normal law's repulsion (which already carries the bridge's pull).
//
// History (1 Real): [0] bridge alive flag (0 or 1).
#include "models/contact_law.hpp"
#include "models/material_parameters.hpp"

namespace cgdem::models {

struct CapillaryBridge {
  static constexpr int history_size = 1;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "capillary";

  // Host side: materials.<name>.capillary: {surface_tension, contact_angle (degrees), liquid_fraction,
  // liquid_volume, min_separation}.
  static constexpr const char* material_block = "capillary";
  static constexpr const char* material_example =
      "capillary: {surface_tension: 0.072, contact_angle: 0, liquid_fraction: 0.00415}";
  static constexpr MaterialParameter material_parameters[] = {
      {"surface_tension", &PairParameters::surface_tension, Mix::geometric_mean, Scales::no, true, 0, 0,
       kUnbounded, true, false, false, "give the surface tension in N/m, e.g. 0.072"},
      {"contact_angle", &PairParameters::contact_angle, Mix::mean, Scales::no, true, 0, 0, 90, true, false,
       true, "give the wetting angle in degrees, 0 <= angle < 90 (a bridge needs a wetting liquid)"},
      {"liquid_fraction", &PairParameters::liquid_fraction, Mix::max, Scales::no, true, 0, 0, kUnbounded,
       true, false, false, "give the liquid fraction >= 0"},
      {"liquid_volume", &PairParameters::liquid_volume, Mix::max, Scales::no, true, 0, 0, kUnbounded, true,
       false, false, "give the liquid volume per bridge >= 0 in m^3"},
      {"min_separation", &PairParameters::min_separation, Mix::max, Scales::no, false, 1e-6, 0, kUnbounded,
       false, false, false, "give the minimum separation in m, e.g. 1e-6"},
  };
  static const char* material_missing(const MaterialSpec& m) {
    const bool liquid = m.law_parameter("capillary.liquid_fraction", 0) > 0 ||
                        m.law_parameter("capillary.liquid_volume", 0) > 0;
    return m.law_parameter("capillary.surface_tension", 0) > 0 && liquid
               ? nullptr
               : "capillary.surface_tension and liquid_fraction or liquid_volume";
  }

  KOKKOS_INLINE_FUNCTION static Real liquid_volume(const PairParameters& p, Real V_i, Real V_j) {
    return p.liquid_volume > 0 ? p.liquid_volume : p.liquid_fraction * (V_i + V_j);
  }
  // V > 0 (math::cbrt_positive: straight-line, as the force pass's loop over pairs needs; the host's
  // interaction range uses the same function, so the two agree to the bit).
  KOKKOS_INLINE_FUNCTION static Real rupture_distance(const PairParameters& p, Real V) {
    return (1 + 0.5 * p.contact_angle) * math::cbrt_positive(V);
  }

  // S_rup for the bridge between spheres of radii R_i and R_j (R_j <= 0 or infinite: a wall, no liquid).
  static Real interaction_range(const PairParameters& p, Real R_i, Real R_j) {
    if (!(p.surface_tension > 0)) return 0;
    const Real c = 4.0 / 3.0 * math::pi;
    const Real V_i = R_i > 0 ? c * R_i * R_i * R_i : 0;
    const Real V_j = (R_j > 0 && math::isfinite(R_j)) ? c * R_j * R_j * R_j : 0;
    const Real V = liquid_volume(p, V_i, V_j);
    return V > 0 ? rupture_distance(p, V) : 0;
  }

  // Straight-line (every quantity computed, numbers selected), so that the force pass's loop over pairs
  // vectorizes; a pair without a bridge computes meaningless numbers that are dropped.
  KOKKOS_INLINE_FUNCTION Real operator()(const PairParameters& p, const PairState& s, NormalResult&,
                                         Real* h) const {
    const Real V = liquid_volume(p, s.volume_i, s.volume_j);
    const Real gap = -s.overlap;
    const bool formed = h[0] > 0.5 || s.overlap >= 0; // forms on contact
    const bool alive = formed && !(gap > rupture_distance(p, V)) && V > 0 && p.surface_tension > 0;
    h[0] = alive ? 1.0 : 0.0;
    const Real S = gap > p.min_separation ? gap : p.min_separation;
    const Real full = 4 * math::pi * s.radius_eff * p.surface_tension * math::cos(p.contact_angle);
    const Real q = V / (math::pi * s.radius_eff * S * S);
    // S_min = 0 at contact: the q -> infinity limit.
    const Real bridge = S > 0 ? full * q / (q + 1 + math::sqrt(1 + q)) : full;
    return alive ? bridge : 0.0;
  }
};

} // namespace cgdem::models
