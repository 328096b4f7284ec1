// Triangle-mesh walls: the nearest point on a triangle, the contact filter on tessellated surfaces, and
// impacts and rolling against the analytic walls they stand for.
#include <gtest/gtest.h>
#include <cmath>
#include <memory>
#include "core/triangle_mesh.hpp"
#include "tests/cli_support.hpp"
#include "tests/test_support.hpp"

using namespace cgdem;
using namespace cgdem::testing;

namespace {

// The rectangle [x0, x1] x [y0, y1] at height z cut into nx x ny cells of two triangles each, normals up.
TriangleMeshData tessellated_floor(double x0, double x1, double y0, double y1, double z, int nx, int ny) {
  TriangleMeshData m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.vertices.push_back({x0 + (x1 - x0) * i / nx, y0 + (y1 - y0) * j / ny, z});
  auto v = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      m.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      m.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  m.lo = {x0, y0, z};
  m.hi = {x1, y1, z};
  return m;
}

WallSpec mesh_wall(TriangleMeshData m) {
  WallSpec w;
  w.type = "mesh";
  w.mesh = std::make_shared<const TriangleMeshData>(std::move(m));
  return w;
}

Vec3 vec(const std::array<double, 3>& a) {
  return {a[0], a[1], a[2]};
}

// The contacts the filter keeps for a sphere at x among the mesh's triangles within r (faces first).
MeshContactFilter contacts(const TriangleMeshData& m, const Vec3& x, Real r) {
  MeshContactFilter f(1e-4 * r);
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const auto& tr = m.triangles[t];
      const Vec3 a = vec(m.vertices[tr[0]]), b = vec(m.vertices[tr[1]]), c = vec(m.vertices[tr[2]]);
      TrianglePoint p = closest_on_triangle(x, a, b, c);
      if (norm2(p.point - x) >= r * r) continue;
      if (acts_as_face(p, x - p.point, triangle_normal(a, b, c))) p.feature = TrianglePoint::Face;
      if ((p.feature == TrianglePoint::Face) != (pass == 0)) continue;
      f.offer(p, (1 / norm(x - p.point)) * (x - p.point), static_cast<int>(t));
    }
  return f;
}

} // namespace

TEST(MeshGeometry, NearestPointOnFaceEdgeAndVertex) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  struct Case {
    Vec3 p, expect;
    int feature, index;
  };
  const Case cases[] = {{{0.2, 0.3, 0.5}, {0.2, 0.3, 0}, TrianglePoint::Face, 0},
                        {{0.5, -0.3, 0.1}, {0.5, 0, 0}, TrianglePoint::Edge, 0},
                        {{0.7, 0.7, -0.2}, {0.5, 0.5, 0}, TrianglePoint::Edge, 1},
                        {{-0.4, 0.25, 0.3}, {0, 0.25, 0}, TrianglePoint::Edge, 2},
                        {{-0.2, -0.1, 0}, {0, 0, 0}, TrianglePoint::Vertex, 0},
                        {{1.5, -0.1, 0.2}, {1, 0, 0}, TrianglePoint::Vertex, 1},
                        {{-0.1, 1.4, -1}, {0, 1, 0}, TrianglePoint::Vertex, 2}};
  for (const Case& k : cases) {
    const TrianglePoint t = closest_on_triangle(k.p, a, b, c);
    EXPECT_EQ(t.feature, k.feature) << k.p.x << " " << k.p.y << " " << k.p.z;
    EXPECT_EQ(t.index, k.index) << k.p.x << " " << k.p.y << " " << k.p.z;
    EXPECT_NEAR(norm(t.point - k.expect), 0, 1e-15) << k.p.x << " " << k.p.y << " " << k.p.z;
  }
  EXPECT_NEAR(norm(triangle_normal(a, b, c) - Vec3{0, 0, 1}), 0, 1e-15);
  EXPECT_NEAR(norm(rotate_about(Vec3{1, 0, 0}, Vec3{0, 0, 1}, math::pi / 2) - Vec3{0, 1, 0}), 0, 1e-15);
}

// A sphere over a floor cut into small triangles (a fifth of its radius), anywhere, also right above a
// shared edge or vertex: one contact, the plane's. On a convex ridge: one contact, on the ridge. In a
// concave crease: one per face.
TEST(MeshGeometry, FilterKeepsTheSurfacesContactsOnly) {
  const TriangleMeshData floor = tessellated_floor(-1, 1, -1, 1, 0, 10, 10);
  const Real r = 1;
  for (int k = 0; k < 200; ++k) {
    const Vec3 x{-0.2 + 0.4 * std::fmod(k * 0.618034, 1.0), -0.2 + 0.4 * std::fmod(k * 0.414214, 1.0),
                 0.3 + 0.5 * std::fmod(k * 0.7548777, 1.0)};
    const MeshContactFilter f = contacts(floor, x, r);
    ASSERT_EQ(f.n, 1) << k;
    EXPECT_NEAR(norm(f.point[0] - Vec3{x.x, x.y, 0}), 0, 1e-14) << k;
  }
  for (const Vec3& x : {Vec3{0, 0, 0.5}, Vec3{0.2, 0.1, 0.5}, Vec3{0.1, 0.3, 0.4}}) { // vertex, edges
    const MeshContactFilter f = contacts(floor, x, r);
    ASSERT_EQ(f.n, 1);
    EXPECT_NEAR(norm(f.point[0] - Vec3{x.x, x.y, 0}), 0, 1e-14);
  }
  // A ridge along y at z = 0, the faces falling at 45 degrees; a sphere above it, off to one side but
  // still beyond both faces' regions, touches the ridge line only.
  TriangleMeshData ridge;
  ridge.vertices = {{-1, -1, -1}, {0, -1, 0}, {0, 1, 0}, {-1, 1, -1}, {1, -1, -1}, {1, 1, -1}};
  ridge.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
  MeshContactFilter f = contacts(ridge, Vec3{0.1, 0.2, 0.5}, 0.6);
  ASSERT_EQ(f.n, 1);
  EXPECT_NEAR(norm(f.point[0] - Vec3{0, 0.2, 0}), 0, 1e-14);
  // A V-shaped crease (the ridge upside down): a sphere in it touches both faces.
  for (auto& v : ridge.vertices)
    v[2] = -v[2];
  f = contacts(ridge, Vec3{0, 0.2, 1.0}, 0.8);
  ASSERT_EQ(f.n, 2);
  EXPECT_TRUE(f.is_face[0] && f.is_face[1]);
}

namespace {

struct Track {
  std::vector<double> x, z, wy;
};

// A sphere (r 1 mm) on the wall with gravity, started at `velocity`; positions and spin every 20 steps.
Track run(const WallSpec& wall, const Vec3d& start, const Vec3d& velocity, double gravity, int frames,
          const std::string& tangential = "mindlin", double restitution = 0.9) {
  const MaterialSpec m = material("glass", 2500, 5e6, 0.3, restitution, 0.3);
  Scene s = basic_scene({m}, "hertz", tangential);
  s.gravity = {0, 0, -gravity};
  WallSpec w = wall;
  w.name = "wall";
  w.material = m.name;
  s.walls.push_back(w);
  ParticleSet p;
  add_particle(p, start, velocity, 1e-3, 2500);
  auto engine = make(s, p, 2e-7);
  Track t;
  for (int k = 0; k < frames; ++k) {
    engine->advance(20);
    const FrameData f = engine->frame();
    t.x.push_back(f.position[0]);
    t.z.push_back(f.position[2]);
    t.wy.push_back(f.angular_velocity[1]);
  }
  return t;
}

} // namespace

TEST(MeshImpact, OneTriangleGivesThePlaneWallsImpact) {
  WallSpec plane;
  TriangleMeshData one;
  one.vertices = {{-0.05, -0.05, 0}, {0.08, -0.05, 0}, {-0.05, 0.08, 0}};
  one.triangles = {{0, 1, 2}};
  one.lo = {-0.05, -0.05, 0};
  one.hi = {0.08, 0.08, 0};
  // An oblique impact with friction: normal and tangential forces, rebound and spin.
  const Track ref = run(plane, {0.001, 0.002, 1.05e-3}, {0.3, 0, -1}, 0, 200);
  const Track tri = run(mesh_wall(one), {0.001, 0.002, 1.05e-3}, {0.3, 0, -1}, 0, 200);
  ASSERT_GT(ref.z.back(), 1.05e-3); // it bounced
  ASSERT_GT(std::fabs(ref.wy.back()), 1);
  for (std::size_t k = 0; k < ref.z.size(); ++k) {
    EXPECT_NEAR(tri.z[k], ref.z[k], 1e-15) << k;
    EXPECT_NEAR(tri.x[k], ref.x[k], 1e-15) << k;
    EXPECT_NEAR(tri.wy[k], ref.wy[k], 1e-9 * std::fabs(ref.wy[k]) + 1e-12) << k;
  }
}

// Rolling with slip over a floor of triangles half the sphere's radius wide: it crosses dozens of shared
// edges and vertices and moves exactly as on the plane (the tangential spring carried across triangles).
TEST(MeshImpact, SphereRollingAcrossATessellatedFloorFeelsThePlane) {
  WallSpec plane;
  const WallSpec floor = mesh_wall(tessellated_floor(-0.02, 0.04, -0.02, 0.02, 0, 120, 80));
  const Vec3d start{0.0001, 0.00013, 0.999e-3}, v{1.0, 0.3, 0};
  const Track ref = run(plane, start, v, 9.81, 1500);
  const Track mesh = run(floor, start, v, 9.81, 1500);
  ASSERT_GT(ref.x.back() - start[0], 0.005); // ten triangles or more crossed
  ASSERT_GT(std::fabs(ref.wy.back()), 10);   // spun up by friction
  double worst_x = 0, worst_w = 0;
  for (std::size_t k = 0; k < ref.x.size(); ++k) {
    worst_x = std::max(worst_x, std::fabs(mesh.x[k] - ref.x[k]) + std::fabs(mesh.z[k] - ref.z[k]));
    worst_w = std::max(worst_w, std::fabs(mesh.wy[k] - ref.wy[k]));
  }
  EXPECT_LT(worst_x, 1e-12);
  EXPECT_LT(worst_w, 1e-6 * std::fabs(ref.wy.back()));
}

// A sphere dropped onto a ridge line (an edge contact) and onto the apex of a pyramid (a vertex contact)
// bounces like on a plane at the same distance: Hertz of a sphere on a point, R* = R.
TEST(MeshImpact, EdgeAndVertexImpactsAreHertzOfASphereOnAPoint) {
  WallSpec plane;
  const Track ref = run(plane, {0, 0, 1.05e-3}, {0, 0, -1}, 0, 150, "none");
  TriangleMeshData ridge;
  ridge.vertices = {{-0.01, -0.01, -0.01}, {0, -0.01, 0},        {0, 0.01, 0},
                    {-0.01, 0.01, -0.01},  {0.01, -0.01, -0.01}, {0.01, 0.01, -0.01}};
  ridge.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
  ridge.lo = {-0.01, -0.01, -0.01};
  ridge.hi = {0.01, 0.01, 0};
  TriangleMeshData pyramid;
  pyramid.vertices = {
      {0, 0, 0}, {-0.01, -0.01, -0.01}, {0.01, -0.01, -0.01}, {0.01, 0.01, -0.01}, {-0.01, 0.01, -0.01}};
  pyramid.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
  pyramid.lo = {-0.01, -0.01, -0.01};
  pyramid.hi = {0.01, 0.01, 0};
  // Above the ridge 1 mm along it; right above the apex.
  const std::pair<TriangleMeshData, Vec3d> cases[] = {{ridge, {0, 0.001, 1.05e-3}},
                                                      {pyramid, {0, 0, 1.05e-3}}};
  for (const auto& [m, start] : cases) {
    const Track t = run(mesh_wall(m), start, {0, 0, -1}, 0, 150, "none");
    ASSERT_GT(ref.z.back(), 1.05e-3);
    for (std::size_t k = 0; k < ref.z.size(); ++k)
      ASSERT_NEAR(t.z[k], ref.z[k], 1e-15) << k;
  }
}

namespace {

const char* mesh_scene = R"(domain:
  lo: [-0.02, -0.02, -0.001]
  hi: [0.02, 0.02, 0.03]
  periodic: [true, true, false]
gravity: [0, 0, -9.81]
materials:
  beads: {density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.3, restitution: 0.7, friction: 0.4}
contact: {normal: hertz, tangential: mindlin}
groups:
  - name: beads
    material: beads
    count: 200
    size: {radius: 0.0005}
    placement: {type: random_box, lo: [-0.008, -0.008, 0.002], hi: [0.008, 0.008, 0.02]}
walls:
  - {name: tray, type: mesh, material: beads, file: tray.stl, scale: 0.001}
time: {end: 0.2, step: 5.0e-6}
output: {every: 0.05, file: tray.h5}
)";

// ASCII STL of a square tray 40 mm wide (in mm), the domain's periodic cross-section: a floor of two
// triangles at z = 0.
const char* tray_stl = R"(solid tray
facet normal 0 0 1
 outer loop
  vertex -20 -20 0
  vertex 20 -20 0
  vertex 20 20 0
 endloop
endfacet
facet normal 0 0 1
 outer loop
  vertex -20 -20 0
  vertex 20 20 0
  vertex -20 20 0
 endloop
endfacet
endsolid tray
)";

} // namespace

// The beads settle on a mesh tray read from an ASCII STL in mm; check reports the mesh; broken meshes are
// one-line scene errors with exit 2.
TEST_F(CliTest, MeshWallFromStlHoldsTheBedAndBadMeshesAreRefused) {
  write("scene.yaml", mesh_scene);
  write("tray.stl", tray_stl);
  Result r = cgdem("check scene.yaml");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("mesh tray"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2 triangles, 4 vertices, bounding box [-0.02, -0.02, 0] - [0.02, 0.02, 0] m"),
            std::string::npos)
      << r.out;
  r = cgdem("run scene.yaml --quiet --threads 1");
  ASSERT_EQ(r.code, 0) << r.err;
  {
    hid_t f = H5Fopen((dir / "tray.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const auto z = read_doubles(f, last_frame(f) + "/position");
    // Every bead above the tray (centre at least 0.9 radius above z = 0): none fell through.
    for (std::size_t i = 2; i < z.size(); i += 3)
      EXPECT_GT(z[i], 0.45e-3) << i / 3;
    // The tray carries the beads' weight once they rest: (wall force z) close to -m g.
    const auto force = read_doubles(f, "series/wall_force/tray"); // 3 per output
    H5Fclose(f);
    const double weight = 200 * 2500 * 4.0 / 3 * M_PI * std::pow(0.5e-3, 3) * 9.81;
    ASSERT_GE(force.size(), 3u);
    EXPECT_NEAR(force.back(), -weight, 0.1 * weight);
  }
  // ParaView: the XDMF draws the tray's triangles beside the particles; a moving tray (lifted at 1 mm/s)
  // has its vertices stored at each frame.
  std::string xdmf = slurp(dir / "tray.xdmf");
  EXPECT_NE(xdmf.find("<Grid Name=\"mesh_tray\""), std::string::npos) << xdmf;
  EXPECT_NE(xdmf.find("TopologyType=\"Triangle\" NumberOfElements=\"2\""), std::string::npos);
  EXPECT_NE(xdmf.find("tray.h5:/meshes/tray/vertices"), std::string::npos);
  r = cgdem("run scene.yaml --quiet --threads 1 --set time.end=0.1 --set 'walls.0.motion={velocity: [0, 0, "
            "0.001]}'");
  ASSERT_EQ(r.code, 0) << r.err;
  xdmf = slurp(dir / "tray.xdmf");
  EXPECT_NE(xdmf.find("tray.h5:/frames/000002/mesh_tray"), std::string::npos) << xdmf;
  {
    hid_t f = H5Fopen((dir / "tray.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const auto v = read_doubles(f, "frames/000002/mesh_tray"); // t = 0.1 s: lifted by 0.1 mm
    ASSERT_EQ(v.size(), 12u);
    for (std::size_t k = 2; k < v.size(); k += 3)
      EXPECT_NEAR(v[k], 1e-4, 1e-12);
    EXPECT_EQ(read_doubles(f, "meshes/tray/triangles").size(), 6u);
    H5Fclose(f);
  }
  // Broken meshes: unreadable, a degenerate triangle, outside the domain.
  write("garbage.stl", "this is not a mesh\n");
  std::string degenerate = tray_stl;
  degenerate.replace(degenerate.find("vertex 20 20 0"), 14, "vertex 0 0 0  ");
  degenerate.replace(degenerate.find("vertex 20 -20 0"), 15, "vertex 0 0 0   ");
  write("degenerate.stl", degenerate);
  struct Bad {
    std::string set, says;
  };
  for (const Bad& b :
       {Bad{"walls.0.file=garbage.stl", "garbage.stl"}, Bad{"walls.0.file=none.stl", "cannot read"},
        Bad{"walls.0.file=degenerate.stl", "degenerate"}, Bad{"walls.0.scale=0.01", "outside the domain"}}) {
    r = cgdem("check scene.yaml --set " + b.set);
    EXPECT_EQ(r.code, 2) << b.set << "\n" << r.err;
    EXPECT_NE(r.err.find(b.says), std::string::npos) << b.set << "\n" << r.err;
    EXPECT_NE(r.err.find("walls.0.file"), std::string::npos) << b.set << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << b.set << "\n" << r.err;
  }
}

// A paddle of two triangles turning about z at 100 rad/s strikes a bead: the moment of the bead's force on
// the paddle about the axis (/series/wall_torque), integrated over the steps as the velocity-Verlet kicks
// integrate it, is minus the bead's change of angular momentum about the axis (orbit and spin).
TEST(MeshImpact, PaddleTorqueMatchesTheBeadsAngularMomentum) {
  const MaterialSpec m = material("glass", 2500, 5e6, 0.3, 0.5, 0.3);
  Scene s = basic_scene({m}, "hertz", "mindlin");
  TriangleMeshData paddle;
  paddle.vertices = {{0.001, 0, -0.005}, {0.01, 0, -0.005}, {0.01, 0, 0.005}, {0.001, 0, 0.005}};
  paddle.triangles = {{0, 1, 2}, {0, 2, 3}};
  paddle.lo = {0.001, 0, -0.005};
  paddle.hi = {0.01, 0, 0.005};
  WallSpec w = mesh_wall(paddle);
  w.name = "paddle";
  w.material = m.name;
  w.axis = {0, 0, 1};
  w.angular_velocity = 100;
  s.walls.push_back(w);
  ParticleSet p;
  add_particle(p, {0.005, 0.0008, 0.0002}, {0, 0, 0}, 5e-4, 2500);
  const double dt = 2e-7;
  auto engine = make(s, p, dt);
  const double mass = 2500 * 4.0 / 3 * M_PI * std::pow(5e-4, 3), inertia = 0.4 * mass * 25e-8;
  auto angular_momentum = [&] {
    const FrameData f = engine->frame();
    return mass * (f.position[0] * f.velocity[1] - f.position[1] * f.velocity[0]) +
           inertia * f.angular_velocity[2];
  };
  const double l0 = angular_momentum();
  double impulse = 0, previous = engine->observe().wall_torque.at(2), peak = 0;
  for (int k = 0; k < 8000; ++k) {
    engine->advance(1);
    const double now = engine->observe().wall_torque.at(2);
    impulse += 0.5 * dt * (previous + now);
    previous = now;
    peak = std::max(peak, std::fabs(now));
  }
  const double gained = angular_momentum() - l0;
  ASSERT_GT(peak, 0);   // the paddle struck the bead
  ASSERT_GT(gained, 0); // and swept it along its rotation
  EXPECT_NEAR(gained, -impulse, 1e-3 * gained);
}
