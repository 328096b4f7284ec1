// Bounded planes (plates: rectangle, disk, orifice) and cones: the geometry of wall_contact against
// hand-computed distances, and impacts on a plate's face and rim against the plane and Hertz.
#include <gtest/gtest.h>
#include <cmath>
#include "core/wall.hpp"
#include "drivers/scene_parser.hpp"
#include "tests/test_support.hpp"

using namespace cgdem;
using namespace cgdem::testing;

namespace {

PlacedWall plate(Real half_width, Real half_height, Real radius = 0, Real orifice = 0) {
  PlacedWall w;
  w.type = Wall::Plate;
  w.base = Vec3{0, 0, 0};
  w.axis = Vec3{0, 0, 1};
  w.edge = Vec3{1, 0, 0};
  w.half_width = half_width;
  w.half_height = half_height;
  w.radius = radius;
  w.orifice = orifice;
  return w;
}

// A hopper-like frustum: radius 1 at z = 0, 3 at z = 2 (half-angle 45 degrees).
PlacedWall cone() {
  PlacedWall w;
  w.type = Wall::Cone;
  w.base = Vec3{0, 0, 0};
  w.axis = Vec3{0, 0, 1};
  w.edge = Vec3{1, 0, 0};
  w.radius = 1;
  w.end_radius = 3;
  w.length = 2;
  return w;
}

} // namespace

TEST(WallGeometry, RectanglePlateFaceEdgeAndCornerDistances) {
  const PlacedWall w = plate(2, 1);
  // Above the face, on either side: distance |z|, pushed away from the sheet.
  WallContact c = wall_contact(w, Vec3{0.5, -0.5, 0.3}, 0.5);
  ASSERT_TRUE(c.reachable);
  EXPECT_DOUBLE_EQ(c.overlap, 0.2);
  EXPECT_DOUBLE_EQ(c.normal.z, -1);
  c = wall_contact(w, Vec3{0.5, -0.5, -0.3}, 0.5);
  EXPECT_DOUBLE_EQ(c.overlap, 0.2);
  EXPECT_DOUBLE_EQ(c.normal.z, 1);
  // Beside the edge x = 2, level with the sheet: the edge is 0.4 away along -x.
  c = wall_contact(w, Vec3{2.4, 0, 0}, 0.5);
  ASSERT_TRUE(c.reachable);
  EXPECT_NEAR(c.overlap, 0.1, 1e-15);
  EXPECT_NEAR(c.normal.x, -1, 1e-15);
  // Off the corner (2, 1, 0) by (0.3, 0.4, 0): distance 0.5.
  c = wall_contact(w, Vec3{2.3, 1.4, 0}, 0.6);
  EXPECT_NEAR(c.overlap, 0.1, 1e-15);
  EXPECT_NEAR(c.normal.x, -0.6, 1e-15);
  EXPECT_NEAR(c.normal.y, -0.8, 1e-15);
  // Far beyond the rectangle: no overlap.
  EXPECT_LT(wall_contact(w, Vec3{5, 0, 0}, 0.5).overlap, 0);
}

TEST(WallGeometry, DiskPlateRimAndOrificeRim) {
  const PlacedWall w = plate(0, 0, 2, 0.5);
  // Outside the disk's rim in its plane, and above the rim diagonally.
  WallContact c = wall_contact(w, Vec3{0, 2.3, 0}, 0.5);
  EXPECT_NEAR(c.overlap, 0.2, 1e-15);
  c = wall_contact(w, Vec3{2.3, 0, 0.4}, 0.6);
  EXPECT_NEAR(c.overlap, 0.1, 1e-15);
  // Inside the orifice: the hole's rim, not the face, and nothing at the centre of a wide hole.
  c = wall_contact(w, Vec3{0.2, 0, 0.4}, 0.6);
  EXPECT_NEAR(c.overlap, 0.1, 1e-15);
  EXPECT_NEAR(c.normal.x, 0.6, 1e-15);
  EXPECT_NEAR(c.normal.z, -0.8, 1e-15);
  EXPECT_LT(wall_contact(w, Vec3{0, 0, 0}, 0.4).overlap, 0);
}

TEST(WallGeometry, ConeFaceDistanceIsThePerpendicularToItsGenerator) {
  const PlacedWall w = cone();
  // The generator in the x-z half-plane runs from (1, 0) to (3, 2): unit inward normal (-1, 1)/sqrt 2.
  // A point at x = 2 - 0.3/sqrt2, z = 1 + 0.3/sqrt2 is 0.3 from it, inside.
  const Real s = 0.3 / std::sqrt(2.0);
  WallContact c = wall_contact(w, Vec3{2 - s, 0, 1 + s}, 0.5);
  ASSERT_TRUE(c.reachable);
  EXPECT_NEAR(c.overlap, 0.2, 1e-14);
  EXPECT_NEAR(c.normal.x, 1 / std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(c.normal.z, -1 / std::sqrt(2.0), 1e-14);
  // The same in any azimuth (rotated to the y axis).
  c = wall_contact(w, Vec3{0, 2 - s, 1 + s}, 0.5);
  EXPECT_NEAR(c.overlap, 0.2, 1e-14);
  EXPECT_NEAR(c.normal.y, 1 / std::sqrt(2.0), 1e-14);
  // Below the orifice, beside its rim (1, 0, 0): distance 0.4 straight down.
  c = wall_contact(w, Vec3{1, 0, -0.4}, 0.5);
  EXPECT_NEAR(c.overlap, 0.1, 1e-14);
  EXPECT_NEAR(c.normal.z, 1, 1e-14);
  // On the axis well inside the orifice: out of reach.
  EXPECT_LT(wall_contact(w, Vec3{0, 0, 0}, 0.5).overlap, 0);
}

TEST(WallGeometry, SpinningConeSurfaceMovesAtItsLocalRadius) {
  PlacedWall w = cone();
  w.spin = 2;
  // Contact at height 1 on the x side: the generator's point (2, 0, 1) moves at 2 rad/s x 2 m along +y.
  const Real s = 0.3 / std::sqrt(2.0);
  const WallContact c = wall_contact(w, Vec3{2 - s, 0, 1 + s}, 0.5);
  const Vec3 v = wall_surface_velocity(w, c);
  EXPECT_NEAR(v.x, 0, 1e-14);
  EXPECT_NEAR(v.y, 4, 1e-14);
  EXPECT_NEAR(v.z, 0, 1e-14);
}

namespace {

// A sphere dropped without gravity at 1 m/s onto a wall; returns the trajectory's x positions.
std::vector<double> impact_track(const WallSpec& wall, const Vec3d& start, const Vec3d& velocity) {
  const MaterialSpec m = material("glass", 2500, 5e6, 0.3, 0.9, 0.0);
  Scene s = basic_scene({m}, "hertz", "none");
  WallSpec w = wall;
  w.name = "wall";
  w.material = m.name;
  s.walls.push_back(w);
  ParticleSet p;
  add_particle(p, start, velocity, 1e-3, 2500);
  auto engine = make(s, p, 2e-7);
  std::vector<double> track;
  for (int k = 0; k < 400; ++k) {
    engine->advance(10);
    const FrameData f = engine->frame();
    track.push_back(f.position[0] + f.position[1] + f.position[2]);
  }
  return track;
}

} // namespace

TEST(WallImpact, PlateFaceGivesExactlyThePlaneWallsImpact) {
  WallSpec plane;
  plane.normal = {1, 0, 0};
  WallSpec rectangle = plane;
  rectangle.size[0] = 0.02;
  rectangle.size[1] = 0.01;
  WallSpec disk = plane;
  disk.radius = 0.01;
  const Vec3d start{1.05e-3, 0.001, -0.002}, v{-1, 0, 0};
  const std::vector<double> ref = impact_track(plane, start, v);
  EXPECT_EQ(impact_track(rectangle, start, v), ref);
  EXPECT_EQ(impact_track(disk, start, v), ref);
  EXPECT_GT(ref.back(), start[0] + start[1] + start[2]); // it bounced
}

TEST(WallImpact, RimImpactIsTheHertzImpactOfASphereOnAPoint) {
  // The rim of a disk in the plane x = 0 (radius 10 mm), hit edge-on from +y: the rim acts like the
  // flat wall at the same distance (a point contact with the sphere's radius), so the tracks agree.
  WallSpec disk;
  disk.normal = {1, 0, 0};
  disk.radius = 0.01;
  WallSpec plane;
  plane.normal = {0, -1, 0};
  plane.point = {0, 0.01, 0};
  const std::vector<double> rim = impact_track(disk, {0, 0.01 + 1.05e-3, 0}, {0, -1, 0});
  const std::vector<double> flat = impact_track(plane, {0, 0.01 - 1.05e-3, 0}, {0, 1, 0});
  ASSERT_EQ(rim.size(), flat.size());
  for (std::size_t k = 0; k < rim.size(); ++k)
    EXPECT_NEAR(rim[k] - 0.01, 0.01 - flat[k], 1e-12) << k;
}

// A checkpoint of the layout before the force record held the walls' moments (3 values per particle and
// part: the forces alone) restores, and the run continues bitwise as from the current layout.
TEST(WallImpact, CheckpointWithoutWallMomentsRestores) {
  const MaterialSpec m = material("glass", 2500, 5e6, 0.3, 0.9, 0.3);
  Scene s = basic_scene({m}, "hertz", "mindlin");
  s.gravity = {0, 0, -9.81};
  WallSpec floor;
  floor.name = "floor";
  floor.material = m.name;
  s.walls.push_back(floor);
  ParticleSet p;
  add_particle(p, {0, 0, 0.99e-3}, {0.1, 0, 0}, 1e-3, 2500);
  add_particle(p, {0.003, 0, 0.99e-3}, {-0.1, 0, 0}, 1e-3, 2500);
  auto a = make(s, p, 2e-7);
  a->advance(500);
  CheckpointData c = a->checkpoint();
  std::vector<double>& record = c.reals.at("wall_force_record");
  ASSERT_EQ(record.size(), 2u * 1 * 6); // 2 particles x 1 part x (force, moment)
  std::vector<double> forces;
  for (std::size_t e = 0; e < record.size() / 6; ++e)
    forces.insert(forces.end(), record.begin() + 6 * e, record.begin() + 6 * e + 3);
  record = forces;
  auto b = make(s, p, 2e-7);
  b->restore(c);
  a->advance(500);
  b->advance(500);
  EXPECT_EQ(a->frame().position, b->frame().position);
  EXPECT_EQ(a->frame().velocity, b->frame().velocity);
  EXPECT_EQ(a->observe().wall_force, b->observe().wall_force);
}

// motion.oscillation: the wall's velocity is the derivative of its displacement, the host's displacement
// (the analyses') is the device's, and the wall stays where it is at stop.
TEST(WallMotion, OscillationVelocityIsTheDerivativeOfItsDisplacement) {
  WallSpec spec;
  spec.oscillation.amplitude = 1.5e-3;
  spec.oscillation.frequency = 60;
  spec.oscillation.direction = {0, 0.6, 0.8};
  spec.oscillation.start = 0.1;
  spec.oscillation.stop = 0.2125; // six and three quarter periods: held at the crest
  Wall w;
  w.oscillation_direction = Vec3{0, 0.6, 0.8};
  w.oscillation_amplitude = 1.5e-3;
  w.oscillation_omega = 2 * M_PI * 60;
  w.oscillation_start = 0.1;
  w.oscillation_stop = 0.2125;
  EXPECT_EQ(norm(w.offset(0.05)), 0);
  EXPECT_EQ(norm(w.translation_velocity(0.05)), 0);
  double highest = 0;
  for (double t = 0.1003; t < 0.212; t += 0.00071) {
    const double h = 1e-7;
    const Vec3 slope = (1 / (2 * h)) * (w.offset(t + h) - w.offset(t - h));
    EXPECT_NEAR(norm(slope - w.translation_velocity(t)), 0, 1e-6 * 1.5e-3 * 2 * M_PI * 60) << t;
    const Vec3d d = spec.displacement(t);
    EXPECT_NEAR(d[1], w.offset(t).y, 1e-15);
    EXPECT_NEAR(d[2], w.offset(t).z, 1e-15);
    highest = std::max(highest, norm(w.offset(t)));
  }
  EXPECT_NEAR(highest, 1.5e-3, 1e-6);
  EXPECT_NEAR(w.offset(0.3).z, -0.8 * 1.5e-3, 1e-12); // sin(2 pi x 6.75) = -1
  EXPECT_EQ(norm(w.translation_velocity(0.3)), 0);
}

// A sphere resting on a floor that vibrates vertically with amplitude A and angular frequency w stays on
// it while A w^2 < g and is thrown off when A w^2 > g (the floor then decelerates faster than gravity
// can pull the sphere after it). The floor starts at speed A w, which kicks the sphere off at first:
// the gaps are taken once that has died down (restitution 0.5), from 0.5 s on.
TEST(WallMotion, SphereLeavesAVibratedFloorOnlyAboveOneG) {
  const auto largest_gap = [](double peak_acceleration_in_g) {
    const MaterialSpec m = material("glass", 2500, 5e6, 0.3, 0.5, 0.3);
    Scene s = basic_scene({m}, "hertz", "mindlin");
    s.gravity = {0, 0, -9.81};
    WallSpec floor;
    floor.name = "floor";
    floor.material = m.name;
    floor.normal = {0, 0, 1};
    const double amplitude = 1e-3;
    floor.oscillation.amplitude = amplitude;
    floor.oscillation.frequency = std::sqrt(peak_acceleration_in_g * 9.81 / amplitude) / (2 * M_PI);
    floor.oscillation.start = 0.05;
    s.walls.push_back(floor);
    ParticleSet p;
    add_particle(p, {0, 0, 1e-3}, {0, 0, 0}, 1e-3, 2500);
    auto engine = make(s, p, 2e-6);
    double gap = 0;
    for (int k = 0; k < 4000; ++k) {
      engine->advance(100);
      const FrameData f = engine->frame();
      if (f.time > 0.5) gap = std::max(gap, f.position[2] - 1e-3 - floor.displacement(f.time)[2]);
    }
    return gap;
  };
  EXPECT_LT(largest_gap(0.5), 1e-6); // within the resting overlap's scale
  EXPECT_GT(largest_gap(4), 1e-4);   // thrown a tenth of a millimetre and more
}

// motion.oscillation in a scene: parsed, its direction made a unit vector; a zero amplitude is refused.
TEST(WallMotion, OscillationInTheScene) {
  const std::string base = R"(domain: {lo: [0, 0, 0], hi: [0.01, 0.01, 0.01]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
walls:
  - {name: floor, type: plane, material: m, point: [0, 0, 0], normal: [0, 0, 1],
     motion: {oscillation: {amplitude: 1.5e-3, frequency: 60, direction: [0, 0, 2], stop: 2}}}
time: {end: 1}
)";
  const Scene s = parse_scene_text(base, "scene.yaml");
  EXPECT_DOUBLE_EQ(s.walls[0].oscillation.amplitude, 1.5e-3);
  EXPECT_DOUBLE_EQ(s.walls[0].oscillation.frequency, 60);
  EXPECT_DOUBLE_EQ(s.walls[0].oscillation.direction[2], 1);
  EXPECT_DOUBLE_EQ(s.walls[0].oscillation.stop, 2);
  std::string bad = base;
  bad.replace(bad.find("amplitude: 1.5e-3"), 17, "amplitude: 0");
  try {
    parse_scene_text(bad, "scene.yaml");
    ADD_FAILURE() << "accepted a zero amplitude";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("walls.0.motion.oscillation.amplitude"), std::string::npos)
        << e.what();
  }
}
