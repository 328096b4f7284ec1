// Analyses (drivers/analyses.hpp) against synthetic data with known answers.
#include <gtest/gtest.h>
#include <cmath>
#include <random>
#include "core/wall.hpp"
#include "drivers/analyses.hpp"
#include "drivers/scene_parser.hpp"

using namespace cgdem;

namespace {

constexpr double kPi = 3.14159265358979323846;

void add(FrameData& f, double x, double y, double z, double r, double vx = 0, double vy = 0, double vz = 0) {
  f.id.push_back(static_cast<std::int64_t>(f.id.size()) + 1);
  f.position.insert(f.position.end(), {x, y, z});
  f.velocity.insert(f.velocity.end(), {vx, vy, vz});
  f.angular_velocity.insert(f.angular_velocity.end(), {0, 0, 0});
  f.radius.push_back(r);
  f.mass.push_back(1);
  f.group.push_back(0);
}

// A cone of apex height h and slope angle `deg` on the floor z = 0: surface particles with their tops
// exactly on the cone, plus random interior particles below it.
FrameData cone(double deg, double h, double r, unsigned seed) {
  FrameData f;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double t = std::tan(deg * kPi / 180), foot = h / t;
  for (int k = 0; k < 20000; ++k) {
    const double rho = foot * std::sqrt(u(rng)), phi = 2 * kPi * u(rng);
    const double top = h - rho * t;
    if (top < 2 * r) continue;
    add(f, rho * std::cos(phi), rho * std::sin(phi), top - r, r);                    // on the surface
    add(f, rho * std::cos(phi), rho * std::sin(phi), r + (top - 3 * r) * u(rng), r); // inside
  }
  return f;
}

} // namespace

TEST(Analyses, LineFitExact) {
  const LineFit f = fit_line({0, 1, 2, 3}, {1, 3, 5, 7});
  EXPECT_NEAR(f.slope, 2, 1e-12);
  EXPECT_NEAR(f.intercept, 1, 1e-12);
  EXPECT_NEAR(f.r2, 1, 1e-12);
  EXPECT_NEAR(f.slope_stderr, 0, 1e-12);
  // The textbook case: y = 2.2 + 0.6 x, residual sum of squares 2.4, Sxx = 10: SE = sqrt(2.4 / 3 / 10).
  const LineFit g = fit_line({1, 2, 3, 4, 5}, {2, 4, 5, 4, 5});
  EXPECT_NEAR(g.slope, 0.6, 1e-12);
  EXPECT_NEAR(g.slope_stderr, std::sqrt(0.08), 1e-12);
  EXPECT_TRUE(std::isnan(fit_line({0, 1}, {0, 1}).slope_stderr)); // two points: no residual to estimate
}

TEST(Analyses, ConeOfKnownAngle) {
  for (double deg : {25.0, 35.0}) {
    const FrameData f = cone(deg, 0.01, 0.0002, 7);
    const PileFit fit = pile_angle(f, {}, 0, 0, 0, 0.0008, 8, 0.2, 0.8);
    EXPECT_NEAR(fit.angle_deg, deg, 1.0) << "cone of " << deg << " degrees";
    EXPECT_NEAR(fit.height, 0.01, 0.0003);
    EXPECT_GE(fit.bins_used, 5u);
    EXPECT_GT(fit.r2, 0.98);
    // A cone of spheres fits its angle to within a fraction of a degree, and says so.
    EXPECT_GT(fit.angle_stderr_deg, 0);
    EXPECT_LT(fit.angle_stderr_deg, 1.0);
    EXPECT_LT(std::fabs(fit.angle_deg - deg), 4 * fit.angle_stderr_deg + 0.3);
  }
}

// A pile whose 8 sectors are not alike, as a rough pile of few large particles is: two sectors slumped to a
// 20-degree slope (ending where the others' 35-degree flank ends). The mean over the sectors reads the
// average of the slopes' tangents (about 31.6 degrees); the median reads the six alike (35 degrees).
TEST(Analyses, SectorMedianIgnoresSlumpedSectors) {
  const double h = 0.01, r = 0.0002, foot = h / std::tan(35 * kPi / 180);
  const FrameData steep = cone(35, h, r, 5), slumped = cone(20, h, r, 6);
  const auto sector = [](double x, double y) {
    return static_cast<int>((std::atan2(y, x) + kPi) / (2 * kPi) * 8);
  };
  FrameData f;
  for (const FrameData* c : {&steep, &slumped})
    for (std::size_t i = 0; i < c->size(); ++i) {
      const double x = c->position[3 * i], y = c->position[3 * i + 1];
      const bool low = sector(x, y) < 2;
      if (low != (c == &slumped) || std::hypot(x, y) > foot) continue;
      add(f, x, y, c->position[3 * i + 2], r);
    }
  const PileFit mean = pile_angle(f, {}, 0, 0, 0, 0.0008, 8, 0.2, 0.8, SectorStatistic::mean);
  const PileFit median = pile_angle(f, {}, 0, 0, 0, 0.0008, 8, 0.2, 0.8, SectorStatistic::median);
  EXPECT_NEAR(median.angle_deg, 35, 1.0);
  const double tangents = (6 * std::tan(35 * kPi / 180) + 2 * std::tan(20 * kPi / 180)) / 8;
  EXPECT_NEAR(mean.angle_deg, std::atan(tangents) * 180 / kPi, 1.0);
  EXPECT_GT(median.angle_deg - mean.angle_deg, 2.0);
  // The two agree on a cone whose sectors are alike.
  const FrameData c = cone(30, h, r, 7);
  EXPECT_NEAR(pile_angle(c, {}, 0, 0, 0, 0.0008, 8, 0.2, 0.8, SectorStatistic::median).angle_deg,
              pile_angle(c, {}, 0, 0, 0, 0.0008, 8, 0.2, 0.8, SectorStatistic::mean).angle_deg, 0.5);
}

TEST(Analyses, AngleOfReposeFromScene) {
  Scene s = parse_scene_text(R"(domain: {lo: [-0.05, -0.05, 0], hi: [0.05, 0.05, 0.05]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
time: {end: 1}
analyses:
  - type: angle_of_repose
    name: pile
    bin_width: 0.0008
    center: [0, 0]
    floor: 0
)",
                             "<test>");
  auto list = make_analyses(s);
  ASSERT_EQ(list.size(), 1u);
  const FrameData f = cone(30, 0.01, 0.0002, 3);
  std::vector<std::string> names;
  std::vector<double> forces;
  std::map<std::string, double> out;
  run_analyses(list, AnalysisInput{f, 0.0, names, forces}, out);
  EXPECT_NEAR(out.at("pile"), 30, 1.0);
  EXPECT_NEAR(out.at("pile_height"), 0.01, 0.0003);
  EXPECT_NEAR(out.at("pile_foot_radius"), 0.01 / std::tan(kPi / 6), 0.001);
  // sector_statistic is read (median on a cone of alike sectors: the same angle), and checked.
  s.analyses[0].params["sector_statistic"] = "median";
  auto median = make_analyses(s);
  std::map<std::string, double> out_median;
  run_analyses(median, AnalysisInput{f, 0.0, names, forces}, out_median);
  EXPECT_NEAR(out_median.at("pile"), 30, 1.0);
  s.analyses[0].params["sector_statistic"] = "mode";
  EXPECT_THROW(make_analyses(s), SceneError);
}

TEST(Analyses, DistanceOfKnownPair) {
  // Shifted copies: W1 = shift, KS = the mass passed over (1 of 4 points per half unit).
  EXPECT_NEAR(wasserstein1({0, 1, 2, 3}, {0.5, 1.5, 2.5, 3.5}), 0.5, 1e-12);
  EXPECT_NEAR(ks_distance({0, 1, 2, 3}, {0.5, 1.5, 2.5, 3.5}), 0.25, 1e-12);
  EXPECT_NEAR(wasserstein1({1, 2}, {1, 2}), 0, 1e-15);
  EXPECT_NEAR(ks_distance({1, 2}, {2, 1}), 0, 1e-15);
  // Point masses: W1 is the distance, KS is 1.
  EXPECT_NEAR(wasserstein1({0}, {3}), 3, 1e-12);
  EXPECT_NEAR(ks_distance({0, 0}, {3}), 1, 1e-12);
  // U(0,1) against U(0,2): W1 = int_0^1 |u - 2u| du = 1/2, KS = sup |x - x/2| = 1/2.
  std::vector<double> a, b;
  for (int i = 0; i < 4000; ++i) {
    a.push_back((i + 0.5) / 4000);
    b.push_back(2 * (i + 0.5) / 4000);
  }
  EXPECT_NEAR(wasserstein1(a, b), 0.5, 1e-3);
  EXPECT_NEAR(ks_distance(a, b), 0.5, 1e-3);
  // Quantile compression keeps the distances of a large sample.
  std::mt19937_64 rng(1);
  std::normal_distribution<double> g(1, 0.2);
  std::vector<double> big, other;
  for (int i = 0; i < 50000; ++i)
    big.push_back(g(rng));
  for (int i = 0; i < 50000; ++i)
    other.push_back(g(rng) + 0.1);
  const auto q = quantile_samples(big, 1000);
  ASSERT_EQ(q.size(), 1000u);
  EXPECT_NEAR(wasserstein1(q, other), wasserstein1(big, other), 2e-3);
  EXPECT_NEAR(ks_distance(q, other), ks_distance(big, other), 2e-3);
}

TEST(Analyses, ProbabilityDensityIntegratesToOne) {
  const auto pdf = probability_density({0.1, 0.2, 0.3, 0.9}, 0, 1, 10);
  double sum = 0;
  for (double p : pdf)
    sum += p * 0.1;
  EXPECT_NEAR(sum, 1, 1e-12);
  EXPECT_NEAR(pdf[1], 2.5, 1e-12); // 1 of 4 samples in a bin 0.1 wide
}

TEST(Analyses, LineOfKnownTilt) {
  for (double tilt : {20.0, -35.0, 70.0}) {
    std::vector<std::array<double, 2>> pts;
    const double t = std::tan(tilt * kPi / 180);
    for (int i = 0; i < 10; ++i)
      pts.push_back({0.001 * i, 0.3 + 0.001 * i * t});
    const TiltFit line = fit_tilt(pts);
    EXPECT_NEAR(line.angle_deg, std::abs(tilt), 1e-9);
    EXPECT_NEAR(line.rms, 0, 1e-12);
  }
  // Pairs of points d above and below the x axis: the line is the axis, at rms distance d.
  const TiltFit off = fit_tilt({{0, 0.001}, {0, -0.001}, {1, 0.001}, {1, -0.001}, {2, 0.001}, {2, -0.001}});
  EXPECT_NEAR(off.angle_deg, 0, 1e-9);
  EXPECT_NEAR(off.rms, 0.001, 1e-12);
}

// Drum along y through the origin, gravity -z, radius 20 mm: a bed below the line z = tan(tilt) x - 0.004
// (tops on it), filled from the drum's floor.
static FrameData drum_bed(double tilt_deg) {
  FrameData f;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const double t = std::tan(tilt_deg * kPi / 180), r = 0.0003, R = 0.02;
  for (int k = 0; k < 30000; ++k) {
    const double x = R * u(rng), y = 0.005 * u(rng);
    const double surface = t * x - 0.004;
    const double z_floor = -std::sqrt(std::max(0.0, R * R - x * x));
    if (surface - 2 * r < z_floor) continue;
    add(f, x, y, surface - r, r);
    for (int fill = 0; fill < 6; ++fill) // dense enough to leave no gap wider than a particle, as a packing
      add(f, x, y, z_floor + r + (surface - z_floor - 2 * r) * 0.5 * (u(rng) + 1), r);
  }
  return f;
}

TEST(Analyses, DrumBedOfKnownTilt) {
  const DrumFit fit = drum_angle(drum_bed(28), {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0.02, 0.0012, 0.6);
  EXPECT_NEAR(fit.angle_deg, 28, 1.0);
  EXPECT_GT(fit.cells_used, 10u);
}

// A cohesive powder's coating of the drum above (radius 20 mm, along y): three layers of particles stuck
// to the whole wall, carried over the top (rings of 400 positions, a quarter step and half a step per
// layer off the axis, 16 rings along it), with a lump of 40 hanging from the ceiling.
static void add_coating(FrameData& f) {
  const double r = 0.0003, R = 0.02;
  for (int layer = 0; layer < 3; ++layer)
    for (int a = 0; a < 400; ++a)
      for (int k = 0; k < 16; ++k) {
        const double phi = 2 * kPi * (a + 0.25 + 0.5 * layer) / 400, rho = R - r - 2 * r * layer;
        add(f, rho * std::cos(phi), -0.005 + 0.000625 * (k + 0.5), rho * std::sin(phi), r);
      }
  for (int k = 0; k < 40; ++k)
    add(f, 0.0005 * (k % 8), -0.004 + 0.0008 * (k / 8), R - 7 * r - 2 * r * (k % 3), r);
}

TEST(Analyses, DrumAngleIsTheBedsSurfaceNotThePowderCoatingTheWall) {
  // The tilted bed, and a cohesive powder's coating: three layers of particles stuck to the whole drum
  // wall, carried over the top of the drum, with a lump hanging from its ceiling. Read as the surface,
  // the coating's top would make a flat or wall-shaped "surface"; the bed's 28 degrees must come out.
  FrameData f = drum_bed(28);
  add_coating(f);
  const DrumFit fit = drum_angle(f, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0.02, 0.0012, 0.6);
  EXPECT_NEAR(fit.angle_deg, 28, 1.0);
  EXPECT_GT(fit.cells_used, 10u);
  // The method's knobs. Over the whole u range (fit_fraction 1) the bed's ends, where its surface bends
  // into the curved wall, pull the line flat; a wider wall layer (5 cells instead of 1.5) leaves them out.
  const DrumFit whole = drum_angle(f, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0.02, 0.0012, 1.0, 0.2, 1.5);
  const DrumFit wide_layer = drum_angle(f, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0.02, 0.0012, 1.0, 0.2, 5.0);
  EXPECT_GT(std::abs(whole.angle_deg - 28), 2.0);
  EXPECT_NEAR(wide_layer.angle_deg, 28, 1.0);
  EXPECT_LT(wide_layer.cells_used, whole.cells_used);
  // A sparse cloud over half the bed (a particle per 2 mm, up to 3 mm above it) is not bed at a solid
  // fraction of 0.2, and is read as the surface (a steeper one) at a threshold below its own.
  FrameData cloud = f;
  for (double x = 0.0; x < 0.012; x += 0.002)
    for (double h = 0.0008; h < 0.003; h += 0.0006)
      add(cloud, x, 0.0, std::tan(28 * kPi / 180) * x - 0.004 + h, 0.0003);
  EXPECT_NEAR(drum_angle(cloud, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0.02, 0.0012, 0.6, 0.2, 1.5).angle_deg, 28,
              1.0);
  EXPECT_GT(drum_angle(cloud, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0.02, 0.0012, 0.6, 0.001, 1.5).angle_deg, 31);
}

TEST(Analyses, DrumCarriedMassIsTheShareAboveTheAxis) {
  // A flat bed below the axis carries nothing over the top.
  FrameData f = drum_bed(0);
  const std::size_t bed = f.size();
  EXPECT_EQ(drum_angle(f, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0.02, 0.0012, 0.6).carried, 0);
  // The coating: 200 of each ring's 400 positions lie above the axis (16 rings of 3 layers), and the
  // lump hanging from the ceiling: 40.
  const double R = 0.02;
  add_coating(f);
  const double above = 3 * 200 * 16 + 40;
  EXPECT_NEAR(drum_angle(f, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, R, 0.0012, 0.6).carried, above / f.size(),
              1e-12);
  // By mass, not by count: the bed's particles (all below the axis) three times as heavy.
  const double coating = double(f.size() - bed);
  for (std::size_t i = 0; i < bed; ++i)
    f.mass[i] = 3;
  EXPECT_NEAR(drum_angle(f, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, R, 0.0012, 0.6).carried,
              above / (3.0 * bed + coating), 1e-12);
}

TEST(Analyses, DrumMeanAngleAveragesTheFramesFromTheGivenTimeOnce) {
  Scene s = parse_scene_text(R"(domain: {lo: [-0.03, -0.01, -0.03], hi: [0.03, 0.01, 0.03]}
gravity: [0, 0, -9.81]
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.0003}, placement: {type: lattice}}]
walls: [{name: drum, type: cylinder, material: m, point: [0, -0.01, 0], axis: [0, 1, 0], radius: 0.02,
         length: 0.02}]
time: {end: 2}
analyses: [{type: drum_angle, name: a, drum: drum, cell_width: 0.0012, average_from: 1.0}]
)",
                             "<test>");
  auto list = make_analyses(s);
  const FrameData f40 = drum_bed(40), f20 = drum_bed(20), f30 = drum_bed(30);
  std::map<std::string, double> out;
  auto at = [&](const FrameData& f, double t) {
    run_analyses(list, AnalysisInput{f, t, {}, {}}, out);
    return out.at("a");
  };
  at(f40, 0.5); // before average_from: not counted, and the mean not yet defined
  EXPECT_TRUE(std::isnan(out.at("a_mean")));
  EXPECT_TRUE(std::isnan(out.at("a_carried_mean")));
  const double a20 = at(f20, 1.0), c20 = out.at("a_carried");
  FrameData flight; // three particles in flight, two above the axis: no bed, so no angle
  for (double z : {0.004, 0.008, -0.006})
    add(flight, 0.001, 0, z, 0.0003);
  EXPECT_TRUE(std::isnan(at(flight, 1.25)));
  const double c_flight = out.at("a_carried");
  EXPECT_DOUBLE_EQ(c_flight, 2.0 / 3);
  const double a30 = at(f30, 1.5), c30 = out.at("a_carried");
  at(f30, 1.5); // the final evaluation of the last output frame: counted once
  EXPECT_NEAR(a20, 20, 1.0);
  EXPECT_NEAR(a30, 30, 1.0);
  EXPECT_DOUBLE_EQ(out.at("a_mean"), 0.5 * (a20 + a30));
  EXPECT_GT(c30, c20); // the steeper bed reaches further above the axis
  EXPECT_DOUBLE_EQ(out.at("a_carried_mean"), (c20 + c_flight + c30) / 3);
  EXPECT_NEAR(out.at("a_std"), std::fabs(a30 - a20) / std::sqrt(2.0), 1e-9); // two frames
  EXPECT_EQ(out.at("a_frames"), 2);
  // A sweep compares and plots the mean, not the angle of whichever frame the run ends on.
  EXPECT_EQ(list[0]->metric(), "a_mean");
}

TEST(Analyses, LatticePorosityAndCoordination) {
  // 5 x 5 x 5 touching spheres in a box that holds exactly their cubic cells: porosity 1 - pi/6 in
  // every slab; coordination 6 inside, 6 - 6/5 = 4.8 on average.
  FrameData f;
  const double r = 0.001;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k)
        add(f, r + 2 * r * i, r + 2 * r * j, r + 2 * r * k, r);
  const Profile p = axis_profile(f, 2, {0, 0, 0}, {0.01, 0.01, 0.01}, 5, 0.01);
  for (int b = 0; b < 5; ++b)
    EXPECT_NEAR(p.porosity[b], 1 - kPi / 6, 1e-12);
  EXPECT_NEAR(p.porosity_total, 1 - kPi / 6, 1e-12);
  EXPECT_NEAR(p.coordination_mean, 4.8, 1e-12);
  EXPECT_NEAR(p.coordination[2], (9 * 6 + 12 * 5 + 4 * 4) / 25.0, 1e-12); // a middle layer
  // Slabs cutting spheres in half: the segments add up to the same solid volume.
  const Profile q = axis_profile(f, 2, {0, 0, 0}, {0.01, 0.01, 0.01}, 4, 0.01);
  EXPECT_NEAR(q.porosity_total, 1 - kPi / 6, 1e-12);
  EXPECT_NEAR(sphere_segment_volume(1, -1, 1), 4 * kPi / 3, 1e-12);
  EXPECT_NEAR(sphere_segment_volume(1, 0, 5), 2 * kPi / 3, 1e-12);
}

TEST(Analyses, WallStressAndPeakStrength) {
  Scene s = parse_scene_text(R"(domain: {lo: [0, 0, 0], hi: [0.01, 0.01, 0.02]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
walls:
  - {name: floor, material: m}
  - {name: piston, material: m, point: [0, 0, 0.01], normal: [0, 0, -1], motion: {velocity: [0, 0, -0.001], start: 0.5}}
time: {end: 1}
analyses:
  - {type: wall_stress, name: s, wall: piston, area: 1e-4, initial_height: 0.01}
  - {type: unconfined_strength, name: ucs, wall: piston, area: 1e-4, initial_height: 0.01}
)",
                             "<test>");
  auto list = make_analyses(s);
  FrameData f;
  add(f, 0.005, 0.005, 0.005, 0.001);
  const std::vector<std::string> names{"floor", "piston"};
  std::map<std::string, double> out;
  // The particles push the piston up (+z) with 2 N at t = 1.5: stress 2e4 Pa, strain 0.001 * 1 / 0.01.
  run_analyses(list, AnalysisInput{f, 1.5, names, {0, 0, -2, 0, 0, 2}}, out);
  EXPECT_NEAR(out.at("s"), 2e4, 1e-6);
  EXPECT_NEAR(out.at("s_strain"), 0.1, 1e-12);
  run_analyses(list, AnalysisInput{f, 2.0, names, {0, 0, -1, 0, 0, 1}}, out);
  EXPECT_NEAR(out.at("ucs"), 2e4, 1e-6);
  EXPECT_NEAR(out.at("ucs_peak_strain"), 0.1, 1e-12);
  EXPECT_NEAR(out.at("ucs_stress"), 1e4, 1e-6);
  EXPECT_NEAR(out.at("ucs_strain"), 0.15, 1e-12);
}

TEST(Analyses, WallStressTakesTheAreaFromTheWallOrDomainAndMeasuresTheHeight) {
  Scene s = parse_scene_text(R"(domain: {lo: [0, 0, 0], hi: [0.01, 0.02, 0.02]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
walls:
  - {name: plate, material: m, point: [0.005, 0.005, 0], normal: [0, 0, 1], radius: 0.004, orifice: 0.001}
  - {name: piston, material: m, point: [0, 0, 0.01], normal: [0, 0, -1], motion: {velocity: [0, 0, -0.001], start: 0.5}}
  - {name: tilted, material: m, point: [0, 0, 0], normal: [1, 0, 1]}
time: {end: 1}
analyses:
  - {type: wall_stress, name: piston, wall: piston}
  - {type: wall_stress, name: plate, wall: plate, initial_height: 0.01}
)",
                             "<test>");
  auto list = make_analyses(s);
  FrameData f;
  add(f, 0.005, 0.005, 0.005, 0.001);
  const std::vector<std::string> names{"plate", "piston", "tilted"};
  std::map<std::string, double> out;
  // At t = 0 the sample reaches from the piston (z = 0.01) down to the particle's bottom edge: 6 mm.
  run_analyses(list, AnalysisInput{f, 0, names, {0, 0, -1, 0, 0, 2, 0, 0, 0}}, out);
  EXPECT_NEAR(out.at("piston"), 2 / (0.01 * 0.02), 1e-9); // the domain's x-y cross-section
  EXPECT_NEAR(out.at("plate"), 1 / (kPi * (0.004 * 0.004 - 0.001 * 0.001)), 1e-6); // the disk less its hole
  EXPECT_NEAR(out.at("piston_strain"), 0, 1e-15);
  run_analyses(list, AnalysisInput{f, 1.5, names, {0, 0, -1, 0, 0, 2, 0, 0, 0}}, out);
  EXPECT_NEAR(out.at("piston_strain"), 0.001 / 0.006, 1e-12);
  // An infinite plane off the axes has no area of its own.
  s.analyses.push_back(s.analyses[0]);
  s.analyses.back().name = "t";
  s.analyses.back().params["wall"] = "tilted";
  try {
    make_analyses(s);
    ADD_FAILURE() << "a tilted infinite plane got an area";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("give the wall's loaded area"), std::string::npos) << e.what();
  }
}

TEST(Analyses, SegmentedPistonApproachLoadUnloadAndStrainFromTestStart) {
  // A piston that approaches fast (0.1 m/s for 0.1 s), loads (-1 mm/s for 1 s), then unloads (+1 mm/s for
  // 0.5 s): the scene's displacement, the device wall's offset and surface velocity, and the analyses'
  // strain counted from the start of loading (`from`) all follow the segments.
  Scene s = parse_scene_text(R"(domain: {lo: [0, 0, 0], hi: [0.01, 0.01, 0.2]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
walls:
  - name: piston
    material: m
    point: [0, 0, 0.15]
    normal: [0, 0, -1]
    motion: {velocity: [0, 0, -0.1], start: 0.1, stop: 0.2,
             then: [{velocity: [0, 0, -0.001], start: 0.2, stop: 1.2}, {velocity: [0, 0, 0.001], start: 1.2, stop: 1.7}]}
time: {end: 2}
analyses:
  - {type: wall_stress, name: s, wall: piston, area: 1e-4, initial_height: 0.01, from: 0.2}
  - {type: unconfined_strength, name: ucs, wall: piston, area: 1e-4, initial_height: 0.01, from: 0.2}
)",
                             "<test>");
  const WallSpec& w = s.walls[0];
  ASSERT_EQ(w.then.size(), 2u);
  for (auto [t, z] : {std::pair{0.05, 0.0},
                      {0.15, -0.005},
                      {0.2, -0.01},
                      {0.7, -0.0105},
                      {1.2, -0.011},
                      {1.45, -0.01075},
                      {2.0, -0.0105}})
    EXPECT_NEAR(w.displacement(t)[2], z, 1e-15) << "t=" << t;
  Wall dev;
  dev.velocity = {0, 0, -0.1};
  dev.motion_start = 0.1;
  dev.motion_stop = 0.2;
  dev.num_then = 2;
  dev.then_velocity[0] = {0, 0, -0.001};
  dev.then_start[0] = 0.2;
  dev.then_stop[0] = 1.2;
  dev.then_velocity[1] = {0, 0, 0.001};
  dev.then_start[1] = 1.2;
  dev.then_stop[1] = 1.7;
  for (double t : {0.05, 0.15, 0.7, 1.45, 2.0})
    EXPECT_NEAR(dev.offset(t).z, w.displacement(t)[2], 1e-15) << t;
  EXPECT_EQ(dev.translation_velocity(0.15).z, -0.1);
  EXPECT_EQ(dev.translation_velocity(0.7).z, -0.001);
  EXPECT_EQ(dev.translation_velocity(1.45).z, 0.001);
  EXPECT_EQ(dev.translation_velocity(1.8).z, 0.0);
  auto list = make_analyses(s);
  FrameData f;
  add(f, 0.005, 0.005, 0.005, 0.001);
  std::map<std::string, double> out;
  const std::vector<std::string> names{"piston"};
  // During the approach the piston is pushed hard (an impact); it must not count as strength.
  run_analyses(list, AnalysisInput{f, 0.15, names, {0, 0, 9}}, out);
  EXPECT_NEAR(out.at("s_strain"), 0, 1e-15);
  run_analyses(list, AnalysisInput{f, 0.7, names, {0, 0, 2}}, out);
  EXPECT_NEAR(out.at("s_strain"), 0.05, 1e-12); // 0.5 mm of loading over 10 mm
  EXPECT_NEAR(out.at("ucs"), 2e4, 1e-6);
  run_analyses(list, AnalysisInput{f, 1.45, names, {0, 0, 1}}, out);
  EXPECT_NEAR(out.at("s_strain"), 0.075, 1e-12); // unloaded by 0.25 mm
  EXPECT_NEAR(out.at("ucs"), 2e4, 1e-6);
  EXPECT_NEAR(out.at("ucs_peak_strain"), 0.05, 1e-12);
  // A segment whose stop is not after its start is a one-line scene error.
  try {
    parse_scene_text(R"(domain: {lo: [0, 0, 0], hi: [1, 1, 1]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
walls: [{name: p, material: m, motion: {then: [{velocity: [0, 0, 1], start: 0.5, stop: 0.2}]}}]
time: {end: 1}
)",
                     "<test>");
    FAIL() << "accepted a segment that stops before it starts";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("walls.0.motion.then.0.stop"), std::string::npos) << e.what();
  }
}

TEST(Analyses, VelocityDistributionSummaries) {
  Scene s = parse_scene_text(R"(domain: {lo: [0, 0, 0], hi: [1, 1, 1]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
time: {end: 1}
analyses: [{type: velocity_distribution, name: v}]
)",
                             "<test>");
  auto list = make_analyses(s);
  ASSERT_TRUE(list[0]->is_distribution());
  FrameData f;
  add(f, 0.1, 0.1, 0.1, 0.001, 3, 4, 0); // speed 5
  add(f, 0.2, 0.1, 0.1, 0.001, 0, 0, 1); // speed 1
  std::map<std::string, double> out;
  run_analyses(list, AnalysisInput{f, 0, {}, {}}, out);
  EXPECT_NEAR(out.at("v"), 3, 1e-12);
  EXPECT_NEAR(out.at("v_std"), 2, 1e-12);
  EXPECT_NEAR(out.at("v_max"), 5, 1e-12);
  const auto sp = list[0]->samples(f);
  EXPECT_EQ(sp, (std::vector<double>{5, 1}));
}

TEST(Analyses, BadSpecsAreOneLineSceneErrors) {
  const std::string base = R"(domain: {lo: [0, 0, 0], hi: [1, 1, 1]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
walls: [{name: floor, material: m}]
time: {end: 1}
)";
  auto error = [&](const std::string& analyses) {
    try {
      make_analyses(parse_scene_text(base + analyses, "s.yaml"));
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("analyses: [{type: angle_of_repos}]").find("did you mean 'angle_of_repose'"),
            std::string::npos);
  EXPECT_NE(error("analyses: [{type: wall_stress, wall: roof, area: 1, initial_height: 1}]")
                .find("analyses.0.wall"),
            std::string::npos);
  EXPECT_NE(error("analyses: [{type: wall_stress, wall: floor, area: -1}]").find("area must be > 0"),
            std::string::npos);
  EXPECT_NE(error("analyses: [{type: profile, binz: 3}]").find("unknown parameter 'binz'"),
            std::string::npos);
  EXPECT_NE(error("analyses: [{type: drum_angle, drum: floor}]").find("cylinder"), std::string::npos);
  EXPECT_NE(error("analyses: [{type: wall_stress, wall: floor, area: 1, initial_height: 1, from: -1}]")
                .find("from must be >= 0"),
            std::string::npos);
}

namespace {

// A planar heap along +x from x = 0: surface tops exactly on z = h - x tan(deg), random across y in [0,
// 0.01], interior particles below, and one particle thrown 10 mm ahead of the front. `sign` -1 mirrors it to
// -x.
FrameData planar_heap(double deg, double h, double r, double sign, unsigned seed) {
  FrameData f;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double t = std::tan(deg * kPi / 180), foot = h / t;
  for (int k = 0; k < 20000; ++k) {
    const double x = foot * u(rng), y = 0.01 * u(rng), top = h - x * t;
    if (top < 2 * r) continue;
    add(f, sign * x, y, top - r, r);
    add(f, sign * x, y, r + (top - 3 * r) * u(rng), r);
  }
  add(f, sign * (foot + 0.01), 0.005, r, r);
  return f;
}

// A one-particle scene whose analyses are `list` (a flow YAML sequence).
Scene scene_with_analyses(const std::string& list) {
  return parse_scene_text(R"(domain: {lo: [-0.05, -0.05, 0], hi: [0.05, 0.05, 0.05]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
time: {end: 1}
analyses: )" + list + "\n",
                          "<test>");
}

} // namespace

TEST(Analyses, PlanarHeapOfKnownAngleRunoutAndHeight) {
  const double h = 0.01, r = 0.0002;
  for (const double sign : {1.0, -1.0}) {
    for (const double deg : {25.0, 35.0}) {
      const FrameData f = planar_heap(deg, h, r, sign, 11);
      const PlanarFlowFit fit = planar_flow(f, {}, 0, sign > 0 ? 1 : -1, 2, 0, 0, 0.0008, 0.2, 0.8);
      // The last particles lie where the top reaches 2 r: x = (h - 2 r) / tan, plus their radius.
      const double front = (h - 2 * r) / std::tan(deg * kPi / 180) + r;
      EXPECT_NEAR(fit.runout, front, 0.0005) << deg << " degrees, sign " << sign;
      EXPECT_NEAR(fit.front, sign * fit.runout, 1e-15);
      EXPECT_NEAR(fit.height, h, 0.0003);
      EXPECT_NEAR(fit.angle_deg, deg, 1.0);
      EXPECT_GT(fit.r2, 0.98);
      EXPECT_GE(fit.bins_used, 5u);
    }
  }
}

TEST(Analyses, PlanarFlowFromSceneWithNanUntilDefined) {
  auto list = make_analyses(scene_with_analyses(
      "[{type: planar_flow, name: slump, axis: -x, bin_width: 0.0008, origin: 0, floor: 0}]"));
  ASSERT_EQ(list.size(), 1u);
  std::vector<std::string> names;
  std::vector<double> forces;
  std::map<std::string, double> out;
  const FrameData heap = planar_heap(30, 0.01, 0.0002, -1, 5);
  run_analyses(list, AnalysisInput{heap, 0.0, names, forces}, out);
  EXPECT_NEAR(out.at("slump"), (0.01 - 0.0004) / std::tan(kPi / 6) + 0.0002, 0.0005);
  EXPECT_NEAR(out.at("slump_angle"), 30, 1.0);
  EXPECT_NEAR(out.at("slump_height"), 0.01, 0.0003);
  // A single column of particles: height and runout defined, no flank to fit.
  FrameData column;
  for (int k = 0; k < 10; ++k)
    add(column, -0.0001, 0.001, 0.0002 + 0.0004 * k, 0.0002);
  out.clear();
  run_analyses(list, AnalysisInput{column, 0.1, names, forces}, out);
  EXPECT_NEAR(out.at("slump"), 0.0003, 1e-12);
  EXPECT_NEAR(out.at("slump_height"), 0.004, 1e-12);
  EXPECT_TRUE(std::isnan(out.at("slump_angle")));
  EXPECT_EQ(out.at("slump_bins"), 0);
  // No particles: nothing defined.
  out.clear();
  run_analyses(list, AnalysisInput{FrameData{}, 0.2, names, forces}, out);
  EXPECT_TRUE(std::isnan(out.at("slump")));
  EXPECT_TRUE(std::isnan(out.at("slump_height")));
  // Bad axes are one-line scene errors naming the key.
  for (const auto& [spec, key] :
       std::vector<std::pair<std::string, std::string>>{{"{type: planar_flow, axis: w}", "analyses.0.axis"},
                                                        {"{type: planar_flow, up: x}", "analyses.0.up"}}) {
    std::string msg;
    try {
      make_analyses(scene_with_analyses("[" + spec + "]"));
    } catch (const SceneError& e) {
      msg = e.what();
    }
    EXPECT_NE(msg.find(key), std::string::npos) << spec << ": " << msg;
  }
}
