#include "drivers/cli.hpp"
#include <stdexcept>

namespace cgdem {

namespace {
double to_number(const std::string& opt, const std::string& v) {
  try {
    std::size_t used = 0;
    const double x = std::stod(v, &used);
    if (used == v.size()) return x;
  } catch (const std::exception&) {
  }
  throw CliError("option " + opt + " expects a number, got '" + v + "'");
}
} // namespace

RunOptions parse_run_options(const std::vector<std::string>& args, bool run_options) {
  RunOptions o;
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& a = args[k];
    auto value = [&]() -> std::string {
      const auto eq = a.find('=');
      if (a.rfind("--", 0) == 0 && eq != std::string::npos) return a.substr(eq + 1);
      if (k + 1 >= args.size()) throw CliError("option " + a + " needs a value (see --help)");
      return args[++k];
    };
    const std::string name = a.substr(0, a.find('='));
    if (name == "--set")
      o.overrides.push_back(value());
    else if (name == "--threads") {
      const double t = to_number(name, value());
      if (t < 1 || t != static_cast<int>(t)) throw CliError("--threads expects a positive integer");
      o.threads = static_cast<int>(t);
    } else if (name == "--backend")
      o.backend = value();
    else if (run_options && name == "--out")
      o.out = value();
    else if (run_options && name == "--checkpoint-every") {
      o.checkpoint_every = to_number(name, value());
      if (o.checkpoint_every <= 0)
        throw CliError("--checkpoint-every expects a positive simulated time in seconds");
    } else if (run_options && name == "--restart")
      o.restart = value();
    else if (run_options && (name == "--quiet" || name == "-q"))
      o.quiet = true;
    else if (!a.empty() && a[0] == '-')
      throw CliError("unknown option '" + a + "' (see --help)");
    else if (o.scene.empty())
      o.scene = a;
    else
      throw CliError("unexpected argument '" + a + "': one scene file per run (use 'cgdem sweep' for many)");
  }
  if (o.scene.empty()) throw CliError("no scene file given (see --help)");
  return o;
}

const char* main_help() {
  return R"(cgdem - coarse-grained discrete element simulation of (cohesive) powders

Usage: cgdem <command> [options]

Commands:
  run SCENE.yaml     simulate a scene; writes HDF5 + XDMF (open the .xdmf in ParaView)
  check SCENE.yaml   validate a scene and print its physics, time step, size and memory; no simulation
  info               version, Kokkos backends and the compiled contact laws
  sweep SCENE.yaml   run a scene at several coarse-graining laws and scale factors against the k = 1
                     reference: speed-up and error of each run (sweep.csv, sweep.h5, PNG plots)
  stability SCENE.yaml  probe a range of time steps; largest stable step vs Rayleigh/contact time
  analyse RUN.h5     evaluate a scene's analyses again over a run's saved frames (other parameters,
                     other analyses, the parts of a continued run); nothing is simulated

Run 'cgdem <command> --help' for the options of a command.

Examples:
  cgdem run scenes/pile_in_cylinder.yaml
  cgdem run scenes/pile_in_cylinder.yaml --set groups.0.count=1000 --threads 2 --out small.h5
  cgdem check scenes/rotating_drum.yaml
  cgdem sweep sweeps/tiny_pile.yaml --laws chen_elliott,bond --k 1,2,3 --out tiny_sweep
  cgdem analyse pile.h5 --set analyses.0.bin_width=0.002
)";
}

const char* run_help() {
  return R"(Usage: cgdem run SCENE.yaml [options]

Simulates SCENE.yaml (format: docs/scene_format.md) and writes frames every output.every seconds of
simulated time to an HDF5 file with an XDMF file beside it (ParaView opens the .xdmf directly).
A progress line shows simulated time, particle-steps per second and the ETA; a summary closes the run.

Options:
  --set key.path=value   override any scene key before validation; nested keys with dots, list items
                         by index (groups.0.count=500); value in YAML syntax ([0,0,0.01], 1e7, true).
                         Repeat for several keys.
  --out FILE.h5          output file (default: the scene's output.file)
  --threads N            OpenMP threads (default: all cores)
  --backend NAME         openmp | serial | cuda, as compiled (see 'cgdem info'); trajectories are bitwise
                         identical across backends and thread counts
  --checkpoint-every T   write the full restart state every T simulated seconds and at the run's end to
                         FILE.checkpoint.h5 (atomically: a kill never leaves a half-written checkpoint)
  --restart FILE         continue from a checkpoint; the continuation is bitwise identical to an
                         uninterrupted run. The scene may differ from the checkpoint's in what is not
                         particle state (materials, wall and outlet positions and motions, the domain,
                         time.end): a second stage, e.g. a bed poured with low friction and then
                         compressed ('cgdem sweep --first-stage'); the contact law, walls, inlets,
                         outlets and analyses must be the same, and the particle count unless inlets
                         or outlets change it
  --quiet                no progress line

Exit codes: 0 done, 2 bad input (one line naming the file, key and fix; also an output path that cannot
be written, a corrupt particle file or checkpoint, a scene needing more memory than the machine has),
3 numerical blow-up (step, particle, neighbours and likely cause; the last good frame stays in the file),
4 output write failed during the run (disk full, file removed: the file keeps every completed frame and
a checkpoint of the current state is written when --checkpoint-every was given).

Examples:
  cgdem run scenes/pile_in_cylinder.yaml
  cgdem run scenes/periodic_box.yaml --set materials.grains.youngs_modulus=1e8 --set time.end=0.01
  cgdem run scenes/settled_bed.yaml --threads 1 --backend serial --out serial.h5
  cgdem run scenes/pile_in_cylinder.yaml --checkpoint-every 0.1
  cgdem run scenes/pile_in_cylinder.yaml --restart pile_in_cylinder.checkpoint.h5
  mpirun -np 4 cgdem run scenes/settled_bed.yaml --threads 1
      (4 MPI ranks, each on its brick of the domain: the same result file, the trajectory to round-off;
      a checkpoint of N ranks restarts on M; docs/mpi.md)
)";
}

const char* check_help() {
  return R"(Usage: cgdem check SCENE.yaml [--set key.path=value ...]

Validates the scene exactly as 'run' would (same errors, exit code 2) and prints, without simulating:
the compiled contact law, the time step with the rule and material pair that set it, the particle
count per group, the neighbour skin and the memory: what the engine holds once it has built its first
neighbour list (built here on one thread, as 'run' would) and what each output frame adds.

Examples:
  cgdem check scenes/pile_in_cylinder.yaml
  cgdem check scenes/pile_in_cylinder.yaml --set time.step=1e-4     # refused: above the stable limit
)";
}

const char* info_help() {
  return R"(Usage: cgdem info [--threads N]

Prints the cgdem version, the Kokkos version, the enabled backends and their thread counts, and the
contact-law combinations compiled into this binary (a scene must name one of them).
)";
}

} // namespace cgdem
