#pragma once
// `cgdem stability`: short probes of a scene over a range of time steps (Hu et al. Fig. 20 method).
//
// Two variants of the scene are probed at every step size:
//  - "conservative": restitution 1, friction 0, rolling friction 0, no adhesion (JKR -> Hertz, EEPA ->
//    its linear loading spring), walls at rest, gravity kept only if a floor holds the particles. Its
//    total energy (kinetic + rotational + elastic + gravitational) must stay constant; the probe fits the
//    relative energy change per characteristic time (Rayleigh time, or the contact time for the linear
//    laws) and calls the step unstable when that growth exceeds a threshold or the engine blows up.
//  - "given": the scene as written. Unstable when the engine throws BlowUpError, or (for non-adhesive,
//    undriven scenes, whose energy can only fall) when its energy grows above the threshold.
// The largest stable step of each variant is the last stable probe below the first unstable one,
// optionally refined by bisection.
#include <limits>
#include <string>
#include <vector>
#include "setup/engine_config.hpp"
#include "core/scene.hpp"
#include "setup/time_step.hpp"
#include "kernels/engine.hpp"

namespace cgdem {

struct StabilitySettings {
  std::vector<double> dts;        // absolute steps in seconds; empty: 0.1 to 10 x the stable limit
  long steps = 2000;              // steps per probe (when probe_time is 0)
  double probe_time = 0;          // > 0: each probe runs this simulated time instead (ceil(time / dt) steps)
  int samples = 20;               // energy samples per probe (least-squares slope)
  double growth_threshold = 1e-4; // relative energy growth per characteristic time that is unstable
  int refine = 3;                 // bisection steps between the last stable and the first unstable
  bool conservative = true, given = true;
  std::string backend;  // empty: the first compiled
  bool verbose = false; // one line per probe on stderr
};

struct StabilityProbe {
  std::string variant; // "conservative" | "given"
  double dt = 0;
  long steps = 0; // completed steps
  double energy_start = 0, energy_end = 0;
  double growth = 0;          // d(E/E0)/dt x characteristic time (least squares over samples)
  double growth_error = 0;    // its standard error (from the fit's residuals; 0 with fewer than 3 samples)
  double max_change = 0;      // max |E/E0 - 1| over the samples
  bool growth_checked = true; // false: energy may legitimately grow (adhesion, moving walls)
  bool blew_up = false;
  std::string diagnosis; // BlowUpError::what()
  bool stable = false;
};

struct StabilityResult {
  TimeStepEstimate estimate;          // of the scene as given (auto step, T_R, t_c, limit)
  double characteristic_time = 0;     // T_R, or t_c when there is no Rayleigh time (linear laws)
  bool gravity_kept = false;          // in the conservative variant
  std::vector<StabilityProbe> probes; // in the order run
  // Largest stable step and smallest unstable step of each variant (0 / +inf when none).
  double critical_conservative = 0, unstable_conservative = std::numeric_limits<double>::infinity();
  double critical_given = 0, unstable_given = std::numeric_limits<double>::infinity();
};

// Least-squares line y = a + b x through the points: the slope b and its standard error
// sqrt(sum(residual^2) / (n - 2) / sum((x - mean x)^2)) (0 with fewer than three points). Hu's criterion
// calls a step unstable when the energy's growth rate is above zero beyond its uncertainty: b > 2 x error.
struct SlopeFit {
  double slope = 0, std_error = 0;
};
SlopeFit fit_slope(const std::vector<double>& x, const std::vector<double>& y);

// Whether a probe's growth is above zero by more than two standard errors (Hu et al. 2022's criterion,
// "the energy increase rate becomes positive", with the fit's uncertainty as the margin).
inline bool grows_significantly(const StabilityProbe& p) {
  return p.blew_up || p.growth > 2 * p.growth_error;
}

// The frictionless, undamped, non-adhesive variant (see above); *gravity_kept tells whether a floor kept
// gravity on.
Scene conservative_scene(const Scene& scene, bool* gravity_kept = nullptr);

// Total mechanical energy of the engine's current state: kinetic + rotational + gravitational potential
// (-m g.x) + elastic energy of every overlapping particle pair and wall contact for the normal law of
// `config` (Hertz 8/15 E* sqrt(R*) delta^2.5; linear 1/2 k_n delta^2; EEPA 1/2 k1 delta^2, exact for its
// conservative variant). Uses the engine's neighbour list (from a checkpoint), so it is exact for the
// pairs the engine sees. Adhesive and scaled (coarse-graining) energies are not included.
double total_energy(const EngineConfig& config, Engine& engine);

// One probe: `steps` steps at `dt` of the given particles and scene (no step-size check).
StabilityProbe stability_probe(const Scene& scene, const ParticleSet& particles, double dt,
                               const StabilitySettings& settings, const std::string& variant);

StabilityResult stability_scan(const Scene& scene, const ParticleSet& particles,
                               const StabilitySettings& settings);

// Writes DIR/stability.csv (one row per probe) and DIR/summary.md; returns the CSV path. Throws
// std::runtime_error naming the file when one cannot be written in full.
std::string write_stability_report(const std::string& dir, const std::string& scene_name,
                                   const StabilityResult& r, const StabilitySettings& settings);

int stability_command(const std::vector<std::string>& args);
const char* stability_help();

} // namespace cgdem
