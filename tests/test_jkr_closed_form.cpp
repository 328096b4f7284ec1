// The JKR law's straight-line path (the one the force pass's loop over pairs vectorizes) against exact
// references: the bit-trick cube root against the library's, the closed-form contact radius
// (jkr::solve_x_closed) against the bracketed Newton solver (jkr::solve_x) and a long-double solution, and
// the law's force over whole loading-unloading loops against the force of the bracketed solution, down to
// next to the separation point (to 1e-12, plus what the root's conditioning there makes of the round-off).
// That a gamma = 0 pair is Hertz-Tsuji bit for bit is JkrFull.ReducesToHertzWhenGammaZero
// (tests/test_cohesive_models.cpp).
#include <gtest/gtest.h>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <vector>
#include "models/jkr_full.hpp"

using namespace cgdem;
using namespace cgdem::models;

namespace {

// The root of y^4 - 2 y - d = 0 above y_S, x = y^2, by Newton's method in long double from above (where
// the quartic is convex, so the iterates fall monotonically onto the root).
long double reference_x(long double d) {
  long double y = std::sqrt(std::sqrt(std::fabs(d))) + 2;
  for (int k = 0; k < 400; ++k) {
    const long double next = y - (y * y * y * y - 2 * y - d) / (4 * y * y * y - 2);
    if (!(next < y)) break;
    y = next;
  }
  return y * y;
}

} // namespace

TEST(JkrClosedForm, CubeRootWithinThreeUlp) {
  double worst = 0;
  for (int k = 0; k <= 200000; ++k) {
    const double x = std::exp(-640 + 1280.0 * k / 200000);
    const double ref = std::cbrt(x);
    worst = std::max(worst, std::fabs(math::cbrt_positive(x) - ref) / ref);
  }
  std::printf("[ report ] cbrt_positive: worst relative difference from cbrt %.2e over 1e-278 .. 1e278\n",
              worst);
  EXPECT_LT(worst, 3 * 2.3e-16);
}

TEST(JkrClosedForm, InverseCubeRootWithinFourUlp) {
  double worst = 0;
  for (int k = 0; k <= 200000; ++k) {
    const long double x = std::exp(-640 + 1280.0 * k / 200000);
    const long double ref = 1 / std::cbrt(x);
    worst = std::max(worst, double(std::fabs((math::inverse_cbrt_positive(double(x)) - ref) / ref)));
  }
  std::printf("[ report ] inverse_cbrt_positive: worst relative difference from 1/cbrt %.2e over 1e-278 .. "
              "1e278\n",
              worst);
  EXPECT_LT(worst, 4 * 2.3e-16);
}

// Per decade of distance from S, the worst error of each solver against the long-double root. Next to S
// the root is fixed by the double d only to ~eps / sqrt(d - d_S) (d delta / dx vanishes at S), for any
// solver: there the closed form must be as good as the bracketed solver; from 1e-5 |d_S| on, within 1e-13.
TEST(JkrClosedForm, ContactRadiusAsAccurateAsTheBracketedSolver) {
  for (int decade = -14; decade <= 6; ++decade) {
    double worst_closed = 0, worst_bracketed = 0;
    for (int k = 0; k < 2000; ++k) {
      const double d = jkr::d_S + std::fabs(jkr::d_S) * std::pow(10.0, decade + k / 2000.0);
      const long double exact = reference_x(d);
      worst_closed = std::max(worst_closed, double(std::fabs((jkr::solve_x_closed(d) - exact) / exact)));
      worst_bracketed = std::max(worst_bracketed, double(std::fabs((jkr::solve_x(d, 0) - exact) / exact)));
    }
    std::printf("[ report ] (d - d_S)/|d_S| 1e%+d: x error closed form %.1e, bracketed %.1e\n", decade,
                worst_closed, worst_bracketed);
    EXPECT_LE(worst_closed, 1.5 * worst_bracketed + 1e-15) << decade;
    if (decade >= -5) {
      EXPECT_LT(worst_closed, 1e-13) << decade;
    }
  }
  // At or below S the physical branch ends at x_S.
  EXPECT_EQ(jkr::solve_x_closed(jkr::d_S), jkr::x_S);
  EXPECT_EQ(jkr::solve_x_closed(jkr::d_S - 1e-3), jkr::x_S);
}

// The law's force along snap-in, loading to 40 u, unloading through zero force and the pull-off point, to
// 1e-7 |d_S| above S, with each separation rule; against the force from the bracketed solution.
TEST(JkrClosedForm, LawForceOverLoadingUnloadingLoopWithinOneInTenToTheTwelve) {
  PairParameters p;
  p.E_eff = 1e6 / (2 * (1 - 0.09));
  p.G_eff = 0.5 * p.E_eff;
  p.surface_energy = 0.05;
  PairState s;
  s.normal = Vec3{1, 0, 0};
  s.radius_i = s.radius_j = 0.5e-3;
  s.radius_eff = 0.25e-3;
  s.mass_eff = 1e-6;
  const jkr::Scales sc = jkr::scales(p.surface_energy, p.E_eff, s.radius_eff);
  for (const double separation : {jkr::d_S, jkr::d_C, 0.0}) {
    p.jkr_separation_overlap = separation;
    // The stop: 1e-7 |d_S| above S, or just above the separation overlap of the rule.
    const double last = separation == jkr::d_S ? jkr::d_S * (1 - 1e-7) : separation + 1e-9;
    std::vector<double> path;
    for (int k = 0; k <= 4000; ++k)
      path.push_back(40.0 * k / 4000);
    for (int k = 0; k <= 4000; ++k)
      path.push_back(40.0 - (40.0 - last) * k / 4000);
    if (separation == jkr::d_S)
      for (int k = 0; k <= 60; ++k) // the last stretch to S, geometrically closer
        path.push_back(jkr::d_S * (1 - std::pow(10.0, -1 - 6.0 * k / 60)));
    Real h[2] = {0, 0};
    double worst = 0, worst_of_bound = 0;
    for (const double d : path) {
      s.overlap = d * sc.u;
      const NormalResult r = JkrFull{}(p, s, h);
      ASSERT_TRUE(r.active) << d;
      const double x = jkr::solve_x(s.overlap / sc.u, 0);
      const double F = sc.F_c * jkr::force_of(x);
      // Next to S the root is ill-conditioned: d(delta)/dx -> 0, so the rounding of the law's inputs (R* K,
      // R* delta, which the law forms in physical units, against delta/u here) moves x by cond_x times
      // the unit round-off, cond_x = |d / (x delta'(x))| (2,250 at 1e-7 |d_S| above S), and the force by
      // cond_F = cond_x |x F'(x)| / |F|. The bound: 1e-12, plus 4 unit round-offs times the condition.
      const double cond_x = std::fabs(d) / (x * std::fabs(2 * x - 1 / std::sqrt(x)));
      const double F_scale = std::max(std::fabs(F), 1e-3 * sc.F_c); // a thousandth of F_c at point B
      const double cond_F = cond_x * x * std::fabs(4.0 / 3.0 * x * x - 2 * std::sqrt(x)) * sc.F_c / F_scale;
      const double err_F = std::fabs(r.force - F) / F_scale;
      worst = std::max(worst, err_F);
      worst_of_bound = std::max(worst_of_bound, err_F / (1e-12 + 4 * DBL_EPSILON * cond_F));
      EXPECT_NEAR(r.stiffness / (2 * p.E_eff), x * sc.a_c, (1e-12 + 4 * DBL_EPSILON * cond_x) * x * sc.a_c)
          << d;
    }
    std::printf("[ report ] JKR law force (separation overlap %.4f u) against the bracketed solution: worst "
                "relative error %.2e over %zu points, %.2f of its bound\n",
                separation, worst, path.size(), worst_of_bound);
    EXPECT_LT(worst_of_bound, 1.0);
    // One step past the separation overlap the pair lets go and forgets its history.
    s.overlap = (separation - 1e-6) * sc.u;
    EXPECT_FALSE(JkrFull{}(p, s, h).active);
    EXPECT_EQ(h[0], 0);
  }
}
