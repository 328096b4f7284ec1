#pragma once
// Verlet neighbour list in CSR form, HALF list: each pair {i, j} is stored once, under the particle with
// the lower store index, so each contact law is evaluated once per pair. The owner adds the reaction to
// the partner directly; the blocks and colours built here make that race-free and deterministic
// (build_blocks; kernels/contact_forces.hpp).
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
// their squared separation as the force pass computes it. A functor, not a generic lambda: CUDA's device
// lambdas cannot be generic.
template <class PositionView, class RadiusView>
struct PartnerVisitor {
  Domain domain;
  CellGrid grid;
  PositionView position;
  RadiusView radius;
  Kokkos::View<const int*, typename PositionView::memory_space> cell_of, start, order;
  Real extra_cutoff;
  Real max_radius; // of any particle: bounds the cut-off of i's pairs, to skip cells beyond it

  template <class F>
  KOKKOS_INLINE_FUNCTION void operator()(int i, F&& f) const {
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
          // A cell's particles are in index order: a cell whose last is not above i holds no partner of
          // i (in a store sorted by cell, the half of the stencil before i's own cell).
          const int first = start(cell), last = start(cell + 1);
          if (first == last || order(last - 1) <= i) continue;
          for (int k = first; k < last; ++k) {
            const int j = order(k);
            if (j <= i) continue;
            const Vec3 d = domain.minimum_image(load3(position, j) - xi);
            const Real cut = ri + radius(j) + extra_cutoff, dist2 = norm2(d);
            if (dist2 < cut * cut) f(j, dist2);
          }
        }
      }
    }
  }
};

// A block's particles in cell order (z, y, then x; a cell's in index order): each z layer of the block
// (whole x rows) is one contiguous run [from, to) of the bins, passed to f(from, to).
template <class BoxView, class StartView>
struct BlockRuns {
  BoxView box;
  StartView start;
  int nx, ny;

  template <class F>
  KOKKOS_INLINE_FUNCTION void operator()(int blk, F&& f) const {
    for (int z = box(blk, 2); z < box(blk, 3); ++z)
      f(start(nx * (box(blk, 0) + ny * z)), start(nx * (box(blk, 1) + ny * z)));
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
  // The force pass's colouring (build_blocks): blocks of cells, listed colour by colour, and their
  // particles in cell order.
  static constexpr int kColours = 4;
  Kokkos::View<int*, Mem> block_offsets; // blocks + 1
  Kokkos::View<int*, Mem> block_members; // n
  int colour_begin[kColours + 1] = {};   // blocks [colour_begin[c], colour_begin[c + 1]) have colour c
  // For the force pass's ordered schedule (ContactForces): each block's neighbours of earlier colours, the
  // only blocks that may write to a particle it writes to (CSR over the blocks).
  Kokkos::View<int*, Mem> block_after_offsets; // blocks + 1
  Kokkos::View<int*, Mem> block_after;
  // The ordered schedule's state during a pass: which blocks are done, how many are claimed.
  Kokkos::View<int*, Mem> block_done;
  Kokkos::View<int, Mem> blocks_claimed{"cgdem::kernels::nl_blocks_claimed"};
  int listed_strips[3] = {}; // the y and z strip counts the blocks were ordered for (0: not yet)
  std::vector<int> block_strip_y, block_strip_z; // host: each block's strips, in the claim order
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
    return (offsets.span() + neighbors.span() + block_offsets.span() + block_members.span() +
            block_after_offsets.span() + block_after.span() + block_done.span() + carry_offsets.span() +
            found.span() + carry_partner.span() + partner_offsets.span() + partner_slots.span() +
            partner_fill.span() + slot_active.span()) *
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
    const PartnerVisitor<PositionView, RadiusView> visit{domain, grid,  position,     radius,    cell_of,
                                                         start,  order, extra_cutoff, max_radius};

    // The stencil is walked once: the count pass keeps each particle's first kFound partners, and the fill
    // pass takes them from there (their separations recomputed, the same bits as the visit's); only a
    // particle with more partners is visited again.
    if (static_cast<int>(found.extent(0)) < n * kFound)
      found = Kokkos::View<int*, Mem>("cgdem::kernels::nl_found", std::size_t(n) * kFound);
    const auto found_j = found;
    Kokkos::parallel_for(
        "cgdem::kernels::nl_count", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          int cnt = 0;
          int* mine = found_j.data() + std::size_t(i) * kFound;
          visit(i, [&](int j, Real) {
            if (cnt < kFound) mine[cnt] = j;
            ++cnt;
          });
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
    build_blocks(domain, grid, bins, n);
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

  // Strips along one axis: about five cells wide, so that a block keeps most of its particles' partners
  // and the colours do not each sweep the whole store (two-cell strips were 9-18 % slower than the old
  // gather at 50k-200k, eight-cell ones 5-15 % faster, five-cell ones as fast on 1 thread and up to 4 %
  // faster on 2: more blocks to share), but at least four where the axis has room. Never narrower than
  // two cells (the colouring's condition). A periodic axis needs an even count (or one strip), so that
  // the last strip and the first, which touch, get different colours. An open axis gets an even count too
  // where its cells allow: with an odd one the colours of the odd strips have half as many blocks as the
  // others (50k bed: 3 z strips gave colours of 6, 6, 3 and 3 blocks, and 3 blocks on two threads leave
  // one idle a third of the time). The count depends on the cells only, never on the thread count.
  static int strip_count(int cells, bool periodic) {
    int strips = cells / 5;
    const int at_least = cells / 2 < 4 ? cells / 2 : 4;
    if (strips < at_least) strips = at_least;
    if (strips < 1) strips = 1;
    if (strips > 1 && strips % 2 == 1) {
      if (periodic || cells / (strips + 1) < 2)
        --strips;
      else
        ++strips;
    }
    return strips;
  }

  // The colouring of the force pass. The cells are at least a cut-off wide, so a listed pair sits in the
  // same or neighbouring cells (in the bins used for this build). Cut y and z into strips of >= 2 cells
  // over the occupied cells (a settled bed is wide, not tall); a block is one y strip by one z strip, whole
  // x rows, which the spatial sort (z, y, x) keeps contiguous in the store (cutting x too was 15 % slower
  // at 200k). A block's particles reach one cell into the neighbouring strips, and with strips >= 2 cells
  // wide, the two neighbours of a strip (same parity) reach different cells. So two blocks whose strips
  // have the same parities on both axes never write to the same particle: 4 colours, run one after the
  // other, each colour's blocks in parallel. `bins` must be the bins of the build (after a restart: of
  // position_at_build).
  void build_blocks(const Domain& domain, const CellGrid& grid, const CellBins<ExecSpace>& bins, int n) {
    partner_slots_indexed = false; // called last by every build and restore: the slots have changed
    const int nx = grid.dims[0], ny = grid.dims[1];
    // Strip k of axis a (1: y, 2: z): cells [edge(a, k), edge(a, k + 1)) of the occupied range [lo, hi],
    // the outer strips extended to the domain's ends. A periodic axis: all of it (its strips pair up
    // across the seam).
    int lo[3] = {0, 0, 0}, hi[3] = {nx - 1, ny - 1, grid.dims[2] - 1}, strips[3] = {1, 1, 1};
    const auto cell_of = bins.cell_of_particle;
    for (int a = 1; a < 3; ++a) {
      if (!domain.periodic[a] && n > 0) {
        const int stride = a == 1 ? nx : nx * ny, cells = grid.dims[a];
        typename Kokkos::MinMax<int>::value_type range;
        Kokkos::parallel_reduce(
            "cgdem::kernels::nl_block_range", Kokkos::RangePolicy<ExecSpace>(0, n),
            KOKKOS_LAMBDA(int i, typename Kokkos::MinMax<int>::value_type& r) {
              const int c = (cell_of(i) / stride) % cells;
              if (c < r.min_val) r.min_val = c;
              if (c > r.max_val) r.max_val = c;
            },
            Kokkos::MinMax<int>(range));
        lo[a] = range.min_val;
        hi[a] = range.max_val;
      }
      strips[a] = strip_count(hi[a] - lo[a] + 1, domain.periodic[a]);
    }
    auto edge = [&](int a, int k) {
      if (k == 0) return 0;
      if (k == strips[a]) return grid.dims[a];
      return lo[a] + k * (hi[a] - lo[a] + 1) / strips[a];
    };
    order_blocks(domain, strips);
    const int nblocks = strips[1] * strips[2];
    // Host: each block's cells (y0, y1, z0, z1) in the claim order (once per build).
    Kokkos::View<int* [4], Mem> box("cgdem::kernels::nl_block_box", nblocks);
    auto hbox = Kokkos::create_mirror_view(box);
    for (int b = 0; b < nblocks; ++b) {
      hbox(b, 0) = edge(1, block_strip_y[b]);
      hbox(b, 1) = edge(1, block_strip_y[b] + 1);
      hbox(b, 2) = edge(2, block_strip_z[b]);
      hbox(b, 3) = edge(2, block_strip_z[b] + 1);
    }
    Kokkos::deep_copy(box, hbox);
    if (static_cast<int>(block_offsets.extent(0)) != nblocks + 1)
      block_offsets = Kokkos::View<int*, Mem>("cgdem::kernels::nl_block_offsets", nblocks + 1);
    if (static_cast<int>(block_members.extent(0)) < n)
      block_members = Kokkos::View<int*, Mem>("cgdem::kernels::nl_block_members", n);
    const auto start = bins.cell_start;
    const auto order = bins.order;
    const auto b_offs = block_offsets;
    const auto members = block_members;
    const BlockRuns<decltype(box), decltype(start)> for_each_run{box, start, nx, ny};
    Kokkos::parallel_for(
        "cgdem::kernels::nl_block_count", Kokkos::RangePolicy<ExecSpace>(0, nblocks), KOKKOS_LAMBDA(int blk) {
          int cnt = 0;
          for_each_run(blk, [&](int from, int to) { cnt += to - from; });
          b_offs(blk + 1) = cnt;
        });
    counts_to_offsets(b_offs, nblocks, "cgdem::kernels::nl_block_scan");
    Kokkos::parallel_for(
        "cgdem::kernels::nl_block_fill", Kokkos::RangePolicy<ExecSpace>(0, nblocks), KOKKOS_LAMBDA(int blk) {
          int m = b_offs(blk);
          for_each_run(blk, [&](int from, int to) {
            for (int k = from; k < to; ++k)
              members(m++) = order(k);
          });
        });
    Kokkos::fence();
  }

  // The blocks in the order the force pass claims them, colour by colour, and each block's neighbours of
  // earlier colours: the blocks whose strips are the same or next to its own on both axes (across the
  // seam of a periodic axis). Two blocks further apart never write to the same particle: each writes its
  // own cells and the one-cell rim around them, and a strip of at least two cells lies between them.
  // (Blocks of one colour are never neighbours, so the earlier ones are those of earlier colours.)
  // Within a colour the order changes no sum (its blocks share no particle) but decides how long a
  // thread of the ordered schedule waits: a colour's first blocks should not need the previous colour's
  // last ones, which are still running. So each colour after the first lists its blocks by the claim
  // position of their last neighbour, earliest first, and the first colour runs backwards so that its
  // last blocks lie at the low ends, away from where the next colours start. (A model of two threads
  // claiming blocks of equal work +-30 %: on the 50k bed's 6 x 4 strips the waiting falls from 1.4 % of
  // the work to 0, on the 200k bed's 12 x 4 from 0.9 % to 0.)
  // It all depends on the strip counts only: made again only when a build changes those.
  void order_blocks(const Domain& domain, const int strips[3]) {
    if (strips[1] == listed_strips[1] && strips[2] == listed_strips[2]) return;
    listed_strips[1] = strips[1];
    listed_strips[2] = strips[2];
    auto next_to = [&](int a, int s, int t) {
      const int d = s > t ? s - t : t - s;
      return d <= 1 || (domain.periodic[a] && d == strips[a] - 1);
    };
    auto neighbours = [&](int y, int z, int e) {
      return next_to(1, y, block_strip_y[e]) && next_to(2, z, block_strip_z[e]);
    };
    block_strip_y.clear();
    block_strip_z.clear();
    for (int colour = 0; colour < kColours; ++colour) {
      const int placed = static_cast<int>(block_strip_y.size());
      colour_begin[colour] = placed;
      struct Candidate {
        int y, z, last_neighbour;
      };
      std::vector<Candidate> blocks;
      for (int z = colour / 2; z < strips[2]; z += 2)
        for (int y = colour % 2; y < strips[1]; y += 2) {
          int last = -1;
          for (int e = 0; e < placed; ++e)
            if (neighbours(y, z, e)) last = e;
          blocks.push_back({y, z, last});
        }
      if (colour == 0)
        std::reverse(blocks.begin(), blocks.end());
      else
        std::stable_sort(blocks.begin(), blocks.end(), [](const Candidate& a, const Candidate& b) {
          return a.last_neighbour < b.last_neighbour;
        });
      for (const Candidate& c : blocks) {
        block_strip_y.push_back(c.y);
        block_strip_z.push_back(c.z);
      }
    }
    const int nblocks = static_cast<int>(block_strip_y.size());
    colour_begin[kColours] = nblocks;
    std::vector<int> offs(nblocks + 1, 0), after;
    for (int bl = 0; bl < nblocks; ++bl) {
      for (int e = 0; e < bl; ++e)
        if (neighbours(block_strip_y[bl], block_strip_z[bl], e)) after.push_back(e);
      offs[bl + 1] = static_cast<int>(after.size());
    }
    block_after_offsets = Kokkos::View<int*, Mem>("cgdem::kernels::nl_block_after_offsets", nblocks + 1);
    block_after = Kokkos::View<int*, Mem>("cgdem::kernels::nl_block_after", after.size());
    block_done = Kokkos::View<int*, Mem>("cgdem::kernels::nl_block_done", nblocks);
    auto h_offs = Kokkos::create_mirror_view(block_after_offsets);
    auto h_after = Kokkos::create_mirror_view(block_after);
    for (int bl = 0; bl <= nblocks; ++bl)
      h_offs(bl) = offs[bl];
    for (std::size_t k = 0; k < after.size(); ++k)
      h_after(k) = after[k];
    Kokkos::deep_copy(block_after_offsets, h_offs);
    Kokkos::deep_copy(block_after, h_after);
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
