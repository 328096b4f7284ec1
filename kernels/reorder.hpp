#pragma once
// Spatial reorder for locality: gather every per-particle field (and per-particle wall history) into
// the order of the cell sort, `order(new) = old`. Field by field through one scratch buffer sized for the
// widest field (gather into the scratch, copy back), instead of into a second particle store: a second
// store would double the largest allocation of the engine for a step that runs every few hundred steps.
#include <Kokkos_Core.hpp>
#include <algorithm>
#include "core/particle_store.hpp"

namespace cgdem::kernels {

// Bytes per particle the scratch buffer of permute_store/permute_rows needs for `row_bytes` wide rows.
inline std::size_t reorder_scratch_bytes(std::size_t row_bytes) {
  return std::max<std::size_t>({3 * sizeof(Real), sizeof(std::int64_t), row_bytes});
}

template <class ExecSpace>
struct Reorder {
  using Mem = typename ExecSpace::memory_space;
  using Scratch = Kokkos::View<double*, Mem>; // raw storage, reinterpreted per field

  // field(i, :) <- field(order(i), :), for a rank-1 view or a rank-2 view with any number of columns.
  template <class FieldView>
  static void permute(const FieldView& field, const Scratch& scratch, const Kokkos::View<int*, Mem>& order,
                      int n) {
    using T = typename FieldView::non_const_value_type;
    const int cols = FieldView::rank == 1 ? 1 : static_cast<int>(field.extent(1));
    if (n == 0 || cols == 0) return;
    Kokkos::View<T**, Kokkos::LayoutRight, Mem, Kokkos::MemoryUnmanaged> tmp(
        reinterpret_cast<T*>(scratch.data()), n, cols);
    Kokkos::parallel_for(
        "cgdem::kernels::reorder_gather", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const int o = order(i);
          for (int c = 0; c < cols; ++c)
            tmp(i, c) = at(field, o, c);
        });
    Kokkos::parallel_for(
        "cgdem::kernels::reorder_copy_back", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          for (int c = 0; c < cols; ++c)
            at(field, i, c) = tmp(i, c);
        });
  }

  static void permute_store(const ParticleStore<Mem>& p, const Scratch& scratch,
                            const Kokkos::View<int*, Mem>& order, int n) {
    ParticleStore<Mem>::for_each_field(
        p, [&](const char*, const auto& field) { permute(field, scratch, order, n); });
  }

private:
  template <class V>
  KOKKOS_INLINE_FUNCTION static typename V::reference_type at(const V& v, int i, int c) {
    if constexpr (V::rank == 1)
      return v(i);
    else
      return v(i, c);
  }
};

} // namespace cgdem::kernels
