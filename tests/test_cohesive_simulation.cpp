// Cohesive binary collisions run through the whole engine (make_engine, neighbour list, integrator)
// against the analytic values of docs/physics.md section 1:
//  - full JKR, undamped and frictionless: a head-on collision below the sticking velocity
//    v_stick = sqrt(2 W_s / m*) sticks, above it rebounds (threshold bracketed within +-1%), and the
//    kinetic energy lost well above v_stick is the work of adhesive peeling W_s;
//  - Rabinovich-Lambert liquid bridge (hertz+capillary): two wetted spheres pulled apart feel the bridge
//    force up to the rupture distance S_rup = (1 + theta/2) V^(1/3) and nothing beyond it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/test_support.hpp"

using namespace cgdem;
using namespace cgdem::testing;

namespace {

// Analytic JKR quantities of a pair of spheres of one material (docs/physics.md 3).
struct JkrPair {
  MaterialSpec mat;
  double r1 = 0, r2 = 0;
  double m1 = 0, m2 = 0, m_eff = 0, r_eff = 0, e_eff = 0;
  double u = 0, delta_s = 0, w_s = 0, v_stick = 0;
};

double sphere_mass(double rho, double r) {
  return rho * 4.0 / 3.0 * M_PI * r * r * r;
}

JkrPair jkr_pair(double r1, double r2, double rho, double E, double nu, double gamma) {
  JkrPair c;
  c.mat = material("grain", rho, E, nu, 1.0, 0.0); // e = 1: no damping; mu = 0
  c.mat.surface_energy = gamma;
  c.r1 = r1;
  c.r2 = r2;
  c.m1 = sphere_mass(rho, r1);
  c.m2 = sphere_mass(rho, r2);
  c.m_eff = c.m1 * c.m2 / (c.m1 + c.m2);
  c.r_eff = r1 * r2 / (r1 + r2);
  c.e_eff = E / (2 * (1 - nu * nu));
  c.u = std::cbrt(M_PI * M_PI * gamma * gamma * c.r_eff / (c.e_eff * c.e_eff));
  c.delta_s = -1.1906 * c.u;
  c.w_s = 22.516 * std::cbrt(std::pow(gamma, 5) * std::pow(c.r_eff, 4) / (c.e_eff * c.e_eff));
  c.v_stick = std::sqrt(2 * c.w_s / c.m_eff);
  return c;
}

struct Collision {
  bool touched = false, separated = false;
  double ke_before = 0, ke_after = 0;
  double v_after = 0;            // separating relative speed after the bond broke
  double max_overlap = 0;        // largest overlap
  double min_bonded_overlap = 0; // most negative overlap seen while still bonded
  double contact_time = 0;       // first touch to bond break
  long steps = 0;
};

// Head-on collision along x at relative approach speed v (zero total momentum), law "jkr" without
// friction. Runs until the bond breaks or t_max; the state is sampled every `every` steps.
Collision collide(const JkrPair& c, double v, double dt, double t_max, int every = 10) {
  Scene s = basic_scene({c.mat}, "jkr", "none");
  ParticleSet p;
  const double gap = 1e-3 * c.r1; // initial surface gap, covered in a few dozen steps
  const double mt = c.m1 + c.m2;
  add_particle(p, {-c.r1 - 0.5 * gap, 0, 0}, {v * c.m2 / mt, 0, 0}, c.r1, c.mat.density);
  add_particle(p, {c.r2 + 0.5 * gap, 0, 0}, {-v * c.m1 / mt, 0, 0}, c.r2, c.mat.density);
  auto engine = make(s, p, dt);
  Collision out;
  out.ke_before = engine->observe().kinetic_energy;
  long first = -1;
  const long max_steps = static_cast<long>(t_max / dt);
  while (engine->step() < max_steps) {
    engine->advance(every);
    const FrameData f = engine->frame();
    const Observables o = engine->observe();
    const double overlap = c.r1 + c.r2 - (f.position[3] - f.position[0]);
    if (!out.touched && overlap >= 0) {
      out.touched = true;
      first = engine->step();
    }
    if (!out.touched) continue;
    out.max_overlap = std::max(out.max_overlap, overlap);
    if (o.contacts > 0) {
      out.min_bonded_overlap = std::min(out.min_bonded_overlap, overlap);
    } else {
      out.separated = true;
      out.contact_time = (engine->step() - first) * dt;
      out.ke_after = o.kinetic_energy;
      out.v_after = f.velocity[3] - f.velocity[0];
      break;
    }
  }
  out.steps = engine->step();
  return out;
}

// The unequal pair of the LAMMPS cross-check (perf/peers/jkr): 0.5 and 1 mm, 2500 kg/m^3, E = 1 MPa,
// nu = 0.3, gamma = 0.5 J/m^2: u = 14 um, W_s = 2.44e-8 J, v_stick = 0.205 m/s, contact ~ 0.5 ms.
JkrPair unequal_pair() {
  return jkr_pair(0.5e-3, 1e-3, 2500, 1e6, 0.3, 0.5);
}
// An equal pair of another material: 1 mm, 1500 kg/m^3, E = 5 MPa, nu = 0.25, gamma = 0.2 J/m^2.
JkrPair equal_pair() {
  return jkr_pair(1e-3, 1e-3, 1500, 5e6, 0.25, 0.2);
}

// Time step: the snap-in (0 -> -8/9 F_c at delta = 0) and the break (-5/9 F_c -> 0 at delta_S) are force
// jumps, each worth up to F_c v dt of energy error against W_s ~ 1.1 F_c u; v dt <= 2e-4 u keeps it far
// below the 2% of W_s that separates 0.99 from 1.01 v_stick. This gives ~ 2e4 steps per contact.
double jkr_dt(const JkrPair& c, double v) {
  return 2e-4 * c.u / v;
}

void expect_sticks_and_rebounds(const JkrPair& c, const char* label) {
  const double dt = jkr_dt(c, c.v_stick);
  // Hertz contact time at v_stick: the bonded phase lasts a few of these.
  const double tc = hertz_contact_time(c.m_eff, c.r_eff, c.e_eff, c.v_stick);
  const Collision below = collide(c, 0.99 * c.v_stick, dt, 5 * tc);
  const Collision above = collide(c, 1.01 * c.v_stick, dt, 5 * tc);
  std::printf("[ report ] %s: v_stick = %.5f m/s, dt = %.3g s (%.0f steps per Hertz contact time)\n", label,
              c.v_stick, dt, tc / dt);
  std::printf("[ report ]   0.99 v_stick: %s after %.3g s, deepest bonded gap %.5f delta_S\n",
              below.separated ? "REBOUND" : "stuck", below.steps * dt, below.min_bonded_overlap / c.delta_s);
  std::printf("[ report ]   1.01 v_stick: %s after %.3g s of contact, v_after %.5f m/s (analytic %.5f)\n",
              above.separated ? "rebound" : "STUCK", above.contact_time, above.v_after,
              std::sqrt(std::pow(1.01 * c.v_stick, 2) - c.v_stick * c.v_stick));
  ASSERT_TRUE(below.touched && above.touched);
  EXPECT_FALSE(below.separated) << label << ": 0.99 v_stick rebounded";
  // It came close to the separation point without passing it.
  EXPECT_GT(below.min_bonded_overlap, c.delta_s);
  EXPECT_LT(below.min_bonded_overlap, 0.5 * c.delta_s);
  EXPECT_TRUE(above.separated) << label << ": 1.01 v_stick stuck";
  // Rebound speed sqrt(v^2 - v_stick^2) = 0.141 v_stick: an energy error of 0.2% of W_s moves it by 7%.
  EXPECT_NEAR(above.v_after / std::sqrt(std::pow(1.01 * c.v_stick, 2) - c.v_stick * c.v_stick), 1.0, 0.1);
}

} // namespace

TEST(JkrCollision, UnequalSpheresStickBelowAndReboundAboveStickingVelocity) {
  expect_sticks_and_rebounds(unequal_pair(), "JKR 0.5 + 1 mm");
}

TEST(JkrCollision, BisectedStickingThresholdMatchesAnalytic) {
  // Bisection on v / v_stick in [0.9, 1.1] down to 0.1%: the measured threshold of the unequal pair.
  const JkrPair c = unequal_pair();
  const double dt = jkr_dt(c, c.v_stick);
  const double tc = hertz_contact_time(c.m_eff, c.r_eff, c.e_eff, c.v_stick);
  double lo = 0.9, hi = 1.1;
  while (hi - lo > 1e-3) {
    const double mid = 0.5 * (lo + hi);
    (collide(c, mid * c.v_stick, dt, 5 * tc).separated ? hi : lo) = mid;
  }
  std::printf("[ report ] JKR 0.5 + 1 mm: measured sticking threshold in [%.4f, %.4f] v_stick\n", lo, hi);
  EXPECT_NEAR(0.5 * (lo + hi), 1.0, 0.01);
}

TEST(JkrCollision, EqualSpheresStickBelowAndReboundAboveStickingVelocity) {
  expect_sticks_and_rebounds(equal_pair(), "JKR 1 + 1 mm");
}

TEST(JkrCollision, EnergyLostInUndampedCollisionIsPeelingWork) {
  for (const JkrPair& c : {unequal_pair(), equal_pair()}) {
    const double v = 3 * c.v_stick;
    const double tc = hertz_contact_time(c.m_eff, c.r_eff, c.e_eff, v);
    const Collision r = collide(c, v, jkr_dt(c, v), 10 * tc);
    ASSERT_TRUE(r.separated);
    const double lost = r.ke_before - r.ke_after;
    std::printf(
        "[ report ] JKR %.1f + %.1f mm at 3 v_stick: KE lost / W_s = %.5f, v_after / analytic = %.5f, "
        "contact %.4g s, max overlap %.4g m\n",
        c.r1 * 1e3, c.r2 * 1e3, lost / c.w_s, r.v_after / std::sqrt(v * v - c.v_stick * c.v_stick),
        r.contact_time, r.max_overlap);
    EXPECT_NEAR(r.ke_before, 0.5 * c.m_eff * v * v, 1e-12 * r.ke_before);
    EXPECT_NEAR(lost / c.w_s, 1.0, 0.01);
  }
}

// ---------------------------------------------------------------------------------------------------
namespace {

// Rabinovich-Lambert bridge force (docs/physics.md 3), written out independently of models/.
double bridge_force(double r_eff, double sigma, double theta, double volume, double s_min, double gap) {
  const double S = std::max(gap, s_min);
  return 4 * M_PI * r_eff * sigma * std::cos(theta) /
         (1 + 1 / (std::sqrt(1 + volume / (M_PI * r_eff * S * S)) - 1));
}

} // namespace

TEST(CapillaryBridgeSimulation, PulledApartSpheresLoseBridgeExactlyAtRuptureDistance) {
  const double r1 = 0.5e-3, r2 = 0.8e-3, rho = 2500, sigma = 0.072, theta = 20 * M_PI / 180;
  const double fraction = 0.083 * 0.05; // Hu: V = 0.083 x 0.05 x (V_i + V_j)
  MaterialSpec m = material("wet", rho, 5e6, 0.3, 1.0, 0.0);
  m.law_parameters["capillary.surface_tension"] = sigma;
  m.law_parameters["capillary.contact_angle"] = theta; // radians in MaterialSpec
  m.law_parameters["capillary.liquid_fraction"] = fraction;
  Scene s = basic_scene({m}, "hertz", "none");
  s.contact.adhesion = "capillary";

  const double m1 = sphere_mass(rho, r1), m2 = sphere_mass(rho, r2), m_eff = m1 * m2 / (m1 + m2);
  const double r_eff = r1 * r2 / (r1 + r2);
  const double volume = fraction * 4.0 / 3.0 * M_PI * (r1 * r1 * r1 + r2 * r2 * r2);
  const double s_rup = (1 + 0.5 * theta) * std::cbrt(volume);
  const double s_min = m.law_parameter("capillary.min_separation", 1e-6);
  // Start touching (overlap 1 nm: the bridge forms, the Hertz push is ~1e-9 N) and separating at
  // 0.5 m/s relative; the bridge takes ~ 1e-8 J of the 8e-8 J kinetic energy.
  const double v0 = 0.5, overlap0 = 1e-9;
  ParticleSet p;
  add_particle(p, {-r1 + 0.5 * overlap0, 0, 0}, {-v0 * m2 / (m1 + m2), 0, 0}, r1, rho);
  add_particle(p, {r2 - 0.5 * overlap0, 0, 0}, {v0 * m1 / (m1 + m2), 0, 0}, r2, rho);
  const double dt = 1e-4 * s_rup / v0; // the gap grows by <= 1e-4 S_rup per step
  auto engine = make(s, p, dt);

  auto state = [&](double& gap, double& vrel) {
    const FrameData f = engine->frame();
    gap = f.position[3] - f.position[0] - r1 - r2;
    vrel = f.velocity[3] - f.velocity[0];
  };
  double gap, vrel;
  // Coarse phase: up to 0.98 S_rup in batches.
  for (int k = 0; k < 1000; ++k) {
    state(gap, vrel);
    if (gap > 0.98 * s_rup) break;
    engine->advance(100);
  }
  ASSERT_GT(gap, 0.98 * s_rup);
  ASSERT_LT(gap, s_rup);
  ASSERT_GT(vrel, 0.5 * v0);

  // Fine phase, step by step through S_rup. Velocity Verlet: v_{n+1} - v_n = dt/2 (a_n + a_{n+1}).
  int before = 0, after = 0, crossing = 0;
  double last_gap_with_force = 0, first_gap_without = 0, worst_rel = 0;
  for (int k = 0; k < 20000 && after < 200; ++k) {
    double gap1, vrel1;
    engine->advance(1);
    state(gap1, vrel1);
    const double dv = vrel1 - vrel;
    const double f0 = gap <= s_rup ? bridge_force(r_eff, sigma, theta, volume, s_min, gap) : 0;
    const double f1 = gap1 <= s_rup ? bridge_force(r_eff, sigma, theta, volume, s_min, gap1) : 0;
    const double expected = -0.5 * dt * (f0 + f1) / m_eff;
    if (gap1 <= s_rup) {
      ++before;
      ASSERT_LT(dv, 0) << "no bridge force at gap " << gap1 / s_rup << " S_rup";
      last_gap_with_force = gap1;
    } else if (gap <= s_rup) {
      ++crossing;
      first_gap_without = gap1;
    } else {
      ++after;
      ASSERT_EQ(dv, 0.0) << "bridge force at gap " << gap1 / s_rup << " S_rup, beyond rupture";
    }
    if (expected != 0) worst_rel = std::max(worst_rel, std::fabs(dv / expected - 1));
    gap = gap1;
    vrel = vrel1;
  }
  std::printf(
      "[ report ] capillary: S_rup = %.6g m; last gap with force %.7f S_rup, first without %.7f S_rup; "
      "%d steps before, %d after; velocity change vs analytic force: worst relative error %.2g\n",
      s_rup, last_gap_with_force / s_rup, first_gap_without / s_rup, before, after, worst_rel);
  EXPECT_GT(before, 50);
  EXPECT_EQ(crossing, 1);
  EXPECT_EQ(after, 200);
  EXPECT_GT(last_gap_with_force, (1 - 2e-4) * s_rup);
  EXPECT_LT(first_gap_without, (1 + 2e-4) * s_rup);
  // The bridge force just before rupture is the analytic one (non-zero: ~ 9% of its contact value).
  EXPECT_LT(worst_rel, 1e-6);
  EXPECT_GT(bridge_force(r_eff, sigma, theta, volume, s_min, s_rup),
            0.05 * 4 * M_PI * r_eff * sigma * std::cos(theta));
}
