#pragma once
// Cell binning with a deterministic counting sort. The result is `order` (sorted position -> particle
// index) and `cell_start` (CSR over cells), identical for any thread count: counts are exact, and the
// particles of one cell are put back in index order after the parallel fill.
#include <Kokkos_Core.hpp>
#include "core/domain.hpp"

namespace cgdem::kernels {

struct CellGrid {
  int dims[3] = {1, 1, 1};
  Vec3 origin;
  Vec3 inv_size;

  CellGrid() = default;
  // Cells at least `min_size` wide covering the domain. Periodic axes need >= 3 cells so a 27-cell
  // stencil never visits a cell twice; the caller checks can_stencil().
  // `max_cells` bounds memory for big, sparsely filled open domains: cells grow (never shrink) to fit.
  CellGrid(const Domain& d, Real min_size, long max_cells) {
    origin = d.lo;
    for (Real size = min_size;; size *= 1.26) {
      long total = 1;
      for (int a = 0; a < 3; ++a) {
        int n = static_cast<int>(d.length[a] / size);
        dims[a] = n < 1 ? 1 : n;
        total *= dims[a];
      }
      if (total <= max_cells) break;
    }
    for (int a = 0; a < 3; ++a)
      inv_size[a] = dims[a] / d.length[a];
  }
  int count() const { return dims[0] * dims[1] * dims[2]; }

  KOKKOS_INLINE_FUNCTION int axis_cell(const Vec3& x, int a) const {
    int c = static_cast<int>((x[a] - origin[a]) * inv_size[a]);
    // Particles outside an open side of the domain go to the boundary cell (they still interact).
    return c < 0 ? 0 : (c >= dims[a] ? dims[a] - 1 : c);
  }
  KOKKOS_INLINE_FUNCTION int cell_of(const Vec3& x) const {
    return axis_cell(x, 0) + dims[0] * (axis_cell(x, 1) + dims[1] * axis_cell(x, 2));
  }
};

// CSR offsets in place: counts(i + 1) holds the count of row i (counts(0) is ignored); afterwards
// counts(i) is where row i starts. Returns the total.
template <class ExecSpace>
int counts_to_offsets(const Kokkos::View<int*, typename ExecSpace::memory_space>& counts, int n,
                      const char* label) {
  int total = 0;
  Kokkos::parallel_scan(
      label, Kokkos::RangePolicy<ExecSpace>(0, n + 1),
      KOKKOS_LAMBDA(int i, int& partial, bool final) {
        partial += i == 0 ? 0 : counts(i);
        if (final) counts(i) = partial;
      },
      total);
  return total;
}

template <class ExecSpace>
struct CellBins {
  using Mem = typename ExecSpace::memory_space;
  Kokkos::View<int*, Mem> cell_of_particle;
  Kokkos::View<int*, Mem> cell_start; // count + 1
  Kokkos::View<int*, Mem> cell_fill;
  Kokkos::View<int*, Mem> order; // particles sorted by cell, index order inside a cell

  std::size_t bytes() const {
    return (cell_of_particle.span() + cell_start.span() + cell_fill.span() + order.span()) * sizeof(int);
  }

  template <class PositionView>
  void build(const CellGrid& grid, const PositionView& position, int n) {
    const int ncell = grid.count();
    if (static_cast<int>(cell_start.extent(0)) != ncell + 1) {
      cell_start = Kokkos::View<int*, Mem>("cgdem::kernels::cell_start", ncell + 1);
      cell_fill = Kokkos::View<int*, Mem>("cgdem::kernels::cell_fill", ncell);
    }
    if (static_cast<int>(order.extent(0)) < n) {
      cell_of_particle = Kokkos::View<int*, Mem>("cgdem::kernels::cell_of_particle", n);
      order = Kokkos::View<int*, Mem>("cgdem::kernels::order", n);
    }
    auto cell_of = cell_of_particle;
    auto start = cell_start;
    auto fill = cell_fill;
    auto ord = order;
    Kokkos::deep_copy(ExecSpace(), fill, 0);
    Kokkos::parallel_for(
        "cgdem::kernels::bin_count", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const int c = grid.cell_of(Vec3{position(i, 0), position(i, 1), position(i, 2)});
          cell_of(i) = c;
          Kokkos::atomic_increment(&fill(c));
        });
    Kokkos::parallel_scan(
        "cgdem::kernels::bin_scan", Kokkos::RangePolicy<ExecSpace>(0, ncell + 1),
        KOKKOS_LAMBDA(int c, int& partial, bool final) {
          const int cnt = c < ncell ? fill(c) : 0;
          if (final) start(c) = partial;
          partial += cnt;
        });
    Kokkos::deep_copy(ExecSpace(), fill, 0);
    Kokkos::parallel_for(
        "cgdem::kernels::bin_fill", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const int c = cell_of(i);
          const int slot = Kokkos::atomic_fetch_add(&fill(c), 1);
          ord(start(c) + slot) = i;
        });
    // The atomic fill order depends on thread timing: restore index order inside each cell (cells hold
    // a handful of particles, so insertion sort is the cheapest stable fix).
    Kokkos::parallel_for(
        "cgdem::kernels::bin_stabilise", Kokkos::RangePolicy<ExecSpace>(0, ncell), KOKKOS_LAMBDA(int c) {
          const int b = start(c), e = start(c + 1);
          for (int k = b + 1; k < e; ++k) {
            const int v = ord(k);
            int m = k - 1;
            while (m >= b && ord(m) > v) {
              ord(m + 1) = ord(m);
              --m;
            }
            ord(m + 1) = v;
          }
        });
    Kokkos::fence();
  }
};

} // namespace cgdem::kernels
