#pragma once
// Pair and wall forces, deterministic without atomics on the forces. Two ways to share the pairs among
// threads (`Path`), the same physics:
//   blocks (the host's default): the particles are split into blocks of cells, coloured so that two blocks
//     of one colour never write to the same particle (ForceBlocks, kernels/force_blocks.hpp); every particle
//     receives from the blocks that write to it in the order of their colours (a barrier after each colour,
//     or each block waiting for its neighbours of earlier colours: `Schedule`), and from a block in its fixed
//     particle order. Each particle evaluates the law once for each pair it owns in the half list, in
//     batches of kLanes pairs side by side (SIMD), and adds the force and torque to itself and the reaction
//     to the partner. Few blocks, each walked by one thread: right for a few CPU cores.
//   pairs (a device's default; on the host an option): one thread per particle evaluates the pairs it owns,
//     one at a time, and stores each pair's force and torques in the pair's slot; then one thread per
//     particle sums its slots as owner, its slots as partner (NeighborList::partner_slots, the full list's
//     other half), and its walls, in that fixed order. As many threads as particles, no thread writes to
//     another's particle, and each particle's sum has one order on every backend and thread count.
// A pair's law is evaluated from the same inputs by the same code (pair_state) on both paths, so each pair
// gets the same bits and the same history; only the order of a particle's sum differs, so the two paths
// agree to round-off and each is bitwise the same on every backend and thread count. The partner gets
// exactly the negated force on both: momentum is conserved to round-off.
#include <sched.h>
#include <type_traits>
#include <Kokkos_Core.hpp>
#include "core/domain.hpp"
#include "core/particle_store.hpp"
#include "core/wall.hpp"
#include "kernels/mesh_walls.hpp"
#include "kernels/force_blocks.hpp"
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

  // What the law sees of a pair: from the separation d (i to j), the relative velocity dv = v_i - v_j, the
  // spins, radii and masses (the scale factors are the caller's). Both paths build it here, so a pair gets
  // the same bits on either.
  KOKKOS_INLINE_FUNCTION static models::PairState pair_state(const models::PairParameters& pp, const Vec3& d,
                                                             const Vec3& dv, const Vec3& wi, const Vec3& wj,
                                                             Real ri, Real rj, Real mi, Real mj, Real dt) {
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
    return st;
  }

  // A listed pair's separation d (i to j, across a seam only for an owner near one) and whether the law must
  // see the pair this step. Not when it is out of reach of every interaction: its history (`row`, H values)
  // starts over, cleared here (most listed pairs are not touching and already zero: read first, write only
  // when needed). Nor when it is apart with nothing kept from an earlier contact: no component acts across
  // a gap unless it bonded at contact and keeps that in its history (models/contact_law.hpp); most pairs
  // within a liquid bridge's reach are such. The overlap is computed as pair_state computes it, so the
  // screen agrees with the law to the last bit. Both paths screen their slots here.
  KOKKOS_INLINE_FUNCTION static bool in_play(const Domain& domain, bool near_seam, const Vec3& xi,
                                             const Vec3& xj, Real ri, Real rj, Real reach, ForceReal* row,
                                             Vec3& d) {
    // Far from a seam, a partner whose plain separation is off by a box is beyond reach either way.
    d = near_seam ? domain.minimum_image(xj - xi) : xj - xi;
    const Real dist2 = norm2(d);
    const Real reach_ij = (ri + rj) + reach;
    if (dist2 >= reach_ij * reach_ij || dist2 == 0) {
      if constexpr (H > 0)
        for (int k = 0; k < H; ++k)
          if (row[k] != 0) row[k] = 0;
      return false;
    }
    if constexpr (H > 0)
      if ((ri + rj) - math::sqrt(dist2) < 0) {
        bool kept = false;
        for (int k = 0; k < H; ++k)
          kept = kept || row[k] != 0;
        return kept;
      }
    return true;
  }

  // One particle's walls: adds their forces and torques on it to f and t (from the first wall part to the
  // last), keeps each part's contact history, stores each part's force when `wall_force` has extent, and
  // returns how many parts it touches. Both paths call it.
  struct WallTerms {
    Kokkos::View<PlacedWall*, Mem> walls; // placed at this step's time by the caller
    ParamTable wall_params;
    Kokkos::View<ForceReal**, Kokkos::LayoutRight, Mem> wall_history;
    Kokkos::View<Real* [3], Mem> wall_force;
    MeshGeometry<Mem> mesh; // the mesh parts' triangles and each particle's candidates
    Law law;
    Real dt = 0, reach = 0;
    int nwalls = 0;
    bool record = false;

    // The law between particle i and a wall surface at distance ri - overlap along `normal` (unit, from the
    // particle toward the surface), whose surface moves at surface_velocity; `wh` its H history values.
    KOKKOS_FORCEINLINE_FUNCTION models::ContactForce
    surface(const PlacedWall& wall, const Vec3& normal, Real overlap, const Vec3& surface_velocity,
            ForceReal* wh, const Vec3& vi, const Vec3& wi, Real ri, Real mi, Real scale_i, int mat_i) const {
      Real h[H > 0 ? H : 1];
      models::PairState st;
      st.normal = normal;
      st.overlap = overlap;
      const models::PairParameters& pp = wall_params(mat_i, wall.material);
      st.lever_share = pp.lever_share;
      // As for a pair: the spin part (w_i x l_i n) is tangential already.
      const Vec3 dv = vi - surface_velocity;
      st.overlap_rate = dot(dv, normal);
      st.tangential_velocity =
          (dv - st.overlap_rate * normal) + cross(wi, models::lever_arm(ri, st) * normal);
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
      return cf;
    }

    KOKKOS_FORCEINLINE_FUNCTION int operator()(int i, const Vec3& xi, const Vec3& vi, const Vec3& wi, Real ri,
                                               Real mi, Real scale_i, int mat_i, Vec3& f, Vec3& t) const {
      int contacts = 0;
      for (int w = 0; w < nwalls; ++w) {
        const PlacedWall& wall = walls(w);
        ForceReal* const wh = wall_history.extent(1) > 0 ? &wall_history(i, wall.history_offset) : nullptr;
        Vec3 fw, mw; // the force on the particle; the moment of its reaction about the part's base
        if (wall.type == Wall::Mesh) {
          contacts += mesh_terms(i, w, wall, wh, xi, vi, wi, ri, mi, scale_i, mat_i, fw, mw, t);
          f += fw;
          if (record) {
            store3(wall_force, 2 * (i * nwalls + w), fw);
            store3(wall_force, 2 * (i * nwalls + w) + 1, mw);
          }
          continue;
        }
        const WallContact wc = wall_contact(wall, xi, ri);
        if (!wc.reachable || wc.overlap <= -reach) {
          // Most particles are far from most walls and their history is already zero: read first.
          if constexpr (H > 0)
            for (int k = 0; k < H; ++k)
              if (wh[k] != 0) wh[k] = 0;
        } else {
          const models::ContactForce cf =
              surface(wall, wc.normal, wc.overlap, wall_surface_velocity(wall, wc), wh, vi, wi, ri, mi,
                      scale_i, mat_i);
          fw = cf.force;
          f += cf.force;
          t += cf.torque;
          contacts += cf.active ? 1 : 0;
          if (record) mw = cross(xi + (ri - wc.overlap) * wc.normal - wall.base, -cf.force);
        }
        if (record) {
          store3(wall_force, 2 * (i * nwalls + w), fw);
          store3(wall_force, 2 * (i * nwalls + w) + 1, mw);
        }
      }
      return contacts;
    }

    // Particle i against mesh part w (kernels/mesh_walls.hpp): its force into fw, the moment of the
    // reaction on the mesh about its base into mw, its torque added to t; returns the contacts.
    KOKKOS_INLINE_FUNCTION int mesh_terms(int i, int w, const PlacedWall& wall, ForceReal* slots,
                                          const Vec3& xi, const Vec3& vi, const Vec3& wi, Real ri, Real mi,
                                          Real scale_i, int mat_i, Vec3& fw, Vec3& mw, Vec3& t) const {
      constexpr int S = MeshSlots::kSlots, W = MeshSlots::kHeader + H;
      // The nearest point on each of this part's candidates within reach, offered to the filter faces
      // first (a second walk over the candidates for edges and vertices: no cap on how many are near).
      // On-plane and coincidence within 1e-4 of the radius: above the rounding of vertices stored as
      // floats (binary STL), far below any real second contact.
      MeshContactFilter filter(1e-4 * ri);
      const Real within = ri + reach;
      for (int pass = 0; pass < 2; ++pass)
        for (int s = mesh.candidate_start(i); s < mesh.candidate_start(i + 1); ++s) {
          const int tr = mesh.candidates(s);
          if (mesh.triangle_part(tr) != w) continue;
          const Vec3 a = mesh.vertex(mesh.triangles(tr, 0)), b = mesh.vertex(mesh.triangles(tr, 1)),
                     c = mesh.vertex(mesh.triangles(tr, 2));
          TrianglePoint p = closest_on_triangle(xi, a, b, c);
          const Vec3 toward = xi - p.point;
          const Real d2 = norm2(toward);
          if (d2 >= within * within || !(d2 > 0)) continue;
          if (acts_as_face(p, toward, triangle_normal(a, b, c))) p.feature = TrianglePoint::Face;
          if ((p.feature == TrianglePoint::Face) != (pass == 0)) continue;
          filter.offer(p, (1 / math::sqrt(d2)) * toward, tr);
        }
      // Slots: by triangle, then by last step's contact point, then a free one.
      int slot_of[MeshContactFilter::kMax];
      bool taken[S] = {};
      for (int k = 0; k < filter.n; ++k) {
        slot_of[k] = -1;
        for (int s = 0; s < S; ++s)
          if (!taken[s] && slots[s * W] == ForceReal(filter.tag[k] + 1)) {
            slot_of[k] = s;
            taken[s] = true;
            break;
          }
      }
      const Real match2 = 0.01 * ri * ri; // within 0.1 radius: the same contact, moved on
      for (int k = 0; k < filter.n; ++k) {
        if (slot_of[k] >= 0) continue;
        for (int s = 0; s < S; ++s) {
          if (taken[s] || slots[s * W] == 0) continue;
          const Vec3 was{Real(slots[s * W + 1]), Real(slots[s * W + 2]), Real(slots[s * W + 3])};
          if (norm2(was - filter.point[k]) < match2) {
            slot_of[k] = s;
            taken[s] = true;
            break;
          }
        }
      }
      for (int k = 0; k < filter.n; ++k) {
        if (slot_of[k] >= 0) continue;
        for (int s = 0; s < S; ++s)
          if (!taken[s] && slots[s * W] == 0) {
            slot_of[k] = s;
            taken[s] = true;
            break;
          }
      }
      // Slots no contact took are cleared; a taken slot keeps its history for its new contact.
      for (int s = 0; s < S; ++s)
        if (!taken[s] && slots[s * W] != 0)
          for (int k = 0; k < W; ++k)
            slots[s * W + k] = 0;
      int contacts = 0;
      for (int k = 0; k < filter.n; ++k) {
        const Vec3 p = filter.point[k];
        const Vec3 d = p - xi;
        const Real dist = norm(d);
        if (!(dist > 0)) continue;
        ForceReal spare[H > 0 ? H : 1] = {};
        ForceReal* row = slot_of[k] >= 0 ? &slots[slot_of[k] * W] : nullptr;
        if (row) {
          row[0] = ForceReal(filter.tag[k] + 1);
          row[1] = ForceReal(p.x);
          row[2] = ForceReal(p.y);
          row[3] = ForceReal(p.z);
        }
        const Vec3 rel = p - wall.base;
        const Vec3 arm = rel - dot(rel, wall.axis) * wall.axis;
        const Vec3 surface_velocity = wall.velocity + wall.spin * cross(wall.axis, arm);
        const models::ContactForce cf =
            surface(wall, (1 / dist) * d, ri - dist, surface_velocity, row ? row + MeshSlots::kHeader : spare,
                    vi, wi, ri, mi, scale_i, mat_i);
        fw += cf.force;
        mw += cross(rel, -cf.force);
        t += cf.torque;
        contacts += cf.active ? 1 : 0;
      }
      return contacts;
    }
  };

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
  // Which way the pairs are shared among threads (see the top of this file). A device runs pairs: its
  // thousands of threads need thousands of independent tasks, which the blocks are not.
  enum class Path { blocks, pairs };
  static constexpr Path kDefaultPath = kHostThreads ? Path::blocks : Path::pairs;

  // What the pass reads besides the store, the list and the law.
  struct Inputs {
    Domain domain;
    ParamTable pair_params, wall_params;                              // materials x materials
    Kokkos::View<PlacedWall*, Mem> walls;                             // placed at this step's time
    Kokkos::View<ForceReal**, Kokkos::LayoutRight, Mem> wall_history; // N x the parts' history widths
    // Extent > 0: per particle and wall part (row 2 (i x parts + w)) the force the particle feels from the
    // part, and (the next row) the moment of the reaction on the part about its base, for the reductions.
    Kokkos::View<Real* [3], Mem> wall_force;
    MeshGeometry<Mem> mesh; // the mesh parts' triangles where they are now, and each particle's candidates
    Real dt = 0;
    Real reach = 0;            // the law's longest interaction range beyond contact
    Real max_radius = 0;       // of the particles in the store
    Real max_displacement = 0; // the largest displacement of a particle since the list was built (so far)
  };

  // Evaluate all contact forces into store.force / store.torque (and in.wall_force when it has extent).
  // `cleared`: the store's forces, torques and contact counts are zero already (the integrator's pass
  // zeroed them); otherwise the blocks path zeroes them first (the pairs path writes every sum whole).
  // The pairs path indexes the list's partner slots first if this build has not (NeighborList).
  // Returns whether blocks.block_worker now holds which worker ran each block (the ordered schedule).
  template <class NeighborListT>
  static bool compute(const ParticleStore<Mem>& p, NeighborListT& nl, const ForceBlocks<ExecSpace>& blocks,
                      const Inputs& in, Law law, int n, bool cleared = false, Path path = kDefaultPath,
                      Schedule schedule = kDefaultSchedule) {
    if (path == Path::pairs) {
      nl.index_partner_slots(n);
      compute_by_pairs(p, nl, in, law, n);
      return false;
    }
    return compute_by_blocks(p, nl, blocks, in, law, n, cleared, schedule);
  }

  // The blocks path (see the top of this file).
  template <class NeighborListT>
  static bool compute_by_blocks(const ParticleStore<Mem>& p, const NeighborListT& nl,
                                const ForceBlocks<ExecSpace>& blocks, const Inputs& in, Law law, int n,
                                bool cleared, Schedule schedule) {
    const Domain domain = in.domain;
    const ParamTable pair_params = in.pair_params;
    const Real dt = in.dt, reach = in.reach, max_radius = in.max_radius,
               max_displacement = in.max_displacement;
    const WallTerms wall_terms = wall_terms_of(in, law);
    const auto offsets = nl.offsets;
    const auto neighbors = nl.neighbors;
    const auto history = nl.history;
    const auto gaps = nl.gap;
    // No particle moved more than max_displacement since the build: a slot whose gap at the build is
    // larger than twice that is still beyond reach, and so are the slots after it (NeighborList::gap).
    // A skipped slot keeps its history as it was: zero, as long as the caller's max_displacement never
    // shrinks between builds (a pair that came within reach is then never skipped again).
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
    const auto block_offsets = blocks.block_offsets;
    const auto block_members = blocks.block_members;
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
        models::PairState st = pair_state(pp, d, dv, wi, wj, b.ri[l], b.rj[l], b.mi[l], b.mj[l], dt);
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
        Vec3 d;
        if (!in_play(domain, near_seam, xi, load3(p.position, j), ri, rj, reach, history_row(s), d)) continue;
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
      const int wall_contacts = wall_terms(i, xi, vi, wi, ri, mi, scale_i, mat_i, f, t);
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
        const int nblocks = blocks.colour_begin[blocks.kColours];
        const auto after_offsets = blocks.block_after_offsets;
        const auto after = blocks.block_after;
        const auto done = blocks.block_done;
        const auto claimed = blocks.blocks_claimed;
        const auto worker_of = blocks.block_worker;
        Kokkos::parallel_for(
            "cgdem::kernels::contact_forces_unclaim", Kokkos::RangePolicy<ExecSpace>(0, nblocks),
            KOKKOS_LAMBDA(int b) {
              done(b) = 0;
              if (b == 0) claimed() = 0;
            });
        // One iteration per worker, each claiming blocks until none is left.
        Kokkos::parallel_for(
            "cgdem::kernels::contact_forces", Kokkos::RangePolicy<ExecSpace>(0, ExecSpace::concurrency()),
            KOKKOS_LAMBDA(int worker) {
              for (int b = Kokkos::atomic_fetch_add(&claimed(), 1); b < nblocks;
                   b = Kokkos::atomic_fetch_add(&claimed(), 1)) {
                worker_of(b) = worker;
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
        return true;
      }
    // The colours in turn; inside one, the blocks in parallel in dynamic chunks (the work per block varies
    // with its contacts and walls, and which thread takes a block does not change any sum).
    using DynamicRange = Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>;
    for (int colour = 0; colour < blocks.kColours; ++colour) {
      const int first = blocks.colour_begin[colour], last = blocks.colour_begin[colour + 1];
      if (first == last) continue;
      Kokkos::parallel_for("cgdem::kernels::contact_forces", DynamicRange(first, last).set_chunk_size(1),
                           block_forces);
    }
    return false;
  }

  // The pairs path (see the top of this file): a pass over the owners writes each pair's terms to its slot
  // (NeighborList::slot_force, slot_torque, slot_torque_j, slot_active), a pass over the particles sums them.
  template <class NeighborListT>
  static void compute_by_pairs(const ParticleStore<Mem>& p, const NeighborListT& nl, const Inputs& in,
                               Law law, int n) {
    const Domain domain = in.domain;
    const ParamTable pair_params = in.pair_params;
    const Real dt = in.dt, reach = in.reach;
    const WallTerms wall_terms = wall_terms_of(in, law);
    const auto offsets = nl.offsets;
    const auto neighbors = nl.neighbors;
    const auto history = nl.history;
    const auto gaps = nl.gap;
    const auto slot_force = nl.slot_force;
    const auto slot_torque = nl.slot_torque;
    const auto slot_torque_j = nl.slot_torque_j;
    const auto slot_active = nl.slot_active;
    const auto partner_offsets = nl.partner_offsets;
    const auto partner_slots = nl.partner_slots;
    // As on the blocks path: slots still beyond reach since the build are skipped, by both passes alike.
    const Real skip_beyond = 2 * in.max_displacement * (1 + 1e-6);
    const Domain::Interior interior = domain.interior((2 * in.max_radius + reach) * (1 + 1e-9));
    const bool one_material = pair_params.extent(0) == 1 && pair_params.extent(1) == 1;
    KOKKOS_ASSERT(H == 0 || history.stride(0) == static_cast<std::size_t>(H));
    auto history_row = [=] KOKKOS_FUNCTION(int s) {
      return history.data() + static_cast<std::size_t>(s) * H;
    };

    Kokkos::parallel_for(
        "cgdem::kernels::pair_terms", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const Vec3 xi = load3(p.position, i);
          const Vec3 vi = load3(p.velocity, i);
          const Vec3 wi = load3(p.angular_velocity, i);
          const Real ri = p.radius(i);
          const Real mi = p.mass(i);
          const int mat_i = one_material ? 0 : p.material(i);
          const bool near_seam = !interior.contains(xi);
          for (int s = offsets(i); s < offsets(i + 1); ++s) {
            if (gaps(s) > skip_beyond) break;
            const int j = neighbors(s);
            const Real rj = p.radius(j);
            Vec3 d;
            models::ContactForce cf; // nothing, for a pair the law need not see
            if (in_play(domain, near_seam, xi, load3(p.position, j), ri, rj, reach, history_row(s), d)) {
              const models::PairParameters& pp = pair_params(mat_i, one_material ? 0 : p.material(j));
              models::PairState st = pair_state(pp, d, vi - load3(p.velocity, j), wi,
                                                load3(p.angular_velocity, j), ri, rj, mi, p.mass(j), dt);
              if (kScaleFactors) {
                st.scale_i = p.scale_factor(i);
                st.scale_j = p.scale_factor(j);
              }
              Real h[H > 0 ? H : 1];
              for (int k = 0; k < H; ++k)
                h[k] = history_row(s)[k];
              cf = law(pp, st, h);
              for (int k = 0; k < H; ++k)
                history_row(s)[k] = static_cast<ForceReal>(h[k]);
            }
            store3(slot_force, s, cf.force);
            store3(slot_torque, s, cf.torque);
            store3(slot_torque_j, s, cf.torque_j);
            slot_active(s) = cf.active;
          }
        });

    Kokkos::parallel_for(
        "cgdem::kernels::pair_sums", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          Vec3 f, t;
          int contacts = 0;
          for (int s = offsets(i); s < offsets(i + 1); ++s) {
            if (gaps(s) > skip_beyond) break;
            f += load3(slot_force, s);
            t += load3(slot_torque, s);
            contacts += slot_active(s);
          }
          // The reactions, as the blocks path adds them: a pair that exerts nothing (a listed, non-touching
          // pair of a law without reach) leaves the partner alone.
          for (int k = partner_offsets(i); k < partner_offsets(i + 1); ++k) {
            const int s = partner_slots(k);
            if (gaps(s) > skip_beyond) continue;
            const Vec3 fs = load3(slot_force, s);
            if (slot_active(s) || norm2(fs) > 0) {
              f -= fs;
              t += load3(slot_torque_j, s);
              contacts += slot_active(s);
            }
          }
          const int wall_contacts =
              wall_terms(i, load3(p.position, i), load3(p.velocity, i), load3(p.angular_velocity, i),
                         p.radius(i), p.mass(i), p.scale_factor(i), one_material ? 0 : p.material(i), f, t);
          store3(p.force, i, f);
          store3(p.torque, i, t);
          p.contacts(i) = contacts;
          p.wall_contacts(i) = wall_contacts;
        });
  }

  static WallTerms wall_terms_of(const Inputs& in, const Law& law) {
    WallTerms w;
    w.walls = in.walls;
    w.wall_params = in.wall_params;
    w.wall_history = in.wall_history;
    w.wall_force = in.wall_force;
    w.law = law;
    w.dt = in.dt;
    w.reach = in.reach;
    w.nwalls = static_cast<int>(in.walls.extent(0));
    w.mesh = in.mesh;
    w.record = in.wall_force.extent(0) > 0;
    return w;
  }
};

} // namespace cgdem::kernels
