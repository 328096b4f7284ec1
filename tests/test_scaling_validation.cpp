// Chen & Elliott's particle-level validation run through the engine at k = 1, 2, 4: under their law the
// head-on (case a) and wall-impact (case c) curves, restitution, contact duration, F/F_c and the sticking
// velocity match the original; angular velocity scales as 1/k; Bond- and Cohesion-number scaling deviate
// as the paper reports (longer contacts, larger overlaps). The CSV driver for validation/ is at the end
// (disabled: run with --gtest_also_run_disabled_tests --gtest_filter='ScalingValidationDriver.*').
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include "tests/test_scaling_support.hpp"

using namespace cgdem;
using namespace cgdem::testing;

namespace {

// Relative normal velocity of a recorded run at time t (linear interpolation), normalised by the approach
// speed.
double velocity_at(const ImpactOutcome& o, double t, double v0) {
  const auto& s = o.series;
  for (std::size_t i = 1; i < s.size(); ++i)
    if (s[i].time >= t) {
      const double w = (t - s[i - 1].time) / (s[i].time - s[i - 1].time);
      return ((1 - w) * s[i - 1].velocity + w * s[i].velocity) / v0;
    }
  return s.back().velocity / v0;
}

} // namespace

TEST(ChenElliottScaling, HeadOnUnequalJkrSpheresMatchOriginal) {
  ImpactSpec a = chen_case_a("chen_elliott", 1);
  a.record = true;
  const ImpactOutcome ref = run_impact(a);
  ASSERT_FALSE(ref.stuck);
  ASSERT_GT(ref.max_attraction, 0.5); // the JKR neck pulls: F/F_c reaches about -1 before separation
  for (double k : {2.0, 4.0}) {
    ImpactSpec c = chen_case_a("chen_elliott", k);
    c.record = true;
    const ImpactOutcome o = run_impact(c);
    EXPECT_NEAR(o.max_overlap / ref.max_overlap, 1, 0.01) << "k=" << k;
    EXPECT_NEAR(o.contact_time / ref.contact_time, 1, 0.01) << "k=" << k;
    EXPECT_NEAR(o.restitution / ref.restitution, 1, 0.01) << "k=" << k;
    EXPECT_NEAR(o.max_attraction / ref.max_attraction, 1, 0.01) << "k=" << k;
    EXPECT_NEAR(o.max_repulsion / ref.max_repulsion, 1, 0.01) << "k=" << k;
    // The whole velocity history, sampled at 50 points through the contact.
    for (int q = 0; q <= 50; ++q) {
      const double t = q * ref.contact_time / 50;
      EXPECT_NEAR(velocity_at(o, t, a.speed), velocity_at(ref, t, a.speed), 0.01) << "k=" << k << " t=" << t;
    }
  }
  std::printf(
      "[ report ] Chen case a (k = 1): e = %.4f, t_c = %.4g s, max overlap %.4g m, min F/F_c = %.4f\n",
      ref.restitution, ref.contact_time, ref.max_overlap, -ref.max_attraction);
}

TEST(ChenElliottScaling, WallImpactRestitutionDurationOverlapMatchOriginal) {
  for (double v : {2.0, 10.0}) {
    const ImpactOutcome ref = run_impact(chen_case_c("chen_elliott", 1, v));
    ASSERT_FALSE(ref.stuck) << v;
    for (double k : {2.0, 4.0}) {
      const ImpactOutcome o = run_impact(chen_case_c("chen_elliott", k, v));
      EXPECT_NEAR(o.restitution / ref.restitution, 1, 0.01) << "k=" << k << " v=" << v;
      EXPECT_NEAR(o.contact_time / ref.contact_time, 1, 0.01) << "k=" << k << " v=" << v;
      EXPECT_NEAR(o.max_overlap / ref.max_overlap, 1, 0.01) << "k=" << k << " v=" << v;
      EXPECT_NEAR(o.max_attraction / ref.max_attraction, 1, 0.01) << "k=" << k << " v=" << v;
    }
  }
}

TEST(ChenElliottScaling, AngularVelocityScalesAsOneOverK) {
  // Oblique wall impact (45 degrees, friction 0.3): the spin after the impact is 1/k of the original's, the
  // tangential velocity the same. The law is exact up to the contact lever arm R - delta/2, which is not
  // similar (R ~ k, delta invariant): the spin deviates by O(delta_max / R). A stiff particle (case c with
  // E = 14 GPa, delta_max / R ~ 0.4 %) checks the law to 1 %; the soft case c particle (delta_max / R ~ 5 %)
  // shows the lever-arm deviation, reported and bounded.
  ImpactSpec stiff = chen_case_c("chen_elliott", 1, 2.0);
  stiff.E = 14e9;
  stiff.mu = 0.3;
  stiff.tangential_speed = 2.0;
  ImpactSpec soft = chen_case_c("chen_elliott", 1, 5.0);
  soft.mu = 0.3;
  soft.tangential_speed = 5.0;
  for (const ImpactSpec& base : {stiff, soft}) {
    const bool is_stiff = base.E > 1e9;
    const ImpactOutcome ref = run_impact(base);
    ASSERT_GT(std::fabs(ref.omega), 0);
    const double tol = is_stiff ? 0.01 : 2 * ref.max_overlap / base.r1;
    for (double k : {2.0, 4.0}) {
      ImpactSpec c = base;
      c.k = k;
      const ImpactOutcome o = run_impact(c);
      EXPECT_NEAR(o.omega * k / ref.omega, 1, tol) << "k=" << k << (is_stiff ? " stiff" : " soft");
      EXPECT_NEAR(o.tangential_after / ref.tangential_after, 1, tol) << "k=" << k;
      EXPECT_NEAR(o.restitution / ref.restitution, 1, 0.01) << "k=" << k;
      std::printf("[ report ] oblique impact (%s, delta_max/R = %.4f): k = %g omega k / omega_1 = %.5f\n",
                  is_stiff ? "E 14 GPa" : "case c", ref.max_overlap / base.r1, k, o.omega * k / ref.omega);
    }
  }
}

TEST(ChenElliottScaling, StickingVelocityInvariant) {
  const double ref = sticking_velocity(chen_case_c("chen_elliott", 1, 1), 0.05, 5, 1e-3);
  for (double k : {2.0, 4.0}) {
    const double v = sticking_velocity(chen_case_c("chen_elliott", k, 1), 0.05, 5, 1e-3);
    EXPECT_NEAR(v / ref, 1, 0.01) << "k=" << k;
  }
  std::printf("[ report ] Chen case c critical sticking velocity (k = 1): %.4f m/s\n", ref);
}

TEST(BondAndCohesionScaling, DeviateFromOriginalWithLongerContactAndLargerOverlap) {
  // Both keep E unscaled: the coarse contact is softer relative to its mass, so it lasts longer and goes
  // deeper (Chen & Elliott figs. 3-5); the deviation grows with k.
  for (const char* law : {"bond", "cohesion"}) {
    ImpactSpec a1 = chen_case_a(law, 1);
    const ImpactOutcome ref = run_impact(a1);
    double last_t = ref.contact_time, last_d = ref.max_overlap;
    for (double k : {2.0, 4.0}) {
      ImpactSpec c = chen_case_a(law, k);
      c.max_contact_times = 30 * k;
      const ImpactOutcome o = run_impact(c);
      EXPECT_GT(o.contact_time / last_t, 1.3) << law << " k=" << k;
      EXPECT_GT(o.max_overlap / last_d, 1.3) << law << " k=" << k;
      last_t = o.contact_time;
      last_d = o.max_overlap;
      std::printf("[ report ] %s k = %g: contact time x %.3f, max overlap x %.3f, e %.4f (original %.4f)\n",
                  law, k, o.contact_time / ref.contact_time, o.max_overlap / ref.max_overlap, o.restitution,
                  ref.restitution);
    }
    // Wall impact as well.
    const ImpactOutcome w1 = run_impact(chen_case_c(law, 1, 10));
    ImpactSpec w4 = chen_case_c(law, 4, 10);
    w4.max_contact_times = 200;
    const ImpactOutcome o4 = run_impact(w4);
    EXPECT_GT(o4.contact_time / w1.contact_time, 2) << law;
    EXPECT_GT(o4.max_overlap / w1.max_overlap, 2) << law;
  }
}

// ---------------------------------------------------------------------------------------------------
// CSV driver for validation/ (not part of the suite's time budget).
namespace {
std::string out_dir() {
  const char* d = std::getenv("CGDEM_VALIDATION_OUT");
  std::string dir = d ? d : "validation/results";
  std::filesystem::create_directories(dir);
  return dir;
}
} // namespace

TEST(ScalingValidationDriver, DISABLED_WriteCsv) {
  const std::string dir = out_dir();
  const char* laws[] = {"chen_elliott", "bond",       "cohesion", "hu_method1",
                        "hu_method2",   "hu_method3", "sakai"};
  // Case a: time series per law and k.
  {
    std::FILE* f = std::fopen((dir + "/case_a_series.csv").c_str(), "w");
    std::fprintf(f, "law,k,time,velocity,overlap,force_over_Fc\n");
    std::FILE* s = std::fopen((dir + "/case_a_summary.csv").c_str(), "w");
    std::fprintf(s,
                 "law,k,restitution,contact_time,max_overlap,max_attraction_over_Fc,max_repulsion_over_Fc\n");
    for (const char* law : laws)
      for (double k : {1.0, 2.0, 4.0}) {
        ImpactSpec c = chen_case_a(law, k);
        c.record = true;
        c.max_contact_times = 30 * k;
        const ImpactOutcome o = run_impact(c);
        long n = 0;
        for (const ImpactSample& q : o.series)
          if (n++ % 4 == 0)
            std::fprintf(f, "%s,%g,%.9g,%.9g,%.9g,%.9g\n", law, k, q.time, q.velocity / c.speed, q.overlap,
                         q.force / o.F_c);
        std::fprintf(s, "%s,%g,%.9g,%.9g,%.9g,%.9g,%.9g\n", law, k, o.restitution, o.contact_time,
                     o.max_overlap, o.max_attraction, o.max_repulsion);
      }
    std::fclose(f);
    std::fclose(s);
  }
  // Case c: against impact velocity.
  {
    std::FILE* f = std::fopen((dir + "/case_c_sweep.csv").c_str(), "w");
    std::fprintf(f, "law,k,speed,restitution,contact_time,max_overlap,stuck\n");
    for (const char* law : laws)
      for (double k : {1.0, 2.0, 4.0})
        for (double v : {0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 13.0, 16.0, 20.0}) {
          ImpactSpec c = chen_case_c(law, k, v);
          c.max_contact_times = 60 * k;
          const ImpactOutcome o = run_impact(c);
          std::fprintf(f, "%s,%g,%g,%.9g,%.9g,%.9g,%d\n", law, k, v, o.restitution, o.contact_time,
                       o.max_overlap, o.stuck ? 1 : 0);
        }
    std::fclose(f);
  }
  // Critical sticking velocity against k.
  {
    std::FILE* f = std::fopen((dir + "/sticking_velocity.csv").c_str(), "w");
    std::fprintf(f, "law,k,sticking_velocity\n");
    for (const char* law : laws)
      for (double k : {1.0, 2.0, 3.0, 4.0, 6.0, 8.0}) {
        ImpactSpec c = chen_case_c(law, k, 1);
        c.max_contact_times = 60 * k;
        std::fprintf(f, "%s,%g,%.6g\n", law, k, sticking_velocity(c, 0.02, 30, 2e-3));
        std::fflush(f);
      }
    std::fclose(f);
  }
}
