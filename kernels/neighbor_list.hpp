#pragma once
// Verlet neighbour list in CSR form, HALF list: each pair {i, j} is stored once, under the particle with
// the lower store index, so each contact law is evaluated once per pair. A transposed CSR lists, for every
// particle, the slots where it is the partner; forces are then gathered per particle in a fixed order
// (own slots, then transposed slots in slot order), so no atomics and bitwise the same sums on any
// backend and thread count (kernels/contact_forces.hpp).
//
// Per-slot contact history (compile-time size) survives rebuilds and spatial reorders; when a reorder
// changes which particle owns a pair, the history is flipped to the new owner's point of view
// (Law::flip_history: tangential displacements change sign, bond flags do not). Across a rebuild only the
// slots whose history is not zero are carried (a compact CSR of partner and history, about the active
// contacts), not the whole previous list: that would double the list's memory for the step of a rebuild.
#include <Kokkos_Core.hpp>
#include <cstdint>
#include "core/domain.hpp"
#include "kernels/cell_grid.hpp"

namespace cgdem::kernels {

template <class ExecSpace, class Law>
struct NeighborList {
  using Mem = typename ExecSpace::memory_space;
  static constexpr int H = Law::history_size;
  using HistoryView = Kokkos::View<ForceReal**, Kokkos::LayoutRight, Mem>;

  Kokkos::View<int*, Mem> offsets;         // n + 1
  Kokkos::View<int*, Mem> neighbors;       // capacity >= offsets(n); every entry > its owner's index
  HistoryView history;                     // capacity x H (no columns, no storage, when the law keeps none)
  Kokkos::View<int*, Mem> partner_offsets; // n + 1: transposed CSR
  Kokkos::View<int*, Mem> partner_slots;   // slots whose partner is the particle, in increasing order
  // What each slot hands to its partner: the pair force on the owner (the partner gets its negative),
  // the torque on the partner, and whether the pair is an active contact.
  Kokkos::View<ForceReal*[3], Mem> slot_force, slot_partner_torque;
  Kokkos::View<std::uint8_t*, Mem> slot_active; // 0: exerts nothing, 1: exerts a force, 2: active contact
  int num_slots = 0;

  // The history to carry into the next build: per particle (by its index at the last build), the
  // partners whose slot history is not zero, and that history. Grows only.
  Kokkos::View<int*, Mem> carry_offsets, carry_partner;
  HistoryView carry_history;

  std::size_t bytes() const {
    return (offsets.span() + neighbors.span() + partner_offsets.span() + partner_slots.span() +
            carry_offsets.span() + carry_partner.span()) *
               sizeof(int) +
           slot_active.span() * sizeof(std::uint8_t) +
           (history.span() + carry_history.span() + slot_force.span() + slot_partner_torque.span()) *
               sizeof(ForceReal);
  }

  // Build from bins whose `order` lists the particles by cell. `old_index(i)` maps a particle's current
  // index to its index when the previous list was built (identity without a reorder).
  template <class PositionView, class RadiusView, class OldIndexView>
  void build(const Domain& domain, const CellGrid& grid, const CellBins<ExecSpace>& bins,
             const PositionView& position, const RadiusView& radius, Real extra_cutoff, int n,
             const OldIndexView& old_index, bool have_old) {
    if constexpr (H > 0)
      if (have_old) carry_nonzero_history(n);
    if (static_cast<int>(offsets.extent(0)) != n + 1)
      offsets = Kokkos::View<int*, Mem>("cgdem::kernels::nl_offsets", n + 1);

    const auto cell_of = bins.cell_of_particle;
    const auto start = bins.cell_start;
    const auto order = bins.order;
    const auto offs = offsets;

    // Visit the partners j > i of particle i in deterministic order (27 stencil cells in fixed order,
    // a cell's particles in sorted order); f(j) is called for partners inside R_i + R_j + extra_cutoff.
    auto visit = [=] KOKKOS_FUNCTION(int i, auto&& f) {
      const Vec3 xi{position(i, 0), position(i, 1), position(i, 2)};
      const Real ri = radius(i);
      const int c = cell_of(i);
      const int cx = c % grid.dims[0], cy = (c / grid.dims[0]) % grid.dims[1],
                cz = c / (grid.dims[0] * grid.dims[1]);
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
              if (j <= i) continue;
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
    const int total = counts_to_offsets(offs, n, "cgdem::kernels::nl_scan");
    num_slots = total;
    if (static_cast<int>(neighbors.extent(0)) < total) reserve(capacity_for(total));
    const auto neigh = neighbors;
    const auto hist = history;
    const auto c_offs = carry_offsets;
    const auto c_partner = carry_partner;
    const auto c_hist = carry_history;
    Kokkos::parallel_for(
        "cgdem::kernels::nl_fill", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          int slot = offs(i);
          visit(i, [&](int j) { neigh(slot++) = j; });
          if constexpr (H > 0) {
            // Carry each pair's history over from the previous list, where the pair was kept under the
            // particle whose OLD index was lower; a new pair (or one whose history was zero) starts at zero.
            const int oi = old_index(i);
            for (int s = offs(i); s < offs(i + 1); ++s) {
              const int oj = old_index(neigh(s));
              const bool flipped = oj < oi;
              const int owner = flipped ? oj : oi, partner = flipped ? oi : oj;
              int found = -1;
              if (have_old)
                for (int t = c_offs(owner); t < c_offs(owner + 1); ++t)
                  if (c_partner(t) == partner) {
                    found = t;
                    break;
                  }
              Real h[H];
              for (int k = 0; k < H; ++k)
                h[k] = found >= 0 ? c_hist(found, k) : 0;
              if (flipped) Law::flip_history(h);
              for (int k = 0; k < H; ++k)
                hist(s, k) = static_cast<ForceReal>(h[k]);
            }
          }
        });
    build_partners(n);
  }

  // CSR offsets in place: counts(i + 1) holds the count of row i (counts(0) is ignored); afterwards
  // counts(i) is where row i starts. Returns the total.
  static int counts_to_offsets(const Kokkos::View<int*, Mem>& counts, int n, const char* label) {
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

  // Copy the slots of the current list whose history is not zero into the carry CSR, in slot order.
  void carry_nonzero_history(int n) {
    if (static_cast<int>(carry_offsets.extent(0)) != n + 1)
      carry_offsets = Kokkos::View<int*, Mem>("cgdem::kernels::nl_carry_offsets", n + 1);
    const auto offs = offsets;
    const auto neigh = neighbors;
    const auto hist = history;
    const auto c_offs = carry_offsets;
    auto nonzero = [=] KOKKOS_FUNCTION(int s) {
      for (int k = 0; k < H; ++k)
        if (hist(s, k) != 0) return true;
      return false;
    };
    Kokkos::parallel_for(
        "cgdem::kernels::nl_carry_count", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          int cnt = 0;
          for (int s = offs(i); s < offs(i + 1); ++s)
            cnt += nonzero(s) ? 1 : 0;
          c_offs(i + 1) = cnt;
        });
    const int total = counts_to_offsets(c_offs, n, "cgdem::kernels::nl_carry_scan");
    if (static_cast<int>(carry_partner.extent(0)) < total) {
      const int capacity = capacity_for(total);
      carry_partner = Kokkos::View<int*, Mem>("cgdem::kernels::nl_carry_partner", capacity);
      carry_history = HistoryView("cgdem::kernels::nl_carry_history", capacity, H);
    }
    const auto c_partner = carry_partner;
    const auto c_hist = carry_history;
    Kokkos::parallel_for(
        "cgdem::kernels::nl_carry_fill", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          int c = c_offs(i);
          for (int s = offs(i); s < offs(i + 1); ++s) {
            if (!nonzero(s)) continue;
            c_partner(c) = neigh(s);
            for (int k = 0; k < H; ++k)
              c_hist(c, k) = hist(s, k);
            ++c;
          }
        });
    Kokkos::fence();
  }

  // The transposed CSR, a pure function of (offsets, neighbors): also rebuilt after a restart.
  void build_partners(int n) {
    if (static_cast<int>(partner_offsets.extent(0)) != n + 1)
      partner_offsets = Kokkos::View<int*, Mem>("cgdem::kernels::nl_partner_offsets", n + 1);
    if (partner_slots.extent(0) < neighbors.extent(0)) reserve(static_cast<int>(neighbors.extent(0)));
    const auto offs = offsets;
    const auto neigh = neighbors;
    const auto p_offs = partner_offsets;
    const auto p_slots = partner_slots;
    Kokkos::deep_copy(ExecSpace(), p_offs, 0);
    Kokkos::parallel_for(
        "cgdem::kernels::nl_partner_count", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          for (int s = offs(i); s < offs(i + 1); ++s)
            Kokkos::atomic_increment(&p_offs(neigh(s) + 1));
        });
    counts_to_offsets(p_offs, n, "cgdem::kernels::nl_partner_scan");
    // Fill with a per-particle cursor (atomics: any order), then sort each particle's few slots so the
    // gather order is fixed.
    Kokkos::View<int*, Mem> cursor(Kokkos::view_alloc(ExecSpace(), "cgdem::kernels::nl_partner_cursor"), n);
    Kokkos::parallel_for(
        "cgdem::kernels::nl_partner_fill", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          for (int s = offs(i); s < offs(i + 1); ++s) {
            const int j = neigh(s);
            p_slots(p_offs(j) + Kokkos::atomic_fetch_add(&cursor(j), 1)) = s;
          }
        });
    Kokkos::parallel_for(
        "cgdem::kernels::nl_partner_sort", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int j) {
          const int b = p_offs(j), e = p_offs(j + 1);
          for (int k = b + 1; k < e; ++k) {
            const int v = p_slots(k);
            int m = k - 1;
            while (m >= b && p_slots(m) > v) {
              p_slots(m + 1) = p_slots(m);
              --m;
            }
            p_slots(m + 1) = v;
          }
        });
    Kokkos::fence();
  }

  // The capacity allocated for `slots` slots: 1/16 headroom, so that the list of a settled or slowly
  // changing scene is rebuilt in place, while the slot arrays (~80 B per slot) stay close to the count.
  // A list that outgrows it is reallocated at the next build, which refills every slot anyway.
  static int capacity_for(int slots) { return slots + slots / 16 + 64; }

  // Room for `capacity` slots (growth only, never per step).
  void reserve(int capacity) {
    if (static_cast<int>(neighbors.extent(0)) < capacity) {
      Kokkos::View<int*, Mem> grown("cgdem::kernels::nl_neighbors", capacity);
      HistoryView grown_history("cgdem::kernels::nl_history", H > 0 ? capacity : 0, H);
      neighbors = grown;
      history = grown_history;
    }
    if (static_cast<int>(partner_slots.extent(0)) < capacity) {
      partner_slots = Kokkos::View<int*, Mem>("cgdem::kernels::nl_partner_slots", capacity);
      slot_force = Kokkos::View<ForceReal* [3], Mem>("cgdem::kernels::slot_force", capacity);
      slot_partner_torque =
          Kokkos::View<ForceReal* [3], Mem>("cgdem::kernels::slot_partner_torque", capacity);
      slot_active = Kokkos::View<std::uint8_t*, Mem>("cgdem::kernels::slot_active", capacity);
    }
  }
};

} // namespace cgdem::kernels
