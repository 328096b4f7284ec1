#pragma once
// Direct force scaling (Hu, Chan, Tsuji, Tanaka & Washino 2022; Sakai & Koshizuka 2009), docs/physics.md 4.2:
// evaluate the ORIGINAL pair's force with the ORIGINAL parameters from the coarse pair's state, then scale
// the force and torque up. DirectForceScaling<Method, Law> wraps any ContactLaw<...> and is itself a law
// (same interface: history_size, interaction_range, const device call operator).
//
// Original state from the coarse one, with l the pair's factor (l_i = l_j = l: exact; mixed factors use
// l = 2 l_i l_j / (l_i + l_j), the wall pair l = l_i, the rule of setup/scaling.hpp):
//   v_O = v_S (overlap rate, tangential contact velocity unchanged), omega_O = l omega_S,
//   R_O = R_S / l (R_i, R_j, R*), m*_O = m*_S / l^3, V_O = V_S / l^3 (liquid bridge volumes),
//   overlap / separation: delta_O = delta_S / l^overlap_power (geometric similarity for Hu methods 1 and 3,
//   unchanged for method 2 and Sakai).
// Coarse force F_S = l^force_power F_O (Sakai: the adhesion component l^adhesion_power), torque
// M_S = l^torque_power M_O with M_O the wrapped law's torque (lever R_O - delta_O / 2). The pair table's
// torque_power, when set, replaces the method's: Hu's eq 30 gives Method 1 l^2, but with t_S = l t_O the
// coarse spin omega_S = omega_O / l stays similar to the original's only with l^3
// (coarse_grain.torque_power: 3).
//
// History: the wrapped law's slots, same size and meaning, holding the ORIGINAL contact's state (JKR bond
// flag and contact radius a_O, bridge flag, tangential spring displacement xi_O). Tangential displacement
// rule: xi_O follows the overlap's geometric rule, xi_O = xi_S / l^overlap_power. It is obtained by
// integrating the (unchanged) tangential velocity over dt_O = dt / l^overlap_power: xi_O += v_t dt_O.
// The same time map keeps a rolling spring's angle at the coarse one's under geometric similarity.
#include "models/contact_law.hpp"

namespace cgdem::models::scaling {

// Exponents per method; the host reads them too (cgdem::direct_exponents in setup/scaling.cpp).
struct HuMethod1 { // recommended by Hu: geometric similarity, l^2
  static constexpr const char* name = "hu_method1";
  static constexpr int overlap_power = 1, force_power = 2, adhesion_power = 2, torque_power = 2;
};
struct HuMethod2 { // conventional: coarse overlap taken as the original's, l^2
  static constexpr const char* name = "hu_method2";
  static constexpr int overlap_power = 0, force_power = 2, adhesion_power = 2, torque_power = 2;
};
struct HuMethod3 { // geometric similarity, l^3
  static constexpr const char* name = "hu_method3";
  static constexpr int overlap_power = 1, force_power = 3, adhesion_power = 3, torque_power = 3;
};
struct Sakai { // Sakai & Koshizuka 2009: contact l^3, adhesive (van der Waals type) l^2, torque l^4
  static constexpr const char* name = "sakai";
  static constexpr int overlap_power = 0, force_power = 3, adhesion_power = 2, torque_power = 4;
};

// l^n for the methods' exponents 0..4, multiplied in the order of 1 * l * l ... In straight-line arithmetic:
// a loop, even of constant length, inside the force pass's loop over pairs keeps that loop from vectorizing.
KOKKOS_INLINE_FUNCTION Real power(Real l, int n) {
  const Real l2 = l * l;
  return n <= 0 ? 1.0 : n == 1 ? l : n == 2 ? l2 : n == 3 ? l2 * l : l2 * l * l;
}

// The exponent t of the pair table (2 or 3), or the method's m where t is 0, and l^n for n in {2, 3, 4}.
// Without a selection: t is the same in every lane of the force pass's loop over pairs, and GCC 12 does not
// vectorize a loop that selects among lane values on such a condition (it finds no vector type for it).
// Both are Lagrange forms whose weights are exactly 1 or 0 at these integers: (2 - t)(3 - t)/6 is 1 at t = 0
// and 0 at 2 and 3; l^n sums l^2, l^3, l^4 weighted 1 for the one of power n and exactly 0 for the others.
KOKKOS_INLINE_FUNCTION Real effective_torque_power(Real t, int m) {
  return t + ((2 - t) * (3 - t) / 6) * m;
}
KOKKOS_INLINE_FUNCTION Real power_2_to_4(Real l, Real n) {
  const Real l2 = l * l, l3 = l2 * l, l4 = l3 * l;
  return ((3 - n) * (4 - n) / 2) * l2 + ((n - 2) * (4 - n)) * l3 + ((n - 2) * (n - 3) / 2) * l4;
}

// Pair factor from the two particles' factors (scale_j <= 0: a wall).
KOKKOS_INLINE_FUNCTION Real pair_factor(Real scale_i, Real scale_j) {
  return scale_j > 0 ? 2 * scale_i * scale_j / (scale_i + scale_j) : scale_i;
}

// The original pair's state seen from the coarse pair (l >= 1).
template <class Method>
KOKKOS_INLINE_FUNCTION PairState original_state(const PairState& s, Real l) {
  const Real g = 1 / power(l, Method::overlap_power); // geometric factor on lengths of the contact
  const Real l3 = l * l * l;
  PairState o = s;
  o.overlap = g * s.overlap;
  // overlap_rate and tangential_velocity: v_O = v_S and omega_O R_O = omega_S R_S.
  o.relative_rotation = l * s.relative_rotation;
  o.omega_i = l * s.omega_i;
  o.omega_j = l * s.omega_j;
  o.radius_i = s.radius_i / l;
  o.radius_j = s.radius_j / l;
  o.radius_eff = s.radius_eff / l;
  o.mass_eff = s.mass_eff / l3;
  o.volume_i = s.volume_i / l3;
  o.volume_j = s.volume_j / l3;
  o.dt = g * s.dt; // xi_O = xi_S / l^overlap_power (see the header)
  o.scale_i = 1;
  o.scale_j = s.scale_j > 0 ? 1 : 0;
  return o;
}

template <class Method, class Law>
struct DirectForceScaling {
  using method_type = Method;
  using law_type = Law;
  static constexpr int history_size = Law::history_size;
  static constexpr bool reads_scale_factors = true; // the pair's factor l

  Law law;

  // The wrapped law keeps its history in original-particle units; seen from the other particle it
  // flips exactly as the wrapped law's does.
  KOKKOS_INLINE_FUNCTION static void flip_history(Real* h) { Law::flip_history(h); }

  // Coarse reach: the original pair's (radii / l) stretched back by l^overlap_power. l is the pair table's
  // coarse_grain_factor (setup/scaling.cpp); the Simulation takes the maximum over all table entries.
  static Real interaction_range(const PairParameters& p, Real R_i, Real R_j) {
    const Real l = p.coarse_grain_factor > 0 ? p.coarse_grain_factor : 1;
    const Real range = Law::interaction_range(p, R_i / l, R_j > 0 ? R_j / l : R_j);
    return range * power(l, Method::overlap_power);
  }

  // Forced inline: called in the force pass's loop over pairs, which vectorizes only if the whole law is
  // inlined.
  KOKKOS_FORCEINLINE_FUNCTION ContactForce operator()(const PairParameters& p, const PairState& s,
                                                      Real* history) const {
    const Real l = pair_factor(s.scale_i, s.scale_j);
    const PairState o = original_state<Method>(s, l);
    // The pair table's torque power (2 or 3; 0: the method's own).
    const Real torque_scale = power_2_to_4(l, effective_torque_power(p.torque_power, Method::torque_power));
    if constexpr (Method::adhesion_power == Method::force_power) {
      ContactForce cf = law(p, o, history);
      cf.force *= power(l, Method::force_power);
      cf.torque *= torque_scale;
      cf.torque_j *= torque_scale;
      return cf;
    } else {
      // The adhesion component scales differently (Sakai): the wrapped ContactLaw's composition, with the
      // contact (normal law + tangential) and adhesion parts scaled separately. Keep in step with
      // ContactLaw::operator() (models/contact_law.hpp).
      const Real fc = power(l, Method::force_power), fa = power(l, Method::adhesion_power);
      const Real ft_scale = torque_scale;
      NormalResult nr = law.normal(p, o, history + Law::normal_offset);
      const Real attraction = law.adhesion(p, o, nr, history + Law::adhesion_offset);
      ContactForce out;
      if (!nr.active) {
        for (int k = Law::tangential_offset; k < Law::history_size; ++k)
          history[k] = 0;
        out.force = (fa * attraction) * o.normal;
        out.active = attraction > 0;
        return out;
      }
      out.active = true;
      const Vec3 ft = law.tangential(p, o, nr, history + Law::tangential_offset);
      const RollingTorque rolling_torque = law.rolling(p, o, nr, history + Law::rolling_offset);
      out.force = (fa * attraction - fc * nr.force) * o.normal + fc * ft;
      const Vec3 n_x_ft = cross(o.normal, ft);
      out.torque = ft_scale * (lever_arm(o.radius_i, o) * n_x_ft + rolling_torque.on_i);
      out.torque_j = ft_scale * (lever_arm(o.radius_j, o) * n_x_ft + rolling_torque.on_j);
      return out;
    }
  }
};

} // namespace cgdem::models::scaling
