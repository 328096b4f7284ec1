// Numerical stability on hard cases (docs/stability.md):
//  - convergence in dt of Hertz (analytic reference) and JKR (16x finer reference) binary impacts;
//  - stiff micron spheres on a stiff wall; size ratio 1:10 dense pack (contacts, history, energy);
//  - JKR over three orders of surface energy (energy balance, no chattering);
//  - dense bed below and above its critical step (energy, blow-up diagnosis through the executable);
//  - overlapping initial particles; single vs double precision; Hu's periodic box via stability_scan.
// With CGDEM_STABILITY_REPORT=<dir> the same tests run at fuller size and write CSV files into <dir>
// (stability/make_report.sh turns them into the committed PNGs and tables).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include "drivers/particle_generation.hpp"
#include "drivers/stability_command.hpp"
#include "models/linear_eepa.hpp"
#include "tests/test_scaling_support.hpp"
#include "tests/test_support.hpp"

using namespace cgdem;
using namespace cgdem::testing;

namespace {

const char* report_dir() {
  const char* d = std::getenv("CGDEM_STABILITY_REPORT");
  return d && *d ? d : nullptr;
}
bool full() {
  return report_dir() != nullptr;
}

std::ofstream report_csv(const std::string& name, const std::string& header) {
  std::ofstream out;
  if (!full()) return out;
  std::filesystem::create_directories(report_dir());
  out.open(std::string(report_dir()) + "/" + name);
  out << header << "\n";
  return out;
}

// Exact Hertz contact time constant: t_c = 2 (int_0^1 dx / sqrt(1 - x^2.5)) delta_max / v = 2.94328 delta_max
// / v (physics.md rounds the equivalent prefactor to 2.868).
constexpr double hertz_tc_over_dmax_v = 2.9432751843;

struct Engined {
  EngineConfig config;
  std::unique_ptr<Engine> engine;
};

Engined build(const Scene& s, const ParticleSet& p, double dt) {
  TimeStepEstimate e = estimate_time_step(s, p);
  e.step = dt;
  Engined out;
  out.config = make_engine_config(s, p, e);
  out.engine = make_engine(out.config, "serial"); // small systems: no thread barriers
  return out;
}

struct Impact {
  bool touched = false, separated = false;
  double max_overlap = 0, contact_time = 0, restitution = 0;
  double ke_before = 0, ke_after = 0;
  int snap_in = 0, snap_off = 0; // transitions of the contact count 0 -> >0 and >0 -> 0
  long steps_in_contact = 0;
};

// Head-on impact along x at relative speed v: two spheres with zero total momentum, or one sphere onto a
// plane wall at x = 0 (r2 == 0, wall material `wall`). The contact starts at the interpolated zero of the
// overlap; it ends at the interpolated zero (Hertz) or, for JKR, at the interpolated crossing of
// `break_overlap` (delta_S) on the step the engine breaks the bond. The maximum overlap comes from a
// parabola through the three samples around the largest one. Runs `after` extra contact durations past
// the separation to catch a re-contact (chattering).
Impact impact(const Scene& scene, double r1, double r2, double rho, double v, double dt, double t_max,
              double break_overlap = 0, double after = 1.0) {
  ParticleSet p;
  const double gap = 1e-4 * r1;
  if (r2 > 0) {
    const double m1 = sphere_mass(rho, r1), m2 = sphere_mass(rho, r2), mt = m1 + m2;
    add_particle(p, {-r1 - 0.5 * gap, 0, 0}, {v * m2 / mt, 0, 0}, r1, rho);
    add_particle(p, {r2 + 0.5 * gap, 0, 0}, {-v * m1 / mt, 0, 0}, r2, rho);
  } else {
    add_particle(p, {r1 + gap, 0, 0}, {-v, 0, 0}, r1, rho);
  }
  Engined e = build(scene, p, dt);
  Impact out;
  out.ke_before = e.engine->observe().kinetic_energy;
  const bool jkr = scene.contact.normal == "jkr";
  std::vector<double> ov;
  long first = -1;
  double t_start = 0, t_end = -1, prev = -gap; // overlap at the start
  long prev_contacts = 0, stop_at = static_cast<long>(t_max / dt);
  for (long step = 1; step <= stop_at; ++step) {
    e.engine->advance(1);
    const FrameData f = e.engine->frame();
    const long contacts = e.engine->observe().contacts;
    const double d = r2 > 0 ? r1 + r2 - (f.position[3] - f.position[0]) : r1 - f.position[0];
    if (contacts > 0 && prev_contacts == 0) ++out.snap_in;
    if (contacts == 0 && prev_contacts > 0) ++out.snap_off;
    prev_contacts = contacts;
    if (!out.touched && d >= 0) {
      out.touched = true;
      first = step;
      t_start = (step - 1) * dt + dt * (0 - prev) / (d - prev);
    }
    if (out.touched && !out.separated) {
      ov.push_back(d);
      ++out.steps_in_contact;
      const bool ended = jkr ? contacts == 0 && step > first : d < 0;
      if (ended) {
        out.separated = true;
        const double level = jkr ? break_overlap : 0.0;
        t_end = (step - 1) * dt + dt * (level - prev) / (d - prev);
        out.contact_time = t_end - t_start;
        stop_at = std::min(stop_at, step + static_cast<long>(after * out.contact_time / dt) + 2);
      }
    }
    if (out.separated) {
      out.restitution = r2 > 0 ? (f.velocity[3] - f.velocity[0]) / v : f.velocity[0] / v;
      out.ke_after = e.engine->observe().kinetic_energy;
    }
    prev = d;
  }
  if (!ov.empty()) {
    const std::size_t k = std::max_element(ov.begin(), ov.end()) - ov.begin();
    out.max_overlap = ov[k];
    if (k > 0 && k + 1 < ov.size()) {
      const double a = ov[k - 1], b = ov[k], c = ov[k + 1], den = a - 2 * b + c;
      if (den < 0) out.max_overlap = b - (c - a) * (c - a) / (8 * den);
    }
  }
  return out;
}

double slope(const std::vector<double>& x, const std::vector<double>& y) {
  // Least-squares slope of log y against log x.
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double lx = std::log(x[k]), ly = std::log(std::max(y[k], 1e-300));
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

} // namespace

// ---------------------------------------------------------------------------------------------------
// 2. Convergence in dt.

TEST(StabilityConvergence, HertzImpactConvergesAtSecondOrderAgainstAnalytic) {
  // Hu's material (R 0.25 mm, rho 1000, E 100 MPa, nu 0.3), elastic and frictionless, at 1 m/s.
  const double r = 0.25e-3, rho = 1000, E = 100e6, nu = 0.3, v = 1.0;
  const Scene s = basic_scene({material("hu", rho, E, nu, 1.0, 0.0)}, "hertz", "none");
  const double m_eff = 0.5 * sphere_mass(rho, r), r_eff = 0.5 * r, e_eff = E / (2 * (1 - nu * nu));
  const double dmax = std::pow(15 * m_eff * v * v / (16 * e_eff * std::sqrt(r_eff)), 0.4);
  const double tc = hertz_tc_over_dmax_v * dmax / v;
  std::vector<double> spc = full() ? std::vector<double>{5, 10, 20, 40, 80, 160, 320, 640, 1280}
                                   : std::vector<double>{10, 20, 40, 80, 160};
  auto csv =
      report_csv("convergence_hertz.csv",
                 "steps_per_contact,dt,dt_over_rayleigh,err_max_overlap,err_contact_time,err_restitution");
  std::vector<double> x, e_ov, e_tc, e_e;
  for (double n : spc) {
    const double dt = tc / n;
    const Impact im = impact(s, r, r, rho, v, dt, 3 * tc);
    ASSERT_TRUE(im.separated) << n;
    x.push_back(n);
    e_ov.push_back(std::fabs(im.max_overlap / dmax - 1));
    e_tc.push_back(std::fabs(im.contact_time / tc - 1));
    e_e.push_back(std::fabs(im.restitution - 1));
    std::printf(
        "[ report ] Hertz %5.0f steps/contact: max overlap %.3e, contact time %.3e, restitution %.3e\n", n,
        e_ov.back(), e_tc.back(), e_e.back());
    if (csv)
      csv << n << "," << dt << "," << dt / rayleigh_time(r, rho, E, nu) << "," << e_ov.back() << ","
          << e_tc.back() << "," << e_e.back() << "\n";
  }
  const double p_ov = -slope(x, e_ov), p_tc = -slope(x, e_tc), p_e = -slope(x, e_e);
  std::printf("[ report ] Hertz observed orders: max overlap %.2f, contact time %.2f, restitution %.2f\n",
              p_ov, p_tc, p_e);
  // Velocity Verlet is second order; the Hertz force is C1 but not C2 at touch, which may cost a little.
  EXPECT_GT(p_ov, 1.7);
  EXPECT_GT(p_tc, 1.7);
  EXPECT_GT(p_e, 1.5);
  // At the 20+ steps per contact the engine's auto step gives (docs/stability.md), errors below 1%.
  EXPECT_LT(e_ov[1], 0.01);
  EXPECT_LT(e_tc[1], 0.01);
  EXPECT_LT(e_e[1], 0.01);
}

namespace {

struct JkrCase {
  double r, rho, E, nu, gamma;
  double m_eff, r_eff, e_eff, u, delta_s, w_s, v_stick;
};

JkrCase jkr_case(double r, double rho, double E, double nu, double gamma) {
  JkrCase c{r, rho, E, nu, gamma, 0, 0, 0, 0, 0, 0, 0};
  c.m_eff = 0.5 * sphere_mass(rho, r);
  c.r_eff = 0.5 * r;
  c.e_eff = E / (2 * (1 - nu * nu));
  c.u = std::cbrt(M_PI * M_PI * gamma * gamma * c.r_eff / (c.e_eff * c.e_eff));
  c.delta_s = -1.1906 * c.u;
  c.w_s = 22.516 * std::cbrt(std::pow(gamma, 5) * std::pow(c.r_eff, 4) / (c.e_eff * c.e_eff));
  c.v_stick = std::sqrt(2 * c.w_s / c.m_eff);
  return c;
}

Scene jkr_scene(const JkrCase& c) {
  MaterialSpec m = material("grain", c.rho, c.E, c.nu, 1.0, 0.0);
  m.surface_energy = c.gamma;
  return basic_scene({m}, "jkr", "none");
}

} // namespace

TEST(StabilityConvergence, JkrImpactAgainstSixteenTimesFinerRun) {
  // 1 mm spheres, rho 1500, E 5 MPa, nu 0.25, gamma 0.2 J/m^2, undamped, at 3 v_stick.
  const JkrCase c = jkr_case(1e-3, 1500, 5e6, 0.25, 0.2);
  const double v = 3 * c.v_stick;
  const Scene s = jkr_scene(c);
  const double tc = hertz_contact_time(c.m_eff, c.r_eff, c.e_eff, v);
  std::vector<double> spc =
      full() ? std::vector<double>{10, 20, 40, 80, 160, 320, 640} : std::vector<double>{20, 40, 80, 160};
  const double n_ref = 16 * spc.back();
  const Impact ref = impact(s, c.r, c.r, c.rho, v, tc / n_ref, 10 * tc, c.delta_s, 0.2);
  ASSERT_TRUE(ref.separated);
  const double e_analytic = std::sqrt(1 - c.v_stick * c.v_stick / (v * v));
  std::printf("[ report ] JKR reference (%.0f steps per Hertz t_c): restitution %.5f (analytic sqrt(1 - "
              "v_stick^2/v^2) = %.5f), contact %.4g s = %.3f t_c\n",
              n_ref, ref.restitution, e_analytic, ref.contact_time, ref.contact_time / tc);
  EXPECT_NEAR(ref.restitution / e_analytic, 1, 0.005);
  auto csv = report_csv("convergence_jkr.csv",
                        "steps_per_contact,dt,err_max_overlap,err_contact_time,err_restitution,"
                        "energy_error_over_ws,snap_in,snap_off");
  std::vector<double> x, e_ov, e_tc, e_e;
  for (double n : spc) {
    const Impact im = impact(s, c.r, c.r, c.rho, v, tc / n, 10 * tc, c.delta_s);
    ASSERT_TRUE(im.separated) << n;
    x.push_back(n);
    e_ov.push_back(std::fabs(im.max_overlap / ref.max_overlap - 1));
    e_tc.push_back(std::fabs(im.contact_time / ref.contact_time - 1));
    e_e.push_back(std::fabs(im.restitution / ref.restitution - 1));
    const double ew = (im.ke_before - im.ke_after) / c.w_s - 1;
    std::printf("[ report ] JKR %4.0f steps/contact: max overlap %.3e, contact time %.3e, restitution %.3e, "
                "(KE lost - W_s)/W_s %+.3e\n",
                n, e_ov.back(), e_tc.back(), e_e.back(), ew);
    if (csv)
      csv << n << "," << tc / n << "," << e_ov.back() << "," << e_tc.back() << "," << e_e.back() << "," << ew
          << "," << im.snap_in << "," << im.snap_off << "\n";
    EXPECT_EQ(im.snap_in, 1) << n;
    EXPECT_EQ(im.snap_off, 1) << n;
  }
  const double p_ov = -slope(x, e_ov), p_tc = -slope(x, e_tc), p_e = -slope(x, e_e);
  std::printf("[ report ] JKR observed orders: max overlap %.2f, contact time %.2f, restitution %.2f\n", p_ov,
              p_tc, p_e);
  // The snap-in and snap-off force jumps make the collision at best first order in dt; the rebound error
  // depends on where the jumps fall inside a step and is not monotone (docs/stability.md).
  EXPECT_GT(p_ov, 0.7);
  EXPECT_GT(p_tc, 0.7);
  EXPECT_LT(e_e.back(), 0.005);
}

// ---------------------------------------------------------------------------------------------------
// 3. Hard cases.

namespace {

struct MicronRun {
  double v, dt_auto, steps_per_contact, e_auto, e_half, contact_time;
};

MicronRun micron_on_wall(double v) {
  // Polystyrene-like micron sphere (diameter 1.27 um) on a stiff wall (glass-like, 98 GPa), e 0.97.
  const double r = 0.635e-6, rho = 1050;
  MaterialSpec ps = material("ps", rho, 140e6, 0.3, 0.97, 0.0);
  MaterialSpec wall = material("wall", 2500, 98e9, 0.3, 0.97, 0.0);
  Scene s = basic_scene({ps, wall}, "hertz", "none");
  s.domain.lo = {-20e-6, -20e-6, -20e-6};
  s.domain.hi = {20e-6, 20e-6, 20e-6};
  WallSpec w;
  w.name = "wall";
  w.material = "wall";
  w.normal = {1, 0, 0};
  s.walls.push_back(w);
  ParticleSet p;
  add_particle(p, {r * 1.0001, 0, 0}, {-v, 0, 0}, r, rho);
  const double dt = estimate_time_step(s, p).step; // time.step: auto
  MicronRun out{v, dt, 0, 0, 0, 0};
  const Impact a = impact(s, r, 0, rho, v, dt, 1e-6);
  const Impact b = impact(s, r, 0, rho, v, dt / 2, 1e-6);
  EXPECT_TRUE(a.separated && b.separated) << v;
  out.e_auto = a.restitution;
  out.e_half = b.restitution;
  out.contact_time = b.contact_time;
  out.steps_per_contact = a.contact_time / dt;
  return out;
}

} // namespace

TEST(StabilityHardCases, StiffMicronSpheresOnStiffWall) {
  const std::vector<double> speeds =
      full() ? std::vector<double>{1, 2, 5, 10, 20} : std::vector<double>{1, 5, 20};
  auto csv =
      report_csv("micron_wall.csv", "speed,dt_auto,steps_per_contact,restitution_auto,restitution_half_dt,"
                                    "relative_change,contact_time");
  for (double v : speeds) {
    const MicronRun m = micron_on_wall(v);
    const double change = std::fabs(m.e_half / m.e_auto - 1);
    std::printf(
        "[ report ] micron sphere at %4.1f m/s: auto dt %.3g s, %.1f steps per contact, e %.5f, with dt/2 "
        "%.5f (change %.2e), contact %.3g s\n",
        v, m.dt_auto, m.steps_per_contact, m.e_auto, m.e_half, change, m.contact_time);
    if (csv)
      csv << v << "," << m.dt_auto << "," << m.steps_per_contact << "," << m.e_auto << "," << m.e_half << ","
          << change << "," << m.contact_time << "\n";
    EXPECT_LT(change, 0.005) << v << " m/s";
    EXPECT_GE(m.steps_per_contact, 20) << v << " m/s";
  }
}

namespace {

// Pairs (by id) overlapping now, found independently of the engine: large particles against all, small
// ones through a uniform grid of cell size 2 r_small_max.
std::set<std::pair<std::int64_t, std::int64_t>> overlapping_pairs(const CheckpointData& c, double box,
                                                                  double r_small) {
  const auto& id = c.ints.at("id");
  const auto& x = c.reals.at("position");
  const auto& r = c.reals.at("radius");
  const std::size_t n = id.size();
  std::set<std::pair<std::int64_t, std::int64_t>> out;
  auto overlap = [&](std::size_t i, std::size_t j) {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
      double d = x[3 * j + a] - x[3 * i + a];
      d -= box * std::round(d / box);
      d2 += d * d;
    }
    return d2 < (r[i] + r[j]) * (r[i] + r[j]);
  };
  auto add = [&](std::size_t i, std::size_t j) {
    out.insert({std::min(id[i], id[j]), std::max(id[i], id[j])});
  };
  const int cells = std::max(1, static_cast<int>(box / (2 * r_small)));
  std::map<long, std::vector<std::size_t>> grid;
  auto cell = [&](double v) {
    return ((static_cast<int>(std::floor(v / box * cells)) % cells) + cells) % cells;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (r[i] > r_small) {
      for (std::size_t j = 0; j < n; ++j)
        if (j != i && overlap(i, j)) add(i, j);
    } else {
      grid[(cell(x[3 * i]) * cells + cell(x[3 * i + 1])) * cells + cell(x[3 * i + 2])].push_back(i);
    }
  }
  for (const auto& [key, members] : grid) {
    const int cx = key / (cells * cells), cy = key / cells % cells, cz = key % cells;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const long other = (((cx + dx + cells) % cells) * cells + (cy + dy + cells) % cells) * cells +
                             (cz + dz + cells) % cells;
          auto it = grid.find(other);
          if (it == grid.end()) continue;
          for (std::size_t i : members)
            for (std::size_t j : it->second)
              if (i < j && overlap(i, j)) add(i, j);
        }
  }
  return out;
}

struct Listed {
  std::set<std::pair<std::int64_t, std::int64_t>> pairs;
  std::map<std::pair<std::int64_t, std::int64_t>, double> history; // |xi| per ordered (i, j) slot
};

Listed listed(const CheckpointData& c) {
  const auto& id = c.ints.at("id");
  const auto& off = c.ints.at("nl_offsets");
  const auto& nb = c.ints.at("nl_neighbors");
  const auto& hist = c.reals.at("nl_history");
  const int h = static_cast<int>(c.scalars.at("history_size"));
  Listed out;
  for (std::size_t i = 0; i < id.size(); ++i)
    for (auto k = off[i]; k < off[i + 1]; ++k) {
      const auto a = id[i], b = id[nb[k]];
      out.pairs.insert({std::min(a, b), std::max(a, b)});
      double s = 0;
      for (int q = 0; q < h; ++q)
        s += hist[h * k + q] * hist[h * k + q];
      out.history[{a, b}] = std::sqrt(s);
    }
  return out;
}

// Bidisperse periodic pack, radius ratio 1:10: `large` spheres of 1 mm placed first, then small ones of
// 0.1 mm (random sequential addition, solid fraction about 0.33), random directions at `speed`.
ParticleSet bidisperse(int large, int small, double box, double speed, unsigned seed) {
  ParticleSet big = random_periodic(large, box, 1e-3, 1e-3, 2500, speed, seed);
  EXPECT_EQ(static_cast<int>(big.size()), large);
  // Small ones: rejection against everything placed so far, via the same helper on a merged set.
  std::mt19937_64 rng(seed + 100);
  std::uniform_real_distribution<double> u(0, 1);
  ParticleSet p = big;
  const double rs = 1e-4;
  int tries = 0;
  const int cells = static_cast<int>(box / (2 * rs));
  std::map<long, std::vector<std::size_t>> grid;
  auto cell = [&](double v) {
    return ((static_cast<int>(std::floor(v / box * cells)) % cells) + cells) % cells;
  };
  auto key = [&](int a, int b, int c) { return (long(a) * cells + b) * cells + c; };
  auto d2 = [&](const Vec3d& a, const Vec3d& b) {
    double s = 0;
    for (int q = 0; q < 3; ++q) {
      double d = a[q] - b[q];
      d -= box * std::round(d / box);
      s += d * d;
    }
    return s;
  };
  while (static_cast<int>(p.size()) < large + small && tries < 50 * small) {
    ++tries;
    const Vec3d x{box * u(rng), box * u(rng), box * u(rng)};
    bool ok = true;
    for (int k = 0; k < large && ok; ++k)
      ok = d2(x, p.position[k]) > (1e-3 + rs) * (1e-3 + rs);
    const int cx = cell(x[0]), cy = cell(x[1]), cz = cell(x[2]);
    for (int dx = -1; dx <= 1 && ok; ++dx)
      for (int dy = -1; dy <= 1 && ok; ++dy)
        for (int dz = -1; dz <= 1 && ok; ++dz) {
          auto it =
              grid.find(key((cx + dx + cells) % cells, (cy + dy + cells) % cells, (cz + dz + cells) % cells));
          if (it == grid.end()) continue;
          for (std::size_t j : it->second)
            if (d2(x, p.position[j]) <= 4 * rs * rs) ok = false;
        }
    if (!ok) continue;
    const double cz2 = 2 * u(rng) - 1, phi = 2 * M_PI * u(rng), sz = std::sqrt(1 - cz2 * cz2);
    grid[key(cx, cy, cz)].push_back(p.size());
    add_particle(p, x, {speed * sz * std::cos(phi), speed * sz * std::sin(phi), speed * cz2}, rs, 2500);
  }
  return p;
}

Scene periodic(double box, const MaterialSpec& m, const std::string& tangential) {
  Scene s = basic_scene({m}, "hertz", tangential);
  s.domain.lo = {0, 0, 0};
  s.domain.hi = {box, box, box};
  s.domain.periodic = {true, true, true};
  return s;
}

} // namespace

TEST(StabilityHardCases, SizeRatioTenNoMissedContactHistoryKeptEnergyConserved) {
  // Box >= 3 neighbour cells of 2 R_large + skin; solid fraction about 0.27 (0.25 large + 0.02 small).
  const double box = full() ? 0.010 : 0.008;
  const int large = full() ? 60 : 30, small = full() ? 10000 : 3000;
  const ParticleSet p = bidisperse(large, small, box, 0.5, 3);
  ASSERT_EQ(static_cast<int>(p.size()), large + small);
  // Frictional and elastic: sustained sliding/sticking contacts with tangential history.
  const MaterialSpec frictional = material("glass", 2500, 5e6, 0.3, 1.0, 0.5);
  Scene s = periodic(box, frictional, "mindlin");
  s.neighbour.skin = 4e-5; // 0.2 small diameters: a list build every few dozen steps
  const double dt = estimate_time_step(s, p).step;
  Engined e = build(s, p, dt);
  const long builds0 = e.engine->timers().list_builds;
  Listed before = listed(e.engine->checkpoint());
  long missed = 0, dropped = 0, persisted = 0, checks = 0;
  const int steps = full() ? 600 : 200;
  for (int k = 0; k < steps; ++k) {
    e.engine->advance(1);
    const CheckpointData c = e.engine->checkpoint();
    const Listed now = listed(c);
    // Every overlapping pair is listed (brute force every 10 steps); a contact with tangential history
    // that is still overlapping keeps a non-zero history across every step, rebuilds included.
    std::set<std::pair<std::int64_t, std::int64_t>> overlapping;
    bool have = false;
    auto overlaps = [&](std::pair<std::int64_t, std::int64_t> pr) {
      if (!have) overlapping = overlapping_pairs(c, box, 1e-4), have = true;
      return overlapping.count({std::min(pr.first, pr.second), std::max(pr.first, pr.second)}) > 0;
    };
    if (k % 10 == 0) {
      ++checks;
      overlaps({0, 0});
      for (const auto& pr : overlapping)
        missed += !now.pairs.count(pr);
    }
    for (const auto& [pr, h] : before.history) {
      if (h <= 0) continue;
      auto it = now.history.find(pr);
      if (it != now.history.end() && it->second > 0)
        ++persisted;
      else if (overlaps(pr))
        ++dropped; // left the list or reset while still in contact
    }
    before = now;
  }
  const long builds = e.engine->timers().list_builds - builds0;
  std::printf(
      "[ report ] 1:10 pack, %d + %d particles, dt %.3g s: %d steps, %ld list builds, %ld brute-force "
      "checks, %ld missed contacts, %ld history entries carried, %ld dropped\n",
      large, small, dt, steps, builds, checks, missed, persisted, dropped);
  EXPECT_GT(builds, 2);
  EXPECT_EQ(missed, 0);
  EXPECT_EQ(dropped, 0);
  EXPECT_GT(persisted, 100);

  // Elastic frictionless variant: total energy conserved.
  Scene elastic = periodic(box, material("glass", 2500, 5e6, 0.3, 1.0, 0.0), "none");
  elastic.neighbour.skin = 4e-5;
  Engined f = build(elastic, p, dt);
  const double e0 = total_energy(f.config, *f.engine);
  const int energy_steps = full() ? 20000 : 2000;
  f.engine->advance(energy_steps);
  const double e1 = total_energy(f.config, *f.engine);
  std::printf("[ report ] 1:10 pack elastic: relative energy change %.3e over %d steps\n", (e1 - e0) / e0,
              energy_steps);
  if (auto csv = report_csv("size_ratio.csv", "large,small,dt,steps,list_builds,missed,dropped,carried,"
                                              "energy_steps,relative_energy_change"))
    csv << large << "," << small << "," << dt << "," << steps << "," << builds << "," << missed << ","
        << dropped << "," << persisted << "," << energy_steps << "," << (e1 - e0) / e0 << "\n";
  EXPECT_LT(std::fabs(e1 - e0) / e0, 1e-3);
}

TEST(StabilityHardCases, JkrThreeOrdersOfSurfaceEnergyAtDefaultStep) {
  // 1 mm spheres, rho 1500, E 5 MPa, nu 0.25; gamma 0.01, 0.1, 1 J/m^2; undamped head-on at 3 v_stick.
  const std::vector<double> gammas =
      full() ? std::vector<double>{0.001, 0.01, 0.1, 1.0} : std::vector<double>{0.01, 0.1, 1.0};
  auto csv = report_csv("jkr_gamma.csv", "gamma,v_stick,dt_auto,steps_per_hertz_contact,v_dt_over_u,"
                                         "energy_error_auto,energy_error_fine,snap_in,snap_off");
  for (double g : gammas) {
    const JkrCase c = jkr_case(1e-3, 1500, 5e6, 0.25, g);
    const double v = 3 * c.v_stick;
    Scene s = jkr_scene(c);
    s.time.resolve_adhesion = true; // the documented setting for collision-resolved JKR studies
    ParticleSet p;
    add_particle(p, {-1e-3, 0, 0}, {0.5 * v, 0, 0}, c.r, c.rho);
    add_particle(p, {1e-3, 0, 0}, {-0.5 * v, 0, 0}, c.r, c.rho);
    const double dt = estimate_time_step(s, p).step;
    const double tc = hertz_contact_time(c.m_eff, c.r_eff, c.e_eff, v);
    const Impact a = impact(s, c.r, c.r, c.rho, v, dt, 20 * tc, c.delta_s, 2.0);
    // The step the force jumps need: v dt <= 2e-3 u (docs/stability.md).
    const double dt_fine = std::min(dt, 2e-3 * c.u / v);
    const Impact b = impact(s, c.r, c.r, c.rho, v, dt_fine, 20 * tc, c.delta_s, 2.0);
    ASSERT_TRUE(a.separated && b.separated) << g;
    const double err_a = (a.ke_before - a.ke_after) / c.w_s - 1,
                 err_b = (b.ke_before - b.ke_after) / c.w_s - 1;
    std::printf(
        "[ report ] JKR gamma %.3g J/m^2: v_stick %.4g m/s, auto dt %.3g s (%.0f steps per Hertz t_c, v dt = "
        "%.3g u): (KE lost - W_s)/W_s %+.4f; at v dt = 2e-3 u: %+.5f; snap-in %d, snap-off %d\n",
        g, c.v_stick, dt, tc / dt, v * dt / c.u, err_a, err_b, a.snap_in, a.snap_off);
    if (csv)
      csv << g << "," << c.v_stick << "," << dt << "," << tc / dt << "," << v * dt / c.u << "," << err_a
          << "," << err_b << "," << a.snap_in << "," << a.snap_off << "\n";
    // No chattering: one snap-in and one snap-off, at the default step and the fine one.
    EXPECT_EQ(a.snap_in, 1) << g;
    EXPECT_EQ(a.snap_off, 1) << g;
    EXPECT_EQ(b.snap_in, 1) << g;
    EXPECT_EQ(b.snap_off, 1) << g;
    // Energy balance within 1% of W_s once v dt <= 2e-3 u.
    EXPECT_LT(std::fabs(err_b), 0.01) << g;
    // At the auto step with time.resolve_adhesion (the scene below sets it; setup/time_step.cpp), which
    // resolves the snap-in/snap-off force jumps. Without it, see the next test.
    EXPECT_LT(std::fabs(err_a), 0.01) << g;
  }
}

// Hu's periodic box (docs/physics.md section 3), reduced to 1000 particles.
TEST(StabilityHardCases, HuPeriodicBoxCriticalStep) {
  const double r = 0.25e-3, rho = 1000, E = 100e6, nu = 0.3;
  const int n = full() ? 8000 : 1000; // 36644 (Hu) does not fit the shared machine
  const double box = std::cbrt(n * 4.0 / 3.0 * M_PI * r * r * r / 0.3); // solid fraction 0.3
  const ParticleSet p = random_periodic(n, box, r, r, rho, 1.0, 9);
  ASSERT_EQ(static_cast<int>(p.size()), n);
  const Scene s = periodic(box, material("hu7", rho, E, nu, 1.0, 0.0), "none");
  const double tr = rayleigh_time(r, rho, E, nu);
  StabilitySettings set;
  set.steps = full() ? 3000 : 1000;
  set.backend = full() ? "openmp" : "serial";
  set.given = false;
  set.refine = 3;
  for (double f : {0.1, 0.14, 0.2, 0.4, 0.7, 1.0, 1.4})
    set.dts.push_back(f * tr);
  const StabilityResult res = stability_scan(s, p, set);
  if (full()) write_stability_report(std::string(report_dir()) + "/hu_box", "Hu periodic box", res, set);
  const double crit = res.critical_conservative / tr;
  std::printf("[ report ] Hu periodic box N=%d: largest stable step %.3f T_R (first unstable %.3f T_R); Hu: "
              "0.14 T_R\n",
              n, crit, res.unstable_conservative / tr);
  for (const auto& pr : res.probes)
    std::printf("[ report ]   dt %.3f T_R: growth %.3g per T_R, max |E/E0-1| %.3g%s\n", pr.dt / tr, pr.growth,
                pr.max_change, pr.blew_up ? " BLOW-UP" : "");
  // Finding F1 (docs/stability.md): velocity Verlet in cgdem stays stable and energy conserving well past
  // Hu's 0.14 T_R; the step at 0.14 T_R is stable here with an energy error below 1e-4.
  EXPECT_GT(crit, 0.14);
  ASSERT_FALSE(res.probes.empty());
  EXPECT_LT(res.probes[1].max_change, 1e-4); // 0.14 T_R
  EXPECT_TRUE(std::isfinite(res.unstable_conservative));
}

TEST(StabilityFit, SlopeAndStandardErrorAgainstHandValues) {
  // y = 1, 3, 2, 5, 4 at x = 0..4: mean x 2, mean y 3, Sxx 10, Sxy 8 -> slope 0.8; residuals
  // -0.4, 0.8, -1.0, 1.2, -0.6 -> SS 3.6 -> standard error sqrt(3.6 / 3 / 10) = sqrt(0.12).
  const SlopeFit f = fit_slope({0, 1, 2, 3, 4}, {1, 3, 2, 5, 4});
  EXPECT_NEAR(f.slope, 0.8, 1e-14);
  EXPECT_NEAR(f.std_error, std::sqrt(0.12), 1e-14);
  // Points on a line: the slope, and no uncertainty.
  const SlopeFit line = fit_slope({0.5, 1.5, 2.5, 4.0}, {2.0, 1.0, 0.0, -1.5});
  EXPECT_NEAR(line.slope, -1.0, 1e-14);
  EXPECT_LT(line.std_error, 1e-14);
  // Two points: a slope, no error; one point: nothing.
  EXPECT_NEAR(fit_slope({0, 2}, {1, 2}).slope, 0.5, 1e-15);
  EXPECT_EQ(fit_slope({0, 2}, {1, 2}).std_error, 0.0);
  EXPECT_EQ(fit_slope({1}, {1}).slope, 0.0);
}

TEST(StabilityHardCases, HuCriterionFlagsGrowthBeyondItsErrorOnly) {
  // Hu's criterion on the periodic box (Table 7 material, 1000 particles): probes of the same simulated
  // time at each step (ceil(T / dt) steps); at 0.14 T_R the fitted growth lies within two standard errors
  // of zero, at 0.8 T_R (docs/stability.md: the energy rises there, without a blow-up) it is above zero
  // beyond them.
  const double r = 0.25e-3, rho = 1000, E = 100e6, nu = 0.3;
  const int n = 1000;
  const double box = std::cbrt(n * 4.0 / 3.0 * M_PI * r * r * r / 0.3);
  const ParticleSet p = random_periodic(n, box, r, r, rho, 1.0, 9);
  const Scene s = periodic(box, material("hu7", rho, E, nu, 1.0, 0.0), "none");
  const double tr = rayleigh_time(r, rho, E, nu);
  StabilitySettings set;
  set.probe_time = 300 * tr;
  set.samples = 30;
  set.backend = "serial";
  const StabilityProbe calm = stability_probe(s, p, 0.14 * tr, set, "conservative");
  const StabilityProbe hot = stability_probe(s, p, 0.8 * tr, set, "conservative");
  std::printf("[ report ] Hu criterion, box of %d: 0.14 T_R growth %.3g +- %.2g per T_R (%ld steps); 0.8 T_R "
              "%.3g +- %.2g (%ld steps)%s\n",
              n, calm.growth, calm.growth_error, calm.steps, hot.growth, hot.growth_error, hot.steps,
              hot.blew_up ? " BLOW-UP" : "");
  EXPECT_EQ(calm.steps, static_cast<long>(std::ceil(300 / 0.14 - 1e-9)));
  EXPECT_GT(calm.growth_error, 0);
  EXPECT_FALSE(grows_significantly(calm));
  ASSERT_FALSE(hot.blew_up);
  EXPECT_TRUE(grows_significantly(hot));
  EXPECT_GT(hot.growth, 2 * hot.growth_error);
}

TEST(StabilityHardCases, HuPeriodicBoxCriticalStepDoublesWithFactorUnderMethod1) {
  // Hu et al. 2022 Fig. 20: under Method 1 (forces l^2 F_O from the original overlap delta_S / l) the
  // scaled-up box, grown with l so that it holds the same number of particles at the same packing, goes
  // unstable at l times the original's step. The probes are placed at the same fractions of each system's
  // own Rayleigh time (l x the original's), so an exactly similar system finds exactly l times the step.
  const double r = 0.25e-3, rho = 1000, E = 100e6, nu = 0.3;
  const int n = 1000;
  const double box = std::cbrt(n * 4.0 / 3.0 * M_PI * r * r * r / 0.3); // solid fraction 0.3
  const double tr = rayleigh_time(r, rho, E, nu);                       // of the original particles
  double critical[3] = {0, 0, 0};
  const double factors[3] = {1, 2, 4};
  for (int q = 0; q < 3; ++q) {
    const double l = factors[q];
    const ParticleSet p = random_periodic(n, l * box, l * r, l * r, rho, 1.0, 9);
    ASSERT_EQ(static_cast<int>(p.size()), n);
    Scene s = periodic(l * box, material("hu7", rho, E, nu, 1.0, 0.0), "mindlin");
    s.groups[0].coarse_grain.law = "hu_method1";
    s.groups[0].coarse_grain.factor = l;
    StabilitySettings set;
    set.steps = 1000;
    set.backend = "serial";
    set.given = false;
    set.refine = 3;
    for (double f : {0.4, 0.7, 1.0, 1.4})
      set.dts.push_back(f * l * tr);
    const StabilityResult res = stability_scan(s, p, set);
    critical[q] = res.critical_conservative;
    ASSERT_GT(critical[q], 0) << "l=" << l;
    std::printf("[ report ] Hu box, Method 1, l = %g: largest stable step %.4g s = %.3f T_R of the original "
                "(first unstable %.3f)\n",
                l, critical[q], critical[q] / tr, res.unstable_conservative / tr);
  }
  EXPECT_NEAR(critical[1] / critical[0], 2.0, 0.2); // Done-when: doubles within 10%
  EXPECT_NEAR(critical[2] / critical[1], 2.0, 0.2);
  std::printf("[ report ] critical step ratios: l 1 -> 2: %.4f, l 2 -> 4: %.4f\n", critical[1] / critical[0],
              critical[2] / critical[1]);
}

TEST(StabilityHardCases, LargeFactorsEightAndSixteenKeepEachLawsInvariant) {
  // Each law's own claim, at k = 8 and 16 (the laws' k = 2, 4 checks live in test_scaling*.cpp).
  for (double k : {8.0, 16.0}) {
    // Chen-Elliott, through the engine: Chen's case c wall impact keeps restitution, contact time, overlap
    // and F/F_c.
    const ImpactOutcome c1 = run_impact(chen_case_c("chen_elliott", 1, 2.0));
    const ImpactOutcome ck = run_impact(chen_case_c("chen_elliott", k, 2.0));
    ASSERT_FALSE(ck.stuck) << "k=" << k;
    EXPECT_NEAR(ck.restitution / c1.restitution, 1, 0.01) << "k=" << k;
    EXPECT_NEAR(ck.contact_time / c1.contact_time, 1, 0.01) << "k=" << k;
    EXPECT_NEAR(ck.max_overlap / c1.max_overlap, 1, 0.01) << "k=" << k;
    EXPECT_NEAR(ck.max_attraction / c1.max_attraction, 1, 0.01) << "k=" << k;

    // Hu Method 1, through the engine: the coarse impact is the original one stretched by l in time and
    // overlap (delta_O = delta_S / l, F_S = l^2 F_O, m_S = l^3 m_O): restitution kept, duration and depth x
    // l.
    const ImpactOutcome h1 = run_impact(chen_case_c("hu_method1", 1, 2.0));
    ImpactSpec hs = chen_case_c("hu_method1", k, 2.0);
    hs.max_contact_times = 30 * k;
    const ImpactOutcome hk = run_impact(hs);
    ASSERT_FALSE(hk.stuck) << "k=" << k;
    EXPECT_NEAR(hk.restitution / h1.restitution, 1, 0.01) << "k=" << k;
    EXPECT_NEAR(hk.contact_time / (k * h1.contact_time), 1, 0.01) << "k=" << k;
    EXPECT_NEAR(hk.max_overlap / (k * h1.max_overlap), 1, 0.01) << "k=" << k;

    // Bond number F_c / (m g) and Behjani's cohesion number (Gamma^5 / (E*^2 R*^8))^(1/3) / (rho g), both
    // from the scaled material of a pair of equal spheres (R* = R / 2, E* = E / (2 (1 - nu^2))).
    MaterialSpec m = material("powder", 1600, 1e7, 0.3, 0.6, 0.5);
    m.surface_energy = 0.015;
    const double R = 0.5e-3, g = 9.81;
    auto bond = [&](const MaterialSpec& s, double r) {
      return 1.5 * M_PI * s.surface_energy * (r / 2) / (s.density * 4.0 / 3.0 * M_PI * r * r * r * g);
    };
    auto cohesion = [&](const MaterialSpec& s, double r) {
      const double E_eff = s.youngs_modulus / (2 * (1 - s.poisson_ratio * s.poisson_ratio));
      const double Gamma = 2 * s.surface_energy; // work of adhesion of a pair
      return std::cbrt(std::pow(Gamma, 5) / (E_eff * E_eff * std::pow(r / 2, 8))) / (s.density * g);
    };
    EXPECT_NEAR(bond(scale_material(m, ScalingLaw::Bond, k), k * R) / bond(m, R), 1, 1e-12) << "k=" << k;
    EXPECT_NEAR(cohesion(scale_material(m, ScalingLaw::Cohesion, k), k * R) / cohesion(m, R), 1, 1e-12)
        << "k=" << k;
    // Chen-Elliott keeps the Bond number too; Bond scaling does not keep the cohesion number (E unscaled).
    EXPECT_NEAR(bond(scale_material(m, ScalingLaw::ChenElliott, k), k * R) / bond(m, R), 1, 1e-12);
    EXPECT_GT(std::fabs(cohesion(scale_material(m, ScalingLaw::Bond, k), k * R) / cohesion(m, R) - 1), 0.5);

    // Thakur: stiffnesses x k, f0 x k^2, so at the similar overlap k delta (and the same overlap rate, mass
    // x k^3) the whole linear EEPA cycle (virgin loading, unloading, adhesive branch, damping) is k^2 the
    // original force; f0 x k or x k^3 breaks it where f0 matters (small overlaps).
    MaterialSpec e = material("eepa", 2000, 1e7, 0.3, 0.5, 0.5);
    e.law_parameters["eepa.k1"] = 1e4;
    e.law_parameters["eepa.k2"] = 5e4;
    e.law_parameters["eepa.k_adh"] = 5e3;
    e.law_parameters["eepa.f0"] = -0.4;
    const models::PairParameters po = mix_pair(e, e, true, ContactSpec{});
    const double overlaps[] = {1e-5, 8e-5, 2e-4, 1.2e-4, 3e-5, 5e-6, 1e-6, 1.5e-4};
    auto worst = [&](ScalingLaw law) {
      const models::PairParameters ps = scale_pair(po, law, k);
      Real ho[1] = {0}, hs_[1] = {0};
      double w = 0;
      for (double d : overlaps) {
        models::PairState so{}, ss{};
        so.overlap = d;
        ss.overlap = k * d;
        so.overlap_rate = ss.overlap_rate = -0.01;
        so.mass_eff = 0.5 * sphere_mass(2000, 2.5e-3);
        ss.mass_eff = so.mass_eff * k * k * k;
        const double fo = models::LinearEepa{}(po, so, ho).force,
                     fs = models::LinearEepa{}(ps, ss, hs_).force;
        w = std::max(w, std::fabs(fs / (k * k * fo) - 1));
      }
      return w;
    };
    EXPECT_LT(worst(ScalingLaw::Thakur), 1e-12) << "k=" << k;
    EXPECT_GT(worst(ScalingLaw::ThakurF0Linear), 0.1) << "k=" << k;
    EXPECT_GT(worst(ScalingLaw::ThakurF0Cubic), 0.1) << "k=" << k;
    std::printf("[ report ] k = %g: chen_elliott e %.5f (k=1 %.5f); hu_method1 t_c / (l t_c1) = %.5f\n", k,
                ck.restitution, c1.restitution, hk.contact_time / (k * h1.contact_time));
  }
}
