#pragma once
// Mixed parameters of one material pair (particle-particle or particle-wall), precomputed on the host
// (setup/materials.cpp) into an ntypes x ntypes table. Every contact component reads what it needs from
// here; a component whose parameters are zero contributes nothing (e.g. gamma = 0 switches adhesion off
// for one pair while the scene's law keeps it for others).
#include "core/types.hpp"

namespace cgdem::models {

struct PairParameters {
  // Elastic, from the two materials (docs/physics.md 0: E*, G*).
  Real E_eff = 0;
  Real G_eff = 0;
  // Restitution of the pair and the damping coefficient eta >= 0 that realises it for the scene's normal law
  // (setup/restitution.hpp): c_n = eta sqrt(m* k_ref), k_ref the law's reference stiffness, and
  // c_t = eta sqrt(m* k_t).
  Real restitution = 1;
  Real damping = 0;
  // Friction.
  Real mu_slide = 0;
  Real mu_roll = 0;
  // Linear spring-dashpot stiffnesses (Cundall-Strack); k_t = 2/7 k_n when not given.
  Real k_n = 0;
  Real k_t = 0;
  // Adhesion: surface energy gamma as it enters the JKR formulas.
  Real surface_energy = 0;
  // Linear EEPA (Thakur): loading, unloading and adhesive stiffness, pull-off force f0 <= 0.
  Real eepa_k1 = 0;
  Real eepa_k2 = 0;
  Real eepa_k_adh = 0;
  Real eepa_f0 = 0;
  // Full JKR: the overlap, in units of u (models/jkr_relation.hpp), below which a bonded pair separates:
  // jkr::d_S (JKR theory, default), jkr::d_C (pull-off point, LAMMPS' rule) or 0 (contact loss, Hu's JKR).
  Real jkr_separation_overlap = -1.19055078897614960606; // jkr::d_S
  // Contact point for lever arms and contact velocities: R - lever_share * overlap (scene contact.lever_arm:
  // contact_point 0.5, radius 0).
  Real lever_share = 0.5;
  // Capillary bridge (Rabinovich-Lambert).
  Real surface_tension = 0;
  Real contact_angle = 0;   // radians
  Real liquid_volume = 0;   // per bridge if > 0 ...
  Real liquid_fraction = 0; // ... else V_liq = liquid_fraction * (V_i + V_j) (Hu eq 42: 0.083 * 0.05)
  Real min_separation = 0;  // S_min
  // Coarse-graining factor of the pair (setup/scaling.cpp: pair_scale_factor), 1 for originals. Read on the
  // host only, by the direct force scaling wrappers' interaction_range (models/scaling/); the device
  // functors take the factors from PairState::scale_i/scale_j.
  Real coarse_grain_factor = 1;
  // Direct force scaling: the interparticle torque scales as l^torque_power; 0 takes the method's own
  // exponent (coarse_grain.torque_power of Hu Method 1 sets 2 or 3).
  Real torque_power = 0;
};

} // namespace cgdem::models
