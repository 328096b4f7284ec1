// Unit tests of the cohesive contact components (models/): full JKR with its three separation rules (Hu's
// JKR among them), DMT, linear EEPA, the Rabinovich-Lambert liquid bridge and the two rolling resistances,
// called directly on the host (and once inside a Kokkos kernel). Reference values: docs/physics.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "setup/restitution.hpp"
#include "models/capillary_bridge.hpp"
#include "models/contact_law.hpp"
#include "models/dmt.hpp"
#include "models/hertz_tsuji.hpp"
#include "models/jkr_full.hpp"
#include "models/linear_eepa.hpp"
#include "models/linear_spring_dashpot.hpp"
#include "models/mindlin_tangential.hpp"
#include "models/rolling_resistance.hpp"

using namespace cgdem;
using namespace cgdem::models;

// ---------------------------------------------------------------------------------------------------
// Every component keeps exactly the per-contact state it needs.
static_assert(ContactLaw<HertzTsuji>::history_size == 0);
static_assert(ContactLaw<LinearSpringDashpot>::history_size == 0);
static_assert(JkrFull::history_size == 1); // bonded flag
static_assert(Dmt::history_size == 0);
static_assert(LinearEepa::history_size == 1);      // plastic overlap
static_assert(CapillaryBridge::history_size == 1); // bridge alive flag
static_assert(RollingConstantTorque::history_size == 0);
static_assert(RollingSpringDashpot::history_size == 3); // relative rolling rotation
static_assert(ContactLaw<HertzTsuji, Dmt, MindlinTangential>::history_size == 3);
static_assert(ContactLaw<LinearEepa, NoAdhesion, MindlinTangential, RollingConstantTorque>::history_size ==
              4);
using FullLaw = ContactLaw<JkrFull, CapillaryBridge, MindlinTangential, RollingSpringDashpot>;
static_assert(FullLaw::history_size == 8);
static_assert(FullLaw::adhesion_offset == 1 && FullLaw::tangential_offset == 2 &&
              FullLaw::rolling_offset == 5);

namespace {

constexpr Real pi = math::pi;

struct Material {
  Real E, nu;
};

// Mixed parameters of two materials (docs/physics.md 0: E*, G*).
PairParameters mixed(Material a, Material b, Real gamma, Real restitution = 1) {
  PairParameters p;
  p.E_eff = 1 / ((1 - a.nu * a.nu) / a.E + (1 - b.nu * b.nu) / b.E);
  p.G_eff = 1 / (2 * (2 - a.nu) * (1 + a.nu) / a.E + 2 * (2 - b.nu) * (1 + b.nu) / b.E);
  p.surface_energy = gamma;
  p.restitution = restitution;
  p.damping = 2 * std::sqrt(5.0 / 6.0) * -restitution_beta(restitution); // Tsuji's, exact for JKR
  return p;
}

// A pair of spheres (R_j <= 0: a wall) with normal n = +x.
PairState pair(Real R_i, Real R_j, Real overlap, Real rho = 1000) {
  PairState s;
  s.overlap = overlap;
  s.normal = Vec3{1, 0, 0};
  s.radius_i = R_i;
  s.radius_j = R_j > 0 ? R_j : 0;
  s.radius_eff = R_j > 0 ? 1 / (1 / R_i + 1 / R_j) : R_i;
  const Real m_i = rho * 4.0 / 3.0 * pi * R_i * R_i * R_i;
  const Real m_j = R_j > 0 ? rho * 4.0 / 3.0 * pi * R_j * R_j * R_j : 0;
  s.mass_eff = R_j > 0 ? 1 / (1 / m_i + 1 / m_j) : m_i;
  s.volume_i = 4.0 / 3.0 * pi * R_i * R_i * R_i;
  s.volume_j = R_j > 0 ? 4.0 / 3.0 * pi * R_j * R_j * R_j : 0;
  s.dt = 1e-6;
  return s;
}

// JKR test cases: (R_i, R_j, E, nu, gamma); R_j = 0 is a wall of the same material.
struct JkrCase {
  const char* label;
  Real R_i, R_j, E, nu, gamma;
};
const JkrCase jkr_cases[] = {
    {"R 0.5+1 mm, E 1 MPa, gamma 0.5", 0.5e-3, 1e-3, 1e6, 0.3, 0.5},
    {"R 10+10 um, E 100 MPa, gamma 0.05", 10e-6, 10e-6, 1e8, 0.25, 0.05},
    {"R 2 mm on wall, E 5 GPa, gamma 0.1", 2e-3, 0, 5e9, 0.35, 0.1},
};

struct JkrSetup {
  PairParameters p;
  PairState s;
  Real R, Es, gamma, u, F_c;
};

JkrSetup setup(const JkrCase& c) {
  JkrSetup j;
  j.p = mixed({c.E, c.nu}, {c.E, c.nu}, c.gamma);
  j.s = pair(c.R_i, c.R_j, 0);
  j.R = j.s.radius_eff;
  j.Es = j.p.E_eff;
  j.gamma = c.gamma;
  j.u = std::cbrt(pi * pi * c.gamma * c.gamma * j.R / (j.Es * j.Es));
  j.F_c = 3 * pi * c.gamma * j.R;
  return j;
}

// JKR force with a fresh bonded history (cold start) or the given history.
struct JkrEval {
  bool active;
  Real force, a;
};
JkrEval jkr_at(const JkrSetup& j, Real overlap, Real* h) {
  PairState s = j.s;
  s.overlap = overlap;
  const NormalResult r = JkrFull{}(j.p, s, h);
  return {r.active, r.force, r.stiffness / (2 * j.p.E_eff)}; // stiffness = 2 E* a
}
JkrEval jkr_bonded(const JkrSetup& j, Real overlap) {
  Real h[1] = {1};
  return jkr_at(j, overlap, h);
}

// The JKR relation in physical units, written out independently of models/jkr_relation.hpp.
Real jkr_delta_of_a(const JkrSetup& j, Real a) {
  return a * a / j.R - std::sqrt(4 * pi * j.gamma * a / j.Es);
}

Real rel(Real x, Real ref) {
  return std::fabs(x - ref) / std::fabs(ref);
}

} // namespace

// ---------------------------------------------------------------------------------------------------
TEST(JkrFull, KeyPointsMatchTable) {
  for (const JkrCase& c : jkr_cases) {
    const JkrSetup j = setup(c);
    const Real R = j.R, g = j.gamma, E = j.Es;

    // A: an approaching pair feels nothing across a gap, then snaps in at zero overlap.
    Real h[2] = {0, 0};
    EXPECT_FALSE(jkr_at(j, -1e-9 * j.u, h).active);
    const JkrEval A = jkr_at(j, 0, h);
    ASSERT_TRUE(A.active);
    const Real a_A = std::cbrt(4 * pi * g * R * R / E);
    EXPECT_LT(rel(A.force, -8.0 / 9.0 * j.F_c), 1e-3);
    EXPECT_LT(rel(A.a, a_A), 1e-3);

    // B: zero force, found by bisection on the bonded branch.
    Real lo = 0, hi = 5 * j.u;
    for (int k = 0; k < 200; ++k) {
      const Real mid = 0.5 * (lo + hi);
      (jkr_bonded(j, mid).force < 0 ? lo : hi) = mid;
    }
    const Real d_B = 0.5 * (lo + hi);
    const JkrEval B = jkr_bonded(j, d_B);
    EXPECT_LT(rel(d_B, 1.4422 * j.u), 1e-3);
    EXPECT_LT(rel(B.a, std::cbrt(9 * pi * g * R * R / E)), 1e-3);

    // S: the smallest overlap a bonded pair survives, by bisection on the break.
    lo = -3 * j.u;
    hi = 0;
    for (int k = 0; k < 200; ++k) {
      const Real mid = 0.5 * (lo + hi);
      (jkr_bonded(j, mid).active ? hi : lo) = mid;
    }
    const Real d_S = hi;
    const JkrEval S = jkr_bonded(j, d_S);
    EXPECT_LT(rel(d_S, -1.1906 * j.u), 1e-3);
    EXPECT_LT(rel(S.force, -5.0 / 9.0 * j.F_c), 1e-3);
    EXPECT_LT(rel(S.a, std::cbrt(pi * g * R * R / (4 * E))), 1e-3);
    EXPECT_NEAR(JkrFull::interaction_range(j.p, c.R_i, c.R_j), -d_S, 1e-9 * j.u);

    // C: the maximum attraction, by golden-section search over the overlap in (delta_S, 0).
    Real x0 = d_S, x3 = 0;
    const Real phi = 0.5 * (std::sqrt(5.0) - 1);
    for (int k = 0; k < 200; ++k) {
      const Real x1 = x3 - phi * (x3 - x0), x2 = x0 + phi * (x3 - x0);
      if (jkr_bonded(j, x1).force < jkr_bonded(j, x2).force)
        x3 = x2;
      else
        x0 = x1;
    }
    const Real d_C = 0.5 * (x0 + x3);
    const JkrEval C = jkr_bonded(j, d_C);
    EXPECT_LT(rel(d_C, -0.5724 * j.u), 1e-3);
    EXPECT_LT(rel(C.force, -j.F_c), 1e-3);
    EXPECT_LT(rel(C.a, std::cbrt(9 * pi * g * R * R / (4 * E))), 1e-3);

    std::printf("[%s] u = %.5g m, F_c = %.5g N\n"
                "  A: F/F_c = %.6f (-0.888889)  a = %.6g m (%.6g)\n"
                "  B: delta/u = %.6f (1.4422)   a = %.6g m\n"
                "  C: F/F_c = %.6f (-1)         delta/u = %.6f (-0.5724)\n"
                "  S: F/F_c = %.6f (-0.555556)  delta/u = %.6f (-1.1906)\n",
                c.label, j.u, j.F_c, A.force / j.F_c, A.a, a_A, d_B / j.u, B.a, C.force / j.F_c, d_C / j.u,
                S.force / j.F_c, d_S / j.u);
  }
}

TEST(JkrFull, HysteresisSnapInAndSeparation) {
  const JkrSetup j = setup(jkr_cases[0]);
  Real h[2] = {0, 0};
  // Approach: nothing across the gap, even inside |delta_S|.
  for (Real d = -2 * j.u; d < 0; d += 0.05 * j.u)
    EXPECT_FALSE(jkr_at(j, d, h).active);
  EXPECT_EQ(h[0], 0);
  EXPECT_TRUE(jkr_at(j, 0, h).active);
  EXPECT_EQ(h[0], 1);
  // Retraction: bonded across the gap down to delta_S, with attraction.
  const Real d_S = jkr::d_S * j.u;
  for (Real d = 0; d > d_S * (1 - 1e-9); d -= 0.01 * j.u) {
    const JkrEval e = jkr_at(j, d, h);
    EXPECT_TRUE(e.active);
    EXPECT_LT(e.force, 0);
  }
  EXPECT_TRUE(jkr_at(j, d_S * (1 - 1e-9), h).active);
  EXPECT_FALSE(jkr_at(j, d_S * (1 + 1e-9), h).active);
  EXPECT_EQ(h[0], 0);
  // Broken: a second approach across the gap again feels nothing.
  EXPECT_FALSE(jkr_at(j, 0.5 * d_S, h).active);
}

TEST(JkrFull, PeelingWorkMatchesAnalytic) {
  for (const JkrCase& c : jkr_cases) {
    const JkrSetup j = setup(c);
    Real h[2] = {0, 0};
    const int n = 200000;
    const Real d_end = jkr::d_S * j.u * (1 - 1e-12);
    Real prev_d = 0, prev_f = jkr_at(j, 0, h).force, work = 0;
    for (int k = 1; k <= n; ++k) {
      // Steps cluster near S, where F(delta) has a square-root shape.
      const Real t = Real(k) / n;
      const Real d = d_end * (1 - (1 - t) * (1 - t));
      const JkrEval e = jkr_at(j, d, h);
      ASSERT_TRUE(e.active);
      work += 0.5 * (e.force + prev_f) * (d - prev_d); // d decreasing, F < 0: positive work
      prev_d = d;
      prev_f = e.force;
    }
    EXPECT_FALSE(jkr_at(j, d_end * 1.001, h).active);
    const Real W_ref = 22.516 * std::cbrt(std::pow(j.gamma, 5) * std::pow(j.R, 4) / (j.Es * j.Es));
    std::printf("[%s] peeling work %.6g J, 22.516 (g^5 R*^4/E*^2)^(1/3) = %.6g J, ratio %.6f\n", c.label,
                work, W_ref, work / W_ref);
    EXPECT_LT(rel(work, W_ref), 5e-3);
  }
}

TEST(JkrFull, NewtonConvergesOnWholeBranch) {
  for (const JkrCase& c : jkr_cases) {
    const JkrSetup j = setup(c);
    const Real d_top = 200 * j.u, d_bot = jkr::d_S * j.u * (1 - 1e-6);
    const int n = 20000;
    Real warm[2] = {0, 0};
    jkr_at(j, d_top, warm); // snap in (d_top >= 0)
    Real worst_warm = 0, worst_cold = 0;
    for (int k = 0; k <= n; ++k) {
      const Real t = Real(k) / n;
      const Real d = d_top + (d_bot - d_top) * (1 - (1 - t) * (1 - t) * (1 - t));
      const Real scale = std::max(std::fabs(d), std::fabs(jkr::d_S * j.u));
      const JkrEval w = jkr_at(j, d, warm);
      ASSERT_TRUE(w.active) << d / j.u;
      const JkrEval cold = jkr_bonded(j, d);
      worst_warm = std::max(worst_warm, std::fabs(jkr_delta_of_a(j, w.a) - d) / scale);
      worst_cold = std::max(worst_cold, std::fabs(jkr_delta_of_a(j, cold.a) - d) / scale);
      // The root is on the physical branch a >= a_S.
      EXPECT_GE(w.a, std::cbrt(pi * j.gamma * j.R * j.R / (4 * j.Es)) * (1 - 1e-12));
    }
    // A warm start from far up the branch straight to next to S, and from an invalid radius.
    const Real a_S = jkr::x_S * std::cbrt(pi * j.gamma * j.R * j.R / j.Es);
    Real jump[2] = {1, 100 * j.u};
    const Real jump_res = std::fabs(jkr_delta_of_a(j, jkr_at(j, d_bot, jump).a) - d_bot) / std::fabs(d_bot);
    Real bad[2] = {1, 0.5 * a_S};
    const Real bad_res =
        std::fabs(jkr_delta_of_a(j, jkr_at(j, 0.3 * j.u, bad).a) - 0.3 * j.u) / std::fabs(d_bot);
    std::printf("[%s] max relative residual of delta(a): warm sweep %.3g, cold %.3g, jumps %.3g %.3g\n",
                c.label, worst_warm, worst_cold, jump_res, bad_res);
    EXPECT_LT(worst_warm, 1e-10);
    EXPECT_LT(worst_cold, 1e-10);
    EXPECT_LT(jump_res, 1e-10);
    EXPECT_LT(bad_res, 1e-10);
  }
  // Iteration counts of the dimensionless solve: warm along a sweep of 1000 steps, and cold.
  int warm_max = 0, cold_max = 0;
  long warm_sum = 0;
  Real x = 0;
  const int n = 1000;
  for (int k = 0; k <= n; ++k) {
    const Real d = 20 + (jkr::d_S * (1 - 1e-6) - 20) * Real(k) / n;
    int it_w = 0, it_c = 0;
    x = jkr::solve_x(d, x, &it_w);
    jkr::solve_x(d, 0, &it_c);
    warm_max = std::max(warm_max, it_w);
    warm_sum += it_w;
    cold_max = std::max(cold_max, it_c);
  }
  std::printf("Newton iterations: warm mean %.2f max %d, cold max %d\n", double(warm_sum) / (n + 1), warm_max,
              cold_max);
  EXPECT_LE(warm_max, 12);
  EXPECT_LE(cold_max, 20);
}

TEST(JkrFull, ReducesToHertzWhenGammaZero) {
  PairParameters p = mixed({1e7, 0.3}, {2e7, 0.25}, 0, 0.6);
  for (Real overlap : {-1e-6, 0.0, 1e-7, 1e-6, 3e-5}) {
    for (Real rate : {-0.5, 0.0, 0.3}) {
      PairState s = pair(1e-3, 2e-3, overlap);
      s.overlap_rate = rate;
      Real h[1] = {1};
      const NormalResult jr = JkrFull{}(p, s, h);
      const NormalResult hr = HertzTsuji{}(p, s, nullptr);
      EXPECT_EQ(jr.active, hr.active);
      EXPECT_EQ(jr.force, hr.force);
      EXPECT_EQ(jr.friction_load, hr.friction_load);
      EXPECT_EQ(jr.k_t, hr.k_t);
      EXPECT_EQ(jr.c_t, hr.c_t);
      EXPECT_EQ(jr.stiffness, hr.stiffness);
      EXPECT_EQ(h[0], 0);
    }
  }
  EXPECT_EQ(JkrFull::interaction_range(p, 1e-3, 2e-3), 0);
  // Continuity: a vanishing surface energy approaches Hertz (elastic part and damping).
  p.surface_energy = 1e-12;
  PairState s = pair(1e-3, 2e-3, 1e-5);
  s.overlap_rate = 0.3;
  Real h[2] = {0, 0};
  const NormalResult jr = JkrFull{}(p, s, h);
  const NormalResult hr = HertzTsuji{}(p, s, nullptr);
  std::printf("gamma = 1e-12: JKR/Hertz force ratio %.9f, k_t ratio %.9f\n", jr.force / hr.force,
              jr.k_t / hr.k_t);
  EXPECT_LT(rel(jr.force, hr.force), 1e-4);
  EXPECT_LT(rel(jr.k_t, hr.k_t), 1e-4);
  EXPECT_LT(rel(jr.c_t, hr.c_t), 1e-4);
}

TEST(JkrFull, DampingTangentialAndFrictionLoad) {
  const JkrSetup j0 = setup(jkr_cases[0]);
  PairParameters p = j0.p;
  p.restitution = 0.5;
  const Real beta = -restitution_beta(0.5);
  p.damping = 2 * std::sqrt(5.0 / 6.0) * beta;
  for (Real d : {-1.0, -0.3, 0.0, 1.0, 10.0}) {
    PairState s = j0.s;
    s.overlap = d * j0.u;
    s.overlap_rate = 0.2;
    Real h[1] = {1};
    const NormalResult r = JkrFull{}(p, s, h);
    const Real a = r.stiffness / (2 * p.E_eff); // stiffness = 2 E* a
    Real h0[1] = {1};
    s.overlap_rate = 0;
    const NormalResult r0 = JkrFull{}(p, s, h0);
    const Real c_n = 2 * std::sqrt(5.0 / 6.0) * beta * std::sqrt(2 * p.E_eff * a * s.mass_eff);
    EXPECT_LT(rel(r.force - r0.force, c_n * 0.2), 1e-10);
    EXPECT_LT(rel(r.k_t, 8 * p.G_eff * a), 1e-14);
    EXPECT_LT(rel(r.c_t, 4 * std::sqrt(5.0 / 3.0) * beta * std::sqrt(s.mass_eff * p.G_eff * a)), 1e-12);
    EXPECT_LT(rel(r.stiffness, 2 * p.E_eff * a), 1e-14);
    // Thornton & Yin: |4 (a/a_0)^3 - 4 (a/a_0)^1.5 + 2| F_c.
    const Real a0 = std::cbrt(9 * pi * j0.gamma * j0.R * j0.R / p.E_eff);
    const Real y = a / a0;
    EXPECT_LT(rel(r.friction_load, std::fabs(4 * y * y * y - 4 * std::pow(y, 1.5) + 2) * j0.F_c), 1e-10);
    // The elastic force is the JKR expression of a.
    const Real F = 4 * p.E_eff * a * a * a / (3 * j0.R) - std::sqrt(16 * pi * j0.gamma * p.E_eff * a * a * a);
    EXPECT_NEAR(r0.force, F, 1e-12 * j0.F_c);
  }
}

// ---------------------------------------------------------------------------------------------------
// Hu's JKR (section 2.3.2, eqs 5, 10, 11, 16, 23) is JkrFull with jkr_separation: contact_loss: one JKR
// contact radius in the repulsion and the attraction, so for delta >= 0 the force is the full JKR curve
// (-8/9 F_c at delta = 0), the Coulomb load is Thornton's |F + 2 F_c|, and nothing acts across a gap.
TEST(JkrFull, ContactLossIsHusJkr) {
  for (const JkrCase& c : jkr_cases) {
    JkrSetup j = setup(c);
    j.p.jkr_separation_overlap = 0;
    EXPECT_EQ(JkrFull::interaction_range(j.p, j.R, 0), 0); // no reach beyond touching
    ContactLaw<JkrFull> law;
    // Loading from first touch, then unloading back through zero.
    Real h[2] = {0, 0};
    const Real path[] = {0.0, 0.01, 0.5, 1.4422, 5.0, 50.0, 5.0, 0.5, 0.0};
    for (Real d : path) {
      PairState s = j.s;
      s.overlap = d * j.u;
      const ContactForce f = law(j.p, s, h);
      EXPECT_TRUE(f.active);
      NormalResult nr = JkrFull{}(j.p, s, h);
      const Real a = nr.stiffness / (2 * j.Es); // stiffness = 2 E* a
      // a solves Hu's eq 11 (the JKR relation) for this overlap ...
      EXPECT_LT(std::fabs(jkr_delta_of_a(j, a) - s.overlap) / std::max(s.overlap, j.u), 1e-10);
      // ... and the force is eq 5 minus eq 23 with that one radius: the full JKR curve.
      const Real F = 4 * j.Es * a * a * a / (3 * j.R) - std::sqrt(16 * pi * j.gamma * j.Es * a * a * a);
      EXPECT_NEAR(-dot(f.force, s.normal), F, 1e-10 * j.F_c);
      EXPECT_NEAR(nr.friction_load, std::fabs(F + 2 * j.F_c), 1e-10 * j.F_c);
      if (d == 0) {
        EXPECT_LT(rel(-F, 8.0 / 9.0 * j.F_c), 1e-10);
        std::printf("[%s] Hu's JKR at delta = 0: %.6f F_c\n", c.label, F / j.F_c);
      }
    }
    // The bond breaks as soon as the overlap is lost, and the history is reset.
    PairState s = j.s;
    s.overlap = -1e-12 * j.u;
    const ContactForce f = law(j.p, s, h);
    EXPECT_FALSE(f.active);
    EXPECT_EQ(norm(f.force), 0);
    EXPECT_EQ(h[0], 0);
  }
}

// ---------------------------------------------------------------------------------------------------
TEST(Dmt, PullOffForceIsFourPiGammaR) {
  for (const JkrCase& c : jkr_cases) {
    const JkrSetup j = setup(c);
    ContactLaw<HertzTsuji, Dmt> law;
    const Real ref = 4 * pi * j.gamma * j.R;
    // The largest attraction along a retraction path: at delta = 0, then nothing.
    Real max_pull = 0;
    bool any_beyond = false;
    for (int k = 0; k <= 2000; ++k) {
      PairState s = j.s;
      s.overlap = (2.0 - 0.002 * k) * j.u; // 2u down to -2u
      const ContactForce f = law(j.p, s, nullptr);
      const Real pull = dot(f.force, s.normal);
      max_pull = std::max(max_pull, pull);
      if (s.overlap < 0) any_beyond = any_beyond || f.active || pull != 0;
    }
    PairState s = j.s;
    s.overlap = 0;
    const Real at_contact = dot(law(j.p, s, nullptr).force, s.normal);
    std::printf("[%s] DMT pull-off %.6g N, 4 pi gamma R* = %.6g N (%.6f F_c)\n", c.label, at_contact, ref,
                at_contact / j.F_c);
    EXPECT_LT(rel(at_contact, ref), 1e-14);
    EXPECT_LE(max_pull, ref * (1 + 1e-14));
    EXPECT_FALSE(any_beyond);
  }
}

// ---------------------------------------------------------------------------------------------------
TEST(LinearEepa, FollowsPiecewiseLawThroughWholeLoop) {
  PairParameters p;
  p.eepa_k1 = 1e4;
  p.eepa_k2 = 2e4;
  p.eepa_k_adh = 2e3;
  p.eepa_f0 = -1e-3;
  p.damping = 0;
  const Real k1 = p.eepa_k1, k2 = p.eepa_k2, ka = p.eepa_k_adh, f0 = p.eepa_f0;
  const Real u = 1e-6;
  // Path (units of u): virgin loading, unloading, reloading along k2 and past the old maximum onto the
  // virgin line, unloading into the adhesive tail, reversal on the tail, separation, a fresh contact.
  const Real knots[] = {0, 10, 7, 9.5, 14, 5, 6, 0.5, -1, 0, 3, -0.5};
  PairState s = pair(1e-3, 1e-3, 0);
  Real h[1] = {0};
  Real delta_max = 0; // independent reference: delta_p = delta_max (1 - k1/k2)
  int n_virgin = 0, n_k2 = 0, n_adh = 0, n_off = 0;
  Real worst = 0;
  for (size_t seg = 0; seg + 1 < sizeof(knots) / sizeof(knots[0]); ++seg) {
    const int steps = 400;
    for (int k = 1; k <= steps; ++k) {
      const Real d = u * (knots[seg] + (knots[seg + 1] - knots[seg]) * Real(k) / steps);
      s.overlap = d;
      const NormalResult r = LinearEepa{}(p, s, h);
      Real ref = 0;
      bool ref_active = false;
      if (d <= 0) {
        delta_max = 0;
        ++n_off;
      } else {
        ref_active = true;
        if (d >= delta_max) {
          delta_max = d;
          ref = f0 + k1 * d;
          ++n_virgin;
        } else {
          const Real unload = k2 * (d - delta_max * (1 - k1 / k2));
          const Real adhesive = -ka * d;
          if (unload > adhesive) {
            ref = f0 + unload;
            ++n_k2;
          } else {
            ref = f0 + adhesive;
            ++n_adh;
          }
        }
      }
      ASSERT_EQ(r.active, ref_active) << d;
      worst = std::max(worst, std::fabs(r.force - ref));
      if (ref_active) {
        EXPECT_NEAR(r.friction_load, std::fabs(ref + ka * d - f0), 1e-14);
        EXPECT_NEAR(h[0], delta_max * (1 - k1 / k2), 1e-18);
      } else {
        EXPECT_EQ(r.force, 0);
        EXPECT_EQ(h[0], 0);
      }
    }
  }
  std::printf("EEPA loop: %d virgin, %d unloading/reloading, %d adhesive, %d separated steps; "
              "max |F - F_ref| = %.3g N (forces up to %.3g N)\n",
              n_virgin, n_k2, n_adh, n_off, worst, f0 + k1 * 14 * u);
  EXPECT_LT(worst, 1e-15);
  EXPECT_GT(n_virgin, 0);
  EXPECT_GT(n_k2, 0);
  EXPECT_GT(n_adh, 0);
  EXPECT_GT(n_off, 0);
  // At delta -> 0 on the adhesive branch the force tends to f0.
  Real h2[1] = {5 * u};
  s.overlap = 1e-15;
  EXPECT_NEAR(LinearEepa{}(p, s, h2).force, f0, 1e-10);
}

TEST(LinearEepa, DampingAndTangential) {
  PairParameters p;
  p.eepa_k1 = 1e4;
  p.eepa_k2 = 3e4;
  p.eepa_k_adh = 1e3;
  p.eepa_f0 = -2e-3;
  p.damping = -2 * restitution_beta(0.4);
  PairState s = pair(1e-3, 2e-3, 3e-6);
  s.overlap_rate = -0.2;
  Real h[1] = {0}, h0[1] = {0};
  const NormalResult r = LinearEepa{}(p, s, h);
  s.overlap_rate = 0;
  const NormalResult r0 = LinearEepa{}(p, s, h0);
  const Real ln_e = std::log(0.4);
  const Real c_n = std::sqrt(4 * s.mass_eff * p.eepa_k1) / std::sqrt(1 + std::pow(pi / ln_e, 2));
  EXPECT_LT(rel(r.force - r0.force, c_n * -0.2), 1e-12);
  EXPECT_LT(rel(r.k_t, 2.0 / 7.0 * p.eepa_k1), 1e-15);
  EXPECT_LT(rel(r.c_t, std::sqrt(4 * s.mass_eff * r.k_t) / std::sqrt(1 + std::pow(pi / ln_e, 2))), 1e-12);
  EXPECT_EQ(r.stiffness, p.eepa_k1);
  EXPECT_EQ(LinearEepa::interaction_range(p, 1e-3, 1e-3), 0);
}

// ---------------------------------------------------------------------------------------------------
namespace {
PairParameters capillary_parameters() {
  PairParameters p = mixed({1e8, 0.3}, {1e8, 0.3}, 0);
  p.surface_tension = 0.072;
  p.contact_angle = 20 * pi / 180;
  p.liquid_fraction = 0.083 * 0.05;
  p.min_separation = 1e-6;
  return p;
}
// physics.md's form, independent of the implementation's rearrangement.
Real capillary_reference(const PairParameters& p, Real R_eff, Real V, Real S) {
  return 4 * pi * R_eff * p.surface_tension * std::cos(p.contact_angle) /
         (1 + 1 / (std::sqrt(1 + V / (pi * R_eff * S * S)) - 1));
}
} // namespace

TEST(CapillaryBridge, ForceRuptureAndVolume) {
  const PairParameters p = capillary_parameters();
  ContactLaw<HertzTsuji, CapillaryBridge> law;
  PairState s = pair(1e-3, 1e-3, 0);
  const Real V = p.liquid_fraction * (s.volume_i + s.volume_j);
  const Real S_rup = (1 + 0.5 * p.contact_angle) * std::cbrt(V);
  EXPECT_LT(rel(CapillaryBridge::interaction_range(p, 1e-3, 1e-3), S_rup), 1e-14);
  NormalResult nr;
  Real h[1] = {0};

  // Not formed yet: nothing across a gap.
  s.overlap = -2 * p.min_separation;
  EXPECT_FALSE(law(p, s, h).active);
  EXPECT_EQ(h[0], 0);

  // Formed on contact; overlapping pairs feel the S_min force.
  s.overlap = 1e-7;
  const Real F_min = CapillaryBridge{}(p, s, nr, h);
  const Real F_min_ref = capillary_reference(p, s.radius_eff, V, p.min_separation);
  EXPECT_EQ(h[0], 1);
  EXPECT_LT(rel(F_min, F_min_ref), 1e-12);
  s.overlap = -0.5 * p.min_separation;
  EXPECT_LT(rel(CapillaryBridge{}(p, s, nr, h), F_min_ref), 1e-12);

  // Pulling apart: strictly decreasing force, equal to the reference, until S_rup.
  Real prev = F_min, worst = 0;
  const int n = 1000;
  for (int k = 1; k <= n; ++k) {
    const Real S = p.min_separation + (S_rup * (1 - 1e-9) - p.min_separation) * Real(k) / n;
    s.overlap = -S;
    const ContactForce f = law(p, s, h);
    const Real F = dot(f.force, s.normal);
    EXPECT_TRUE(f.active);
    EXPECT_LT(F, prev);
    worst = std::max(worst, rel(F, capillary_reference(p, s.radius_eff, V, S)));
    prev = F;
  }
  EXPECT_LT(worst, 1e-9);
  std::printf(
      "capillary: V = %.4g m^3, S_rup = %.5g m, F(S_min) = %.5g N, F(S_rup-) = %.5g N, max rel err %.2g\n", V,
      S_rup, F_min, prev, worst);
  s.overlap = -S_rup * (1 + 1e-9);
  EXPECT_FALSE(law(p, s, h).active);
  EXPECT_EQ(h[0], 0);
  // Ruptured: approaching again across a gap feels nothing until contact.
  s.overlap = -0.5 * S_rup;
  EXPECT_EQ(CapillaryBridge{}(p, s, nr, h), 0);

  // Monotone growth with the liquid volume at fixed separation.
  PairParameters pv = p;
  s.overlap = -10e-6;
  Real last = 0;
  for (Real Vb : {1e-14, 1e-13, 1e-12, 1e-11, 1e-10}) {
    pv.liquid_volume = Vb;
    Real hb[1] = {1};
    const Real F = CapillaryBridge{}(pv, s, nr, hb);
    EXPECT_GT(F, last) << Vb;
    EXPECT_LT(rel(F, capillary_reference(pv, s.radius_eff, Vb, 10e-6)), 1e-12);
    last = F;
  }
  // Particle-wall: the wall brings no liquid.
  PairState w = pair(1e-3, 0, 0);
  EXPECT_LT(rel(CapillaryBridge::interaction_range(p, 1e-3, 0),
                (1 + 0.5 * p.contact_angle) * std::cbrt(p.liquid_fraction * w.volume_i)),
            1e-14);
}

// ---------------------------------------------------------------------------------------------------
TEST(RollingResistance, ConstantTorqueOpposesOwnRotation) {
  PairParameters p;
  p.mu_roll = 0.1;
  PairState s = pair(1e-3, 2e-3, 1e-6);
  NormalResult nr;
  nr.friction_load = 2;
  nr.active = true;
  s.omega_i = Vec3{0, 3, 4};
  s.relative_rotation = s.omega_i; // omega_j = 0
  const Vec3 t = RollingConstantTorque{}(p, s, nr, nullptr).on_i;
  EXPECT_LT(dot(t, s.relative_rotation), 0);
  EXPECT_LT(rel(norm(t), 0.1 * 2 * 1e-3), 1e-14);
  EXPECT_NEAR(t.y / t.z, 0.75, 1e-14);
  s.omega_i = Vec3{};
  EXPECT_EQ(norm(RollingConstantTorque{}(p, s, nr, nullptr).on_i), 0);
  std::printf("constant torque: |tau| = %.6g N m (mu_r |F_n| R_i = %.6g)\n", norm(t), 0.1 * 2 * 1e-3);
}

TEST(RollingResistance, SpringOpposesRelativeRotationAndCaps) {
  PairParameters p;
  p.mu_roll = 0.2;
  PairState s = pair(1e-3, 1e-3, 1e-6);
  s.dt = 1e-3;
  NormalResult nr;
  nr.stiffness = 1e5;
  nr.friction_load = 1;
  nr.active = true;
  const Real k_r = 2.25 * nr.stiffness * p.mu_roll * p.mu_roll * s.radius_eff * s.radius_eff;
  const Real cap = p.mu_roll * s.radius_eff * nr.friction_load;
  // Rolling about y plus a twist about the normal (x), which the rolling spring ignores.
  s.relative_rotation = Vec3{5, 1, 0};
  PairState sj = s; // the (j, i) view
  sj.normal = -s.normal;
  sj.relative_rotation = -s.relative_rotation;
  Real h[3] = {0, 0, 0}, hj[3] = {0, 0, 0};
  int steps_to_cap = -1;
  for (int k = 1; k <= 100; ++k) {
    const RollingTorque both = RollingSpringDashpot{}(p, s, nr, h);
    const Vec3 t = both.on_i;
    EXPECT_EQ(both.on_j.y, -t.y);
    const Vec3 tj = RollingSpringDashpot{}(p, sj, nr, hj).on_i;
    EXPECT_LT(dot(t, s.relative_rotation), 0);
    EXPECT_EQ(t.x, 0);
    EXPECT_EQ(tj.y, -t.y);
    EXPECT_LE(norm(t), cap * (1 + 1e-14));
    if (steps_to_cap < 0) {
      if (k_r * k * s.dt < cap) {
        EXPECT_LT(rel(t.y, -k_r * k * s.dt), 1e-12);
      } else {
        steps_to_cap = k;
        EXPECT_LT(rel(norm(t), cap), 1e-14);
      }
    } else {
      EXPECT_LT(rel(norm(t), cap), 1e-14);
    }
  }
  ASSERT_GT(steps_to_cap, 1);
  // Reversing the rotation unloads elastically from the cap.
  s.relative_rotation = Vec3{0, -1, 0};
  const Vec3 back = RollingSpringDashpot{}(p, s, nr, h).on_i;
  EXPECT_LT(rel(back.y, -(cap - k_r * s.dt)), 1e-10);
  std::printf("rolling spring: k_r = %.4g N m/rad, cap mu_r R* |F_n| = %.4g N m reached after %d steps\n",
              k_r, cap, steps_to_cap);
}

// ---------------------------------------------------------------------------------------------------
// The composed law runs inside a Kokkos kernel and gives the host's numbers.
TEST(CohesiveModels, ComposedLawRunsInKernel) {
  PairParameters p = capillary_parameters();
  p.surface_energy = 0.05;
  p.mu_slide = 0.5;
  p.mu_roll = 0.1;
  p.damping = 2 * std::sqrt(5.0 / 6.0) * -restitution_beta(0.7);
  const int n = 64;
  using Exec = Kokkos::DefaultExecutionSpace;
  Kokkos::View<Real**, Exec::memory_space> hist("cgdem::tests::history", n, FullLaw::history_size);
  Kokkos::View<Real*, Exec::memory_space> out("cgdem::tests::force", n);
  PairState base = pair(0.5e-3, 1e-3, 0);
  base.tangential_velocity = Vec3{0, 1e-3, 0};
  base.relative_rotation = Vec3{0, 0, 2};
  base.omega_i = Vec3{0, 0, 2};
  base.overlap_rate = 0.01;
  const FullLaw law;
  for (int step = 0; step < 3; ++step) {
    Kokkos::parallel_for(
        "cgdem::tests::composed_law", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(const int i) {
          PairState s = base;
          s.overlap = (i - n / 2) * 1e-7 + step * 1e-8;
          Real h[FullLaw::history_size];
          for (int k = 0; k < FullLaw::history_size; ++k)
            h[k] = hist(i, k);
          const ContactForce f = law(p, s, h);
          for (int k = 0; k < FullLaw::history_size; ++k)
            hist(i, k) = h[k];
          out(i) = f.force.x + f.force.y + f.torque.z;
        });
  }
  Kokkos::fence();
  auto out_h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  for (int i = 0; i < n; ++i) {
    Real h[FullLaw::history_size] = {};
    Real ref = 0;
    for (int step = 0; step < 3; ++step) {
      PairState s = base;
      s.overlap = (i - n / 2) * 1e-7 + step * 1e-8;
      const ContactForce f = law(p, s, h);
      ref = f.force.x + f.force.y + f.torque.z;
    }
    EXPECT_EQ(out_h(i), ref) << i;
  }
}

// LAMMPS' rule (contact.jkr_separation: pull_off): a bonded pair separates at the pull-off point delta_C
// = -0.5724 u instead of delta_S; everything before that point is the same curve.
TEST(JkrFull, PullOffSeparationRuleForLammpsComparisons) {
  JkrSetup j = setup(jkr_cases[0]);
  j.p.jkr_separation_overlap = jkr::d_C;
  const Real d_C = -0.57235 * j.u; // docs/physics.md table, 5 digits
  Real h[2] = {0, 0};
  EXPECT_TRUE(jkr_at(j, 0, h).active);
  EXPECT_TRUE(jkr_at(j, d_C * 0.999, h).active);
  EXPECT_FALSE(jkr_at(j, d_C * 1.001, h).active);
  EXPECT_EQ(h[0], 0);
  // The default rule keeps the bond there.
  j.p.jkr_separation_overlap = jkr::d_S;
  Real g[2] = {0, 0};
  EXPECT_TRUE(jkr_at(j, 0, g).active);
  EXPECT_TRUE(jkr_at(j, d_C * 1.001, g).active);
  EXPECT_TRUE(jkr_at(j, 1.19 * (-j.u), g).active);
}
