#pragma once
// Verlet neighbour list in CSR form (full list: each particle lists all partners, so each particle
// sums its own forces and the result does not depend on the thread count), with per-slot contact
// history of a compile-time size that survives rebuilds and spatial reorders.
//
// Order of neighbours: the 27 stencil cells in fixed order, particles of a cell in sorted order, so
// the list, and the summation order of forces, is the same on every backend and thread count.
#include <Kokkos_Core.hpp>
#include "core/domain.hpp"
#include "kernels/cell_grid.hpp"

namespace cgdem::kernels {

template <class ExecSpace, int HistorySize>
struct NeighborList {
  using Mem = typename ExecSpace::memory_space;
  static constexpr int history_size = HistorySize;

  Kokkos::View<int*, Mem> offsets;   // n + 1
  Kokkos::View<int*, Mem> neighbors; // capacity >= offsets(n)
  Kokkos::View<Real**, Kokkos::LayoutRight, Mem> history;  // capacity x HistorySize (0 columns: none)
  int num_slots = 0;

  // Previous list kept for the history transfer at the next build (swapped, never reallocated per step).
  Kokkos::View<int*, Mem> old_offsets, old_neighbors;
  Kokkos::View<Real**, Kokkos::LayoutRight, Mem> old_history;

  std::size_t bytes() const {
    return offsets.span() * sizeof(int) + neighbors.span() * sizeof(int) + history.span() * sizeof(Real);
  }

  // Build from bins whose `order` lists the particles by cell. `old_index(i)` maps a particle's
  // current index to its index when the previous list was built (identity without a reorder), so the
  // history of pair (i, j) is found under (old_index(i), old_index(j)).
  template <class PositionView, class RadiusView, class OldIndexView>
  void build(const Domain& domain, const CellGrid& grid, const CellBins<ExecSpace>& bins,
             const PositionView& position, const RadiusView& radius, Real extra_cutoff, int n,
             const OldIndexView& old_index, bool have_old) {
    std::swap(old_offsets, offsets);
    std::swap(old_neighbors, neighbors);
    std::swap(old_history, history);
    if (static_cast<int>(offsets.extent(0)) != n + 1) offsets = Kokkos::View<int*, Mem>("cgdem::kernels::nl_offsets", n + 1);

    const auto cell_of = bins.cell_of_particle;
    const auto start = bins.cell_start;
    const auto order = bins.order;
    const auto offs = offsets;

    // Visit every candidate partner of i in deterministic order; f(j) is called for partners inside
    // R_i + R_j + extra_cutoff.
    auto visit = [=] KOKKOS_FUNCTION(int i, auto&& f) {
      const Vec3 xi{position(i, 0), position(i, 1), position(i, 2)};
      const Real ri = radius(i);
      const int c = cell_of(i);
      const int cx = c % grid.dims[0], cy = (c / grid.dims[0]) % grid.dims[1], cz = c / (grid.dims[0] * grid.dims[1]);
      for (int dz = -1; dz <= 1; ++dz) {
        int z = cz + dz;
        if (z < 0 || z >= grid.dims[2]) {
          if (!domain.periodic[2]) continue;
          z = (z + grid.dims[2]) % grid.dims[2];
        }
        for (int dy = -1; dy <= 1; ++dy) {
          int y = cy + dy;
          if (y < 0 || y >= grid.dims[1]) {
            if (!domain.periodic[1]) continue;
            y = (y + grid.dims[1]) % grid.dims[1];
          }
          for (int dx = -1; dx <= 1; ++dx) {
            int x = cx + dx;
            if (x < 0 || x >= grid.dims[0]) {
              if (!domain.periodic[0]) continue;
              x = (x + grid.dims[0]) % grid.dims[0];
            }
            const int cell = x + grid.dims[0] * (y + grid.dims[1] * z);
            for (int k = start(cell); k < start(cell + 1); ++k) {
              const int j = order(k);
              if (j == i) continue;
              const Vec3 d = domain.minimum_image(Vec3{position(j, 0), position(j, 1), position(j, 2)} - xi);
              const Real cut = ri + radius(j) + extra_cutoff;
              if (norm2(d) < cut * cut) f(j);
            }
          }
        }
      }
    };

    Kokkos::parallel_for(
        "cgdem::kernels::nl_count", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          int cnt = 0;
          visit(i, [&](int) { ++cnt; });
          offs(i + 1) = cnt;
        });
    int total = 0;
    Kokkos::parallel_scan(
        "cgdem::kernels::nl_scan", Kokkos::RangePolicy<ExecSpace>(0, n + 1),
        KOKKOS_LAMBDA(int i, int& partial, bool final) {
          const int cnt = i == 0 ? 0 : offs(i);
          partial += cnt;
          if (final) offs(i) = partial;
        },
        total);
    num_slots = total;
    if (static_cast<int>(neighbors.extent(0)) < total) {
      // Grow with headroom so that a slowly densifying system does not reallocate at every build.
      const int cap = static_cast<int>(total * 1.2) + 64;
      neighbors = Kokkos::View<int*, Mem>("cgdem::kernels::nl_neighbors", cap);
      history = Kokkos::View<Real**, Kokkos::LayoutRight, Mem>("cgdem::kernels::nl_history", HistorySize > 0 ? cap : 0,
                                                               HistorySize);
    }
    const auto neigh = neighbors;
    const auto hist = history;
    const auto o_offs = old_offsets;
    const auto o_neigh = old_neighbors;
    const auto o_hist = old_history;
    Kokkos::parallel_for(
        "cgdem::kernels::nl_fill", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          int slot = offs(i);
          visit(i, [&](int j) { neigh(slot++) = j; });
          if constexpr (HistorySize > 0) {
            // Carry each pair's history over from the previous list; a new pair starts at zero.
            const int oi = old_index(i);
            for (int s = offs(i); s < offs(i + 1); ++s) {
              const int oj = old_index(neigh(s));
              int found = -1;
              if (have_old)
                for (int t = o_offs(oi); t < o_offs(oi + 1); ++t)
                  if (o_neigh(t) == oj) {
                    found = t;
                    break;
                  }
              for (int h = 0; h < HistorySize; ++h) hist(s, h) = found >= 0 ? o_hist(found, h) : 0;
            }
          }
        });
    Kokkos::fence();
  }
};

} // namespace cgdem::kernels
