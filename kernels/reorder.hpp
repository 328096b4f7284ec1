#pragma once
// Spatial reorder for locality: gather every per-particle field (and per-particle wall history) into
// the order of the cell sort. `order(new) = old`. Writes into a scratch store the caller swaps in, so
// nothing is allocated per reorder.
#include <Kokkos_Core.hpp>
#include "core/particle_store.hpp"

namespace cgdem::kernels {

template <class ExecSpace>
void permute_store(const ParticleStore<typename ExecSpace::memory_space>& src,
                   const ParticleStore<typename ExecSpace::memory_space>& dst,
                   const Kokkos::View<int*, typename ExecSpace::memory_space>& order, int n) {
  Kokkos::parallel_for(
      "cgdem::kernels::reorder_store", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
        const int o = order(i);
        dst.id(i) = src.id(o);
        for (int a = 0; a < 3; ++a) {
          dst.position(i, a) = src.position(o, a);
          dst.velocity(i, a) = src.velocity(o, a);
          dst.angular_velocity(i, a) = src.angular_velocity(o, a);
          dst.force(i, a) = src.force(o, a);
          dst.torque(i, a) = src.torque(o, a);
          dst.position_at_build(i, a) = src.position_at_build(o, a);
        }
        dst.radius(i) = src.radius(o);
        dst.mass(i) = src.mass(o);
        dst.inertia(i) = src.inertia(o);
        dst.scale_factor(i) = src.scale_factor(o);
        dst.material(i) = src.material(o);
        dst.group(i) = src.group(o);
        dst.contacts(i) = src.contacts(o);
        dst.wall_contacts(i) = src.wall_contacts(o);
      });
}

template <class ExecSpace, class RowView>
void permute_rows(const RowView& src, const RowView& dst, const Kokkos::View<int*, typename ExecSpace::memory_space>& order,
                  int n) {
  const int cols = static_cast<int>(src.extent(1));
  if (cols == 0) return;
  Kokkos::parallel_for(
      "cgdem::kernels::reorder_rows", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
        for (int c = 0; c < cols; ++c) dst(i, c) = src(order(i), c);
      });
}

} // namespace cgdem::kernels
