#pragma once
// Verlet neighbour list in CSR form, HALF list: each pair {i, j} is stored once, under the particle with
// the lower store index, so each contact law is evaluated once per pair. The owner adds the reaction to
// the partner directly; the force pass's schedule (kernels/force_blocks.hpp) makes that race-free and
// deterministic on the host, and the pairs path indexes each particle's partner slots instead
// (index_partner_slots; kernels/contact_forces.hpp).
//
// Per-slot contact history (compile-time size) survives rebuilds and spatial reorders; when a reorder
// changes which particle owns a pair, the history is flipped to the new owner's point of view
// (Law::flip_history: tangential displacements change sign, bond flags do not). Across a rebuild only the
// slots whose history is not zero are carried (a compact CSR of partner and history, about the active
// contacts), not the whole previous list: that would double the list's memory for the step of a rebuild.
#include <Kokkos_Core.hpp>
#include <algorithm>
#include <vector>
#include "core/domain.hpp"
#include "core/particle_store.hpp"
#include "kernels/cell_grid.hpp"

namespace cgdem::kernels {

// Visits the partners j > i of particle i in deterministic order (the 27 stencil cells in fixed order, a
// cell's particles in sorted order): f(j, dist2) for each partner inside R_i + R_j + extra_cutoff, with
// their squared separation as the force pass computes it; candidates(i, g) calls g(j, dist2, inside) for
// every candidate j > i of the stencil, so that a caller can count without a branch per candidate. A
// functor, not a generic lambda: CUDA's device lambdas cannot be generic.
// `sorted`: the store is in the bins' order (order(k) == k, as after each spatial reorder), so a cell
// before i's own holds no partner and is passed without reading its bounds, and a cell's particles are
// the indices from its start, read without the indirection. The same candidates in the same order.
template <class PositionView, class RadiusView>
struct PartnerVisitor {
  Domain domain;
  CellGrid grid;
  PositionView position;
  RadiusView radius;
  Kokkos::View<const int*, typename PositionView::memory_space> cell_of, start, order;
  Real extra_cutoff;
  Real max_radius; // of any particle: bounds the cut-off of i's pairs, to skip cells beyond it
  bool sorted;

  template <class F>
  KOKKOS_INLINE_FUNCTION void operator()(int i, F&& f) const {
    candidates(i, [&](int j, Real dist2, bool inside) {
      if (inside) f(j, dist2);
    });
  }

  template <class G>
  KOKKOS_INLINE_FUNCTION void candidates(int i, G&& g) const {
    const Vec3 xi = load3(position, i);
    const Real ri = radius(i);
    const int c = cell_of(i);
    const int cx = c % grid.dims[0], cy = (c / grid.dims[0]) % grid.dims[1],
              cz = c / (grid.dims[0] * grid.dims[1]);
    // How far i is from the faces of its cell: a neighbouring cell lies at least that far along each axis
    // it is offset on, so a corner or edge cell whose nearest point is beyond the largest cut-off of i's
    // pairs holds no partner (about a quarter of the stencil in a dense bed). The bound carries a relative
    // margin far above rounding, so the skipped cells are exactly ones the distance test would reject.
    const Real cut_max = (ri + max_radius + extra_cutoff) * (1 + 1e-6), cut_max2 = cut_max * cut_max;
    const Real below[3] = {(xi.x - grid.origin.x) - cx / grid.inv_size.x,
                           (xi.y - grid.origin.y) - cy / grid.inv_size.y,
                           (xi.z - grid.origin.z) - cz / grid.inv_size.z};
    const Real above[3] = {1 / grid.inv_size.x - below[0], 1 / grid.inv_size.y - below[1],
                           1 / grid.inv_size.z - below[2]};
    const auto face_gap2 = [&](int axis, int d) {
      const Real g = d < 0 ? below[axis] : (d > 0 ? above[axis] : 0);
      return g > 0 ? g * g : Real(0);
    };
    for (int dz = -1; dz <= 1; ++dz) {
      int z = cz + dz;
      if (z < 0 || z >= grid.dims[2]) {
        if (!domain.periodic[2]) continue;
        z = (z + grid.dims[2]) % grid.dims[2];
      }
      const Real gap2_z = face_gap2(2, dz);
      for (int dy = -1; dy <= 1; ++dy) {
        int y = cy + dy;
        if (y < 0 || y >= grid.dims[1]) {
          if (!domain.periodic[1]) continue;
          y = (y + grid.dims[1]) % grid.dims[1];
        }
        const Real gap2_yz = gap2_z + face_gap2(1, dy);
        if (gap2_yz > cut_max2) continue;
        for (int dx = -1; dx <= 1; ++dx) {
          if (gap2_yz + face_gap2(0, dx) > cut_max2) continue;
          int x = cx + dx;
          if (x < 0 || x >= grid.dims[0]) {
            if (!domain.periodic[0]) continue;
            x = (x + grid.dims[0]) % grid.dims[0];
          }
          const int cell = x + grid.dims[0] * (y + grid.dims[1] * z);
          const auto test = [&](int j) {
            const Vec3 d = domain.minimum_image(load3(position, j) - xi);
            const Real cut = ri + radius(j) + extra_cutoff, dist2 = norm2(d);
            g(j, dist2, dist2 < cut * cut);
          };
          if (sorted) {
            if (cell < c) continue;
            const int last = start(cell + 1);
            for (int j = cell == c ? i + 1 : start(cell); j < last; ++j)
              test(j);
            continue;
          }
          // A cell's particles are in index order: a cell whose last is not above i holds no partner of
          // i (in a store sorted by cell, the half of the stencil before i's own cell).
          const int first = start(cell), last = start(cell + 1);
          if (first == last || order(last - 1) <= i) continue;
          for (int k = first; k < last; ++k) {
            const int j = order(k);
            if (j > i) test(j);
          }
        }
      }
    }
  }
};

template <class ExecSpace, class Law>
struct NeighborList {
  using Mem = typename ExecSpace::memory_space;
  static constexpr int H = Law::history_size;
  using HistoryView = Kokkos::View<ForceReal**, Kokkos::LayoutRight, Mem>;

  Kokkos::View<int*, Mem> offsets;   // n + 1
  Kokkos::View<int*, Mem> neighbors; // capacity >= offsets(n); every entry > its owner's index
  HistoryView history;               // capacity x H (no columns, no storage, when the law keeps none)
  // Per slot, how far the pair was beyond the law's reach at the build (surface gap minus reach, rounded
  // down), or -1 for a pair within reach then. Two particles that each moved at most D since the build
  // come no closer than that gap - 2 D: while it stays positive the pair exerts nothing and its history
  // stays zero, so the force pass skips it (kernels/contact_forces.hpp). Each particle's slots are
  // ordered touching first, then within reach, then beyond reach by increasing gap, so the force pass
  // stops at the first slot it may skip.
  Kokkos::View<float*, Mem> gap;
  int num_slots = 0;
  // The list build's scratch: each particle's first kFound partners, found by the count pass.
  static constexpr int kFound = 16;
  Kokkos::View<int*, Mem> found;

  // For the force pass's pairs path (ContactForces::Path::pairs; index_partner_slots): the other half of a
  // full list, each particle's slots as the partner, ascending (CSR over the particles), and each slot's
  // terms as the law gave them on the last pass: the force and torque on the owner, the torque on the
  // partner, whether the pair counts as a contact. Empty until that path first runs.
  Kokkos::View<int*, Mem> partner_offsets; // n + 1
  Kokkos::View<int*, Mem> partner_slots;
  Kokkos::View<int*, Mem> partner_fill; // n, scratch of index_partner_slots
  Kokkos::View<Real*[3], Mem> slot_force, slot_torque, slot_torque_j;
  Kokkos::View<int*, Mem> slot_active;
  bool partner_slots_indexed = false; // for the slots as they are (reset by every build and restore)

  // The history to carry into the next build: per particle (by its index at the last build), the
  // partners whose slot history is not zero, and that history. Grows only.
  Kokkos::View<int*, Mem> carry_offsets, carry_partner;
  HistoryView carry_history;

  std::size_t bytes() const {
    return (offsets.span() + neighbors.span() + carry_offsets.span() + found.span() + carry_partner.span() +
            partner_offsets.span() + partner_slots.span() + partner_fill.span() + slot_active.span()) *
               sizeof(int) +
           gap.span() * sizeof(float) + (history.span() + carry_history.span()) * sizeof(ForceReal) +
           (slot_force.span() + slot_torque.span() + slot_torque_j.span()) * sizeof(Real);
  }

  // Build from bins whose `order` lists the particles by cell. `old_index(i)` maps a particle's current
  // index to its index when the previous list was built (identity without a reorder).
  // `max_radius` bounds every particle's radius (the visitor skips stencil cells beyond the largest cut-off).
  template <class PositionView, class RadiusView, class OldIndexView>
  void build(const Domain& domain, const CellGrid& grid, const CellBins<ExecSpace>& bins,
             const PositionView& position, const RadiusView& radius, Real extra_cutoff, Real max_radius,
             Real reach, int n, const OldIndexView& old_index, bool have_old) {
    if constexpr (H > 0)
      if (have_old) carry_nonzero_history(n);
    if (static_cast<int>(offsets.extent(0)) != n + 1)
      offsets = Kokkos::View<int*, Mem>("cgdem::kernels::nl_offsets", n + 1);

    const auto cell_of = bins.cell_of_particle;
    const auto start = bins.cell_start;
    const auto order = bins.order;
    const auto offs = offsets;

    // Visit the partners j > i of particle i in deterministic order (PartnerVisitor).
    int unsorted = 0;
    Kokkos::parallel_reduce(
        "cgdem::kernels::nl_sorted", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int k, int& count) { count += order(k) != k ? 1 : 0; }, unsorted);
    const PartnerVisitor<PositionView, RadiusView> visit{
        domain, grid, position, radius, cell_of, start, order, extra_cutoff, max_radius, unsorted == 0};

    // The stencil is walked once: the count pass keeps each particle's first kFound partners, and the fill
    // pass takes them from there (their separations recomputed, the same bits as the visit's); only a
    // particle with more partners is visited again.
    if (static_cast<int>(found.extent(0)) < n * kFound)
      found = Kokkos::View<int*, Mem>("cgdem::kernels::nl_found", std::size_t(n) * kFound);
    const auto found_j = found;
    Kokkos::parallel_for(
        "cgdem::kernels::nl_count", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          // Every candidate is written to the next free place and kept only if inside: no branch on the
          // distance test (a coin toss per candidate in a dense bed). Place kFound takes the overflow.
          int cnt = 0, kept[kFound + 1];
          visit.candidates(i, [&](int j, Real, bool inside) {
            kept[cnt < kFound ? cnt : kFound] = j;
            cnt += inside ? 1 : 0;
          });
          int* mine = found_j.data() + std::size_t(i) * kFound;
          for (int k = 0; k < kFound && k < cnt; ++k)
            mine[k] = kept[k];
          offs(i + 1) = cnt;
        });
    const int total = counts_to_offsets(offs, n, "cgdem::kernels::nl_scan");
    num_slots = total;
    if (static_cast<int>(neighbors.extent(0)) < total + kSpareSlots) reserve(capacity_for(total));
    const auto neigh = neighbors;
    const auto hist = history;
    const auto c_offs = carry_offsets;
    const auto c_partner = carry_partner;
    const auto c_hist = carry_history;
    const auto gaps = gap;
    Kokkos::parallel_for(
        "cgdem::kernels::nl_fill", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          // The pairs touching now first, in visiting order: the force pass branches on touching per
          // slot, and T..TN..N costs one mispredicted branch per particle where the visiting order's mix
          // costs about one per touching pair (contacts outlive a build). The others follow, ordered below.
          int front = offs(i), back = offs(i + 1);
          const Real ri = radius(i);
          const auto place = [&](int j, Real dist2) {
            const Real touch = ri + radius(j);
            const float g = gap_beyond_reach(dist2, touch + reach);
            if (dist2 < touch * touch) {
              gaps(front) = g;
              neigh(front++) = j;
            } else {
              gaps(--back) = g;
              neigh(back) = j;
            }
          };
          const int cnt = back - front;
          if (cnt <= kFound) {
            const Vec3 xi = load3(position, i);
            const int* mine = found_j.data() + std::size_t(i) * kFound;
            for (int k = 0; k < cnt; ++k)
              place(mine[k], norm2(domain.minimum_image(load3(position, mine[k]) - xi)));
          } else {
            visit(i, place);
          }
          for (int a = front, b = offs(i + 1) - 1; a < b; ++a, --b) { // the others back in visiting order
            const int t = neigh(a);
            neigh(a) = neigh(b);
            neigh(b) = t;
            const float tg = gaps(a);
            gaps(a) = gaps(b);
            gaps(b) = tg;
          }
          // Then the others within reach (gap -1) before those beyond, by increasing gap; stable, so that
          // equal gaps keep the visiting order.
          for (int a = front + 1; a < offs(i + 1); ++a) {
            const int j = neigh(a);
            const float g = gaps(a);
            int b = a;
            for (; b > front && gaps(b - 1) > g; --b) {
              neigh(b) = neigh(b - 1);
              gaps(b) = gaps(b - 1);
            }
            neigh(b) = j;
            gaps(b) = g;
          }
          if (H > 0) { // a plain if: CUDA's device lambdas cannot first capture inside `if constexpr`
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
              // A pair beyond reach now starts over, as the force pass would make it on this step.
              if (gaps(s) >= 0) found = -1;
              Real h[H > 0 ? H : 1];
              for (int k = 0; k < H; ++k)
                h[k] = found >= 0 ? c_hist(found, k) : 0;
              if (flipped) Law::flip_history(h);
              for (int k = 0; k < H; ++k)
                hist(s, k) = static_cast<ForceReal>(h[k]);
            }
          }
        });
    partner_slots_indexed = false;
  }

  // The slot's gap (see `gap`) from the pair's squared separation at the build and R_i + R_j + reach:
  // rounded down (float, and 1e-6 of it less, 1e-12 of the reach distance less), so that skipping
  // while gap > 2 D never skips a pair the exact test would find within reach. A coincident pair
  // (separation 0, which the force pass treats as beyond reach) is never skipped.
  KOKKOS_INLINE_FUNCTION static float gap_beyond_reach(Real dist2, Real reach_ij) {
    if (dist2 < reach_ij * reach_ij || dist2 == 0) return -1;
    const Real g = (math::sqrt(dist2) - reach_ij - 1e-12 * reach_ij) * (1 - 1e-6);
    return g > 0 ? static_cast<float>(g) : 0.0f;
  }

  // The gaps of the slots as they are (a restored list) from the positions at its build. A particle
  // whose slots are not in the order the force pass stops on (a list written by an older version) gets
  // -1 on all of them: never skipped, so the restored run stays right, only slower until the next build.
  template <class PositionView, class RadiusView>
  void compute_gaps(const Domain& domain, const PositionView& position, const RadiusView& radius, Real reach,
                    int n) {
    const auto offs = offsets;
    const auto neigh = neighbors;
    const auto gaps = gap;
    Kokkos::parallel_for(
        "cgdem::kernels::nl_gaps", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const Vec3 xi = load3(position, i);
          bool ordered = true;
          for (int s = offs(i); s < offs(i + 1); ++s) {
            const int j = neigh(s);
            const Real dist2 = norm2(domain.minimum_image(load3(position, j) - xi));
            gaps(s) = gap_beyond_reach(dist2, radius(i) + radius(j) + reach);
            if (s > offs(i) && gaps(s) < gaps(s - 1)) ordered = false;
          }
          if (!ordered)
            for (int s = offs(i); s < offs(i + 1); ++s)
              gaps(s) = -1;
        });
    Kokkos::fence();
  }

  // CSR offsets in place (kernels/cell_grid.hpp).
  static int counts_to_offsets(const Kokkos::View<int*, Mem>& counts, int n, const char* label) {
    return kernels::counts_to_offsets<ExecSpace>(counts, n, label);
  }

  // Index, for each particle, the slots where it is the partner (partner_slots, ascending), and size the
  // slots' terms: what the pairs path of the force pass needs beyond the half list. Once per build. The
  // slots are counted per partner with atomics and placed at an atomic cursor, in whatever order the
  // threads arrive, then each particle's few are sorted: the index is the same on every backend and thread
  // count.
  void index_partner_slots(int n) {
    if (partner_slots_indexed) return;
    if (static_cast<int>(partner_offsets.extent(0)) != n + 1) {
      partner_offsets = Kokkos::View<int*, Mem>("cgdem::kernels::nl_partner_offsets", n + 1);
      partner_fill = Kokkos::View<int*, Mem>("cgdem::kernels::nl_partner_fill", n);
    }
    const int capacity = static_cast<int>(neighbors.extent(0));
    if (static_cast<int>(slot_active.extent(0)) < capacity) {
      slot_force = Kokkos::View<Real* [3], Mem>("cgdem::kernels::nl_slot_force", capacity);
      slot_torque = Kokkos::View<Real* [3], Mem>("cgdem::kernels::nl_slot_torque", capacity);
      slot_torque_j = Kokkos::View<Real* [3], Mem>("cgdem::kernels::nl_slot_torque_j", capacity);
      slot_active = Kokkos::View<int*, Mem>("cgdem::kernels::nl_slot_active", capacity);
    }
    if (static_cast<int>(partner_slots.extent(0)) < num_slots)
      partner_slots = Kokkos::View<int*, Mem>("cgdem::kernels::nl_partner_slots", capacity);
    const auto offs = offsets;
    const auto neigh = neighbors;
    const auto p_offs = partner_offsets;
    const auto fill = partner_fill;
    const auto p_slots = partner_slots;
    Kokkos::deep_copy(ExecSpace(), p_offs, 0);
    Kokkos::parallel_for(
        "cgdem::kernels::nl_partner_count", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          for (int s = offs(i); s < offs(i + 1); ++s)
            Kokkos::atomic_fetch_add(&p_offs(neigh(s) + 1), 1);
        });
    counts_to_offsets(p_offs, n, "cgdem::kernels::nl_partner_scan");
    Kokkos::parallel_for(
        "cgdem::kernels::nl_partner_start", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int j) { fill(j) = p_offs(j); });
    Kokkos::parallel_for(
        "cgdem::kernels::nl_partner_fill", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          for (int s = offs(i); s < offs(i + 1); ++s)
            p_slots(Kokkos::atomic_fetch_add(&fill(neigh(s)), 1)) = s;
        });
    Kokkos::parallel_for(
        "cgdem::kernels::nl_partner_sort", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int j) {
          for (int a = p_offs(j) + 1; a < p_offs(j + 1); ++a) {
            const int s = p_slots(a);
            int b = a;
            for (; b > p_offs(j) && p_slots(b - 1) > s; --b)
              p_slots(b) = p_slots(b - 1);
            p_slots(b) = s;
          }
        });
    Kokkos::fence();
    partner_slots_indexed = true;
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

  // The capacity allocated for `slots` slots: 1/16 headroom, so that the list of a settled or slowly
  // changing scene is rebuilt in place, while the slot arrays (index and history, ~28 B per slot) stay
  // close to the count.
  // A list that outgrows it is reallocated at the next build, which refills every slot anyway.
  // At least kSpareSlots beyond the last slot: the force pass reads the index two slots ahead without
  // testing for the end (ContactForces, a prefetch hint).
  static constexpr int kSpareSlots = 2;
  static int capacity_for(int slots) { return slots + slots / 16 + 64; }
  static_assert(64 >= kSpareSlots, "capacity_for keeps the spare slots");

  // Room for `capacity` slots (growth only, never per step).
  void reserve(int capacity) {
    if (static_cast<int>(neighbors.extent(0)) < capacity) {
      Kokkos::View<int*, Mem> grown("cgdem::kernels::nl_neighbors", capacity);
      HistoryView grown_history("cgdem::kernels::nl_history", H > 0 ? capacity : 0, H);
      neighbors = grown;
      history = grown_history;
      gap = Kokkos::View<float*, Mem>("cgdem::kernels::nl_gap", capacity);
    }
  }
};

} // namespace cgdem::kernels
