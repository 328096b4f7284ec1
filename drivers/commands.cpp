#include "drivers/commands.hpp"
#include "drivers/kokkos_session.hpp"
#include <Kokkos_Core.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <unistd.h>
#include "core/checkpoint.hpp"
#include "setup/materials.hpp"
#include "core/result_writer.hpp"
#include "setup/time_step.hpp"
#include "drivers/analyses.hpp"
#include "drivers/cli.hpp"
#include "drivers/engine_setup.hpp"
#include "drivers/resolution_check.hpp"
#include "drivers/inlets_outlets.hpp"
#include "drivers/wall_triggers.hpp"
#include "drivers/particle_generation.hpp"
#include "drivers/preflight.hpp"
#include "drivers/scene_parser.hpp"
#include "kernels/engine.hpp"
#include "models/component_lists.hpp"
#include "parallel/distributed_engine.hpp"
#include "parallel/mpi_session.hpp"

namespace cgdem {

namespace {

// A result or checkpoint write that failed during the run (disk full, file removed, ...).
struct OutputFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

bool wants_help(const std::vector<std::string>& args) {
  for (const auto& a : args)
    if (a == "--help" || a == "-h") return true;
  return false;
}

// --help or the options of a command; returns an exit code when the command should stop here, else -1.
int read_options(const std::vector<std::string>& args, const char* command, const char* help, bool run_only,
                 RunOptions& out) {
  if (wants_help(args)) {
    std::cout << help;
    return 0;
  }
  try {
    out = parse_run_options(args, run_only);
  } catch (const CliError& e) {
    std::cerr << "cgdem " << command << ": " << e.what() << "\n";
    return exit_bad_input;
  }
  return -1;
}

std::string default_backend() {
  return compiled_backends().front();
}

int backend_threads(const std::string& backend) {
#if defined(KOKKOS_ENABLE_OPENMP)
  if (backend == "openmp") return Kokkos::OpenMP::concurrency();
#endif
  return 1;
}

// Everything 'run' and 'check' share: parse, generate, validate, estimate the step, configure.
struct PreparedRun {
  Scene scene;
  ParticleSet particles;
  TimeStepEstimate dt;
  EngineConfig config;
};

PreparedRun prepare(const RunOptions& o) {
  PreparedRun p;
  p.scene = parse_scene_file(o.scene, o.overrides);
  p.particles = generate_particles(p.scene);
  if (p.scene.stability.relax_initial_overlaps) {
    const RelaxReport r = relax_overlaps(p.scene, p.particles);
    if (r.initial_max_overlap > 0)
      std::fprintf(stderr,
                   "relaxed initial overlaps: largest %.3g -> %.3g of the smaller radius in %d sweeps\n",
                   r.initial_max_overlap, r.final_max_overlap, r.sweeps);
  }
  check_particles(p.scene, p.particles);
  p.dt = estimate_time_step(p.scene, p.particles);
  if (p.scene.time.step > 0 && p.scene.time.step > p.dt.limit && !p.scene.time.force_step) {
    std::ostringstream what, fix;
    what << "step " << p.scene.time.step << " s is above the stable limit " << p.dt.limit << " s ("
         << p.dt.reason.substr(p.dt.reason.find("from ") + 5);
    fix << "use 'step: auto', a step <= " << p.dt.limit
        << " s, or set time.force_step: true to run it anyway";
    throw SceneError(scene_error_message(p.scene.source_file, "time.step", what.str(), fix.str()));
  }
  p.config = make_engine_config(p.scene, p.particles, p.dt);
  return p;
}

std::string human_bytes(double b) {
  const char* unit[] = {"B", "KiB", "MiB", "GiB"};
  int u = 0;
  while (b >= 1024 && u < 3) {
    b /= 1024;
    ++u;
  }
  char s[32];
  std::snprintf(s, sizeof s, "%.1f %s", b, unit[u]);
  return s;
}

std::string human_duration(double s) {
  char buf[32];
  if (s < 120)
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 7200)
    std::snprintf(buf, sizeof buf, "%.1f min", s / 60);
  else
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600);
  return buf;
}

SeriesRow series_row(const Observables& o) {
  SeriesRow r;
  r.time = o.time;
  r.step = o.step;
  r.kinetic_energy = o.kinetic_energy;
  r.rotational_energy = o.rotational_energy;
  r.contacts = o.contacts;
  r.wall_force = o.wall_force;
  r.wall_torque = o.wall_torque;
  return r;
}

std::string checkpoint_path_for(const std::string& h5) {
  std::filesystem::path p(h5);
  return (p.parent_path() / (p.stem().string() + ".checkpoint.h5")).string();
}

// Particles that leave the domain through a non-periodic side keep moving and interacting, binned in the
// edge cells; a few are harmless, many slow contact detection and usually mean a wall is missing or the
// domain is too small. Checked on each output frame; said once when first seen, counted at the end.
class EscapeWatch {
public:
  explicit EscapeWatch(const DomainSpec& d) : domain_(d) {}
  void check(const FrameData& f) {
    static const char* axis[3] = {"x", "y", "z"};
    long outside = 0;
    std::size_t first = 0;
    int first_axis = 0;
    for (std::size_t i = 0; i < f.size(); ++i)
      for (int a = 0; a < 3; ++a) {
        const double x = f.position[3 * i + a];
        if (domain_.periodic[a] || (x >= domain_.lo[a] && x <= domain_.hi[a])) continue;
        if (outside == 0) first = i, first_axis = a;
        ++outside;
        break;
      }
    last_count_ = outside;
    if (outside == 0 || warned_) return;
    warned_ = true;
    const double x = f.position[3 * first + first_axis];
    std::fprintf(stderr,
                 "\nwarning: t = %.4g s: %ld particle(s) outside the domain (first: id %lld at %s = %.4g m, "
                 "domain %s in [%.4g, %.4g] m); they keep moving, binned in the edge cells: add a wall or "
                 "enlarge domain.lo/hi\n",
                 f.time, outside, static_cast<long long>(f.id[first]), axis[first_axis], x, axis[first_axis],
                 domain_.lo[first_axis], domain_.hi[first_axis]);
  }
  long outside_now() const { return last_count_; }

private:
  DomainSpec domain_;
  bool warned_ = false;
  long last_count_ = 0;
};

} // namespace

int run_command(const std::vector<std::string>& args) {
  RunOptions o;
  if (const int code = read_options(args, "run", run_help(), true, o); code >= 0) return code;
  // Under mpirun every rank runs this same function on its share of the particles (the engine's calls
  // are collective); rank 0 alone prints and writes files.
  const bool distributed = parallel::world_size() > 1, root = parallel::world_rank() == 0;
  if (!root) std::freopen("/dev/null", "w", stderr);
  KokkosSession kokkos(o.threads);
  const std::string backend = o.backend.empty() ? default_backend() : o.backend;
  PreparedRun p;
  std::unique_ptr<Engine> engine;
  CheckpointData restart;
  std::vector<std::unique_ptr<Analysis>> analyses; // the scene's analyses: outputs go into each series row
  std::unique_ptr<ParticleExchange> exchange;      // inlets and outlets
  std::unique_ptr<WallTriggers> triggers;          // segments that end at a force
  try {
    p = prepare(o);
    analyses = make_analyses(p.scene);
    exchange = std::make_unique<ParticleExchange>(p.scene, p.particles, p.dt.step);
    // Host copies of the particles cost ~100 B per particle each: the scene's set is in p.config by now,
    // and p.config's is on the device once the engine exists.
    p.particles = ParticleSet{};
    if (distributed) {
      if (exchange->active())
        throw std::runtime_error("inlets and outlets run in one process: run this scene without mpirun");
      p.config.resizable = true; // each rank keeps its share
    }
    engine = make_engine(p.config, backend);
    p.config.particles = ParticleSet{};
    if (distributed)
      engine = parallel::make_distributed_engine(std::move(engine), p.config.domain, p.config.skin);
    triggers = std::make_unique<WallTriggers>(p.scene);
    if (!o.restart.empty()) {
      restart = read_checkpoint(o.restart);
      try {
        engine->restore(restart);
        exchange->load(restart);
        load_analysis_states(analyses, restart);
        triggers->load(restart, *engine, analyses);
      } catch (const std::runtime_error& e) {
        throw std::runtime_error("cannot restart from '" + o.restart + "': " + e.what());
      }
    }
  } catch (const SceneError& e) {
    std::cerr << "cgdem: " << e.what() << "\n";
    return exit_bad_input;
  } catch (const std::exception& e) {
    std::cerr << "cgdem: " << o.scene << ": " << e.what() << "\n";
    return exit_bad_input;
  }

  const double dt = p.dt.step;
  const long end_step = static_cast<long>(std::ceil(p.scene.time.end / dt - 1e-9));
  const long frame_every =
      p.scene.output.every > 0 ? std::max(1L, std::lround(p.scene.output.every / dt)) : end_step;
  const long checkpoint_every =
      o.checkpoint_every > 0 ? std::max(1L, std::lround(o.checkpoint_every / dt)) : 0;
  const std::string out = o.out.empty() ? p.scene.output.file : o.out;
  // Every file the run will write is checked before any work: a bad destination is bad input.
  {
    std::vector<std::string> files = {out, xdmf_path_for(out)};
    if (checkpoint_every > 0) files.push_back(checkpoint_path_for(out));
    for (const std::string& f : files)
      if (const std::string problem = output_file_problem(f); !problem.empty()) {
        std::fprintf(stderr, "cgdem: %s\n", problem.c_str());
        return exit_bad_input;
      }
  }

  RunInfo info;
  info.cgdem_version = CGDEM_VERSION;
  info.scene_yaml = p.scene.resolved_yaml;
  info.backend = backend;
  info.threads = backend_threads(backend);
  info.time_step = dt;
  info.scaling_law = p.scene.groups.empty() ? "none" : p.scene.groups.front().coarse_grain.law;
  info.scale_factor = p.scene.groups.empty() ? 1.0 : p.scene.groups.front().coarse_grain.factor;
  info.wall_names = p.config.wall_names;
  for (const Wall& w : p.config.walls)
    if (w.type == Wall::Mesh)
      info.meshes.push_back({p.config.wall_names[w.owner], p.config.meshes[w.mesh], w});
  std::unique_ptr<ResultWriter> writer_ptr; // rank 0's only
  try {
    if (root) writer_ptr = std::make_unique<ResultWriter>(out, info, p.scene.output.fields);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cgdem: output write failed: %s\n", e.what());
    if (distributed) parallel::abort_all(exit_write_failed);
    return exit_write_failed;
  }

  const int n = engine->size();
  const std::string inlet_note =
      exchange->waiting() > 0 ? " (+" + std::to_string(exchange->waiting()) + " to come from inlets)" : "";
  std::fprintf(stderr, "cgdem %s: %s, %d particles%s, %s on %s (%d threads), dt = %.4g s (%s)\n",
               CGDEM_VERSION, o.scene.c_str(), n, inlet_note.c_str(), engine->physics().c_str(),
               backend.c_str(), info.threads, dt, p.dt.reason.c_str());
  for (const std::string& w : resolution_warnings(p.scene))
    std::fprintf(stderr, "%s\n", w.c_str());
  EscapeWatch escapes(p.scene.domain);
  auto emit = [&]() {
    Observables obs = engine->observe();
    FrameData frame = engine->frame();
    escapes.check(frame);
    SeriesRow row = series_row(obs);
    // A restart between two outputs gives a frame the uninterrupted run does not have.
    const bool output_step = obs.step % frame_every == 0 || obs.step == end_step;
    run_analyses(analyses, AnalysisInput{frame, obs.time, info.wall_names, obs.wall_force, output_step},
                 row.analyses);
    exchange->record(row.analyses, engine->size());
    try {
      if (writer_ptr) {
        writer_ptr->write_frame(std::move(frame));
        writer_ptr->write_series(std::move(row));
      }
    } catch (const std::runtime_error& e) {
      throw OutputFailure(e.what());
    }
    return obs;
  };
  const std::string checkpoint_path = checkpoint_path_for(out);
  auto checkpoint = [&]() {
    try {
      CheckpointData c = engine->checkpoint();
      exchange->save(c);
      save_analysis_states(analyses, c);
      triggers->save(c);
      if (root) write_checkpoint(checkpoint_path, c);
    } catch (const std::runtime_error& e) {
      throw OutputFailure(e.what());
    }
  };
  // A failed write stops the run: the result file keeps every frame committed before the failure (the
  // writer never touches the visible file), and a checkpoint of the current state is attempted when asked
  // for.
  auto write_failed = [&](std::string what) {
    std::replace(what.begin(), what.end(), '\n', ' '); // HDF5's messages carry a time stamp with a newline
    std::fprintf(stderr, "\ncgdem: output write failed at step %ld: %s\n", engine->step(), what.c_str());
    try {
      if (writer_ptr) writer_ptr->close();
    } catch (const std::exception&) { // the same failure, already reported
    }
    std::string saved;
    // The other ranks wait in the next collective call: the checkpoint below cannot gather them.
    if (checkpoint_every > 0 && what.find(checkpoint_path) == std::string::npos && !distributed) {
      try {
        CheckpointData c = engine->checkpoint();
        exchange->save(c);
        save_analysis_states(analyses, c);
        triggers->save(c);
        write_checkpoint(checkpoint_path, c);
        saved = "; checkpoint of step " + std::to_string(engine->step()) + " in " + checkpoint_path;
      } catch (const std::exception& e) {
        saved = "; the checkpoint failed too: " + std::string(e.what());
      }
    } else if (checkpoint_every > 0) {
      saved = "; " + checkpoint_path + " holds the previous checkpoint";
    }
    std::replace(saved.begin(), saved.end(), '\n', ' ');
    std::fprintf(stderr, "cgdem: %s keeps %lld complete frames%s\n", writer_ptr->path().c_str(),
                 static_cast<long long>(writer_ptr->frames_written()), saved.c_str());
    if (distributed) parallel::abort_all(exit_write_failed);
    return exit_write_failed;
  };
  try {
    emit();
  } catch (const OutputFailure& e) {
    return write_failed(e.what());
  }

  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto last_progress = start;
  const long first_step = engine->step();
  long last_step = first_step;
  double particle_steps = 0; // done so far (the count changes with inlets and outlets)
  bool stopped_early = false;
  const bool interactive = isatty(fileno(stderr));
  try {
    while (engine->step() < end_step) {
      long next = std::min(end_step, (engine->step() / frame_every + 1) * frame_every);
      if (checkpoint_every > 0)
        next = std::min(next, (engine->step() / checkpoint_every + 1) * checkpoint_every);
      const long exchange_every = exchange->every_steps();
      if (exchange->active()) next = std::min(next, (engine->step() / exchange_every + 1) * exchange_every);
      next = triggers->next_check(engine->step(), dt, next);
      // Progress at most every ~second even between frames: advance in slices.
      const long slice =
          std::max(1L, std::min(next - engine->step(), 2000000L / std::max(1, engine->size()) + 1));
      engine->advance(std::min(slice, next - engine->step()));
      const long s = engine->step();
      particle_steps += double(s - last_step) * engine->size();
      last_step = s;
      if (exchange->active() && s % exchange_every == 0) exchange->apply(*engine);
      triggers->check(*engine, analyses);
      if (s % frame_every == 0 || s == end_step) {
        const Observables obs = emit();
        if (p.scene.stop.kinetic_energy_below > 0 && obs.time >= p.scene.stop.min_time &&
            obs.kinetic_energy < p.scene.stop.kinetic_energy_below) {
          std::fprintf(stderr, "\nstop: kinetic energy %.3g J below %.3g J at t = %.4g s\n",
                       obs.kinetic_energy, p.scene.stop.kinetic_energy_below, obs.time);
          stopped_early = true;
          break;
        }
      }
      if (checkpoint_every > 0 && s % checkpoint_every == 0) checkpoint();
      const auto now = clock::now();
      // A terminal gets a line rewritten every second; a log file a new line every 10 seconds.
      if (!o.quiet &&
          std::chrono::duration<double>(now - last_progress).count() > (interactive ? 1.0 : 10.0)) {
        last_progress = now;
        const double wall = std::chrono::duration<double>(now - start).count();
        const double rate = particle_steps / wall;
        const double eta = double(end_step - s) * std::max(1, engine->size()) / rate;
        std::fprintf(stderr, "%s  t = %.4g / %.4g s  step %ld / %ld  %.3g particle-steps/s  ETA %s   %s",
                     interactive ? "\r" : "", s * dt, p.scene.time.end, s, end_step, rate,
                     human_duration(eta).c_str(), interactive ? "" : "\n");
      }
    }
    // The checkpoint holds the run's last step too (its end, or where `stop` ended it), so that a finished
    // run can be continued to a later end or start a second stage (--restart with another scene state).
    if (checkpoint_every > 0 && engine->step() % checkpoint_every != 0) checkpoint();
    try {
      if (writer_ptr) writer_ptr->flush();
    } catch (const std::runtime_error& e) {
      throw OutputFailure(e.what());
    }
  } catch (const BlowUpError& e) {
    try {
      if (writer_ptr) writer_ptr->flush();
    } catch (const std::exception& w) {
      std::fprintf(stderr, "\ncgdem: output write failed too: %s\n", w.what());
    }
    std::fprintf(stderr, "\ncgdem: %s\n", e.what());
    return exit_blow_up;
  } catch (const OutputFailure& e) {
    return write_failed(e.what());
  }
  const double wall = std::chrono::duration<double>(clock::now() - start).count();
  const long steps = engine->step() - first_step;
  const StepTimers t = engine->timers();
  const double timed = t.integrate + t.binning + t.neighbor_list + t.forces + t.communication;
  const Observables last = engine->observe();
  if (!writer_ptr) return 0; // a rank other than 0: rank 0 reports
  const ResultWriter& writer = *writer_ptr;
  if (interactive) std::fprintf(stderr, "\r%100s\r", "");
  std::fprintf(
      stderr,
      "done%s: %ld steps of %d particles in %s: %.3g particle-steps/s\n"
      "  time split: forces %.0f%%, neighbour list %.0f%%, binning+reorder %.0f%%, integration %.0f%%%s "
      "(%ld list builds)\n"
      "  final: t = %.4g s, kinetic energy %.4g J, %ld contacts\n"
      "  wrote %s (%lld frames) and %s\n",
      stopped_early ? " (stop condition)" : "", steps, engine->size(), human_duration(wall).c_str(),
      particle_steps / wall, 100 * t.forces / timed, 100 * t.neighbor_list / timed, 100 * t.binning / timed,
      100 * t.integrate / timed,
      distributed ? (", MPI communication " + std::to_string(std::lround(100 * t.communication / timed)) +
                     "% (the most of any rank; particles per rank: largest " +
                     std::to_string(std::lround(100 * t.load_imbalance)) + "% above the mean, " +
                     std::to_string(t.rebalances) + " rebalances)")
                        .c_str()
                  : "",
      t.list_builds, last.time, last.kinetic_energy, last.contacts, writer.path().c_str(),
      static_cast<long long>(writer.frames_written()), writer.xdmf_path().c_str());
  if (escapes.outside_now() > 0)
    std::fprintf(stderr, "  %ld particle(s) outside the domain in the last frame\n", escapes.outside_now());
  for (const std::string& line : exchange->shortfalls(last.time))
    std::fprintf(stderr, "%s\n", line.c_str());
  return 0;
}

namespace {

// The analyses valid and the physics compiled; returns the physics' name ("@<method>" under direct scaling).
std::string require_analyses_and_physics(const PreparedRun& p) {
  make_analyses(p.scene); // validates the analyses (types, parameters, walls)
  const std::string physics = physics_name(p.config.contact);
  for (const auto& c : compiled_physics())
    if (c == physics) return physics;
  // Every sensible combination of components is compiled (models/component_lists.hpp, and the parser
  // refuses the others): what is missing is a direct scaling method around a law it is not compiled for.
  if (p.config.contact.scaling == "none") {
    std::string all;
    for (const auto& c : compiled_physics())
      all += " " + c;
    throw SceneError(scene_error_message(p.scene.source_file, "contact",
                                         "the combination '" + physics + "' is not compiled",
                                         "choose one of:" + all));
  }
  const std::string method = "@" + p.config.contact.scaling;
  std::string laws;
  for (const auto& c : compiled_physics())
    if (c.size() > method.size() && c.compare(c.size() - method.size(), method.size(), method) == 0)
      laws += (laws.empty() ? "" : ", ") + c.substr(0, c.size() - method.size());
  throw SceneError(scene_error_message(
      p.scene.source_file, "contact",
      "direct force scaling " + p.config.contact.scaling + " is compiled around " + laws +
          " (the laws of Hu et al. 2022), not around " + physics.substr(0, physics.size() - method.size()),
      "use one of those laws, or scale the parameters instead (coarse_grain.law: chen_elliott, bond, "
      "cohesion or thakur)"));
}

} // namespace

RunCheck check_run(const std::string& scene, const std::vector<std::string>& overrides) {
  RunOptions o;
  o.scene = scene;
  o.overrides = overrides;
  const PreparedRun p = prepare(o);
  require_analyses_and_physics(p);
  // The engine built once: grid and neighbour-list checks (periodic axes >= 3 cells); its particles' masses
  // are the ones the run simulates.
  const auto engine = make_engine(p.config, default_backend());
  RunCheck c;
  c.particles = static_cast<long>(p.particles.size());
  for (double m : engine->frame().mass)
    c.mass += m;
  c.warnings = resolution_warnings(p.scene);
  return c;
}

int check_command(const std::vector<std::string>& args) {
  RunOptions o;
  if (const int code = read_options(args, "check", check_help(), false, o); code >= 0) return code;
  KokkosSession kokkos(1);
  try {
    const PreparedRun p = prepare(o);
    const std::string physics = require_analyses_and_physics(p);
    std::printf("scene        %s\n", o.scene.c_str());
    std::printf("physics      %s (%s)\n", physics.c_str(),
                p.scene.contact.wall_adhesion ? "same law on walls" : "walls without adhesion");
    {
      const ContactSpec& c = p.scene.contact;
      const bool spring = models::is_spring_like(c.normal);
      const bool adhesive = c.normal == "jkr" || c.adhesion == "dmt";
      char at_speed[160];
      std::snprintf(at_speed, sizeof at_speed,
                    "eta solved from the damped %s collision at %g x the sticking velocity (adhesive pairs; "
                    "non-adhesive ones as Hertz)",
                    c.normal == "jkr" ? "JKR" : "DMT", c.restitution_speed_ratio);
      std::printf("damping      %s: %s\n", c.damping.c_str(),
                  spring                        ? "eta = 2|beta(e)|, exact for the linear spring"
                  : c.damping == "beta_formula" ? "eta = 2 sqrt(5/6) |beta(e)| (Tsuji, as LIGGGHTS / EDEM)"
                  : adhesive && c.restitution_speed_ratio > 0
                      ? at_speed
                      : (c.normal == "jkr" ? "eta = 2 sqrt(5/6) |beta(e)|, exact for the unclamped Hertz-JKR "
                                             "contact far above the sticking velocity"
                                           : "eta solved from the damped Hertz equation (force held >= 0)"));
      for (std::size_t m = 0; m < p.scene.materials.size(); ++m)
        std::printf(
            "             %s: e = %g -> eta = %.6g\n", p.scene.materials[m].name.c_str(),
            p.scene.materials[m].restitution,
            damping_coefficient(p.scene.materials[m].restitution, c, p.scene.materials[m].surface_energy));
      std::printf("lever arm    %s%s\n", resolved_lever_arm(p.scene).c_str(),
                  c.lever_arm == "auto" ? " (auto: radius under chen_elliott, else contact_point)" : "");
      if (c.normal == "jkr") std::printf("jkr          separation at %s\n", c.jkr_separation.c_str());
    }
    std::printf("time step    %.4g s: %s\n", p.dt.step, p.dt.reason.c_str());
    std::printf("             Rayleigh time %.4g s, shortest contact time %.4g s, %.0f steps per contact\n",
                p.dt.rayleigh_time, p.dt.contact_time, p.dt.contact_time / p.dt.step);
    std::printf("end time     %.4g s = %.0f steps\n", p.scene.time.end,
                std::ceil(p.scene.time.end / p.dt.step));
    std::size_t from_inlets = 0;
    for (std::size_t g = 0; g < p.scene.groups.size(); ++g)
      if (p.scene.groups[g].placement.kind == "inlet")
        for (int gi : p.particles.group)
          from_inlets += gi == static_cast<int>(g);
    std::printf("particles    %zu", p.particles.size());
    if (from_inlets > 0)
      std::printf(" (%zu placed at the start, %zu from inlets during the run)",
                  p.particles.size() - from_inlets, from_inlets);
    std::printf("\n");
    for (std::size_t g = 0; g < p.scene.groups.size(); ++g) {
      std::size_t count = 0;
      for (int gi : p.particles.group)
        count += gi == static_cast<int>(g);
      const auto& cg = p.scene.groups[g].coarse_grain;
      std::printf("  group %-10s %zu particles, material %s, coarse-graining %s (k = %g",
                  p.scene.groups[g].name.c_str(), count, p.scene.groups[g].material.c_str(), cg.law.c_str(),
                  cg.factor);
      if (cg.surface_energy_power >= 0) std::printf(", surface energy ~ k^%g", cg.surface_energy_power);
      std::printf(")\n");
    }
    std::printf("walls        %zu named, %zu parts\n", p.config.wall_names.size(), p.config.walls.size());
    for (const WallSpec& w : p.scene.walls)
      if (w.mesh)
        std::printf(
            "  mesh %-12s %zu triangles, %zu vertices, bounding box [%.4g, %.4g, %.4g] - [%.4g, %.4g, "
            "%.4g] m (%s)\n",
            w.name.c_str(), w.mesh->triangles.size(), w.mesh->vertices.size(), w.mesh->lo[0], w.mesh->lo[1],
            w.mesh->lo[2], w.mesh->hi[0], w.mesh->hi[1], w.mesh->hi[2], w.file.c_str());
    // What a wall's motion does beyond its prescribed segments.
    for (const WallSpec& w : p.scene.walls) {
      for (int k = -1; k < static_cast<int>(w.then.size()); ++k)
        if (w.segment(k).until_force > 0)
          std::printf("  wall %-12s %s ends at %.4g N against its velocity (until_force), else at %.4g s\n",
                      w.name.c_str(), k < 0 ? "motion" : ("motion.then." + std::to_string(k)).c_str(),
                      w.segment(k).until_force, w.segment(k).stop);
      if (w.oscillation.amplitude > 0) {
        char until[48] = "";
        if (w.oscillation.stop < 1e299) std::snprintf(until, sizeof until, " to %.4g s", w.oscillation.stop);
        std::printf("  wall %-12s oscillates %.4g m at %.4g Hz along [%.3g, %.3g, %.3g] from %.4g s%s\n",
                    w.name.c_str(), w.oscillation.amplitude, w.oscillation.frequency,
                    w.oscillation.direction[0], w.oscillation.direction[1], w.oscillation.direction[2],
                    w.oscillation.start, until);
      }
    }
    std::printf("skin         %.4g m\n", p.config.skin);
    // Measured, not estimated: the engine as `run` builds it (store, first neighbour list with its history,
    // cells), plus the host copy each output frame takes while the writer runs (FrameData: id, position,
    // velocity, angular velocity, radius, mass, group).
    {
      const auto engine = make_engine(p.config, default_backend());
      const double n = std::max(1.0, static_cast<double>(engine->size()));
      const double frame = n * double(FrameData::bytes_per_particle());
      if (engine->size() > 0)
        std::printf("memory       %s in the engine (%.0f B per particle after the first neighbour list) + %s "
                    "per output frame%s\n",
                    human_bytes(double(engine->bytes())).c_str(), double(engine->bytes()) / n,
                    human_bytes(frame).c_str(),
                    from_inlets > 0 ? " at the start; each particle an inlet adds costs about as much" : "");
      else
        std::printf("memory       %s in the engine before the inlets add their particles (cells and walls)\n",
                    human_bytes(double(engine->bytes())).c_str());
    }
    for (const std::string& w : resolution_warnings(p.scene))
      std::printf("%s\n", w.c_str());
    return 0;
  } catch (const SceneError& e) {
    std::cerr << "cgdem: " << e.what() << "\n";
    return exit_bad_input;
  } catch (const std::exception& e) {
    std::cerr << "cgdem: " << o.scene << ": " << e.what() << "\n";
    return exit_bad_input;
  }
}

int info_command(const std::vector<std::string>& args) {
  if (wants_help(args)) {
    std::cout << info_help();
    return 0;
  }
  int threads = 0;
  for (std::size_t k = 0; k + 1 < args.size(); ++k)
    if (args[k] == "--threads") threads = std::atoi(args[k + 1].c_str());
  KokkosSession kokkos(threads);
  std::printf("cgdem %s\n", CGDEM_VERSION);
  std::printf("Kokkos %d.%d.%d\n", KOKKOS_VERSION / 10000, KOKKOS_VERSION / 100 % 100, KOKKOS_VERSION % 100);
  std::printf("backends:");
  for (const auto& b : compiled_backends())
    std::printf(" %s (%d threads)", b.c_str(), backend_threads(b));
  std::printf("\ndefault backend: %s\n", default_backend().c_str());
  std::printf("compiled contact laws (normal[+adhesion][+tangential][+rolling]):\n");
  for (const auto& c : compiled_physics())
    std::printf("  %s\n", c.c_str());
  std::printf("force accumulation: half neighbour list, reactions added to the partners block by block in "
              "4 colours (no atomics; deterministic on every backend)\n");
  std::printf("precision: positions, velocities, total forces double; contact history %s\n",
              sizeof(ForceReal) == sizeof(float) ? "float (CGDEM_FLOAT_FORCES)" : "double");
  std::printf("instruction set: %s (CGDEM_ARCH)\n", CGDEM_ARCH);
  return 0;
}

} // namespace cgdem
