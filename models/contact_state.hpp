#pragma once
// What a contact law sees of one pair, and what it returns. Built by kernels/pair_forces.hpp and
// kernels/wall_forces.hpp; a wall is a partner with infinite radius and mass (R_eff = R_i, m_eff = m_i).
//
// Conventions (docs/physics.md 0): n is the unit normal from i to j; overlap > 0 in contact, < 0 is a gap;
// overlap_rate > 0 while approaching; forces are returned as the force ON i.
// The state of (j, i) is the exact negative of (i, j) in every vector, so that forces come out as
// exact negatives and momentum is conserved to round-off.
#include "core/types.hpp"

namespace cgdem::models {

struct PairState {
  Real overlap = 0;         // R_i + R_j - |x_j - x_i|
  Real overlap_rate = 0;    // (v_i - v_j) . n
  Vec3 normal;              // unit, i -> j
  Vec3 tangential_velocity; // tangential part of the velocity of i's surface relative to j's at the contact
                            // point
  Vec3 relative_rotation;   // omega_i - omega_j
  Vec3 omega_i;             // the particles' own angular velocities (constant directional torque rolling)
  Vec3 omega_j;             // zero for a wall
  Real radius_i = 0;
  Real radius_j = 0;   // 0 for a wall
  Real radius_eff = 0; // R*
  Real mass_eff = 0;   // m*
  Real volume_i = 0;   // particle volumes (liquid bridge volume)
  Real volume_j = 0;
  Real dt = 0;
  // Coarse-graining factors k of the two particles (1: original size; scale_j = 0 for a wall). Read by
  // the direct force scaling wrappers (models/scaling/); plain contact laws ignore them.
  Real scale_i = 1;
  Real scale_j = 1;
  // Where the contact point sits: lever = R - lever_share * overlap from each centre (PairParameters).
  Real lever_share = 0.5;
};

// Distance from a centre to the contact point. lever_share 0.5 puts the point in the middle of the overlap
// lens (default); 0 takes the radius, as Chen & Elliott's law assumes when it scales torques by k^4 (the
// overlap is invariant under that law, R - delta/2 is not similar).
KOKKOS_INLINE_FUNCTION Real lever_arm(Real radius, const PairState& s) {
  return radius - s.lever_share * (s.overlap > 0 ? s.overlap : 0);
}

struct ContactForce {
  Vec3 force;    // total force on i (j gets exactly -force)
  Vec3 torque;   // torque on i about its centre, lever arm included
  Vec3 torque_j; // torque on j about its centre (a half neighbour list evaluates each pair once)
  // Counts as a contact (touching, or bonded across a gap): 0 or 1. A number, not a bool: a law that returns
  // a ContactForce it received from another (the scaling wrappers) would otherwise keep the force pass's loop
  // over pairs from vectorizing (GCC does not vectorize the copy of a struct holding a bool).
  int active = 0;
};

struct RollingTorque {
  Vec3 on_i, on_j;
};

// Output of a normal law, consumed by the tangential, adhesion and rolling components.
struct NormalResult {
  Real force = 0;         // along -n on i (repulsive > 0), elastic + damping
  Real friction_load = 0; // the load the Coulomb limit uses, >= 0
  Real k_t = 0;           // tangential stiffness for this step
  Real c_t = 0;           // tangential damping coefficient
  Real stiffness = 0;     // current normal stiffness (rolling spring uses it)
  bool active = false;
};

} // namespace cgdem::models
