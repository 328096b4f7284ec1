#pragma once
// `cgdem sweep`: the scene run at every (coarse-graining law, scale factor k) against the k = 1 reference of
// original-size particles, as separate `cgdem run` processes; speed-up and error of each run against the
// reference, written to DIR/sweep.csv, DIR/sweep.h5 and PNG plots (docs/sweeps.md).
//
// Each finished run leaves a record DIR/records/<run>.txt (written atomically: temporary file, fsync,
// rename); a run whose record exists is complete and is skipped when the sweep is started again. The
// tables and plots are computed only from the records.
#include <map>
#include <string>
#include <vector>

namespace cgdem {

struct SweepOptions {
  std::string scene;
  std::vector<std::string> laws;
  std::vector<double> factors;        // --k
  std::vector<std::string> overrides; // --set, applied before the sweep's own
  // --coarse-set: key=value of every group's coarse_grain map in the coarse-grained runs (a law's option,
  // e.g. surface_energy_power=1), applied after the sweep's {law, factor}; the reference has none.
  std::vector<std::string> coarse_sets;
  std::string out = "sweep";   // directory
  int threads = 0;             // 0: all hardware threads
  std::string policy = "auto"; // auto | serial | parallel
  bool quiet = false;
  bool plots = true; // --no-plots: skip the python plots
  // --seeds: every case once per seed of the initial packing (groups.<g>.placement.seed = seed + 1000 g);
  // empty: once, with the scene's seeds. --reference-seeds: the reference's own (default: --seeds).
  std::vector<long> seeds, reference_seeds;
  // --checkpoint-every: each run checkpoints every T simulated seconds, and a run stopped before its
  // record was written continues from its checkpoint when the sweep is started again. 0: off.
  double checkpoint_every = 0;
  // --first-stage: overrides of a first stage that every run runs first (to that stage's time.end), each
  // run then continuing from the stage's last step with the scene as given (`cgdem run --restart`): a
  // bed poured with low friction and then compressed, a periodic sample then set free. Empty: one stage.
  std::vector<std::string> first_stage;
  double first_stage_end = 0; // the first stage's time.end, from the scene with its overrides
};

// One run's own figures, as recorded.
struct RunRecord {
  std::string run, law, status; // status: ok | failed (exit N)
  double k = 1;
  int exit_code = 0;
  long particles = 0, steps = 0;
  double mass = 0; // kg, of the run's particles at the start (0: not recorded)
  double time_step = 0, wall_time = 0, particle_steps_per_s = 0, engine_particle_steps_per_s = 0;
  double cpu_time = 0; // user + system seconds of the run's process (0: not recorded)
  int threads = 1;
  long seed = -1; // the --seeds entry the run used (-1: the scene's own seeds)
  int pieces = 1; // processes it took (> 1: continued from checkpoints; times summed, CPU time estimated)
  std::map<std::string, double> values;               // final value of every analysis output
  std::map<std::string, std::vector<double>> samples; // distribution analyses: final-frame samples
};

void write_record(const std::string& path, const RunRecord& r); // atomic
RunRecord read_record(const std::string& path);                 // throws std::runtime_error

// What a sweep takes from the scene's analyses to compare runs.
struct SweepAnalyses {
  std::vector<std::string> main;               // the values compared (Analysis::metric of each analysis)
  std::vector<std::string> distributions;      // distribution analyses: their samples are compared
  std::map<std::string, double> mass_exponent; // value -> p, value ~ mass^p (Analysis::mass_exponents)
};

// A run against the reference: speed-up = reference wall time / run wall time (speedup_cpu: the same with
// CPU seconds, which a loaded machine does not distort for single-threaded runs); errors = |x - x_ref| /
// |x_ref| per value (|x - x_ref| when x_ref = 0); W1 and KS between the sample sets of each distribution.
// mass_matched: the same error against the reference corrected to the run's mass, x_ref (m / m_ref)^p, for
// each value with a mass exponent p, when both masses are recorded.
// A run is failed when it exited non-zero or lacks a finite main figure (a value, or a distribution's
// samples): `ok` is false and `status` says why ("failed (exit 3)", "failed (nan: pile)"). A reference
// that exited non-zero leaves every error out; one with a nan value, the errors of that value.
struct SweepRow {
  RunRecord record;
  bool ok = true;
  std::string status;
  double speedup = 0, speedup_cpu = 0;
  std::map<std::string, double> error, mass_matched, w1, ks;
};
std::vector<SweepRow> compare_runs(const std::vector<RunRecord>& runs, const RunRecord& reference,
                                   const SweepAnalyses& analyses = {});
// |x / x_ref' - 1| with x_ref' = x_ref (mass / ref_mass)^p (|x - x_ref'| when x_ref' = 0): the relative error
// against the reference scaled to the run's mass; nan when a mass is not positive.
double mass_matched_error(double x, double x_ref, double mass, double ref_mass, double p);

SweepOptions parse_sweep_options(const std::vector<std::string>& args); // throws CliError
const char* sweep_help();
int sweep_command(const std::vector<std::string>& args);

} // namespace cgdem
