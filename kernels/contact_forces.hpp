#pragma once
// Pair and wall forces, deterministic without atomics and without a second pass over the pairs:
//   - the particles are split into blocks of cells, coloured so that two blocks of one colour never
//     write to the same particle (NeighborList::build_blocks); every particle receives from the blocks
//     that write to it in the order of their colours (a barrier after each colour, or each block waiting
//     for its neighbours of earlier colours: `Schedule`), and from a block in its fixed particle order;
//   - each particle evaluates the law once for each pair it owns in the half list and for each wall, and
//     adds the force and torque to itself and the reaction (-force, the partner's torque) to the partner.
// Every particle's sum therefore has a fixed order (colour, then block order), the same on every backend
// and thread count, and the partner gets exactly the negated force: momentum is conserved to round-off.
// Nothing is stored per slot but the contact history.
#include <sched.h>
#include <type_traits>
#include <Kokkos_Core.hpp>
#include "core/domain.hpp"
#include "core/particle_store.hpp"
#include "core/wall.hpp"
#include "models/contact_law.hpp"

namespace cgdem::kernels {

template <class ExecSpace, class Law>
struct ContactForces {
  using Mem = typename ExecSpace::memory_space;
  using ParamTable = Kokkos::View<models::PairParameters**, Mem>;
  static constexpr int H = Law::history_size;
  // Pairs evaluated side by side (see `evaluate`): two AVX2 vectors of doubles, one AVX-512 vector.
  static constexpr int kLanes = 8;
  // Whether the law reads the particles' coarse-graining factors (PairState::scale_i/j); a law that does
  // not say is assumed to.
  template <class L, class = void>
  struct ReadsScaleFactors : std::true_type {};
  template <class L>
  struct ReadsScaleFactors<L, std::void_t<decltype(L::reads_scale_factors)>>
      : std::bool_constant<L::reads_scale_factors> {};
  static constexpr bool kScaleFactors = ReadsScaleFactors<Law>::value;
  // Lane l of a batch's three rows of a vector (x, y, z rows of kLanes each).
  using LaneRows = Real[3][kLanes];
  KOKKOS_INLINE_FUNCTION static void put_lane(LaneRows& rows, int l, const Vec3& v) {
    rows[0][l] = v.x;
    rows[1][l] = v.y;
    rows[2][l] = v.z;
  }
  KOKKOS_INLINE_FUNCTION static Vec3 lane(const LaneRows& rows, int l) {
    return {rows[0][l], rows[1][l], rows[2][l]};
  }

  // A batch: the pairs (owner i, partner j, slot s), all of one pair of materials (a pair of another starts
  // a new batch) so that the law's parameters are the same in every lane, and what the law needs of them,
  // copied in by the list's walk: the separation as the list saw it, the relative velocity, spins, radii,
  // masses, scale factors and the slot's history. The lanes then read only these rows, which the compiler
  // loads as vectors (gathering from the particle store inside the loop it does not vectorize). At class
  // scope: CUDA's device lambdas take no function-local types as parameters.
  struct PairBatch {
    int i[kLanes], j[kLanes], slot[kLanes];
    int material_i = 0, material_j = 0;
    LaneRows d, dv, wi, wj;
    Real ri[kLanes], rj[kLanes], mi[kLanes], mj[kLanes], scale_i[kLanes], scale_j[kLanes];
    Real h[H > 0 ? H : 1][kLanes];
    int n = 0;
  };

  // How the blocks share the threads. Both give every particle its terms in the same order (colour, then
  // the block's own order), so the same bits.
  //   by_colour: a colour's blocks in parallel, then a barrier before the next colour. Portable; but a
  //     thread that finishes its share of a colour waits for the other's last block (2 threads, 50k bed:
  //     the pass's wall time ~10 % above half its busy time, with the busy time shared evenly).
  //   by_neighbours: the threads claim the blocks one by one in the colours' order, and a block starts
  //     as soon as its neighbours of earlier colours (NeighborList::block_after, the only blocks that
  //     write to its particles) are done, so the colours overlap. A block waits only for blocks claimed
  //     before it, whose threads never wait for it: no deadlock when all workers run at once, as host
  //     threads do (a GPU's threads need not: by_colour there).
  enum class Schedule { by_colour, by_neighbours };
  static constexpr bool kHostThreads = std::is_same<Mem, Kokkos::HostSpace>::value;
  static constexpr Schedule kDefaultSchedule = kHostThreads ? Schedule::by_neighbours : Schedule::by_colour;

  // What the pass reads besides the store, the list and the law.
  struct Inputs {
    Domain domain;
    ParamTable pair_params, wall_params;                              // materials x materials
    Kokkos::View<PlacedWall*, Mem> walls;                             // placed at this step's time
    Kokkos::View<ForceReal**, Kokkos::LayoutRight, Mem> wall_history; // N x (wall parts x H)
    // Extent > 0: the force each particle feels from each wall part is stored there too (N x wall parts,
    // for the wall reductions).
    Kokkos::View<Real* [3], Mem> wall_force;
    Real dt = 0;
    Real reach = 0;            // the law's longest interaction range beyond contact
    Real max_radius = 0;       // of the particles in the store
    Real max_displacement = 0; // the largest displacement of a particle since the list was built
  };

  // Evaluate all contact forces into store.force / store.torque (and in.wall_force when it has extent).
  // `cleared`: the store's forces, torques and contact counts are zero already (the integrator's pass
  // zeroed them); otherwise this zeroes them first.
  template <class NeighborListT>
  static void compute(const ParticleStore<Mem>& p, const NeighborListT& nl, const Inputs& in, Law law, int n,
                      bool cleared = false, Schedule schedule = kDefaultSchedule) {
    const Domain domain = in.domain;
    const ParamTable pair_params = in.pair_params, wall_params = in.wall_params;
    const auto walls = in.walls;
    const auto wall_history = in.wall_history;
    const auto wall_force = in.wall_force;
    const Real dt = in.dt, reach = in.reach, max_radius = in.max_radius,
               max_displacement = in.max_displacement;
    const int nwalls = static_cast<int>(walls.extent(0));
    const bool record_wall_force = wall_force.extent(0) > 0;
    const auto offsets = nl.offsets;
    const auto neighbors = nl.neighbors;
    const auto history = nl.history;
    const auto gaps = nl.gap;
    // No particle moved more than max_displacement since the build: a slot whose gap at the build is
    // larger than twice that is still beyond reach, and so are the slots after it (NeighborList::gap).
    const Real skip_beyond = 2 * max_displacement * (1 + 1e-6);
    // A slot's history row, H apart (like load3, without the View's runtime stride).
    KOKKOS_ASSERT(H == 0 || history.stride(0) == static_cast<std::size_t>(H));
    auto history_row = [=] KOKKOS_FUNCTION(int s) {
      return history.data() + static_cast<std::size_t>(s) * H;
    };
    // Particles farther than any pair can interact (2 R_max + reach, a hair more for rounding) from the
    // periodic faces: their partners within reach are stored on the same side of every seam, so the
    // separation is the plain difference, the one minimum_image would return. Most of a periodic bed.
    const Domain::Interior interior = domain.interior((2 * max_radius + reach) * (1 + 1e-9));
    const auto block_offsets = nl.block_offsets;
    const auto block_members = nl.block_members;
    // One material (most scenes): no partner's material to fetch.
    const bool one_material = pair_params.extent(0) == 1 && pair_params.extent(1) == 1;

    // Every particle receives from its partners before or after its own turn: start from zero.
    if (!cleared)
      Kokkos::parallel_for(
          "cgdem::kernels::clear_forces", Kokkos::RangePolicy<ExecSpace>(0, n),
          KOKKOS_LAMBDA(int i) { clear_force_sums(p, i); });

    // The pairs within reach are evaluated in batches of kLanes, one law evaluation per lane in a loop
    // the compiler turns into SIMD instructions (a contact's chain of roots and divisions is longer than
    // the core looks ahead, so one contact at a time leaves it waiting; eight side by side keep it busy;
    // perf/README.md). IEEE arithmetic is lane-wise exact and there is no fused multiply-add, so a lane
    // gives bitwise what the same law gives alone: the batching changes no result but the order in which
    // a particle's sum receives its terms, which is fixed by the block's order on every backend.
    // Evaluate a full or partly full batch and add each lane's force and torque to its two particles in lane
    // order. A partly full batch's spare lanes repeat lane 0 (their results are dropped), so the loop always
    // runs kLanes wide.
    auto evaluate = [=] KOKKOS_FUNCTION(PairBatch & b) {
      for (int l = b.n; l < kLanes; ++l) {
        for (int k = 0; k < 3; ++k) {
          b.d[k][l] = b.d[k][0];
          b.dv[k][l] = b.dv[k][0];
          b.wi[k][l] = b.wi[k][0];
          b.wj[k][l] = b.wj[k][0];
        }
        b.ri[l] = b.ri[0];
        b.rj[l] = b.rj[0];
        b.mi[l] = b.mi[0];
        b.mj[l] = b.mj[0];
        if constexpr (kScaleFactors) {
          b.scale_i[l] = b.scale_i[0];
          b.scale_j[l] = b.scale_j[0];
        }
        for (int k = 0; k < H; ++k)
          b.h[k][l] = b.h[k][0];
      }
      LaneRows out_force, out_torque, out_torque_j;
      int out_active[kLanes]; // not bool: a byte per lane would ask for 32 lanes per vector
      // By value: the lanes read a handful of its fields, each a constant of the loop.
      const models::PairParameters pp = pair_params(b.material_i, b.material_j);
      for (int l = 0; l < kLanes; ++l) {
        const Vec3 d = lane(b.d, l);
        const Vec3 dv = lane(b.dv, l);
        const Vec3 wi = lane(b.wi, l);
        const Vec3 wj = lane(b.wj, l);
        const Real ri = b.ri[l], rj = b.rj[l], mi = b.mi[l], mj = b.mj[l];
        const Real dist = math::sqrt(norm2(d));
        models::PairState st;
        st.normal = (1.0 / dist) * d;
        st.overlap = (ri + rj) - dist;
        st.lever_share = pp.lever_share;
        // Velocity of i's contact point relative to j's, the lever arms (models::lever_arm) l_i along +n and
        // l_j along -n: (v_i + w_i x l_i n) - (v_j - w_j x l_j n) = (v_i - v_j) + (l_i w_i + l_j w_j) x n.
        // The spin part is tangential already, so only the centres' relative velocity loses its normal part.
        st.overlap_rate = dot(dv, st.normal);
        st.tangential_velocity =
            (dv - st.overlap_rate * st.normal) +
            cross(models::lever_arm(ri, st) * wi + models::lever_arm(rj, st) * wj, st.normal);
        st.relative_rotation = wi - wj;
        st.omega_i = wi;
        st.omega_j = wj;
        st.radius_i = ri;
        st.radius_j = rj;
        st.radius_eff = ri * rj / (ri + rj);
        st.mass_eff = mi * mj / (mi + mj);
        st.volume_i = (4.0 / 3.0) * math::pi * ri * ri * ri;
        st.volume_j = (4.0 / 3.0) * math::pi * rj * rj * rj;
        st.dt = dt;
        if constexpr (kScaleFactors) {
          st.scale_i = b.scale_i[l];
          st.scale_j = b.scale_j[l];
        }
        Real h[H > 0 ? H : 1];
        for (int k = 0; k < H; ++k)
          h[k] = b.h[k][l];
        const models::ContactForce cf = law(pp, st, h);
        for (int k = 0; k < H; ++k)
          b.h[k][l] = h[k];
        put_lane(out_force, l, cf.force);
        put_lane(out_torque, l, cf.torque);
        put_lane(out_torque_j, l, cf.torque_j);
        out_active[l] = cf.active;
      }
      for (int l = 0; l < b.n; ++l) {
        const int i = b.i[l], j = b.j[l];
        if (H > 0) // plain: CUDA device lambdas cannot first capture (history_row) inside `if constexpr`
          for (int k = 0; k < H; ++k)
            history_row(b.slot[l])[k] = static_cast<ForceReal>(b.h[k][l]);
        const Vec3 f = lane(out_force, l);
        store3(p.force, i, load3(p.force, i) + f);
        store3(p.torque, i, load3(p.torque, i) + lane(out_torque, l));
        // The reaction on j; a pair that exerts nothing (a listed, non-touching pair of a law without
        // reach) leaves j alone.
        if (out_active[l] || norm2(f) > 0) {
          store3(p.force, j, load3(p.force, j) - f);
          store3(p.torque, j, load3(p.torque, j) + lane(out_torque_j, l));
          if (out_active[l]) {
            p.contacts(i) += 1;
            p.contacts(j) += 1;
          }
        }
      }
      b.n = 0;
    };

    // One particle's pairs (into the batch) and walls (at once); writes to itself and its partners only.
    auto particle_forces = [=] KOKKOS_FUNCTION(int i, PairBatch& batch) {
      const Vec3 xi = load3(p.position, i);
      const Vec3 vi = load3(p.velocity, i);
      const Vec3 wi = load3(p.angular_velocity, i);
      const Real ri = p.radius(i);
      const Real mi = p.mass(i);
      const Real scale_i = p.scale_factor(i);
      const int mat_i = one_material ? 0 : p.material(i);
      const bool near_seam = !interior.contains(xi);

      const int slot_end = offsets(i + 1);
      for (int s = offsets(i); s < slot_end; ++s) {
        if (gaps(s) > skip_beyond) break;
        const int j = neighbors(s);
        // The partner two slots ahead: its position, velocities, radius, mass, and the force and torque
        // the reaction is added to, are seven scattered cache lines; without the hint each slot started by
        // waiting for them when the law ran one pair at a time (perf/README.md; with the batches, four
        // slots ahead measured the same as two). No test for the end of i's slots: the list keeps spare slots
        // beyond the last (NeighborList::kSpareSlots), a hint never faults whatever index a slot past i's
        // holds, and a hint for another particle's partner costs less than the branch, mispredicted once per
        // particle.
        static_assert(NeighborListT::kSpareSlots >= 2, "the index two slots ahead is read unguarded");
        const int ahead = neighbors(s + 2);
        math::prefetch(row3(p.position, ahead));
        math::prefetch(row3(p.velocity, ahead));
        math::prefetch(row3(p.angular_velocity, ahead));
        math::prefetch(p.radius.data() + ahead);
        math::prefetch(p.mass.data() + ahead);
        math::prefetch(row3(p.force, ahead));
        math::prefetch(row3(p.torque, ahead));
        const Real rj = p.radius(j);
        // Far from a seam, a partner whose plain separation is off by a box is beyond reach either way.
        const Vec3 stored = load3(p.position, j) - xi;
        const Vec3 d = near_seam ? domain.minimum_image(stored) : stored;
        const Real dist2 = norm2(d);
        const Real reach_ij = (ri + rj) + reach;
        if (dist2 >= reach_ij * reach_ij || dist2 == 0) {
          // Out of reach of every interaction: the pair's history (if any) starts over. Most listed
          // pairs are not touching and already zero: read first, write only when needed.
          if (H > 0) // plain, as above
            for (int k = 0; k < H; ++k)
              if (history_row(s)[k] != 0) history_row(s)[k] = 0;
          continue;
        }
        // Apart, with nothing kept from an earlier contact: no component acts across a gap unless it
        // bonded at contact and keeps that in its history (models/contact_law.hpp), so the pair is not worth
        // a lane. Most pairs within a liquid bridge's reach are such. The overlap is computed as the lane
        // computes it, so the screen agrees with the law to the last bit.
        if constexpr (H > 0)
          if ((ri + rj) - math::sqrt(dist2) < 0) {
            bool kept = false;
            for (int k = 0; k < H; ++k)
              kept = kept || history_row(s)[k] != 0;
            if (!kept) continue;
          }
        const int mat_j = one_material ? 0 : p.material(j);
        if (batch.n > 0 && (batch.material_i != mat_i || batch.material_j != mat_j)) evaluate(batch);
        if (batch.n == 0) {
          batch.material_i = mat_i;
          batch.material_j = mat_j;
        }
        const int l = batch.n++;
        batch.i[l] = i;
        batch.j[l] = j;
        batch.slot[l] = s;
        const Vec3 dv = vi - load3(p.velocity, j);
        const Vec3 wj = load3(p.angular_velocity, j);
        put_lane(batch.d, l, d);
        put_lane(batch.dv, l, dv);
        put_lane(batch.wi, l, wi);
        put_lane(batch.wj, l, wj);
        batch.ri[l] = ri;
        batch.rj[l] = rj;
        batch.mi[l] = mi;
        batch.mj[l] = p.mass(j);
        if constexpr (kScaleFactors) {
          batch.scale_i[l] = scale_i;
          batch.scale_j[l] = p.scale_factor(j);
        }
        for (int k = 0; k < H; ++k)
          batch.h[k][l] = history_row(s)[k];
        if (batch.n == kLanes) evaluate(batch);
      }

      Vec3 f, t;
      int wall_contacts = 0;
      Real h[H > 0 ? H : 1];
      for (int w = 0; w < nwalls; ++w) {
        const PlacedWall& wall = walls(w); // placed at this step's time by the caller
        const WallContact wc = wall_contact(wall, xi, ri);
        ForceReal* const wh = H > 0 ? &wall_history(i, w * H) : nullptr; // this wall's H values
        Vec3 fw;
        if (!wc.reachable || wc.overlap <= -reach) {
          // Most particles are far from most walls and their history is already zero: read first.
          if constexpr (H > 0)
            for (int k = 0; k < H; ++k)
              if (wh[k] != 0) wh[k] = 0;
        } else {
          const Vec3 surface_velocity = wall_surface_velocity(wall, wc);
          models::PairState st;
          st.normal = wc.normal;
          st.overlap = wc.overlap;
          const models::PairParameters& pp = wall_params(mat_i, wall.material);
          st.lever_share = pp.lever_share;
          // As for a pair: the spin part (w_i x l_i n) is tangential already.
          const Vec3 dv = vi - surface_velocity;
          st.overlap_rate = dot(dv, wc.normal);
          st.tangential_velocity =
              (dv - st.overlap_rate * wc.normal) + cross(wi, models::lever_arm(ri, st) * wc.normal);
          st.relative_rotation = wi;
          st.omega_i = wi;
          st.radius_i = ri;
          st.radius_j = 0;
          st.radius_eff = ri;
          st.mass_eff = mi;
          st.volume_i = (4.0 / 3.0) * math::pi * ri * ri * ri;
          st.volume_j = 0;
          st.dt = dt;
          st.scale_i = scale_i;
          st.scale_j = 0;
          if constexpr (H > 0)
            for (int k = 0; k < H; ++k)
              h[k] = wh[k];
          const models::ContactForce cf = law(pp, st, h);
          if constexpr (H > 0)
            for (int k = 0; k < H; ++k)
              wh[k] = static_cast<ForceReal>(h[k]);
          fw = cf.force;
          f += cf.force;
          t += cf.torque;
          wall_contacts += cf.active ? 1 : 0;
        }
        if (record_wall_force) store3(wall_force, i * nwalls + w, fw);
      }
      store3(p.force, i, load3(p.force, i) + f);
      store3(p.torque, i, load3(p.torque, i) + t);
      p.wall_contacts(i) = wall_contacts;
    };

    auto block_forces = [=] KOKKOS_FUNCTION(int b) {
      PairBatch batch;
      for (int m = block_offsets(b); m < block_offsets(b + 1); ++m)
        particle_forces(block_members(m), batch);
      if (batch.n > 0) evaluate(batch);
    };
    if constexpr (kHostThreads)
      if (schedule == Schedule::by_neighbours) {
        const int nblocks = nl.colour_begin[nl.kColours];
        const auto after_offsets = nl.block_after_offsets;
        const auto after = nl.block_after;
        const auto done = nl.block_done;
        const auto claimed = nl.blocks_claimed;
        Kokkos::parallel_for(
            "cgdem::kernels::contact_forces_unclaim", Kokkos::RangePolicy<ExecSpace>(0, nblocks),
            KOKKOS_LAMBDA(int b) {
              done(b) = 0;
              if (b == 0) claimed() = 0;
            });
        // One iteration per worker, each claiming blocks until none is left.
        Kokkos::parallel_for(
            "cgdem::kernels::contact_forces", Kokkos::RangePolicy<ExecSpace>(0, ExecSpace::concurrency()),
            KOKKOS_LAMBDA(int) {
              for (int b = Kokkos::atomic_fetch_add(&claimed(), 1); b < nblocks;
                   b = Kokkos::atomic_fetch_add(&claimed(), 1)) {
                // Spin, then leave the core to others (a machine running more threads than cores).
                for (int k = after_offsets(b); k < after_offsets(b + 1); ++k)
                  for (int spins = 0; Kokkos::atomic_fetch_add(&done(after(k)), 0) == 0; ++spins)
                    if (spins > 1000) sched_yield();
                Kokkos::memory_fence(); // the neighbours' forces, seen before this block adds to them
                block_forces(b);
                Kokkos::memory_fence();
                Kokkos::atomic_exchange(&done(b), 1);
              }
            });
        return;
      }
    // The colours in turn; inside one, the blocks in parallel in dynamic chunks (the work per block varies
    // with its contacts and walls, and which thread takes a block does not change any sum).
    using DynamicRange = Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>;
    for (int colour = 0; colour < nl.kColours; ++colour) {
      const int first = nl.colour_begin[colour], last = nl.colour_begin[colour + 1];
      if (first == last) continue;
      Kokkos::parallel_for("cgdem::kernels::contact_forces", DynamicRange(first, last).set_chunk_size(1),
                           block_forces);
    }
  }
};

} // namespace cgdem::kernels
