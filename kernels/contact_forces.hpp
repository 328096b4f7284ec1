#pragma once
// Pair and wall forces in two passes over the particles, both deterministic (no atomics):
//   1. each particle i evaluates the law once for each pair it owns in the half list and for each wall,
//      sums what it feels, and leaves in the slot what the partner feels (-force, its torque);
//   2. each particle adds what its partners left for it, in slot order, and (when asked) applies the
//      closing half kick of velocity-Verlet with its final force right there: a separate kick kernel
//      would read force, mass and velocity again and cost one more launch per step, which is what
//      dominates small coarse-grained scenes.
// The sum order is fixed by the list alone, so every backend and thread count gives the same bits, and
// the partner gets exactly the negated force: momentum is conserved to round-off.
#include <Kokkos_Core.hpp>
#include "core/domain.hpp"
#include "core/particle_store.hpp"
#include "core/wall.hpp"
#include "models/contact_law.hpp"

namespace cgdem::kernels {

// The closing half kick v += dt/2 (F/m + g), omega += dt/2 T/I, fused into the force gather.
struct ClosingKick {
  bool enabled = false;
  Vec3 gravity;
  Real half_dt = 0;
};

template <class ExecSpace, class Law>
struct ContactForces {
  using Mem = typename ExecSpace::memory_space;
  using ParamTable = Kokkos::View<models::PairParameters**, Mem>;
  static constexpr int H = Law::history_size;

  // Evaluate all contact forces into store.force / store.torque. When `wall_force` has extent > 0
  // the force each particle feels from each wall part is stored there too (for the wall reductions).
  template <class NeighborListT>
  static void compute(const ParticleStore<Mem>& p, const NeighborListT& nl, const Domain& domain,
                      const ParamTable& pair_params, const ParamTable& wall_params,
                      const Kokkos::View<Wall*, Mem>& walls,
                      const Kokkos::View<ForceReal**, Kokkos::LayoutRight, Mem>& wall_history,
                      const Kokkos::View<Real* [3], Mem>& wall_force, Real time, Real dt, Real reach, Law law,
                      int n, ClosingKick kick = {}) {
    const int nwalls = static_cast<int>(walls.extent(0));
    const bool record_wall_force = wall_force.extent(0) > 0;
    const auto offsets = nl.offsets;
    const auto neighbors = nl.neighbors;
    const auto history = nl.history;
    const auto slot_force = nl.slot_force;
    const auto slot_torque = nl.slot_partner_torque;
    const auto slot_active = nl.slot_active;
    // Dynamic chunks: the work per particle varies with its contacts and walls, and the spatial order puts
    // whole layers (the floor layer, the loose top) into one static half. Each particle's result does not
    // depend on which thread computes it, so this stays bitwise deterministic.
    using DynamicRange = Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>;
    Kokkos::parallel_for(
        "cgdem::kernels::contact_forces", DynamicRange(0, n), KOKKOS_LAMBDA(int i) {
          const Vec3 xi = load3(p.position, i);
          const Vec3 vi = load3(p.velocity, i);
          const Vec3 wi = load3(p.angular_velocity, i);
          const Real ri = p.radius(i);
          const Real mi = p.mass(i);
          const int mat_i = p.material(i);
          const Real vol_i = (4.0 / 3.0) * math::pi * ri * ri * ri;
          const Real scale_i = p.scale_factor(i);
          Vec3 f, t;
          int contacts = 0, wall_contacts = 0;
          Real h[H > 0 ? H : 1];

          const int slot_end = offsets(i + 1);
          for (int s = offsets(i); s < slot_end; ++s) {
            const int j = neighbors(s);
            // The partner two slots ahead: its position, velocities, radius and mass are five scattered
            // cache lines, and one contact's ~500 instructions are more than the core looks ahead, so
            // without the hint each slot starts by waiting for them (perf/README.md).
            if (s + 2 < slot_end) {
              const int ahead = neighbors(s + 2);
              math::prefetch(&p.position(ahead, 0));
              math::prefetch(&p.velocity(ahead, 0));
              math::prefetch(&p.angular_velocity(ahead, 0));
              math::prefetch(&p.radius(ahead));
              math::prefetch(&p.mass(ahead));
            }
            const Real rj = p.radius(j);
            const Vec3 d = domain.minimum_image(load3(p.position, j) - xi);
            const Real dist2 = norm2(d);
            const Real touch = ri + rj;
            const Real reach_ij = touch + reach;
            if (dist2 >= reach_ij * reach_ij || dist2 == 0) {
              // Out of reach of every interaction: the pair's history (if any) starts over. Most listed
              // pairs are not touching and already zero: read first, write only when needed.
              if constexpr (H > 0)
                for (int k = 0; k < H; ++k)
                  if (history(s, k) != 0) history(s, k) = 0;
              slot_active(s) = 0;
              continue;
            }
            const Real dist = math::sqrt(dist2);
            models::PairState st;
            st.normal = (1.0 / dist) * d;
            st.overlap = touch - dist;
            const Vec3 vj = load3(p.velocity, j);
            const Vec3 wj = load3(p.angular_velocity, j);
            const models::PairParameters& pp = pair_params(mat_i, p.material(j));
            st.lever_share = pp.lever_share;
            // Contact point velocities: lever arms (models::lever_arm) along +n for i and -n for j.
            const Vec3 vci = vi + cross(wi, models::lever_arm(ri, st) * st.normal);
            const Vec3 vcj = vj + cross(wj, (-models::lever_arm(rj, st)) * st.normal);
            const Vec3 vrel = vci - vcj;
            st.overlap_rate = dot(vi - vj, st.normal);
            st.tangential_velocity = vrel - dot(vrel, st.normal) * st.normal;
            st.relative_rotation = wi - wj;
            st.omega_i = wi;
            st.omega_j = wj;
            st.radius_i = ri;
            st.radius_j = rj;
            st.radius_eff = ri * rj / (ri + rj);
            const Real mj = p.mass(j);
            st.mass_eff = mi * mj / (mi + mj);
            st.volume_i = vol_i;
            st.volume_j = (4.0 / 3.0) * math::pi * rj * rj * rj;
            st.dt = dt;
            st.scale_i = scale_i;
            st.scale_j = p.scale_factor(j);
            if constexpr (H > 0)
              for (int k = 0; k < H; ++k)
                h[k] = history(s, k);
            const models::ContactForce cf = law(pp, st, h);
            if constexpr (H > 0)
              for (int k = 0; k < H; ++k)
                history(s, k) = static_cast<ForceReal>(h[k]);
            // i feels the force as j will read it from the slot (rounded to ForceReal: the identity in
            // double), so each pair exerts exactly +F and -F in either precision.
            const Vec3 fij = as_stored(cf.force);
            f += fij;
            t += cf.torque;
            contacts += cf.active ? 1 : 0;
            // What j feels, picked up by j in pass 2. A pair that exerts nothing (a listed, non-touching
            // pair of a law without reach) only clears its flag.
            const bool exerts = cf.active || norm2(cf.force) > 0;
            slot_active(s) = exerts ? (cf.active ? 2 : 1) : 0;
            if (exerts) {
              store3(slot_force, s, -fij);
              store3(slot_torque, s, cf.torque_j);
            }
          }

          for (int w = 0; w < nwalls; ++w) {
            const Wall& wall = walls(w); // a reference: the struct with its motion segments is ~50 words
            const WallContact wc = wall_contact(wall, time, xi, ri);
            Vec3 fw;
            if (!wc.reachable || wc.overlap <= -reach) {
              // Most particles are far from most walls and their history is already zero: read first.
              if constexpr (H > 0)
                for (int k = 0; k < H; ++k)
                  if (wall_history(i, w * H + k) != 0) wall_history(i, w * H + k) = 0;
            } else {
              const Vec3 surface_velocity = wall_surface_velocity(wall, time, wc);
              models::PairState st;
              st.normal = wc.normal;
              st.overlap = wc.overlap;
              const models::PairParameters& pp = wall_params(mat_i, wall.material);
              st.lever_share = pp.lever_share;
              const Vec3 vci = vi + cross(wi, models::lever_arm(ri, st) * wc.normal);
              const Vec3 vrel = vci - surface_velocity;
              st.overlap_rate = dot(vi - surface_velocity, wc.normal);
              st.tangential_velocity = vrel - dot(vrel, wc.normal) * wc.normal;
              st.relative_rotation = wi;
              st.omega_i = wi;
              st.radius_i = ri;
              st.radius_j = 0;
              st.radius_eff = ri;
              st.mass_eff = mi;
              st.volume_i = vol_i;
              st.volume_j = 0;
              st.dt = dt;
              st.scale_i = scale_i;
              st.scale_j = 0;
              if constexpr (H > 0)
                for (int k = 0; k < H; ++k)
                  h[k] = wall_history(i, w * H + k);
              const models::ContactForce cf = law(pp, st, h);
              if constexpr (H > 0)
                for (int k = 0; k < H; ++k)
                  wall_history(i, w * H + k) = static_cast<ForceReal>(h[k]);
              fw = cf.force;
              f += cf.force;
              t += cf.torque;
              wall_contacts += cf.active ? 1 : 0;
            }
            if (record_wall_force) store3(wall_force, i * nwalls + w, fw);
          }
          store3(p.force, i, f);
          store3(p.torque, i, t);
          p.contacts(i) = contacts;
          p.wall_contacts(i) = wall_contacts;
        });
    const auto partner_offsets = nl.partner_offsets;
    const auto partner_slots = nl.partner_slots;
    const int total_slots = nl.num_slots;
    Kokkos::parallel_for(
        "cgdem::kernels::gather_partner_forces", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int j) {
          Vec3 f, t;
          int contacts = 0;
          const int gather_end = partner_offsets(j + 1);
          for (int k = partner_offsets(j); k < gather_end; ++k) {
            const int s = partner_slots(k);
            // The slots four entries ahead (across particles: a particle has only ~2): scattered
            // over the owners' slot arrays, each one a cache miss the short loop cannot hide.
            if (k + 4 < total_slots) {
              const int ahead = partner_slots(k + 4);
              math::prefetch(&slot_force(ahead, 0));
              math::prefetch(&slot_torque(ahead, 0));
            }
            const int flag = slot_active(s);
            if (flag == 0) continue;
            f += load3(slot_force, s);
            t += load3(slot_torque, s);
            contacts += flag == 2 ? 1 : 0;
          }
          Vec3 force = load3(p.force, j), torque = load3(p.torque, j);
          if (contacts != 0 || norm2(f) != 0 || norm2(t) != 0) {
            force = force + f;
            torque = torque + t;
            store3(p.force, j, force);
            store3(p.torque, j, torque);
            p.contacts(j) += contacts;
          }
          if (!kick.enabled) return;
          // The closing half kick of velocity-Verlet (the opening one is Integrator::kick_drift).
          const Real inv_m = 1.0 / p.mass(j);
          const Real inv_i = 1.0 / p.inertia(j);
          store3(p.velocity, j, load3(p.velocity, j) + kick.half_dt * (inv_m * force + kick.gravity));
          store3(p.angular_velocity, j, load3(p.angular_velocity, j) + (kick.half_dt * inv_i) * torque);
        });
  }
};

} // namespace cgdem::kernels
