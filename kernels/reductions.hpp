#pragma once
// Whole-system observables, evaluated at output times: kinetic energies, contact count, largest
// overlap and speed (blow-up checks) and the force on each wall.
#include <Kokkos_Core.hpp>
#include <vector>
#include "core/particle_store.hpp"

namespace cgdem::kernels {

struct SystemSums {
  Real kinetic = 0, rotational = 0;
  Real momentum[3] = {0, 0, 0};
  long contacts = 0;
  long pair_slots = 0; // the owned particles' particle-particle contacts, each pair counted from both ends
  Real max_speed = 0;

  KOKKOS_INLINE_FUNCTION SystemSums& operator+=(const SystemSums& o) {
    kinetic += o.kinetic;
    rotational += o.rotational;
    for (int a = 0; a < 3; ++a)
      momentum[a] += o.momentum[a];
    contacts += o.contacts;
    pair_slots += o.pair_slots;
    max_speed = max_speed > o.max_speed ? max_speed : o.max_speed;
    return *this;
  }
};

template <class ExecSpace>
SystemSums system_sums(const ParticleStore<typename ExecSpace::memory_space>& p, int n) {
  // Summed in index order on the host mirror so the figures do not depend on the thread count
  // (they are outputs only, but users diff them across backends).
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.velocity);
  auto w = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.angular_velocity);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.mass);
  auto I = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.inertia);
  auto c = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.contacts);
  auto cw = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.wall_contacts);
  auto halo = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.halo);
  long pair_slots = 0;
  SystemSums s;
  for (int i = 0; i < n; ++i) {
    if (halo(i)) continue; // its owner counts it
    const Vec3 vi{v(i, 0), v(i, 1), v(i, 2)};
    const Vec3 wi{w(i, 0), w(i, 1), w(i, 2)};
    s.kinetic += 0.5 * m(i) * norm2(vi);
    s.rotational += 0.5 * I(i) * norm2(wi);
    for (int a = 0; a < 3; ++a)
      s.momentum[a] += m(i) * vi[a];
    pair_slots += c(i);
    s.contacts += cw(i);
    const Real sp = norm(vi);
    if (sp > s.max_speed) s.max_speed = sp;
  }
  // Each particle-particle contact is seen from both sides; a contact with a halo copy is counted here
  // once and once more on the copy's owner (the caller sums the ranks' slots before halving).
  s.contacts += pair_slots / 2;
  s.pair_slots = pair_slots;
  return s;
}

// Force and moment on each named wall, from the force pass's record (2 rows per particle and part: the
// force the particle feels, the moment of the reaction on the part about the part's base): the force is
// minus the sum of the particles' forces, the moment the sum of the moments.
struct WallLoads {
  std::vector<Real> force, torque; // 3 per named wall
};
template <class ExecSpace>
WallLoads wall_loads(const Kokkos::View<Real* [3], typename ExecSpace::memory_space>& record,
                     const Kokkos::View<int*, typename ExecSpace::memory_space>& halo,
                     const std::vector<int>& owner, int num_named, int n) {
  auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), record);
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), halo);
  const int parts = static_cast<int>(owner.size());
  WallLoads out{std::vector<Real>(3 * num_named, 0.0), std::vector<Real>(3 * num_named, 0.0)};
  for (int i = 0; i < n; ++i)
    for (int w = 0; w < parts && !h(i); ++w) // a halo copy's load is counted by its owner
      for (int a = 0; a < 3; ++a) {
        out.force[3 * owner[w] + a] -= f(2 * (i * parts + w), a);
        out.torque[3 * owner[w] + a] += f(2 * (i * parts + w) + 1, a);
      }
  return out;
}

} // namespace cgdem::kernels
