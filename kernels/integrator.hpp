#pragma once
// Velocity-Verlet for translation and rotation of spheres:
//   kick_drift: v += dt/2 (F/m + g), omega += dt/2 T/I, x += dt v (wrapped into periodic axes);
//               returns the largest squared displacement since the last list build (NaN/Inf -> +inf,
//               which the caller reports as a blow-up);
//   closing_kick: v += dt/2 (F/m + g), omega += dt/2 T/I with the new forces.
// When nothing reads the velocities between one step's closing kick and the next step's kick, kick_drift
// does both in one pass (close_previous): the same operations in the same order, so the trajectory is
// bitwise the one of the separate passes, without one sweep over the store per step.
#include <Kokkos_Core.hpp>
#include "core/domain.hpp"
#include "core/particle_store.hpp"
#include "kernels/force_blocks.hpp"

namespace cgdem::kernels {

template <class ExecSpace>
struct Integrator {
  using Mem = typename ExecSpace::memory_space;

  // Half a step of particle i's forces on velocities u: every kick uses exactly this.
  struct Velocities {
    Vec3 v, w;
  };
  KOKKOS_INLINE_FUNCTION static Velocities stored_velocities(const ParticleStore<Mem>& p, int i) {
    return {load3(p.velocity, i), load3(p.angular_velocity, i)};
  }
  KOKKOS_INLINE_FUNCTION static Velocities half_kick(const ParticleStore<Mem>& p, int i, const Velocities& u,
                                                     const Vec3& gravity, Real half) {
    const Real inv_m = 1.0 / p.mass(i);
    const Real inv_i = 1.0 / p.inertia(i);
    return {u.v + half * (inv_m * load3(p.force, i) + gravity), u.w + (half * inv_i) * load3(p.torque, i)};
  }

  // One particle's kick and drift (close_previous, clear_forces: see kick_drift); returns its squared
  // displacement since the last list build, +inf if its state is no longer finite.
  struct KickDrift {
    ParticleStore<Mem> p;
    Domain domain;
    Vec3 gravity;
    Real dt, half;
    bool close_previous, clear_forces;

    KOKKOS_INLINE_FUNCTION Real operator()(int i) const {
      Velocities u = stored_velocities(p, i);
      if (close_previous) u = half_kick(p, i, u, gravity, half);
      const auto [v, w] = half_kick(p, i, u, gravity, half);
      if (clear_forces) clear_force_sums(p, i);
      const Vec3 x = domain.wrap(load3(p.position, i) + dt * v);
      store3(p.velocity, i, v);
      store3(p.angular_velocity, i, w);
      store3(p.position, i, x);
      const Real d2 = norm2(domain.minimum_image(x - load3(p.position_at_build, i)));
      return math::isfinite(d2) && math::isfinite(norm2(w)) ? d2
                                                            : Kokkos::Experimental::infinity<Real>::value;
    }
  };

  // close_previous: the forces in the store are the previous step's new ones, not yet applied by a
  // closing_kick; apply them first. clear_forces: zero each particle's force, torque and contact count
  // once read, for the force pass that follows (ContactForces::compute's `cleared`), instead of a
  // sweep of its own over the store.
  // The particles are shared among the threads in even ranges of the store, or, when `claims` holds the
  // last force pass's claims (ForceBlocks::claims_recorded), each worker takes the blocks it ran there:
  // their forces were just written by its own core. Each particle's operations are the same either way.
  static Real kick_drift(const ParticleStore<Mem>& p, const Domain& domain, const Vec3& gravity, Real dt,
                         int n, bool close_previous = false, bool clear_forces = false,
                         const ForceBlocks<ExecSpace>* claims = nullptr) {
    const KickDrift one{p, domain, gravity, dt, Real(0.5) * dt, close_previous, clear_forces};
    Real max_disp2 = 0;
    if (claims && claims->claims_recorded) {
      const auto worker_of = claims->block_worker;
      const auto offsets = claims->block_offsets;
      const auto members = claims->block_members;
      const int nblocks = claims->colour_begin[ForceBlocks<ExecSpace>::kColours];
      Kokkos::parallel_reduce(
          "cgdem::kernels::kick_drift_by_blocks", Kokkos::RangePolicy<ExecSpace>(0, ExecSpace::concurrency()),
          KOKKOS_LAMBDA(int worker, Real& worst) {
            for (int b = 0; b < nblocks; ++b) {
              if (worker_of(b) != worker) continue;
              for (int m = offsets(b); m < offsets(b + 1); ++m) {
                const Real d2 = one(members(m));
                if (d2 > worst) worst = d2;
              }
            }
          },
          Kokkos::Max<Real>(max_disp2));
      return max_disp2;
    }
    Kokkos::parallel_reduce(
        "cgdem::kernels::kick_drift", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int i, Real& worst) {
          const Real d2 = one(i);
          if (d2 > worst) worst = d2;
        },
        Kokkos::Max<Real>(max_disp2));
    return max_disp2;
  }

  static void closing_kick(const ParticleStore<Mem>& p, const Vec3& gravity, Real dt, int n) {
    const Real half = 0.5 * dt;
    Kokkos::parallel_for(
        "cgdem::kernels::closing_kick", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const auto [v, w] = half_kick(p, i, stored_velocities(p, i), gravity, half);
          store3(p.velocity, i, v);
          store3(p.angular_velocity, i, w);
        });
  }
};

} // namespace cgdem::kernels
