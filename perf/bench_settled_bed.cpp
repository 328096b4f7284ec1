// Benchmark of the engine core on the shared settled beds (10k, 50k, and 200k = 50k copied 2 x 2):
// Hertz-Mindlin with history, d = 1 mm, rho 2500, E 5 MPa, nu 0.3, e 0.9, mu 0.3, floor wall,
// periodic x and y, dt 1e-5 s, skin 0.2 d. Reports particle-steps per second, the time split and
// the bytes per particle. Threads come from Kokkos' own flag: --kokkos-threads=N (perf/run_bench.sh
// runs 1 and 2); --backend=serial uses the Serial backend.
#include <benchmark/benchmark.h>
#include <Kokkos_Core.hpp>
#include <cstring>
#include <map>
#include "setup/time_step.hpp"
#include "drivers/engine_setup.hpp"
#include "drivers/particle_generation.hpp"
#include "drivers/scene_parser.hpp"
#include "kernels/engine.hpp"

namespace {

std::string backend = "openmp";

std::string scene_text(const std::string& csv, double box) {
  const std::string b = std::to_string(box);
  return "domain: {lo: [0, 0, 0], hi: [" + b + ", " + b + ", 0.04], periodic: [true, true, false]}\n"
         "gravity: [0, 0, -9.81]\n"
         "materials:\n"
         "  beads: {density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.3, restitution: 0.9, friction: 0.3}\n"
         "contact: {normal: hertz, tangential: mindlin}\n"
         "groups:\n"
         "  - {name: bed, material: beads, placement: {type: file, file: " + csv + "}}\n"
         "walls:\n"
         "  - {name: floor, type: plane, material: beads, point: [0, 0, 0], normal: [0, 0, 1]}\n"
         "time: {end: 1.0, step: 1.0e-5}\n"
         "neighbour: {skin: 0.0002}\n"
         "stability: {overlap_tolerance: 0.05}\n";
}

std::unique_ptr<cgdem::Engine> make_bed(int thousands) {
  using namespace cgdem;
  // The box extent comes from the CSV's header line ("box: 0 <xhi> xlo xhi; ...").
  const std::string dir = CGDEM_SHARED_DIR "/data/";
  const std::string csv = dir + (thousands == 10 ? "settled_bed_10k.csv" : "settled_bed_50k.csv");
  double extent = 0;
  {
    std::FILE* f = std::fopen(csv.c_str(), "r");
    char line[512];
    if (f && std::fgets(line, sizeof line, f)) {
      const char* at = std::strstr(line, "box: 0 ");
      if (at) extent = std::atof(at + 7);
    }
    if (f) std::fclose(f);
    if (!(extent > 0)) throw std::runtime_error("cannot read the box extent from " + csv);
  }
  Scene scene = parse_scene_text(scene_text(csv, extent), "bench");
  ParticleSet p = generate_particles(scene);
  if (thousands == 200) {
    // The 50k bed copied 2 x 2 in x and y, shifted by the box extent.
    const ParticleSet base = p;
    for (int c = 1; c < 4; ++c)
      for (std::size_t i = 0; i < base.size(); ++i) {
        p.id.push_back(base.id[i] + c * static_cast<std::int64_t>(base.size()));
        Vec3d x = base.position[i];
        x[0] += (c & 1) * extent;
        x[1] += (c >> 1) * extent;
        p.position.push_back(x);
        p.velocity.push_back(base.velocity[i]);
        p.angular_velocity.push_back(base.angular_velocity[i]);
        p.radius.push_back(base.radius[i]);
        p.density.push_back(base.density[i]);
        p.material.push_back(base.material[i]);
        p.group.push_back(base.group[i]);
      }
    scene.domain.hi[0] = scene.domain.hi[1] = 2 * extent;
  }
  const TimeStepEstimate dt = estimate_time_step(scene, p);
  return make_engine(make_engine_config(scene, p, dt), backend);
}

void BM_SettledBed(benchmark::State& state) {
  const int thousands = static_cast<int>(state.range(0));
  auto engine = make_bed(thousands);
  engine->advance(50);  // warm-up: first list rebuilds and page faults out of the timing
  const cgdem::StepTimers before = engine->timers();
  const long steps_per_iteration = 100;
  for (auto _ : state) engine->advance(steps_per_iteration);
  const cgdem::StepTimers after = engine->timers();
  const double n = engine->size();
  const double steps = static_cast<double>(state.iterations()) * steps_per_iteration;
  state.counters["particle_steps_per_s"] = benchmark::Counter(n * steps, benchmark::Counter::kIsRate);
  const double forces = after.forces - before.forces, list = after.neighbor_list - before.neighbor_list,
               bins = after.binning - before.binning, integ = after.integrate - before.integrate;
  const double total = forces + list + bins + integ;
  state.counters["forces_%"] = 100 * forces / total;
  state.counters["list_%"] = 100 * list / total;
  state.counters["binning_%"] = 100 * bins / total;
  state.counters["integrate_%"] = 100 * integ / total;
  state.counters["list_builds"] = static_cast<double>(after.list_builds - before.list_builds);
  state.counters["bytes_per_particle"] = engine->bytes() / n;
  state.counters["contacts_per_particle"] = 2.0 * engine->observe().contacts / n;
  state.SetLabel(backend + " x" + std::to_string(backend == "serial" ? 1 : Kokkos::OpenMP::concurrency()));
}
BENCHMARK(BM_SettledBed)->Arg(10)->Arg(50)->Arg(200)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

} // namespace

int main(int argc, char** argv) {
  for (int k = 1; k < argc; ++k)
    if (!std::strncmp(argv[k], "--backend=", 10)) backend = argv[k] + 10;
  Kokkos::ScopeGuard kokkos(argc, argv);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
