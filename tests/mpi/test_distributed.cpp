// The engine spread over MPI ranks against the same scene in one process (ctest runs this binary under
// `mpirun -np 2` and `-np 4`). Every rank builds the one-process reference too and compares the gathered
// state with it, so every rank reaches the same verdict.
#include <gtest/gtest.h>
#include <mpi.h>
#include <Kokkos_Core.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include "core/checkpoint.hpp"
#include "drivers/engine_setup.hpp"
#include "drivers/kokkos_session.hpp"
#include "drivers/particle_generation.hpp"
#include "drivers/scene_parser.hpp"
#include "kernels/engine.hpp"
#include "parallel/distributed_engine.hpp"
#include "parallel/mpi_session.hpp"
#include "setup/time_step.hpp"
#include "tests/bed_scene.hpp"

namespace cgdem::testing {
namespace {

// The scene's engine configuration; `adjust` may change the particles first (initial velocities).
template <class Adjust = void (*)(ParticleSet&)>
EngineConfig config_of(
    const std::string& yaml, Adjust adjust = [](ParticleSet&) {}) {
  const Scene scene = parse_scene_text(yaml, "<mpi test>");
  ParticleSet particles = generate_particles(scene);
  adjust(particles);
  const TimeStepEstimate dt = estimate_time_step(scene, particles);
  EngineConfig c = make_engine_config(scene, particles, dt);
  c.resizable = true;
  return c;
}

std::unique_ptr<Engine> distributed(const EngineConfig& c) {
  return parallel::make_distributed_engine(make_engine(c, "openmp"), c.domain, c.skin);
}

struct Difference {
  double position = 0, velocity = 0, angular_velocity = 0;
};

// Largest differences between two frames of the same particles (both in id order).
Difference compare(const FrameData& a, const FrameData& b) {
  EXPECT_EQ(a.id, b.id);
  Difference d;
  if (a.id != b.id) return d;
  for (std::size_t k = 0; k < a.position.size(); ++k) {
    d.position = std::max(d.position, std::abs(a.position[k] - b.position[k]));
    d.velocity = std::max(d.velocity, std::abs(a.velocity[k] - b.velocity[k]));
    d.angular_velocity =
        std::max(d.angular_velocity, std::abs(a.angular_velocity[k] - b.angular_velocity[k]));
  }
  return d;
}

int ranks() {
  return parallel::world_size();
}

// Files the tests share between ranks and between the 2- and 4-rank runs (ctest sets it to the build's
// test directory).
std::string test_dir() {
  const char* dir = std::getenv("CGDEM_MPI_TEST_DIR");
  return dir ? dir : ".";
}

TEST(Distributed, BedMatchesOneProcessOver1000Steps) {
  const EngineConfig c = config_of(kBedScene);
  auto one = make_engine(c, "openmp");
  auto many = distributed(c);
  EXPECT_EQ(many->size(), one->size());
  one->advance(1000);
  many->advance(1000);
  const FrameData a = one->frame(), b = many->frame();
  const Difference d = compare(a, b);
  const Observables oa = one->observe(), ob = many->observe();
  const long builds = many->timers().list_builds; // collective, like every call of the distributed engine
  if (parallel::world_rank() == 0)
    std::printf(
        "[ %d ranks ] bed 1000 steps: max |dx| %.3g m, |dv| %.3g m/s, |dw| %.3g rad/s; kinetic energy "
        "%.10g / %.10g J; contacts %ld / %ld; list builds %ld\n",
        ranks(), d.position, d.velocity, d.angular_velocity, oa.kinetic_energy, ob.kinetic_energy,
        oa.contacts, ob.contacts, builds);
  // Round-off only: the force sums run in another order (a rank's own store order), nothing else differs.
  // Radii are ~0.2 mm, speeds ~1 cm/s: these bounds are 1e-9 of both.
  EXPECT_LT(d.position, 2e-13);
  EXPECT_LT(d.velocity, 1e-11);
  EXPECT_LT(d.angular_velocity, 1e-7);
  EXPECT_NEAR(ob.kinetic_energy, oa.kinetic_energy, 1e-9 * oa.kinetic_energy);
  EXPECT_EQ(ob.contacts, oa.contacts);
  ASSERT_EQ(ob.wall_force.size(), oa.wall_force.size());
  for (std::size_t k = 0; k < oa.wall_force.size(); ++k)
    EXPECT_NEAR(ob.wall_force[k], oa.wall_force[k], 1e-9 * std::abs(oa.wall_force[2]));
  EXPECT_GT(builds, 1); // the floor's push makes the lists rebuild: particles migrate
}

// Two beads pressed together between two walls, sliding past each other while both travel along x
// through every rank's brick and across the periodic face. Their tangential spring (the contact history)
// builds up from the first step: if it were lost or mirrored at a migration, the trajectory would leave
// the one-process one by far more than round-off. A row of beads far above them, at rest, spreads the
// decomposition's cuts along x.
TEST(Distributed, SlidingPairKeepsItsHistoryAcrossRanksAndThePeriodicFace) {
  const double r = 1e-3, gap = 0.995 * r; // each contact overlaps by 0.5 % of the radius
  const std::string csv = (std::filesystem::path(test_dir()) / "sliding_pair.csv").string();
  if (parallel::world_rank() == 0) {
    std::FILE* f = std::fopen(csv.c_str(), "w");
    ASSERT_NE(f, nullptr) << csv;
    std::fprintf(f, "id,x,y,z,radius\n1,0.02,%.17g,0.002,%.17g\n2,0.02,%.17g,0.002,%.17g\n", gap, r, 3 * gap,
                 r);
    for (int k = 0; k < 8; ++k)
      std::fprintf(f, "%d,%.17g,0.002,0.015,%.17g\n", 3 + k, 0.002 + 0.005 * k, r);
    std::fclose(f);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  char yaml[2048];
  std::snprintf(yaml, sizeof yaml,
                R"(domain: {lo: [0, 0, 0], hi: [0.04, %.17g, 0.02], periodic: [true, false, false]}
gravity: [0, 0, 0]
materials:
  beads: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3, restitution: 0.5, friction: 0.5}
contact: {normal: hertz, tangential: mindlin}
groups:
  - {name: beads, material: beads, placement: {type: file, file: %s}}
walls:
  - {name: left, type: plane, material: beads, point: [0, 0, 0], normal: [0, 1, 0]}
  - {name: right, type: plane, material: beads, point: [0, %.17g, 0], normal: [0, -1, 0]}
time: {end: 0.04, step: 2.0e-6}
)",
                4 * gap, csv.c_str(), 4 * gap);
  EngineConfig c;
  try {
    c = config_of(yaml, [](ParticleSet& p) {
      p.velocity[0] = {1.1, 0, 0}; // the pair slides at 0.2 m/s while travelling at 1 m/s
      p.velocity[1] = {0.9, 0, 0};
    });
  } catch (const std::exception& e) {
    FAIL() << e.what();
  }
  auto one = make_engine(c, "serial");
  auto many = distributed(c);
  // 0.04 s slowing down from 1 m/s (the walls' friction): 3.3 cm from x = 2 cm, through the other
  // ranks' bricks (cuts at 2 cm for 2 ranks; 1.2, 2 and 2.7 cm for 4) and across the periodic face.
  const double start_x = c.particles.position[0][0];
  double worst = 0;
  for (int chunk = 0; chunk < 10; ++chunk) {
    one->advance(2000);
    many->advance(2000);
    const Difference d = compare(one->frame(), many->frame());
    worst = std::max(worst, d.position);
  }
  const FrameData a = one->frame(), b = many->frame();
  const Difference d = compare(a, b);
  // The history acted: friction spun the beads.
  double spin = 0;
  for (int k = 0; k < 6; ++k)
    spin = std::max(spin, std::abs(a.angular_velocity[k]));
  if (parallel::world_rank() == 0)
    std::printf(
        "[ %d ranks ] sliding pair, 20000 steps: bead 1 from x = %.4f to %.4f (wrapped), max |dx| %.3g "
        "m (worst %.3g), |dv| %.3g m/s, |dw| %.3g rad/s; spin %.4g rad/s\n",
        ranks(), start_x, a.position[0], d.position, worst, d.velocity, d.angular_velocity, spin);
  EXPECT_LT(a.position[0], start_x); // moving +x, it went round through the periodic face
  EXPECT_GT(spin, 1.0);
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(d.velocity, 1e-9);
  EXPECT_LT(d.angular_velocity, 1e-6);
}

// A column of beads contracting towards the floor (each bead's downward speed in proportion to its
// height, apart enough never to touch): the cut across the column (z, its long axis) starts at the median
// height, and as the column shrinks to 70 % of its height the upper rank's share falls towards 30 %; the
// ranks move their cuts to the new quantiles at a redistribution. Without contacts the trajectory is
// exactly the one-process one, whatever the bricks.
TEST(Distributed, ContractingColumnIsRebalanced) {
  const std::string column =
      R"(domain: {lo: [0, 0, 0], hi: [0.0075, 0.0075, 0.03], periodic: [true, true, false]}
gravity: [0, 0, 0]
materials:
  beads: {density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.3, restitution: 0.7, friction: 0.4}
contact: {normal: hertz, tangential: mindlin}
groups:
  - name: column
    material: beads
    count: 3000
    size: {radius: 0.00025}
    placement: {type: lattice, lo: [0, 0, 0.001], hi: [0.0075, 0.0075, 0.03], spacing: 0.00075}
time: {end: 0.05, step: 1.0e-5}
)";
  const double rate = 0.3 / 0.05; // 1/s: 30 % of every height in 0.05 s
  const EngineConfig c = config_of(column, [&](ParticleSet& p) {
    for (std::size_t i = 0; i < p.size(); ++i)
      p.velocity[i] = {0, 0, -rate * p.position[i][2]};
  });
  auto one = make_engine(c, "serial");
  auto many = distributed(c);
  one->advance(5000);
  many->advance(5000);
  const Difference d = compare(one->frame(), many->frame());
  const StepTimers t = many->timers();
  if (parallel::world_rank() == 0)
    std::printf(
        "[ %d ranks ] contracting column, 5000 steps: %ld list builds, %ld rebalances, particles per rank "
        "at the end: largest %.1f %% above the mean; max |dx| %.3g m, |dv| %.3g m/s\n",
        ranks(), t.list_builds, t.rebalances, 100 * t.load_imbalance, d.position, d.velocity);
  EXPECT_GE(t.rebalances, 1);
  EXPECT_LT(t.load_imbalance, 0.15);
  EXPECT_EQ(d.position, 0);
  EXPECT_EQ(d.velocity, 0);
  EXPECT_EQ(many->observe().contacts, 0);
}

// The checkpoint of one rank count is the single-process form: the 2-rank run writes one after 500
// steps (DistributedRestart.Write), the 4-rank run restarts from it (DistributedRestart.Read, a ctest
// fixture) and after 500 more steps matches the uninterrupted one-process run.
std::string checkpoint_file() {
  return (std::filesystem::path(test_dir()) / "mpi_restart.checkpoint.h5").string();
}

TEST(DistributedRestart, Write) {
  if (ranks() != 2) GTEST_SKIP() << "written by the 2-rank run";
  auto many = distributed(config_of(kBedScene));
  many->advance(500);
  const CheckpointData c = many->checkpoint();
  if (parallel::world_rank() == 0) write_checkpoint(checkpoint_file(), c);
  MPI_Barrier(MPI_COMM_WORLD);
}

TEST(DistributedRestart, Read) {
  if (ranks() != 4) GTEST_SKIP() << "read by the 4-rank run";
  const EngineConfig c = config_of(kBedScene);
  auto one = make_engine(c, "openmp");
  one->advance(1000);
  auto many = distributed(c);
  many->restore(read_checkpoint(checkpoint_file()));
  EXPECT_EQ(many->step(), 500);
  many->advance(500);
  const Difference d = compare(one->frame(), many->frame());
  if (parallel::world_rank() == 0)
    std::printf("[ 2 -> 4 ranks ] bed restarted at step 500, at 1000: max |dx| %.3g m, |dv| %.3g m/s\n",
                d.position, d.velocity);
  EXPECT_LT(d.position, 2e-13);
  EXPECT_LT(d.velocity, 1e-11);
}

} // namespace
} // namespace cgdem::testing

int main(int argc, char** argv) {
  cgdem::parallel::MpiSession mpi(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  cgdem::KokkosSession kokkos(1);
  // One report, from rank 0; every rank runs every test (they are collective) and their verdicts are
  // combined.
  if (cgdem::parallel::world_rank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  int failed = RUN_ALL_TESTS();
  MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return failed;
}
