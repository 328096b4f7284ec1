#pragma once
// A contact law is composed at compile time from four components, one per axis:
//   Normal      -> NormalResult from the overlap (HertzTsuji, LinearSpringDashpot, JkrFull, LinearEepa)
//   Adhesion    -> an attractive normal force added to the normal law's (NoAdhesion, Dmt, CapillaryBridge)
//   Tangential  -> tangential force from its own spring history (NoFriction, MindlinTangential)
//   Rolling     -> a resisting torque (NoRolling, RollingConstantTorque, RollingSpringDashpot)
// Each component declares `static constexpr int history_size` (Reals per contact it keeps),
// `static constexpr bool history_antisymmetric` (its history changes sign when the pair is seen from the
// other particle, like a tangential displacement; scalars such as a bond flag do not), a host-side
// `static Real interaction_range(const PairParameters&, Real R_i, Real R_j)` (how far beyond touching it
// may still act; the neighbour cut-off follows the longest), and a const device call operator.
// A component with history_size 0 stores nothing; ContactLaw::history_size is the sum.
// Contract: a component exerts nothing on a pair apart (overlap < 0) whose whole history is zero; a force
// across a gap (a JKR neck, a liquid bridge) exists only after a contact that the component recorded in its
// history. The force pass relies on it to skip such pairs within reach (kernels/contact_forces.hpp).
#include <type_traits>
#include "models/contact_state.hpp"
#include "models/pair_parameters.hpp"

namespace cgdem::models {

// ---------------------------------------------------------------------------------------------------
// Empty components: compile away.
struct NoAdhesion {
  static constexpr int history_size = 0;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "none";
  static Real interaction_range(const PairParameters&, Real, Real) { return 0; }
  // Returns the attractive force (>= 0, pulling i toward j); may raise nr.friction_load.
  KOKKOS_INLINE_FUNCTION Real operator()(const PairParameters&, const PairState&, NormalResult&,
                                         Real*) const {
    return 0;
  }
};

struct NoFriction {
  static constexpr int history_size = 0;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "none";
  KOKKOS_INLINE_FUNCTION Vec3 operator()(const PairParameters&, const PairState&, const NormalResult&,
                                         Real*) const {
    return Vec3{};
  }
};

struct NoRolling {
  static constexpr int history_size = 0;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "none";
  KOKKOS_INLINE_FUNCTION RollingTorque operator()(const PairParameters&, const PairState&,
                                                  const NormalResult&, Real*) const {
    return RollingTorque{};
  }
};

// ---------------------------------------------------------------------------------------------------
template <class Normal, class Adhesion = NoAdhesion, class Tangential = NoFriction, class Rolling = NoRolling>
struct ContactLaw {
  using normal_type = Normal;
  using adhesion_type = Adhesion;
  using tangential_type = Tangential;
  using rolling_type = Rolling;

  static constexpr int normal_offset = 0;
  static constexpr int adhesion_offset = normal_offset + Normal::history_size;
  static constexpr int tangential_offset = adhesion_offset + Adhesion::history_size;
  static constexpr int rolling_offset = tangential_offset + Tangential::history_size;
  static constexpr int history_size = rolling_offset + Rolling::history_size;
  // The components read nothing of PairState::scale_i / scale_j (only the scaling wrappers of
  // models/scaling/ do): the force pass need not fetch the particles' factors.
  static constexpr bool reads_scale_factors = false;

  Normal normal;
  Adhesion adhesion;
  Tangential tangential;
  Rolling rolling;

  // The pair's history as the other particle would keep it: the neighbour list stores each pair once,
  // under whichever particle comes first, and that owner can change when the store is reordered.
  KOKKOS_INLINE_FUNCTION static void flip_history(Real* h) {
    flip<Normal>(h + normal_offset);
    flip<Adhesion>(h + adhesion_offset);
    flip<Tangential>(h + tangential_offset);
    flip<Rolling>(h + rolling_offset);
  }
  template <class Component>
  KOKKOS_INLINE_FUNCTION static void flip(Real* h) {
    if constexpr (Component::history_antisymmetric)
      for (int k = 0; k < Component::history_size; ++k)
        h[k] = -h[k];
  }

  static Real interaction_range(const PairParameters& p, Real R_i, Real R_j) {
    const Real a = Normal::interaction_range(p, R_i, R_j);
    const Real b = Adhesion::interaction_range(p, R_i, R_j);
    return a > b ? a : b;
  }

  // Force and torque on i. `history` points at history_size Reals owned by this (i, j) slot; a law
  // that finds the pair inactive leaves its history zeroed so a later contact starts fresh.
  KOKKOS_FORCEINLINE_FUNCTION ContactForce operator()(const PairParameters& p, const PairState& s,
                                                      Real* history) const {
    NormalResult nr = normal(p, s, history + normal_offset);
    const Real attraction = adhesion(p, s, nr, history + adhesion_offset);
    ContactForce out;
    if (!nr.active) {
      // Tangential and rolling springs only live while the pair touches; a liquid bridge may still pull.
      for (int k = tangential_offset; k < history_size; ++k)
        history[k] = 0;
      out.force = attraction * s.normal;
      out.active = attraction > 0;
      return out;
    }
    out.active = true;
    const Vec3 ft = tangential(p, s, nr, history + tangential_offset);
    const RollingTorque rolling_torque = rolling(p, s, nr, history + rolling_offset);
    out.force = (attraction - nr.force) * s.normal + ft;
    // Lever arms from the centres to the contact point (lever_arm: R - share x overlap) along +n for i and
    // -n for j; j feels -ft, so both tangential torques are lever * (n x ft).
    const Vec3 n_x_ft = cross(s.normal, ft);
    out.torque = lever_arm(s.radius_i, s) * n_x_ft;
    out.torque_j = lever_arm(s.radius_j, s) * n_x_ft;
    if constexpr (!std::is_same<Rolling, NoRolling>::value) { // x + 0.0 is not x for x = -0.0: not folded
      out.torque += rolling_torque.on_i;
      out.torque_j += rolling_torque.on_j;
    }
    return out;
  }
};

} // namespace cgdem::models
