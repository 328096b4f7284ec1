#include "drivers/stability_command.hpp"
#include "drivers/kokkos_session.hpp"
#include <Kokkos_Core.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include "drivers/cli.hpp"
#include "drivers/engine_setup.hpp"
#include "drivers/particle_generation.hpp"
#include "drivers/preflight.hpp"
#include "drivers/scene_parser.hpp"
#include "models/component_lists.hpp"

namespace cgdem {

namespace {

bool compiled(const ContactSpec& c) {
  const std::string name = physics_name(c);
  for (const auto& p : compiled_physics())
    if (p == name) return true;
  return false;
}

double dot3(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// A floor holds the particles when a plane (or a capped cylinder) faces against gravity on an axis
// that is not periodic.
bool floor_holds(const Scene& s) {
  const double g = std::sqrt(dot3(s.gravity, s.gravity));
  if (g == 0) return false;
  for (int a = 0; a < 3; ++a)
    if (s.domain.periodic[a] && std::fabs(s.gravity[a]) > 1e-6 * g) return false;
  for (const WallSpec& w : s.walls) {
    if (w.type == "plane" && dot3(w.normal, s.gravity) < -0.5 * g * std::sqrt(dot3(w.normal, w.normal)))
      return true;
    if (w.type == "cone" && std::min(w.radius, w.end_radius) == 0 &&
        std::fabs(dot3(w.axis, s.gravity)) > 0.5 * g * std::sqrt(dot3(w.axis, w.axis)))
      return true;
    if (w.type == "cylinder" && w.caps &&
        std::fabs(dot3(w.axis, s.gravity)) > 0.5 * g * std::sqrt(dot3(w.axis, w.axis)))
      return true;
  }
  return false;
}

bool driven(const Scene& s) {
  for (const WallSpec& w : s.walls)
    if (w.translates() || w.angular_velocity != 0) return true;
  return false;
}

bool adhesive(const Scene& s) {
  if (s.contact.adhesion != "none") return true;
  if (s.contact.normal == "jkr") return true;
  if (s.contact.normal == "eepa") return true; // hysteretic: energy bookkeeping not exact
  return false;
}

double characteristic_time(const TimeStepEstimate& e) {
  if (std::isfinite(e.rayleigh_time) && e.rayleigh_time > 0) return e.rayleigh_time;
  return e.contact_time;
}

// Reference positions by id for the gravitational potential (measured from the start of each probe).
struct EnergyMeter {
  const EngineConfig* config = nullptr;
  std::map<std::int64_t, Vec3> x0;
  double measure(Engine& engine, bool set_reference);
};

double EnergyMeter::measure(Engine& engine, bool set_reference) {
  const EngineConfig& cfg = *config;
  const Observables o = engine.observe();
  const CheckpointData c = engine.checkpoint();
  const auto& id = c.ints.at("id");
  const auto& mat = c.ints.at("material");
  const auto& off = c.ints.at("nl_offsets");
  const auto& nb = c.ints.at("nl_neighbors");
  const auto& x = c.reals.at("position");
  const auto& r = c.reals.at("radius");
  const auto& m = c.reals.at("mass");
  const int nm = cfg.num_materials;
  const std::string law = cfg.contact.normal;
  auto elastic = [&](const models::PairParameters& p, double r_eff, double delta) {
    if (delta <= 0) return 0.0;
    if (law == "linear") return 0.5 * p.k_n * delta * delta;
    if (law == "eepa") return 0.5 * p.eepa_k1 * delta * delta;
    return 8.0 / 15.0 * p.E_eff * std::sqrt(r_eff) * std::pow(delta, 2.5);
  };
  const std::size_t n = id.size();
  if (set_reference) x0.clear();
  double u = 0, pot = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 xi{x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    if (set_reference) x0[id[i]] = xi;
    const Vec3 d = cfg.domain.minimum_image(xi - x0.at(id[i]));
    pot -= m[i] * dot(cfg.gravity, d);
    for (auto k = off[i]; k < off[i + 1]; ++k) {
      const auto j = static_cast<std::size_t>(nb[k]);
      if (j < i) continue; // full list: each pair once
      const Vec3 xj{x[3 * j], x[3 * j + 1], x[3 * j + 2]};
      const double dist = norm(cfg.domain.minimum_image(xj - xi));
      const double r_eff = r[i] * r[j] / (r[i] + r[j]);
      u += elastic(cfg.pair_params[mat[i] * nm + mat[j]], r_eff, r[i] + r[j] - dist);
    }
    for (const Wall& w : cfg.walls) {
      const WallContact wc = wall_contact(w, engine.time(), xi, r[i]);
      if (wc.reachable) u += elastic(cfg.wall_params[mat[i] * nm + w.material], r[i], wc.overlap);
    }
  }
  return o.kinetic_energy + o.rotational_energy + u + pot;
}

// "0.1tr" -> 0.1 T_R, "0.5tc" -> 0.5 t_c, "2limit" -> 2 x the stable limit, "1e-7" -> seconds.
double parse_step(const std::string& text, const TimeStepEstimate& e) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    throw CliError("cannot read time step '" + text + "' (a number in s, or with tr / tc / limit)");
  }
  const std::string unit = text.substr(used);
  if (unit.empty() || unit == "s") return v;
  if (unit == "tr") return v * e.rayleigh_time;
  if (unit == "tc") return v * e.contact_time;
  if (unit == "limit") return v * e.limit;
  throw CliError("unknown unit '" + unit + "' in time step '" + text + "' (use s, tr, tc or limit)");
}

std::vector<double> geometric(double lo, double hi, int n) {
  std::vector<double> out;
  if (n <= 1) return {lo};
  for (int k = 0; k < n; ++k)
    out.push_back(lo * std::pow(hi / lo, double(k) / (n - 1)));
  return out;
}

} // namespace

Scene conservative_scene(const Scene& scene, bool* gravity_kept) {
  Scene s = scene;
  for (MaterialSpec& m : s.materials) {
    m.restitution = 1;
    m.friction = 0;
    m.rolling_friction = 0;
    m.surface_energy = 0;
    // Every attractive parameter a component declares (liquid bridges, EEPA's adhesive branch) off.
    models::for_each_component([&](auto component) {
      using C = typename decltype(component)::type;
      models::for_each_material_parameter<C>([&](const char* block, const models::MaterialParameter& d) {
        if (d.attractive) m.law_parameters[models::parameter_path(block, d)] = 0;
      });
    });
    // EEPA unloads along its loading line: elastic, no plastic overlap.
    if (s.contact.normal == "eepa") m.law_parameters["eepa.k2"] = m.law_parameter("eepa.k1", 0);
  }
  for (PairOverrideSpec& p : s.pair_overrides) {
    if (p.restitution >= 0) p.restitution = 1;
    if (p.friction >= 0) p.friction = 0;
    if (p.rolling_friction >= 0) p.rolling_friction = 0;
    if (p.surface_energy >= 0) p.surface_energy = 0;
  }
  for (WallSpec& w : s.walls) {
    w.velocity = {0, 0, 0};
    w.then.clear();
    w.angular_velocity = 0;
  }
  const bool keep = floor_holds(scene);
  if (!keep) s.gravity = {0, 0, 0};
  if (gravity_kept) *gravity_kept = keep;
  if (s.contact.normal == "jkr") s.contact.normal = "hertz";
  s.contact.adhesion = "none";
  // Prefer no tangential / rolling component; with friction 0 a compiled Mindlin spring exerts no force.
  // Direct force scaling (Hu, Sakai) is compiled with the Mindlin spring only: keep the components then.
  bool direct_scaling = false;
  for (const GroupSpec& g : s.groups)
    direct_scaling =
        direct_scaling || g.coarse_grain.law.rfind("hu_method", 0) == 0 || g.coarse_grain.law == "sakai";
  if (direct_scaling) return s;
  const Scene original = s;
  s.contact.tangential = "none";
  s.contact.rolling = "none";
  if (!compiled(s.contact)) {
    s.contact.tangential = original.contact.tangential == "none" ? "mindlin" : original.contact.tangential;
    if (!compiled(s.contact)) s.contact.rolling = original.contact.rolling;
  }
  return s;
}

double total_energy(const EngineConfig& config, Engine& engine) {
  EnergyMeter meter;
  meter.config = &config;
  return meter.measure(engine, true);
}

SlopeFit fit_slope(const std::vector<double>& x, const std::vector<double>& y) {
  SlopeFit f;
  const std::size_t n = x.size();
  if (n < 2 || y.size() != n) return f;
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < n; ++k) {
    mx += x[k];
    my += y[k];
  }
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < n; ++k) {
    sxx += (x[k] - mx) * (x[k] - mx);
    sxy += (x[k] - mx) * (y[k] - my);
  }
  if (!(sxx > 0)) return f;
  f.slope = sxy / sxx;
  if (n < 3) return f;
  double ss = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double r = y[k] - (my + f.slope * (x[k] - mx));
    ss += r * r;
  }
  f.std_error = std::sqrt(ss / static_cast<double>(n - 2) / sxx);
  return f;
}

StabilityProbe stability_probe(const Scene& scene, const ParticleSet& particles, double dt,
                               const StabilitySettings& settings, const std::string& variant) {
  TimeStepEstimate est = estimate_time_step(scene, particles);
  const double tau = characteristic_time(est);
  est.step = dt;
  const EngineConfig cfg = make_engine_config(scene, particles, est);
  const std::string backend = settings.backend.empty() ? compiled_backends().front() : settings.backend;
  StabilityProbe p;
  p.variant = variant;
  p.dt = dt;
  p.growth_checked = variant == "conservative" || (!adhesive(scene) && !driven(scene));
  std::unique_ptr<Engine> engine = make_engine(cfg, backend);
  EnergyMeter meter;
  meter.config = &cfg;
  p.energy_start = meter.measure(*engine, true);
  // Relative to the energy that can move: kinetic + elastic at the start (potential measured from there).
  const double scale = std::max(std::fabs(p.energy_start), 1e-300);
  std::vector<double> t{0}, e{0};
  const int samples = std::max(2, settings.samples);
  try {
    const long steps = settings.probe_time > 0 ? static_cast<long>(std::ceil(settings.probe_time / dt - 1e-9))
                                               : settings.steps;
    for (int k = 1; k <= samples; ++k) {
      const long target = steps * k / samples;
      engine->advance(target - engine->step());
      const double en = meter.measure(*engine, false);
      t.push_back(engine->time());
      e.push_back(en / scale - 1);
      p.energy_end = en;
      if (!std::isfinite(en))
        throw BlowUpError("the total energy became NaN or Inf at step " + std::to_string(engine->step()));
    }
  } catch (const BlowUpError& err) {
    p.blew_up = true;
    p.diagnosis = err.what();
  }
  p.steps = engine->step();
  for (double v : e)
    p.max_change = std::max(p.max_change, std::fabs(v));
  // Least-squares slope of E/E0 - 1 against time, per characteristic time.
  const SlopeFit fit = fit_slope(t, e);
  p.growth = fit.slope * tau;
  p.growth_error = fit.std_error * tau;
  if (p.blew_up) {
    p.growth = std::numeric_limits<double>::infinity();
    p.growth_error = 0;
  }
  p.stable = !p.blew_up && (!p.growth_checked || p.growth <= settings.growth_threshold);
  if (settings.verbose)
    std::fprintf(
        stderr,
        "  %-12s dt %.4g s (%.4f T_R), %ld steps: %s, energy growth %.3g +- %.2g per T_R, max |E/E0-1| "
        "%.3g\n",
        variant.c_str(), dt, dt / est.rayleigh_time, p.steps,
        p.blew_up ? "BLOW-UP" : (p.stable ? "stable" : "UNSTABLE"), p.growth, p.growth_error, p.max_change);
  return p;
}

StabilityResult stability_scan(const Scene& scene, const ParticleSet& particles,
                               const StabilitySettings& settings) {
  StabilityResult r;
  r.estimate = estimate_time_step(scene, particles);
  r.characteristic_time = characteristic_time(r.estimate);
  const Scene elastic = conservative_scene(scene, &r.gravity_kept);
  std::vector<double> dts = settings.dts;
  if (dts.empty()) dts = geometric(0.1 * r.estimate.limit, 10 * r.estimate.limit, 13);
  std::sort(dts.begin(), dts.end());
  auto scan = [&](const Scene& s, const std::string& variant, double& critical, double& unstable) {
    int failures = 0;
    for (double dt : dts) {
      const StabilityProbe p = stability_probe(s, particles, dt, settings, variant);
      r.probes.push_back(p);
      if (p.stable && dt < unstable) critical = std::max(critical, dt);
      if (!p.stable) {
        unstable = std::min(unstable, dt);
        if (++failures >= 2) break;
      } else {
        failures = 0;
      }
    }
    for (int k = 0; k < settings.refine && critical > 0 && std::isfinite(unstable); ++k) {
      const double mid = std::sqrt(critical * unstable);
      const StabilityProbe p = stability_probe(s, particles, mid, settings, variant);
      r.probes.push_back(p);
      (p.stable ? critical : unstable) = mid;
    }
  };
  if (settings.conservative) scan(elastic, "conservative", r.critical_conservative, r.unstable_conservative);
  if (settings.given) scan(scene, "given", r.critical_given, r.unstable_given);
  return r;
}

std::string write_stability_report(const std::string& dir, const std::string& scene_name,
                                   const StabilityResult& r, const StabilitySettings& settings) {
  std::filesystem::create_directories(dir);
  const std::string csv = (std::filesystem::path(dir) / "stability.csv").string();
  const TimeStepEstimate& e = r.estimate;
  {
    std::ofstream out(csv);
    out << "# cgdem stability " << scene_name << ": rayleigh_time " << e.rayleigh_time << " s, contact_time "
        << e.contact_time << " s, limit " << e.limit << " s, auto_step " << e.step << " s, threshold "
        << settings.growth_threshold << " per characteristic time " << r.characteristic_time << " s\n";
    out << "variant,dt,dt_over_rayleigh,dt_over_contact,steps,energy_start,energy_end,growth_per_char_time,"
           "max_rel_change,growth_checked,blew_up,stable,growth_std_error,grows\n";
    char line[512];
    auto sorted = r.probes;
    std::stable_sort(sorted.begin(), sorted.end(), [](const StabilityProbe& a, const StabilityProbe& b) {
      return a.variant != b.variant ? a.variant < b.variant : a.dt < b.dt;
    });
    for (const StabilityProbe& p : sorted) {
      std::snprintf(line, sizeof line, "%s,%.6e,%.6f,%.6f,%ld,%.10e,%.10e,%.6e,%.6e,%d,%d,%d,%.6e,%d\n",
                    p.variant.c_str(), p.dt, p.dt / e.rayleigh_time, p.dt / e.contact_time, p.steps,
                    p.energy_start, p.energy_end, p.growth, p.max_change, int(p.growth_checked),
                    int(p.blew_up), int(p.stable), p.growth_error, int(grows_significantly(p)));
      out << line;
    }
    out.close();
    if (!out) throw std::runtime_error("cannot write " + csv);
  }
  const std::string md_path = (std::filesystem::path(dir) / "summary.md").string();
  std::ofstream md(md_path);
  char buf[512];
  md << "# Stability scan of " << scene_name << "\n\n";
  char probe_length[64];
  if (settings.probe_time > 0)
    std::snprintf(probe_length, sizeof probe_length, "probes of %.4g s simulated", settings.probe_time);
  else
    std::snprintf(probe_length, sizeof probe_length, "%ld steps per probe", settings.steps);
  std::snprintf(
      buf, sizeof buf,
      "Rayleigh time %.4g s, shortest contact time %.4g s, stable limit estimate %.4g s, auto step %.4g s; "
      "%s (%d energy samples each), growth threshold %.3g per characteristic time (%.4g s); gravity %s in "
      "the conservative variant.\n\n",
      e.rayleigh_time, e.contact_time, e.limit, e.step, probe_length, settings.samples,
      settings.growth_threshold, r.characteristic_time, r.gravity_kept ? "kept" : "off");
  md << buf;
  md << "| variant | largest stable dt (s) | dt / T_R | dt / t_c | first unstable dt (s) | auto step / "
        "largest stable |\n";
  md << "|---|---|---|---|---|---|\n";
  auto row = [&](const char* name, double crit, double unst) {
    std::snprintf(buf, sizeof buf, "| %s | %.4g | %.4f | %.4f | %.4g | %.3f |\n", name, crit,
                  crit / e.rayleigh_time, crit / e.contact_time, unst, crit > 0 ? e.step / crit : 0.0);
    md << buf;
  };
  if (settings.conservative) row("conservative", r.critical_conservative, r.unstable_conservative);
  if (settings.given) row("given", r.critical_given, r.unstable_given);
  // Hu's criterion: the first step whose growth is above zero beyond two standard errors.
  md << "\nHu's criterion (growth above zero by more than two standard errors of its fit):\n\n";
  md << "| variant | largest step with no significant growth (s) | dt / T_R | first step that grows (s) | "
        "dt / T_R | its growth per T_R |\n|---|---|---|---|---|---|\n";
  for (const char* variant : {"conservative", "given"}) {
    std::vector<StabilityProbe> ps;
    for (const StabilityProbe& p : r.probes)
      if (p.variant == variant && p.growth_checked) ps.push_back(p);
    if (ps.empty()) continue;
    std::sort(ps.begin(), ps.end(),
              [](const StabilityProbe& a, const StabilityProbe& b) { return a.dt < b.dt; });
    double last_flat = 0;
    const StabilityProbe* first_growing = nullptr;
    for (const StabilityProbe& p : ps) {
      if (grows_significantly(p)) {
        first_growing = &p;
        break;
      }
      last_flat = p.dt;
    }
    if (first_growing)
      std::snprintf(buf, sizeof buf, "| %s | %.4g | %.4f | %.4g | %.4f | %.3g +- %.2g |\n", variant,
                    last_flat, last_flat / e.rayleigh_time, first_growing->dt,
                    first_growing->dt / e.rayleigh_time, first_growing->growth, first_growing->growth_error);
    else
      std::snprintf(buf, sizeof buf, "| %s | %.4g | %.4f | none probed | | |\n", variant, last_flat,
                    last_flat / e.rayleigh_time);
    md << buf;
  }
  for (const StabilityProbe& p : r.probes)
    if (p.blew_up) {
      md << "\nFirst blow-up diagnosis (" << p.variant << ", dt " << p.dt << " s):\n\n    " << p.diagnosis
         << "\n";
      break;
    }
  md.close();
  if (!md) throw std::runtime_error("cannot write " + md_path);
  return csv;
}

const char* stability_help() {
  return R"(Usage: cgdem stability SCENE.yaml [options]

Probes the scene over a range of time steps and reports the largest stable step, as a number and as a
fraction of the Rayleigh time and of the contact time (Hu et al. 2022, Fig. 20 method). Two variants run
at every step: 'conservative' (restitution 1, no friction, rolling friction or adhesion, walls at rest,
gravity only if a floor holds the particles), whose total energy must not grow, and 'given' (the scene
as written), which must not blow up. A step is unstable when the energy grows faster than --threshold
per Rayleigh time (least-squares slope over the probe) or the engine stops with a blow-up diagnosis.
Writes DIR/stability.csv, DIR/summary.md and DIR/stability.png (energy growth rate against dt).

Options:
  --set key.path=value   override a scene key (as for 'run')
  --dts a,b,...          time steps to probe; plain numbers are seconds, suffixes scale: 0.1tr (x Rayleigh
                         time), 0.5tc (x contact time), 2limit (x the stable-limit estimate)
  --range lo:hi:n        n geometrically spaced steps from lo to hi (same units); default 0.1limit:10limit:13
  --steps N              steps per probe (default 2000)
  --time T               simulated time per probe instead (seconds): ceil(T / dt) steps at each dt, so
                         every probe covers the same time (Hu's runs: 0.1 s)
  --samples N            energy samples per probe for the growth fit (default 20); the CSV gives the
                         slope's standard error and whether it grows beyond two of them (Hu's criterion)
  --refine K             bisection steps between the last stable and the first unstable (default 3)
  --threshold X          energy growth per Rayleigh time counted as unstable (default 1e-4)
  --variant V            conservative | given | both (default both)
  --out DIR              output directory (default stability_<scene name>)
  --threads N, --backend NAME   as for 'run'
  --quiet                no line per probe

Examples:
  cgdem stability scenes/periodic_box.yaml --range 0.05tr:0.5tr:10 --steps 3000
  cgdem stability scenes/settled_bed.yaml --set groups.0.count=1000 --dts 0.5limit,1limit,2limit
)";
}

int stability_command(const std::vector<std::string>& args) {
  for (const auto& a : args)
    if (a == "--help" || a == "-h") {
      std::cout << stability_help();
      return 0;
    }
  std::string scene_path, out, backend, dts_text, range_text, variant = "both";
  std::vector<std::string> overrides;
  StabilitySettings settings;
  settings.verbose = true;
  int threads = 0;
  try {
    for (std::size_t k = 0; k < args.size(); ++k) {
      const std::string& a = args[k];
      const std::string name = a.substr(0, a.find('='));
      auto value = [&]() -> std::string {
        if (a.rfind("--", 0) == 0 && a.find('=') != std::string::npos) return a.substr(a.find('=') + 1);
        if (k + 1 >= args.size()) throw CliError("option " + a + " needs a value (see --help)");
        return args[++k];
      };
      auto number = [&](const std::string& v) {
        try {
          std::size_t used = 0;
          const double x = std::stod(v, &used);
          if (used == v.size()) return x;
        } catch (const std::exception&) {
        }
        throw CliError("option " + name + " expects a number, got '" + v + "'");
      };
      if (name == "--set")
        overrides.push_back(value());
      else if (name == "--dts")
        dts_text = value();
      else if (name == "--range")
        range_text = value();
      else if (name == "--steps")
        settings.steps = static_cast<long>(number(value()));
      else if (name == "--time")
        settings.probe_time = number(value());
      else if (name == "--samples")
        settings.samples = static_cast<int>(number(value()));
      else if (name == "--refine")
        settings.refine = static_cast<int>(number(value()));
      else if (name == "--threshold")
        settings.growth_threshold = number(value());
      else if (name == "--variant")
        variant = value();
      else if (name == "--out")
        out = value();
      else if (name == "--threads")
        threads = static_cast<int>(number(value()));
      else if (name == "--backend")
        backend = value();
      else if (name == "--quiet" || name == "-q")
        settings.verbose = false;
      else if (!a.empty() && a[0] == '-')
        throw CliError("unknown option '" + a + "' (see --help)");
      else if (scene_path.empty())
        scene_path = a;
      else
        throw CliError("unexpected argument '" + a + "': one scene file");
    }
    if (scene_path.empty()) throw CliError("no scene file given (see --help)");
    if (settings.steps < 10) throw CliError("--steps expects at least 10");
    if (settings.probe_time < 0) throw CliError("--time expects a simulated time > 0 in seconds");
    if (settings.samples < 3) throw CliError("--samples expects at least 3 (a slope and its error)");
    if (variant != "both" && variant != "conservative" && variant != "given")
      throw CliError("--variant expects conservative, given or both");
  } catch (const CliError& e) {
    std::cerr << "cgdem stability: " << e.what() << "\n";
    return exit_bad_input;
  }
  settings.conservative = variant != "given";
  settings.given = variant != "conservative";
  settings.backend = backend;
  KokkosSession kokkos(threads);
  try {
    const Scene scene = parse_scene_file(scene_path, overrides);
    const ParticleSet particles = generate_particles(scene);
    check_particles(scene, particles);
    const TimeStepEstimate est = estimate_time_step(scene, particles);
    try {
      if (!dts_text.empty()) {
        std::stringstream ss(dts_text);
        std::string item;
        while (std::getline(ss, item, ','))
          settings.dts.push_back(parse_step(item, est));
      }
      if (!range_text.empty()) {
        const auto c1 = range_text.find(':'), c2 = range_text.rfind(':');
        if (c1 == std::string::npos || c1 == c2)
          throw CliError("--range expects lo:hi:n, got '" + range_text + "'");
        const double lo = parse_step(range_text.substr(0, c1), est);
        const double hi = parse_step(range_text.substr(c1 + 1, c2 - c1 - 1), est);
        const int n = std::atoi(range_text.substr(c2 + 1).c_str());
        if (!(lo > 0) || !(hi > lo) || n < 2) throw CliError("--range expects 0 < lo < hi and n >= 2");
        for (double d : geometric(lo, hi, n))
          settings.dts.push_back(d);
      }
    } catch (const CliError& e) {
      std::cerr << "cgdem stability: " << e.what() << "\n";
      return exit_bad_input;
    }
    const std::string stem = std::filesystem::path(scene_path).stem().string();
    if (out.empty()) out = "stability_" + stem;
    if (const std::string problem = output_dir_problem(out); !problem.empty()) {
      std::cerr << "cgdem stability: " << problem << "\n";
      return exit_bad_input;
    }
    std::fprintf(
        stderr,
        "cgdem stability: %s, %zu particles; Rayleigh time %.4g s, contact time %.4g s, stable limit "
        "%.4g s, auto step %.4g s\n",
        scene_path.c_str(), particles.size(), est.rayleigh_time, est.contact_time, est.limit, est.step);
    const StabilityResult r = stability_scan(scene, particles, settings);
    std::string csv;
    try {
      csv = write_stability_report(out, scene_path, r, settings);
    } catch (const std::exception& e) {
      std::cerr << "cgdem stability: output write failed: " << e.what() << "\n";
      return exit_write_failed;
    }
    auto report = [&](const char* name, double crit, double unst) {
      if (crit > 0)
        std::printf("largest stable step (%s): %.4g s = %.4f Rayleigh times = %.4f contact times "
                    "(first unstable %.4g s); auto step = %.3f of it\n",
                    name, crit, crit / est.rayleigh_time, crit / est.contact_time, unst, est.step / crit);
      else
        std::printf("largest stable step (%s): none of the probed steps was stable (smallest %.4g s)\n", name,
                    unst);
    };
    if (settings.conservative) report("conservative", r.critical_conservative, r.unstable_conservative);
    if (settings.given) report("as given", r.critical_given, r.unstable_given);
    const std::string png = (std::filesystem::path(out) / "stability.png").string();
    const std::string script = std::string(CGDEM_SOURCE_DIR) + "/stability/plot_stability.py";
    std::string wrote = csv + ", " + (std::filesystem::path(out) / "summary.md").string();
    if (std::filesystem::exists(script) && std::filesystem::exists("/usr/bin/python3")) {
      const std::string cmd =
          "/usr/bin/python3 '" + script + "' '" + csv + "' '" + png + "' > /dev/null 2>&1";
      if (std::system(cmd.c_str()) == 0) wrote += ", " + png;
    }
    std::printf("wrote %s\n", wrote.c_str());
    return 0;
  } catch (const SceneError& e) {
    std::cerr << "cgdem: " << e.what() << "\n";
    return exit_bad_input;
  } catch (const std::exception& e) {
    std::cerr << "cgdem: " << scene_path << ": " << e.what() << "\n";
    return exit_bad_input;
  }
}

} // namespace cgdem
