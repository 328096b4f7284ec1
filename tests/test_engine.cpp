// Engine-level invariants: neighbour list against brute force (also after a reorder), history carried
// across rebuilds and reorders, momentum and energy conservation in closed periodic boxes.
#include <gtest/gtest.h>
#include <algorithm>
#include <array>
#include <limits>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include "core/domain.hpp"
#include "core/particle_store.hpp"
#include "kernels/neighbor_list.hpp"
#include "setup/materials.hpp"
#include "kernels/contact_forces.hpp"
#include "models/hertz_tsuji.hpp"
#include "models/mindlin_tangential.hpp"
#include "tests/test_support.hpp"

using namespace cgdem;
using namespace cgdem::testing;

namespace {

Scene periodic_scene(double box, const MaterialSpec& m, const std::string& tangential = "mindlin") {
  Scene s = basic_scene({m}, "hertz", tangential);
  s.domain.lo = {0, 0, 0};
  s.domain.hi = {box, box, box};
  s.domain.periodic = {true, true, true};
  return s;
}

// Neighbour sets by id from a checkpoint (which holds the half list exactly as the engine uses it:
// each pair once, under the particle with the lower store index).
std::map<std::int64_t, std::set<std::int64_t>> listed(const CheckpointData& c) {
  const auto& id = c.ints.at("id");
  const auto& off = c.ints.at("nl_offsets");
  const auto& nb = c.ints.at("nl_neighbors");
  std::map<std::int64_t, std::set<std::int64_t>> out;
  for (std::size_t i = 0; i < id.size(); ++i) {
    out[id[i]];
    for (auto k = off[i]; k < off[i + 1]; ++k) {
      EXPECT_GT(nb[k], static_cast<std::int64_t>(i)) << "a half list stores a pair under its lower index";
      EXPECT_TRUE(out[id[i]].insert(id[nb[k]]).second) << "duplicate neighbour";
      EXPECT_TRUE(out[id[nb[k]]].insert(id[i]).second) << "duplicate neighbour";
    }
  }
  return out;
}

std::map<std::int64_t, std::set<std::int64_t>> brute_force(const CheckpointData& c, double box, double skin) {
  const auto& id = c.ints.at("id");
  const auto& x = c.reals.at("position");
  const auto& r = c.reals.at("radius");
  std::map<std::int64_t, std::set<std::int64_t>> out;
  for (std::size_t i = 0; i < id.size(); ++i) {
    out[id[i]];
    for (std::size_t j = 0; j < id.size(); ++j) {
      if (i == j) continue;
      double d2 = 0;
      for (int a = 0; a < 3; ++a) {
        double d = x[3 * j + a] - x[3 * i + a];
        d -= box * std::round(d / box);
        d2 += d * d;
      }
      const double cut = r[i] + r[j] + skin;
      if (d2 < cut * cut) out[id[i]].insert(id[j]);
    }
  }
  return out;
}

using ListLaw = models::ContactLaw<models::HertzTsuji, models::NoAdhesion, models::MindlinTangential>;
using HostExec = Kokkos::DefaultHostExecutionSpace;

// A half list built directly (no engine) over a particle set whose radii are scaled by `swell`, with
// cells for radii up to swell x rmax.
struct BuiltList {
  Kokkos::View<double* [3], Kokkos::HostSpace> x;
  Kokkos::View<double*, Kokkos::HostSpace> r;
  kernels::NeighborList<HostExec, ListLaw> nl;
  kernels::ForceBlocks<HostExec> blocks;
};
BuiltList build_list(const ParticleSet& p, const Domain& domain, double skin, double swell, double rmax) {
  const int n = static_cast<int>(p.size());
  BuiltList b{Kokkos::View<double* [3], Kokkos::HostSpace>("x", n),
              Kokkos::View<double*, Kokkos::HostSpace>("r", n),
              {},
              {}};
  Kokkos::View<int*, Kokkos::HostSpace> identity("identity", n);
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a)
      b.x(i, a) = p.position[i][a];
    b.r(i) = swell * p.radius[i];
    identity(i) = i;
  }
  const kernels::CellGrid grid(domain, 2 * swell * rmax + skin, 1L << 20);
  kernels::CellBins<HostExec> bins;
  bins.build(grid, b.x, n);
  b.nl.build(domain, grid, bins, b.x, b.r, skin, swell * rmax, 0.0, n, identity, false);
  b.blocks.build(domain, grid, bins, n);
  return b;
}

} // namespace

TEST(NeighborList, EqualsBruteForceOnPolydispersePeriodicPacksAlsoAfterReorder) {
  const MaterialSpec m = material("glass", 2500, 5e6, 0.3, 0.9, 0.3);
  for (unsigned seed : {1u, 2u, 3u}) {
    const double box = 0.012, skin = 0.2e-3;
    ParticleSet p = random_periodic(1500, box, 0.25e-3, 1e-3, 2500, 0.5, seed); // size ratio 1:4
    auto engine = make(periodic_scene(box, m), p, 1e-6, "openmp", skin);
    CheckpointData c = engine->checkpoint();
    EXPECT_EQ(listed(c), brute_force(c, box, skin)) << "seed " << seed;
    engine->advance(50);
    engine->rebuild_neighbors(); // forced rebuild with a spatial reorder
    c = engine->checkpoint();
    EXPECT_NE(c.ints.at("id"), p.id) << "the reorder should have permuted the store";
    EXPECT_EQ(listed(c), brute_force(c, box, skin)) << "after reorder, seed " << seed;
  }
}

// The force pass adds each pair's reaction to the partner directly; it is race-free only if no two
// blocks of one colour write to the same particle (the block itself and its members' partners), and
// complete only if every particle is in exactly one block. Checked on packs whose cells do not divide
// evenly into strips: periodic on every axis (strips must pair up across the seam), open in z, a
// tall open column where the occupied range decides the strips, and a bed shape (6 x 4 strips, like the
// 50k bed's). And, for the schedule that lets the colours overlap, that a block's list of blocks to wait
// for holds every earlier one it shares a particle with, and that the claim order does not start a colour
// with a block that must wait for the previous colour's last one when it need not (the order of 6 x 4
// strips colour by colour, z then y, did).
TEST(NeighborList, ColouredBlocksNeverShareAParticleWithinAColour) {
  struct Case {
    double box;
    bool periodic_z;
    double fill_height; // fraction of the box height the particles occupy
  };
  for (const Case& c : {Case{0.0286, true, 1.0}, Case{0.0157, false, 1.0}, Case{0.0143, false, 0.3},
                        Case{0.034, false, 0.65}}) {
    ParticleSet p = random_periodic(2500, c.box, 0.2e-3, 0.5e-3, 2500, 0, 7);
    for (auto& x : p.position)
      x[2] *= c.fill_height;
    const int n = static_cast<int>(p.size());
    const Domain domain({0, 0, 0}, {c.box, c.box, c.box}, true, true, c.periodic_z);
    const BuiltList built = build_list(p, domain, 0.1e-3, 1.0, 0.5e-3);
    const auto& nl = built.nl;
    const auto& blocks = built.blocks;

    int blocks_with_particles = 0;
    std::vector<int> block_of(n, -1);
    for (int b = 0; b < blocks.colour_begin[blocks.kColours]; ++b) {
      blocks_with_particles += blocks.block_offsets(b + 1) > blocks.block_offsets(b) ? 1 : 0;
      for (int m = blocks.block_offsets(b); m < blocks.block_offsets(b + 1); ++m) {
        ASSERT_EQ(block_of[blocks.block_members(m)], -1) << "particle in two blocks";
        block_of[blocks.block_members(m)] = b;
      }
    }
    for (int i = 0; i < n; ++i)
      ASSERT_GE(block_of[i], 0) << "particle " << i << " in no block";
    EXPECT_GE(blocks_with_particles, 8) << "box " << c.box << ": too few blocks to share between threads";
    for (int colour = 0; colour < blocks.kColours; ++colour) {
      std::vector<int> writer(n, -1);
      for (int b = blocks.colour_begin[colour]; b < blocks.colour_begin[colour + 1]; ++b)
        for (int m = blocks.block_offsets(b); m < blocks.block_offsets(b + 1); ++m) {
          const int i = blocks.block_members(m);
          std::vector<int> written{i};
          for (int s = nl.offsets(i); s < nl.offsets(i + 1); ++s)
            written.push_back(nl.neighbors(s));
          for (int j : written) {
            ASSERT_TRUE(writer[j] == -1 || writer[j] == b)
                << "box " << c.box << ", colour " << colour << ": blocks " << writer[j] << " and " << b
                << " both write to particle " << j;
            writer[j] = b;
          }
        }
    }
    // The ordered schedule lets a block start once the blocks in its block_after list are done: every
    // earlier block that writes to a particle it writes to must be there.
    std::vector<std::vector<int>> writers(n);
    for (int b = 0; b < blocks.colour_begin[blocks.kColours]; ++b)
      for (int m = blocks.block_offsets(b); m < blocks.block_offsets(b + 1); ++m) {
        const int i = blocks.block_members(m);
        writers[i].push_back(b);
        for (int s = nl.offsets(i); s < nl.offsets(i + 1); ++s)
          writers[nl.neighbors(s)].push_back(b);
      }
    int waits = 0;
    for (int j = 0; j < n; ++j)
      for (int later : writers[j])
        for (int earlier : writers[j]) {
          if (earlier >= later) continue;
          const int* first = blocks.block_after.data() + blocks.block_after_offsets(later);
          const int* last = blocks.block_after.data() + blocks.block_after_offsets(later + 1);
          ASSERT_TRUE(std::find(first, last, earlier) != last)
              << "box " << c.box << ": blocks " << earlier << " and " << later << " both write to particle "
              << j << ", but " << later << " would not wait for " << earlier;
          ++waits;
        }
    EXPECT_GT(waits, 0);
    // The claim order: a colour's first block waits for the previous colour's last one (likely still
    // running when it is claimed) only where every block of the colour would.
    for (int colour = 1; colour < blocks.kColours; ++colour) {
      const int first = blocks.colour_begin[colour], end = blocks.colour_begin[colour + 1];
      if (first == end || blocks.colour_begin[colour - 1] == first) continue;
      auto waits_for_last = [&](int b) {
        const int* from = blocks.block_after.data() + blocks.block_after_offsets(b);
        const int* to = blocks.block_after.data() + blocks.block_after_offsets(b + 1);
        return std::find(from, to, first - 1) != to;
      };
      bool avoidable = false;
      for (int b = first; b < end; ++b)
        avoidable = avoidable || !waits_for_last(b);
      EXPECT_FALSE(avoidable && waits_for_last(first))
          << "box " << c.box << ", strips " << blocks.listed_strips[1] << " x " << blocks.listed_strips[2]
          << ": colour " << colour << " starts with a block that waits for the previous colour's last";
    }
  }
}

// The force pass branches per slot on touching; the build lists each particle's touching partners
// first so that branch turns once per particle. The set must stay the brute-force one (test above); here:
// the split, and the spare slots the force pass reads ahead into without a bounds test.
TEST(NeighborList, ListsTouchingPartnersFirstAndKeepsSpareSlots) {
  const double box = 0.012;
  ParticleSet p = random_periodic(1500, box, 0.25e-3, 0.5e-3, 2500, 0, 3);
  const int n = static_cast<int>(p.size());
  const Domain domain({0, 0, 0}, {box, box, box}, true, true, true);
  // Radii swollen by 10 %: a pack with touching and merely listed pairs.
  const BuiltList built = build_list(p, domain, 0.2e-3, 1.1, 0.5e-3);
  const auto& nl = built.nl;
  const auto& x = built.x;
  const auto& r = built.r;

  auto touching = [&](int i, int j) {
    const Vec3 d = domain.minimum_image(load3(x, j) - load3(x, i));
    return norm2(d) < (r(i) + r(j)) * (r(i) + r(j));
  };
  int touching_slots = 0, particles_with_both = 0;
  for (int i = 0; i < n; ++i) {
    bool seen_far = false, seen_touching = false;
    for (int s = nl.offsets(i); s < nl.offsets(i + 1); ++s) {
      const bool t = touching(i, nl.neighbors(s));
      ASSERT_FALSE(t && seen_far) << "particle " << i
                                  << ": a touching partner listed after a non-touching one";
      seen_far = seen_far || !t;
      seen_touching = seen_touching || t;
      touching_slots += t ? 1 : 0;
    }
    particles_with_both += seen_far && seen_touching ? 1 : 0;
  }
  EXPECT_GT(touching_slots, n / 4) << "the swollen pack should have many contacts";
  EXPECT_GT(particles_with_both, n / 8) << "the split is only tested where a list has both kinds";
  EXPECT_GE(static_cast<int>(nl.neighbors.extent(0)), nl.num_slots + nl.kSpareSlots);
}

// The force pass skips the slots whose gap at the build exceeds twice the largest displacement since
// (NeighborList::gap). Exact by construction: after every particle moved by up to D (up to half the skin,
// as between two builds), forces, torques, contact counts and histories with the skip equal those of
// the same pass told nothing may be skipped (D infinite), bitwise; and the gaps are sorted and never
// above the true gap.
TEST(NeighborList, SkippingPairsBeyondReachSinceTheBuildChangesNothing) {
  using Mem = Kokkos::HostSpace;
  const double box = 0.012, skin = 0.2e-3;
  ParticleSet ps = random_periodic(1500, box, 0.25e-3, 0.5e-3, 2500, 0.5, 11);
  const int n = static_cast<int>(ps.size());
  const Domain domain({0, 0, 0}, {box, box, box}, true, true, true);
  ParticleStore<Mem> p(n);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  double rmax = 0;
  for (int i = 0; i < n; ++i) {
    const double r = 1.1 * ps.radius[i]; // swollen: contacts and near misses
    rmax = std::max(rmax, r);
    p.radius(i) = r;
    p.mass(i) = 2500 * 4.0 / 3.0 * M_PI * r * r * r;
    p.inertia(i) = 0.4 * p.mass(i) * r * r;
    p.scale_factor(i) = 1;
    for (int a = 0; a < 3; ++a) {
      p.position(i, a) = ps.position[i][a];
      p.velocity(i, a) = u(rng);
      p.angular_velocity(i, a) = 100 * u(rng);
    }
  }
  Kokkos::View<int*, Mem> identity("identity", n);
  for (int i = 0; i < n; ++i)
    identity(i) = i;
  const kernels::CellGrid grid(domain, 2 * rmax + skin, 1L << 20);
  kernels::CellBins<HostExec> bins;
  bins.build(grid, p.position, n);
  kernels::NeighborList<HostExec, ListLaw> nl;
  nl.build(domain, grid, bins, p.position, p.radius, skin, rmax, 0.0, n, identity, false);
  kernels::ForceBlocks<HostExec> blocks;
  blocks.build(domain, grid, bins, n);
  Kokkos::deep_copy(p.position_at_build, p.position);

  // Gaps: -1 within reach, then non-decreasing, and never above the true gap.
  int beyond = 0;
  for (int i = 0; i < n; ++i)
    for (int s = nl.offsets(i); s < nl.offsets(i + 1); ++s) {
      const int j = nl.neighbors(s);
      const double dist = norm(domain.minimum_image(load3(p.position, j) - load3(p.position, i)));
      const double g = dist - p.radius(i) - p.radius(j);
      if (g < 0) {
        ASSERT_EQ(nl.gap(s), -1.0f);
        continue;
      }
      ++beyond;
      ASSERT_LE(nl.gap(s), g);
      ASSERT_GE(nl.gap(s), 0.999 * g - 1e-15);
      if (s > nl.offsets(i)) {
        ASSERT_LE(nl.gap(s - 1), nl.gap(s)) << "slots beyond reach sorted by gap";
      }
    }
  EXPECT_GT(beyond, n);

  // Every particle moves by up to D, in a random direction.
  const double D = 0.5 * skin;
  double moved = 0;
  for (int i = 0; i < n; ++i) {
    Vec3 step{u(rng), u(rng), u(rng)};
    step = (D * std::abs(u(rng)) / norm(step)) * step;
    store3(p.position, i, domain.wrap(load3(p.position, i) + step));
    moved = std::max(moved, norm(domain.minimum_image(load3(p.position, i) - load3(p.position_at_build, i))));
  }
  const MaterialSpec m = material("glass", 2500, 5e6, 0.3, 0.9, 0.3);
  Kokkos::View<models::PairParameters**, Mem> params("params", 1, 1);
  params(0, 0) = mix_pair(m, m, false, ContactSpec{});
  Kokkos::View<PlacedWall*, Mem> walls("walls", 0);
  Kokkos::View<ForceReal**, Kokkos::LayoutRight, Mem> wall_history("wall_history", n, 0);
  Kokkos::View<Real* [3], Mem> no_record("no_record", 0);
  Kokkos::View<ForceReal**, Kokkos::LayoutRight, Mem> history0("history0", nl.history.extent(0), 3);
  Kokkos::deep_copy(history0, nl.history);
  // A history the pass must carry (or zero, for pairs now apart): random on every slot within reach.
  for (int i = 0; i < n; ++i)
    for (int s = nl.offsets(i); s < nl.offsets(i + 1); ++s)
      if (nl.gap(s) < 0)
        for (int k = 0; k < 3; ++k)
          history0(s, k) = 1e-6 * u(rng);

  // One pass from history0 on the given backend's path; returns per particle its force and torque
  // (interleaved) and contact count, then every slot's history.
  auto run_pass = [&](auto exec, auto& list, const auto& list_blocks, double max_displacement, auto path,
                      auto schedule) {
    using Exec = decltype(exec);
    using PassOn = kernels::ContactForces<Exec, ListLaw>;
    Kokkos::deep_copy(list.history, history0);
    typename PassOn::Inputs in;
    in.domain = domain;
    in.pair_params = in.wall_params = params;
    in.walls = walls;
    in.wall_history = wall_history;
    in.wall_force = no_record;
    in.dt = 1e-6;
    in.max_radius = rmax;
    in.max_displacement = max_displacement;
    PassOn::compute(p, list, list_blocks, in, ListLaw{}, n, false, path, schedule);
    std::vector<double> out;
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        out.push_back(p.force(i, a));
        out.push_back(p.torque(i, a));
      }
      out.push_back(p.contacts(i));
    }
    for (std::size_t k = 0; k < list.history.span(); ++k)
      out.push_back(list.history.data()[k]);
    return out;
  };
  using Pass = kernels::ContactForces<HostExec, ListLaw>;
  auto pass = [&](double max_displacement, Pass::Path path = Pass::Path::blocks,
                  Pass::Schedule schedule = Pass::kDefaultSchedule) {
    return run_pass(HostExec(), nl, blocks, max_displacement, path, schedule);
  };
  const double everything = std::numeric_limits<double>::infinity();
  const std::vector<double> skipping = pass(moved), exhaustive = pass(everything);
  ASSERT_EQ(skipping.size(), exhaustive.size());
  int contacts = 0;
  for (int i = 0; i < n; ++i)
    contacts += p.contacts(i);
  EXPECT_GT(contacts, n / 2);
  for (std::size_t k = 0; k < skipping.size(); ++k)
    ASSERT_EQ(skipping[k], exhaustive[k]) << "entry " << k;
  // The two schedules of the blocks (a barrier per colour, or each block after its earlier neighbours)
  // give every particle its terms in the same order: the same bits, on however many threads run.
  for (const auto schedule : {Pass::Schedule::by_colour, Pass::Schedule::by_neighbours}) {
    const std::vector<double> scheduled = pass(moved, Pass::Path::blocks, schedule);
    for (std::size_t k = 0; k < skipping.size(); ++k)
      ASSERT_EQ(scheduled[k], skipping[k]) << "entry " << k << ", schedule " << static_cast<int>(schedule);
  }

  // The pairs path (each pair alone into its slot, then each particle sums its slots) evaluates the same
  // pairs from the same inputs: the same histories and contact counts, bitwise, and the same force and
  // torque sums up to their order (round-off of the largest term). Skipping changes nothing on it either,
  // and the Serial backend gives its bits.
  const std::vector<double> pairs = pass(moved, Pass::Path::pairs),
                            pairs_all = pass(everything, Pass::Path::pairs);
  ASSERT_EQ(pairs.size(), skipping.size());
  for (std::size_t k = 0; k < pairs.size(); ++k)
    ASSERT_EQ(pairs[k], pairs_all[k]) << "entry " << k;
  double force_scale = 0, torque_scale = 0;
  for (int k = 0; k < 7 * n; ++k)
    if (k % 7 < 6)
      (k % 2 == 0 ? force_scale : torque_scale) =
          std::max(k % 2 == 0 ? force_scale : torque_scale, std::abs(skipping[k]));
  ASSERT_GT(force_scale, 0);
  ASSERT_GT(torque_scale, 0);
  int different = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const bool sum = k < std::size_t(7 * n) && k % 7 < 6;
    if (!sum) {
      ASSERT_EQ(pairs[k], skipping[k])
          << (k < std::size_t(7 * n) ? "contact count of particle " : "history entry ")
          << (k < std::size_t(7 * n) ? k / 7 : k - 7 * n);
      continue;
    }
    const double scale = k % 2 == 0 ? force_scale : torque_scale;
    ASSERT_NEAR(pairs[k], skipping[k], 1e-13 * scale) << "particle " << k / 7 << ", entry " << k % 7;
    different += pairs[k] != skipping[k];
  }
  // Not a test that cannot fail: the sums do come in another order.
  EXPECT_GT(different, 0);
#ifdef KOKKOS_ENABLE_SERIAL
  {
    // The same list built on Serial from the positions at the build, then the pass from the moved ones.
    using SerialPass = kernels::ContactForces<Kokkos::Serial, ListLaw>;
    Kokkos::View<Real* [3], Mem> moved_position("moved", n);
    Kokkos::deep_copy(moved_position, p.position);
    Kokkos::deep_copy(p.position, p.position_at_build);
    kernels::CellBins<Kokkos::Serial> serial_bins;
    serial_bins.build(grid, p.position, n);
    kernels::NeighborList<Kokkos::Serial, ListLaw> serial_nl;
    serial_nl.build(domain, grid, serial_bins, p.position, p.radius, skin, rmax, 0.0, n, identity, false);
    Kokkos::deep_copy(p.position, moved_position);
    ASSERT_EQ(serial_nl.num_slots, nl.num_slots);
    const std::vector<double> serial =
        run_pass(Kokkos::Serial(), serial_nl, kernels::ForceBlocks<Kokkos::Serial>{}, moved,
                 SerialPass::Path::pairs, SerialPass::kDefaultSchedule);
    for (std::size_t k = 0; k < pairs.size(); ++k)
      ASSERT_EQ(serial[k], pairs[k]) << "entry " << k << ": Serial vs OpenMP, pairs path";
  }
#endif

  // A restored list gets its gaps from the positions at the build; a particle whose slots are not in the
  // order the pass stops on (an older checkpoint) must never be skipped.
  std::vector<float> built(nl.gap.data(), nl.gap.data() + nl.num_slots);
  int shuffled = -1;
  for (int i = 0; i < n && shuffled < 0; ++i)
    if (nl.offsets(i + 1) - nl.offsets(i) >= 2 && nl.gap(nl.offsets(i + 1) - 1) > 0) shuffled = i;
  ASSERT_GE(shuffled, 0);
  std::reverse(nl.neighbors.data() + nl.offsets(shuffled), nl.neighbors.data() + nl.offsets(shuffled + 1));
  nl.compute_gaps(domain, p.position_at_build, p.radius, 0.0, n);
  for (int i = 0; i < n; ++i)
    for (int s = nl.offsets(i); s < nl.offsets(i + 1); ++s)
      if (i == shuffled)
        ASSERT_EQ(nl.gap(s), -1.0f) << "slot " << s << " of the reordered particle";
      else
        ASSERT_EQ(nl.gap(s), built[s]) << "slot " << s;
}

namespace {
// Two identical engines on a dense, frictional periodic box of 1200 spheres: many sustained sliding
// contacts, for tests that run the same scene two ways.
std::array<std::unique_ptr<Engine>, 2> twin_dense_boxes(unsigned seed) {
  const MaterialSpec m = material("glass", 2500, 5e6, 0.3, 0.5, 0.5);
  const double box = 0.01;
  const ParticleSet p = random_periodic(1200, box, 0.4e-3, 0.5e-3, 2500, 0.3, seed);
  return {make(periodic_scene(box, m), p, 2e-6, "openmp", 0.1e-3),
          make(periodic_scene(box, m), p, 2e-6, "openmp", 0.1e-3)};
}
} // namespace

TEST(Integrator, ClosingKickFusedIntoTheNextStepGivesTheSameTrajectory) {
  // advance(n) leaves each step's closing kick to the next step's kick_drift; advance(1) never does
  // (its last step always closes). The two must agree bitwise: the fused pass is the same arithmetic.
  auto [fused, separate] = twin_dense_boxes(11);
  fused->advance(250); // crosses two health checks, where the kick is not fused either
  for (int s = 0; s < 250; ++s)
    separate->advance(1);
  const FrameData a = fused->frame(), b = separate->frame();
  ASSERT_GT(fused->observe().contacts, 100) << "the test needs contacts";
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.velocity, b.velocity);
  EXPECT_EQ(a.angular_velocity, b.angular_velocity);
}

TEST(ContactHistory, TangentialSpringSurvivesForcedRebuildAndReorder) {
  // A dense, sheared frictional box: many sustained sliding contacts. Rebuilding and reordering must
  // carry every (i, j) history entry over unchanged, so the next forces equal those without a rebuild.
  auto [a, b] = twin_dense_boxes(7);
  a->advance(300);
  b->advance(300);
  // Keyed by (smaller id, larger id) and seen from the smaller id: the owner of a pair may change with
  // a reorder, and the tangential displacement then changes sign (Law::flip_history).
  auto history_by_pair = [](const CheckpointData& c) {
    std::map<std::pair<std::int64_t, std::int64_t>, std::array<double, 3>> h;
    const auto& id = c.ints.at("id");
    const auto& off = c.ints.at("nl_offsets");
    const auto& nb = c.ints.at("nl_neighbors");
    const auto& hist = c.reals.at("nl_history");
    for (std::size_t i = 0; i < id.size(); ++i)
      for (auto k = off[i]; k < off[i + 1]; ++k)
        if (hist[3 * k] != 0 || hist[3 * k + 1] != 0 || hist[3 * k + 2] != 0) {
          const double sign = id[i] < id[nb[k]] ? 1 : -1;
          h[{std::min(id[i], id[nb[k]]), std::max(id[i], id[nb[k]])}] = {
              sign * hist[3 * k], sign * hist[3 * k + 1], sign * hist[3 * k + 2]};
        }
    return h;
  };
  const auto before = history_by_pair(b->checkpoint());
  b->rebuild_neighbors();
  const auto after = history_by_pair(b->checkpoint());
  ASSERT_GT(before.size(), 100u) << "the test needs sustained contacts";
  EXPECT_EQ(before, after); // bitwise: every spring carried over, none lost or invented
  // Forces one step later: same to round-off (only the summation order changed with the reorder).
  a->advance(1);
  b->advance(1);
  const FrameData fa = a->frame(), fb = b->frame();
  double worst = 0, scale = 0;
  for (std::size_t k = 0; k < fa.velocity.size(); ++k) {
    worst = std::max(worst, std::fabs(fa.velocity[k] - fb.velocity[k]));
    scale = std::max(scale, std::fabs(fa.velocity[k]));
  }
  EXPECT_LT(worst, 1e-12 * scale);
}

TEST(Conservation, MomentumToRoundOffInClosedPeriodicBox) {
  const MaterialSpec m = material("glass", 2500, 5e6, 0.3, 0.7, 0.5);
  const double box = 0.012;
  ParticleSet p = random_periodic(2000, box, 0.3e-3, 0.6e-3, 2500, 0.5, 11);
  auto engine = make(periodic_scene(box, m), p, 2e-6);
  const Observables o0 = engine->observe();
  double scale = 0; // sum of |m v|, the size of the numbers that cancel
  const FrameData f0 = engine->frame();
  for (std::size_t i = 0; i < f0.size(); ++i)
    scale += f0.mass[i] * std::sqrt(f0.velocity[3 * i] * f0.velocity[3 * i] +
                                    f0.velocity[3 * i + 1] * f0.velocity[3 * i + 1] +
                                    f0.velocity[3 * i + 2] * f0.velocity[3 * i + 2]);
  engine->advance(2000);
  const Observables o1 = engine->observe();
  EXPECT_GT(o1.contacts, 0);
  for (int a = 0; a < 3; ++a)
    EXPECT_LT(std::fabs(o1.momentum[a] - o0.momentum[a]), 1e-13 * scale) << "axis " << a;
  EXPECT_LT(o1.kinetic_energy, o0.kinetic_energy); // dissipative contacts did work
}

TEST(Conservation, ElasticFrictionlessBoxDriftsLessThan1e4OverTenThousandSteps) {
  // Hu Table 7 material: d 0.5 mm, rho 1000, E 100 MPa, nu 0.3, e 1, mu 0; random directions at 1 m/s.
  const MaterialSpec m = material("hu7", 1000, 100e6, 0.3, 1.0, 0.0);
  const double r = 0.25e-3, box = 0.0105;
  ParticleSet p = random_periodic(5000, box, r, r, 1000, 1.0, 5);
  ASSERT_EQ(p.size(), 5000u);
  const double dt = 0.1 * rayleigh_time(r, 1000, 100e6, 0.3);
  Scene s = periodic_scene(box, m, "none");
  auto engine = make(s, p, dt);
  const double e_star = 100e6 / (2 * (1 - 0.09)), r_eff = r / 2;
  // Total energy: kinetic plus the Hertz elastic energy 8/15 E* sqrt(R*) delta^2.5 of every contact.
  auto total_energy = [&]() {
    const Observables o = engine->observe();
    const CheckpointData c = engine->checkpoint();
    const auto& x = c.reals.at("position");
    const auto& off = c.ints.at("nl_offsets");
    const auto& nb = c.ints.at("nl_neighbors");
    double elastic = 0;
    for (std::size_t i = 0; i + 1 < off.size(); ++i)
      for (auto k = off[i]; k < off[i + 1]; ++k) {
        const auto j = nb[k];
        double d2 = 0;
        for (int a = 0; a < 3; ++a) {
          double d = x[3 * j + a] - x[3 * i + a];
          d -= box * std::round(d / box);
          d2 += d * d;
        }
        const double ov = 2 * r - std::sqrt(d2);
        if (ov > 0) elastic += (8.0 / 15.0) * e_star * std::sqrt(r_eff) * std::pow(ov, 2.5); // each pair once
      }
    return o.kinetic_energy + o.rotational_energy + elastic;
  };
  const double e0 = total_energy();
  long contacts_seen = 0;
  for (int k = 0; k < 10; ++k) {
    engine->advance(1000);
    contacts_seen += engine->observe().contacts;
  }
  const double e1 = total_energy();
  std::printf("[ report ] elastic box N=5000 dt=0.1 T_R: relative energy drift %.3e over 10000 steps\n",
              (e1 - e0) / e0);
  EXPECT_GT(contacts_seen, 0);
  EXPECT_LT(std::fabs(e1 - e0) / e0, 1e-4);
}

// load3/store3 index n x 3 fields by hand when the layout allows it (perf/README.md, constant strides);
// they must address exactly what the View's own indexing does, on the host layout and on LayoutLeft (the
// CUDA default, which keeps the View's indexing).
template <class Layout>
void check_rows_match_view_indexing() {
  Kokkos::View<Real* [3], Layout, Kokkos::HostSpace> v("v", 5);
  for (int i = 0; i < 5; ++i)
    store3(v, i, Vec3{10.0 * i, 10.0 * i + 1, 10.0 * i + 2});
  for (int i = 0; i < 5; ++i) {
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(v(i, c), 10.0 * i + c) << "row " << i << " component " << c;
    EXPECT_EQ(row3(v, i), &v(i, 0));
    const Vec3 r = load3(v, i);
    EXPECT_EQ(r.x, v(i, 0));
    EXPECT_EQ(r.y, v(i, 1));
    EXPECT_EQ(r.z, v(i, 2));
  }
}

TEST(ParticleStore, RowAccessMatchesViewIndexingOnEveryLayout) {
  static_assert(packed_rows3<Kokkos::View<Real* [3], Kokkos::LayoutRight, Kokkos::HostSpace>>());
  static_assert(!packed_rows3<Kokkos::View<Real* [3], Kokkos::LayoutLeft, Kokkos::HostSpace>>());
  check_rows_match_view_indexing<Kokkos::LayoutRight>();
  check_rows_match_view_indexing<Kokkos::LayoutLeft>();
}

// minimum_image compares against a precomputed half box, infinite on open axes.
TEST(Domain, MinimumImageWrapsPeriodicAxesOnlyAndIsOdd) {
  const Domain d({0, 0, 0}, {1, 2, 4}, true, false, true);
  const Vec3 far{0.7, 1.5, -3.0};
  const Vec3 m = d.minimum_image(far);
  EXPECT_DOUBLE_EQ(m.x, 0.7 - 1.0); // periodic, beyond half a box
  EXPECT_EQ(m.y, 1.5);              // open axis: never wrapped, however far
  EXPECT_DOUBLE_EQ(m.z, -3.0 + 4.0);
  const Vec3 n = d.minimum_image(Vec3{-0.7, -1.5, 3.0});
  EXPECT_EQ(n.x, -m.x);
  EXPECT_EQ(n.y, -m.y);
  EXPECT_EQ(n.z, -m.z);
  const Vec3 near{0.4, 0.1, 1.9};
  const Vec3 k = d.minimum_image(near);
  EXPECT_EQ(k.x, near.x);
  EXPECT_EQ(k.y, near.y);
  EXPECT_EQ(k.z, near.z);
  const Domain open; // default: no periodic axis
  EXPECT_EQ(open.minimum_image(far).z, far.z);
}

// The force pass skips minimum_image for particles in Domain::interior(range): there, every partner
// closer than `range` (wrapped into the box like the store's positions) must have its plain separation
// equal to the minimum image bitwise; and the interior must leave out exactly the seam bands.
TEST(Domain, InteriorParticlesSeeCloserPartnersWithoutMinimumImage) {
  const Domain d({-0.01, 0, 0}, {0.02, 0.03, 0.05}, true, true, false);
  const double range = 0.004;
  const Domain::Interior in = d.interior(range);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  int interior = 0, partners = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 xi{d.lo.x + u(rng) * d.length.x, d.lo.y + u(rng) * d.length.y, d.lo.z + u(rng) * d.length.z};
    const bool near_face =
        xi.x < d.lo.x + range || xi.x >= d.hi.x - range || xi.y < d.lo.y + range || xi.y >= d.hi.y - range;
    ASSERT_EQ(in.contains(xi), !near_face) << "only the periodic faces' bands are outside (z is open)";
    if (!in.contains(xi)) continue;
    ++interior;
    for (int m = 0; m < 8; ++m) {
      Vec3 step{u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5};
      step = (range * 0.999 * u(rng) / norm(step)) * step;
      const Vec3 xj = d.wrap(xi + step);
      const Vec3 plain = xj - xi, image = d.minimum_image(plain);
      ASSERT_EQ(plain.x, image.x);
      ASSERT_EQ(plain.y, image.y);
      ASSERT_EQ(plain.z, image.z);
      ++partners;
    }
  }
  EXPECT_GT(interior, 5000);
  EXPECT_GT(partners, 40000);
}
