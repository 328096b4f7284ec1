#pragma once
// The host force pass's schedule (kernels/contact_forces.hpp, Path::blocks): the particles cut into blocks
// of cells, the blocks coloured so that two blocks of one colour never write to the same particle, and
// for the ordered schedule each block's neighbours of earlier colours. Made from the cell bins of each
// neighbour-list build (or restore), independent of the list itself; the pairs path (the device's) does
// not use it.
#include <Kokkos_Core.hpp>
#include <algorithm>
#include <vector>
#include "core/domain.hpp"
#include "kernels/cell_grid.hpp"

namespace cgdem::kernels {

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

template <class ExecSpace>
struct ForceBlocks {
  using Mem = typename ExecSpace::memory_space;

  // Blocks of cells, listed colour by colour, and their particles in cell order.
  static constexpr int kColours = 4;
  Kokkos::View<int*, Mem> block_offsets; // blocks + 1
  Kokkos::View<int*, Mem> block_members; // n
  int colour_begin[kColours + 1] = {};   // blocks [colour_begin[c], colour_begin[c + 1]) have colour c
  // For the ordered schedule (ContactForces): each block's neighbours of earlier colours, the only blocks
  // that may write to a particle it writes to (CSR over the blocks).
  Kokkos::View<int*, Mem> block_after_offsets; // blocks + 1
  Kokkos::View<int*, Mem> block_after;
  // The ordered schedule's state during a pass: which blocks are done, how many are claimed.
  Kokkos::View<int*, Mem> block_done;
  Kokkos::View<int, Mem> blocks_claimed{"cgdem::kernels::blocks_claimed"};
  // Which worker of the ordered schedule ran each block on the last force pass, so that the integrator
  // can give each worker the particles whose forces it has just written (Integrator::kick_drift): on a
  // host those lines are still in the writer's core's cache. Valid while claims_recorded; a build clears it.
  Kokkos::View<int*, Mem> block_worker;
  bool claims_recorded = false;
  int listed_strips[3] = {}; // the y and z strip counts the blocks were ordered for (0: not yet)
  std::vector<int> block_strip_y, block_strip_z; // host: each block's strips, in the claim order

  std::size_t bytes() const {
    return (block_offsets.span() + block_members.span() + block_after_offsets.span() + block_after.span() +
            block_done.span() + block_worker.span()) *
           sizeof(int);
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
  void build(const Domain& domain, const CellGrid& grid, const CellBins<ExecSpace>& bins, int n) {
    claims_recorded = false;
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
            "cgdem::kernels::block_range", Kokkos::RangePolicy<ExecSpace>(0, n),
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
    Kokkos::View<int* [4], Mem> box("cgdem::kernels::block_box", nblocks);
    auto hbox = Kokkos::create_mirror_view(box);
    for (int b = 0; b < nblocks; ++b) {
      hbox(b, 0) = edge(1, block_strip_y[b]);
      hbox(b, 1) = edge(1, block_strip_y[b] + 1);
      hbox(b, 2) = edge(2, block_strip_z[b]);
      hbox(b, 3) = edge(2, block_strip_z[b] + 1);
    }
    Kokkos::deep_copy(box, hbox);
    if (static_cast<int>(block_offsets.extent(0)) != nblocks + 1)
      block_offsets = Kokkos::View<int*, Mem>("cgdem::kernels::block_offsets", nblocks + 1);
    if (static_cast<int>(block_members.extent(0)) < n)
      block_members = Kokkos::View<int*, Mem>("cgdem::kernels::block_members", n);
    const auto start = bins.cell_start;
    const auto order = bins.order;
    const auto b_offs = block_offsets;
    const auto members = block_members;
    const BlockRuns<decltype(box), decltype(start)> for_each_run{box, start, nx, ny};
    Kokkos::parallel_for(
        "cgdem::kernels::block_count", Kokkos::RangePolicy<ExecSpace>(0, nblocks), KOKKOS_LAMBDA(int blk) {
          int cnt = 0;
          for_each_run(blk, [&](int from, int to) { cnt += to - from; });
          b_offs(blk + 1) = cnt;
        });
    counts_to_offsets<ExecSpace>(b_offs, nblocks, "cgdem::kernels::block_scan");
    Kokkos::parallel_for(
        "cgdem::kernels::block_fill", Kokkos::RangePolicy<ExecSpace>(0, nblocks), KOKKOS_LAMBDA(int blk) {
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
    block_after_offsets = Kokkos::View<int*, Mem>("cgdem::kernels::block_after_offsets", nblocks + 1);
    block_after = Kokkos::View<int*, Mem>("cgdem::kernels::block_after", after.size());
    block_done = Kokkos::View<int*, Mem>("cgdem::kernels::block_done", nblocks);
    block_worker = Kokkos::View<int*, Mem>("cgdem::kernels::block_worker", nblocks);
    auto h_offs = Kokkos::create_mirror_view(block_after_offsets);
    auto h_after = Kokkos::create_mirror_view(block_after);
    for (int bl = 0; bl <= nblocks; ++bl)
      h_offs(bl) = offs[bl];
    for (std::size_t k = 0; k < after.size(); ++k)
      h_after(k) = after[k];
    Kokkos::deep_copy(block_after_offsets, h_offs);
    Kokkos::deep_copy(block_after, h_after);
  }
};

} // namespace cgdem::kernels
