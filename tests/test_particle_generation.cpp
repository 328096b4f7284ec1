// Particle generation: sizes, placements, files, ids, velocities, and the initial-state check.
#include <gtest/gtest.h>

#include <hdf5.h>

#include <cmath>
#include <tuple>
#include <filesystem>
#include <fstream>
#include <set>

#include "drivers/particle_generation.hpp"
#include "setup/scaling.hpp"
#include "drivers/scene_parser.hpp"

using namespace cgdem;

namespace {

Scene scene_with(const std::string& domain, const std::string& groups,
                 const std::vector<std::string>& overrides = {}) {
  const std::string text = "domain: " + domain +
                           "\nmaterials: {glass: {density: 2500, youngs_modulus: 5e6}}\n"
                           "groups:\n" +
                           groups + "time: {end: 1}\n";
  return parse_scene_text(text, "gen.yaml", overrides);
}

double dist(const Vec3d& a, const Vec3d& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

// Brute force: no pair closer than the sum of radii (non-periodic).
void expect_no_overlaps(const ParticleSet& ps) {
  for (size_t i = 0; i < ps.size(); ++i)
    for (size_t j = i + 1; j < ps.size(); ++j)
      ASSERT_GE(dist(ps.position[i], ps.position[j]), ps.radius[i] + ps.radius[j] - 1e-15) << i << " " << j;
}

std::string check_error(const Scene& s, const ParticleSet& ps) {
  try {
    check_particles(s, ps);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

const std::string kBox = "{lo: [0, 0, 0], hi: [0.01, 0.01, 0.02]}";

} // namespace

TEST(ParticleGeneration, LatticeFillsXThenYThenZ) {
  const Scene s =
      scene_with(kBox, "  - {material: glass, count: 150, size: {radius: 0.0005},\n"
                       "     placement: {type: lattice, lo: [0, 0, 0], hi: [0.01, 0.01, 0.02]}}\n");
  const ParticleSet ps = generate_particles(s);
  ASSERT_EQ(ps.size(), 150u);
  const double sp = 1.05e-3;
  // 9 sites per row in x (first at r, last <= hi - r), 81 per layer.
  EXPECT_NEAR(ps.position[0][0], 0.0005, 1e-15);
  EXPECT_NEAR(ps.position[1][0] - ps.position[0][0], sp, 1e-12);
  EXPECT_NEAR(ps.position[9][1] - ps.position[0][1], sp, 1e-12);
  EXPECT_NEAR(ps.position[81][2] - ps.position[0][2], sp, 1e-12);
  for (size_t i = 0; i < ps.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(ps.position[i][a] - ps.radius[i], -1e-15);
      EXPECT_LE(ps.position[i][a] + ps.radius[i], (a == 2 ? 0.02 : 0.01) + 1e-15);
    }
  expect_no_overlaps(ps);
  EXPECT_EQ(check_error(s, ps), "");
  std::set<std::int64_t> ids(ps.id.begin(), ps.id.end());
  EXPECT_EQ(ids.size(), ps.size());
  EXPECT_EQ(*ids.begin(), 1);
  EXPECT_DOUBLE_EQ(ps.density[0], 2500);
}

TEST(ParticleGeneration, LatticeTooSmallNamesTheGroup) {
  const Scene s =
      scene_with(kBox, "  - {name: blocks, material: glass, count: 2000, size: {radius: 0.0005},\n"
                       "     placement: {type: lattice}}\n");
  try {
    generate_particles(s);
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("gen.yaml:4: groups.0.placement: group 'blocks': the lattice box holds only", 0), 0u)
        << msg;
    EXPECT_NE(msg.find("reduce count"), std::string::npos) << msg;
  }
}

TEST(ParticleGeneration, RandomBoxIsDeterministicAndInside) {
  const std::string g =
      "  - {material: glass, count: 400, size: {distribution: uniform, min: 0.0003, max: 0.0005},\n"
      "     placement: {type: random_box, lo: [0.001, 0, 0], hi: [0.009, 0.01, 0.015], seed: 3},\n"
      "     velocity: [0.1, 0, 0], velocity_random: 0.2}\n";
  const Scene s = scene_with(kBox, g);
  const ParticleSet a = generate_particles(s);
  const ParticleSet b = generate_particles(s);
  ASSERT_EQ(a.size(), 400u);
  expect_no_overlaps(a);
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.position[i], b.position[i]);
    EXPECT_EQ(a.velocity[i], b.velocity[i]);
    EXPECT_GE(a.radius[i], 0.0003);
    EXPECT_LE(a.radius[i], 0.0005);
    EXPECT_GE(a.position[i][0] - a.radius[i], 0.001 - 1e-15);
    EXPECT_LE(a.position[i][0] + a.radius[i], 0.009 + 1e-15);
    EXPECT_LE(a.position[i][2] + a.radius[i], 0.015 + 1e-15);
    const Vec3d dv{a.velocity[i][0] - 0.1, a.velocity[i][1], a.velocity[i][2]};
    EXPECT_NEAR(dist(dv, {0, 0, 0}), 0.2, 1e-12);
  }
  EXPECT_EQ(check_error(s, a), "");
  const ParticleSet c = generate_particles(scene_with(kBox, g, {"groups.0.placement.seed=4"}));
  EXPECT_NE(a.position[0], c.position[0]);
}

TEST(ParticleGeneration, RandomCylinderIsDeterministicAndInside) {
  const std::string g =
      "  - {material: glass, count: 300, size: {radius: 0.0004},\n"
      "     placement: {type: random_cylinder, center: [0.005, 0.005, 0.002], radius: 0.004,\n"
      "                 height: 0.015}}\n";
  const Scene s = scene_with(kBox, g);
  const ParticleSet a = generate_particles(s);
  const ParticleSet b = generate_particles(s);
  ASSERT_EQ(a.size(), 300u);
  expect_no_overlaps(a);
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.position[i], b.position[i]);
    const double rho = std::hypot(a.position[i][0] - 0.005, a.position[i][1] - 0.005);
    EXPECT_LE(rho + a.radius[i], 0.004 + 1e-15);
    EXPECT_GE(a.position[i][2] - a.radius[i], 0.002 - 1e-15);
    EXPECT_LE(a.position[i][2] + a.radius[i], 0.017 + 1e-15);
  }
}

// placement.axis: a cylinder along any direction (a horizontal drum's fill); the default is +z, and an
// explicit +z axis of any length places exactly the same particles.
TEST(ParticleGeneration, RandomCylinderAlongAnyAxis) {
  const auto cylinder = [](const std::string& axis, const std::string& center, double height) {
    return "  - {material: glass, count: 150, size: {radius: 0.0004},\n"
           "     placement: {type: random_cylinder, center: " +
           center + ", radius: 0.004, height: " + std::to_string(height) + axis + "}}\n";
  };
  const ParticleSet z = generate_particles(scene_with(kBox, cylinder("", "[0.005, 0.005, 0.002]", 0.015)));
  const ParticleSet z2 =
      generate_particles(scene_with(kBox, cylinder(", axis: [0, 0, 2]", "[0.005, 0.005, 0.002]", 0.015)));
  ASSERT_EQ(z.size(), z2.size());
  for (size_t i = 0; i < z.size(); ++i)
    EXPECT_EQ(z.position[i], z2.position[i]);
  const double c = std::sqrt(0.5);
  for (const auto& [axis, a, center, base, height] :
       {std::make_tuple(std::string(", axis: [1, 0, 0]"), Vec3d{1, 0, 0},
                        std::string("[0.0005, 0.005, 0.01]"), Vec3d{0.0005, 0.005, 0.01}, 0.009),
        std::make_tuple(std::string(", axis: [0, -1, 1]"), Vec3d{0, -c, c},
                        std::string("[0.005, 0.0068, 0.005]"), Vec3d{0.005, 0.0068, 0.005}, 0.005)}) {
    const ParticleSet ps = generate_particles(scene_with(kBox, cylinder(axis, center, height)));
    ASSERT_EQ(ps.size(), 150u) << axis;
    expect_no_overlaps(ps);
    for (size_t i = 0; i < ps.size(); ++i) {
      const Vec3d d{ps.position[i][0] - base[0], ps.position[i][1] - base[1], ps.position[i][2] - base[2]};
      const double along = d[0] * a[0] + d[1] * a[1] + d[2] * a[2];
      const Vec3d radial{d[0] - along * a[0], d[1] - along * a[1], d[2] - along * a[2]};
      EXPECT_GE(along - ps.radius[i], -1e-15) << axis;
      EXPECT_LE(along + ps.radius[i], height + 1e-15) << axis;
      EXPECT_LE(dist(radial, {0, 0, 0}) + ps.radius[i], 0.004 + 1e-15) << axis;
    }
  }
  // A cylinder that leaves the domain is refused at the key, whatever its direction.
  try {
    generate_particles(scene_with(kBox, cylinder(", axis: [1, 0, 0]", "[0.005, 0.005, 0.01]", 0.009)));
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("placement cylinder"), std::string::npos) << e.what();
  }
}

TEST(ParticleGeneration, RandomPlacementThatCannotFitFails) {
  const Scene s = scene_with(kBox, "  - {name: crowd, material: glass, count: 5000, size: {radius: 0.0005},\n"
                                   "     placement: {type: random_box}}\n");
  try {
    generate_particles(s);
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("group 'crowd'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("enlarge the region"), std::string::npos) << msg;
    EXPECT_NE(msg.find("fewer particles"), std::string::npos) << msg;
  }
  // Near the jamming limit: fails after the bounded number of tries rather than hanging.
  const Scene t = scene_with(kBox, "  - {name: dense, material: glass, count: 1000, size: {radius: 0.0005},\n"
                                   "     placement: {type: random_box, hi: [0.01, 0.01, 0.0045]}}\n");
  try {
    generate_particles(t);
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("group 'dense'"), std::string::npos) << e.what();
  }
}

TEST(ParticleGeneration, SizeDistributions) {
  const Scene s = scene_with(
      kBox, "  - {material: glass, count: 500, size: {distribution: normal, mean: 0.0003, std: 0.0001, min: "
            "0.0002,\n"
            "     max: 0.00045}, placement: {type: random_box}}\n"
            "  - {material: glass, count: 500, size: {distribution: lognormal, mean: 0.0002, std: 0.00005},\n"
            "     placement: {type: random_box}}\n");
  const ParticleSet ps = generate_particles(s);
  ASSERT_EQ(ps.size(), 1000u);
  double mean_ln = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    if (ps.group[i] == 0) {
      EXPECT_GE(ps.radius[i], 0.0002);
      EXPECT_LE(ps.radius[i], 0.00045);
    } else {
      mean_ln += ps.radius[i] / 500;
    }
  }
  EXPECT_NEAR(mean_ln, 0.0002, 0.00001); // the mean of the radius itself
  EXPECT_EQ(check_error(s, ps), "");
}

TEST(ParticleGeneration, CoarseGrainScalesTheRadius) {
  const Scene s =
      scene_with(kBox, "  - {material: glass, count: 20, size: {radius: 0.0002},\n"
                       "     placement: {type: random_box}, coarse_grain: {law: hu_method1, factor: 2}}\n");
  EXPECT_DOUBLE_EQ(group_scale_factor(s.groups[0]), 2);
  const ParticleSet ps = generate_particles(s);
  ASSERT_EQ(ps.size(), 20u);
  EXPECT_DOUBLE_EQ(ps.radius[0], 0.0004);
  GroupSpec none;
  none.coarse_grain.factor = 3;
  EXPECT_DOUBLE_EQ(group_scale_factor(none), 1);
}

TEST(ParticleGeneration, ReadsTheSharedSettledBed) {
  const std::string path = std::string(CGDEM_SHARED_DIR) + "/data/settled_bed_10k.csv";
  Scene s = scene_with("{lo: [0, 0, 0], hi: [0.02031, 0.02031, 0.04], periodic: [true, true, false]}",
                       "  - {material: glass, placement: {type: file, file: '" + path + "'}}\n");
  const ParticleSet ps = generate_particles(s);
  ASSERT_EQ(ps.size(), 10000u);
  // The settled bed has overlaps of up to about 2% of the radius under its own weight.
  const std::string msg = check_error(s, ps);
  EXPECT_NE(msg.find("overlap by"), std::string::npos) << msg;
  s.stability.overlap_tolerance = 0.03;
  EXPECT_EQ(ps.id[0], 1);
  EXPECT_EQ(ps.id[9999], 10000);
  EXPECT_DOUBLE_EQ(ps.radius[0], 0.0005);
  EXPECT_DOUBLE_EQ(ps.density[0], 2500);
  EXPECT_NEAR(ps.position[0][0], 0.00046877053189437964, 1e-18);
  EXPECT_EQ(check_error(s, ps), "");
  // count takes the first particles; a generated group continues the ids after the file's.
  const Scene t = scene_with("{lo: [0, 0, 0], hi: [0.02031, 0.02031, 0.04], periodic: [true, true, false]}",
                             "  - {material: glass, count: 100, placement: {type: file, file: '" + path +
                                 "'}}\n"
                                 "  - {material: glass, count: 10, size: {radius: 0.0005}, placement: {type: "
                                 "random_box, lo: [0, 0, 0.03]}}\n");
  const ParticleSet pt = generate_particles(t);
  ASSERT_EQ(pt.size(), 110u);
  EXPECT_EQ(pt.id[99], 100);
  EXPECT_EQ(pt.id[100], 101);
}

TEST(ParticleGeneration, ReadsTheLastFrameOfAnHdf5File) {
  const std::string path = (std::filesystem::temp_directory_path() / "cgdem_gen_test.h5").string();
  {
    const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t frames = H5Gcreate2(f, "frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    for (int frame = 0; frame < 2; ++frame) {
      const std::string name = frame == 0 ? "000000" : "000010";
      const hid_t g = H5Gcreate2(frames, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      const double pos[9] = {0.001, 0.001, 0.001 + frame * 0.001, 0.003, 0.001, 0.001, 0.005, 0.001, 0.001};
      const double rad[3] = {0.0005, 0.0005, 0.0004};
      const std::int64_t id[3] = {7, 8, 9};
      hsize_t d2[2] = {3, 3}, d1[1] = {3};
      hid_t sp = H5Screate_simple(2, d2, nullptr);
      hid_t ds = H5Dcreate2(g, "position", H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, pos);
      H5Dclose(ds), H5Sclose(sp);
      sp = H5Screate_simple(1, d1, nullptr);
      ds = H5Dcreate2(g, "radius", H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rad);
      H5Dclose(ds);
      ds = H5Dcreate2(g, "id", H5T_STD_I64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      H5Dwrite(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, id);
      H5Dclose(ds), H5Sclose(sp), H5Gclose(g);
    }
    H5Gclose(frames), H5Fclose(f);
  }
  const Scene s = scene_with(kBox, "  - {material: glass, placement: {type: file, file: '" + path + "'}}\n");
  const ParticleSet ps = generate_particles(s);
  ASSERT_EQ(ps.size(), 3u);
  EXPECT_DOUBLE_EQ(ps.position[0][2], 0.002); // the last frame
  EXPECT_DOUBLE_EQ(ps.radius[2], 0.0004);
  EXPECT_EQ(ps.id[2], 9);
  EXPECT_DOUBLE_EQ(ps.density[1], 2500);
  std::filesystem::remove(path);
}

TEST(ParticleGeneration, Hdf5RadiusLargerThanItsFileIsRefusedBeforeAllocation) {
  // A chunked dataset with no chunk written is a valid HDF5 file of a few kB that claims any extent: here
  // 1e11 radii (800 GB). The reader must refuse it by name instead of allocating the claim.
  const std::string path = (std::filesystem::temp_directory_path() / "cgdem_gen_huge.h5").string();
  {
    const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t frames = H5Gcreate2(f, "frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t g = H5Gcreate2(frames, "000000", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t dims[1] = {100000000000ull}, chunk[1] = {1024};
    const hid_t sp = H5Screate_simple(1, dims, nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, chunk);
    const hid_t ds = H5Dcreate2(g, "radius", H5T_IEEE_F64LE, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    H5Dclose(ds), H5Pclose(dcpl), H5Sclose(sp), H5Gclose(g), H5Gclose(frames), H5Fclose(f);
  }
  const Scene s = scene_with(kBox, "  - {material: glass, placement: {type: file, file: '" + path + "'}}\n");
  try {
    generate_particles(s);
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("/frames/000000/radius claims 100000000000 particles, more than the "),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("placement.file"), std::string::npos) << msg;
  }
  std::filesystem::remove(path);
}

TEST(ParticleGeneration, BadParticleFiles) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "cgdem_gen_files";
  fs::create_directories(dir);
  {
    std::ofstream(dir / "bad.csv")
        << "id,x,y,z,radius\n1,0.001,0.001,0.001,0.0005\n2,0.003,oops,0.001,0.0005\n";
    std::ofstream(dir / "dup.csv")
        << "id,x,y,z,radius\n1,0.001,0.001,0.001,0.0005\n1,0.003,0.001,0.001,0.0005\n";
  }
  auto gen_error = [](const Scene& s) -> std::string {
    try {
      generate_particles(s);
    } catch (const SceneError& e) {
      return e.what();
    }
    return "";
  };
  std::string msg = gen_error(scene_with(kBox, "  - {material: glass, placement: {type: file, file: '" +
                                                   (dir / "bad.csv").string() + "'}}\n"));
  EXPECT_NE(msg.find("bad.csv' line 3: y 'oops' is not a number"), std::string::npos) << msg;
  // A particle 1e60 m away (a fuzzer's input: the placement grid's cell index overflowed int): generated,
  // then refused by name.
  {
    std::ofstream(dir / "far.csv") << "x,y,z,radius\n1e60,0.001,-1e60,0.0005\n0.003,0.003,0.003,0.0005\n";
    const Scene far = scene_with(kBox, "  - {material: glass, placement: {type: file, file: '" +
                                           (dir / "far.csv").string() + "'}}\n");
    const ParticleSet ps = generate_particles(far);
    ASSERT_EQ(ps.size(), 2u);
    EXPECT_NE(check_error(far, ps).find("is outside the domain"), std::string::npos) << check_error(far, ps);
  }
  msg = gen_error(scene_with(kBox, "  - {material: glass, placement: {type: file, file: '" +
                                       (dir / "dup.csv").string() + "'}}\n"));
  EXPECT_NE(msg.find("particle id 1 appears twice"), std::string::npos) << msg;
  // Unreadable at generation time (file removed after parsing): the path is named.
  Scene s = scene_with(kBox, "  - {material: glass, placement: {type: file, file: '" +
                                 (dir / "bad.csv").string() + "'}}\n");
  s.groups[0].placement.file = (dir / "gone.csv").string();
  msg = gen_error(s);
  EXPECT_NE(msg.find("cannot read particle file '" + (dir / "gone.csv").string() + "'"), std::string::npos)
      << msg;
  EXPECT_EQ(msg.rfind("gen.yaml:4: groups.0.placement.file: ", 0), 0u) << msg;
  fs::remove_all(dir);
}

namespace {
ParticleSet two_particles(const Vec3d& a, const Vec3d& b, double r) {
  ParticleSet ps;
  ps.id = {41, 42};
  ps.position = {a, b};
  ps.velocity = ps.angular_velocity = {Vec3d{0, 0, 0}, Vec3d{0, 0, 0}};
  ps.radius = {r, r};
  ps.density = {2500, 2500};
  ps.material = {0, 0};
  ps.group = {0, 0};
  return ps;
}
} // namespace

TEST(ParticleGeneration, OverlapsAcrossPeriodicImages) {
  const Scene s =
      scene_with("{lo: [0, 0, 0], hi: [0.01, 0.01, 0.02], periodic: [true, false, false]}",
                 "  - {material: glass, count: 1, size: {radius: 0.0005}, placement: {type: lattice}}\n");
  // 0.4 mm apart through the x boundary: overlap 0.6 mm.
  const ParticleSet ps = two_particles({0.0002, 0.005, 0.005}, {0.0098, 0.005, 0.005}, 0.0005);
  std::string msg = check_error(s, ps);
  EXPECT_EQ(
      msg.rfind("gen.yaml:4: groups.0: particles 41 and 42 overlap by 0.0006 m (120% of the smaller radius",
                0),
      0u)
      << msg;
  EXPECT_NE(msg.find("stability.relax_initial_overlaps: true"), std::string::npos) << msg;
  // The same pair through a non-periodic axis is far apart.
  EXPECT_EQ(check_error(s, two_particles({0.005, 0.0002, 0.005}, {0.005, 0.0098, 0.005}, 0.0005)), "");
  // Within the tolerance (1% of the radius): accepted; beyond: rejected.
  EXPECT_EQ(check_error(s, two_particles({0.0002, 0.005, 0.005}, {0.0002 + 0.000996, 0.005, 0.005}, 0.0005)),
            "");
  EXPECT_NE(check_error(s, two_particles({0.0002, 0.005, 0.005}, {0.0002 + 0.00099, 0.005, 0.005}, 0.0005)),
            "");
  // Periodic position beyond the box but within one box length is fine; relax allows overlaps.
  EXPECT_EQ(check_error(s, two_particles({-0.003, 0.005, 0.005}, {0.005, 0.005, 0.005}, 0.0005)), "");
  Scene relaxed = s;
  relaxed.stability.relax_initial_overlaps = true;
  EXPECT_EQ(check_error(relaxed, ps), "");
  EXPECT_NE(check_error(relaxed, two_particles({0.002, 0.005, 0.005}, {0.002, 0.005, 0.005}, 0.0005))
                .find("same position"),
            std::string::npos);
}

TEST(ParticleGeneration, OutsideTheDomain) {
  const Scene s =
      scene_with("{lo: [0, 0, 0], hi: [0.01, 0.01, 0.02], periodic: [true, false, false]}",
                 "  - {material: glass, count: 1, size: {radius: 0.0005}, placement: {type: lattice}}\n");
  std::string msg = check_error(s, two_particles({0.005, 0.005, -0.001}, {0.005, 0.005, 0.005}, 0.0005));
  EXPECT_NE(msg.find("particle 41 is outside the domain: z = -0.001 not in [0, 0.02]"), std::string::npos)
      << msg;
  msg = check_error(s, two_particles({0.025, 0.005, 0.001}, {0.005, 0.005, 0.005}, 0.0005));
  EXPECT_NE(msg.find("more than a box length outside the periodic domain"), std::string::npos) << msg;
}

TEST(ParticleGeneration, RandomGroupsAvoidEarlierGroups) {
  const Scene s = scene_with(kBox, "  - {material: glass, count: 300, size: {radius: 0.0005},\n"
                                   "     placement: {type: lattice, hi: [0.01, 0.01, 0.006]}}\n"
                                   "  - {material: glass, count: 300, size: {radius: 0.0004},\n"
                                   "     placement: {type: random_box, hi: [0.01, 0.01, 0.012]}}\n");
  const ParticleSet ps = generate_particles(s);
  ASSERT_EQ(ps.size(), 600u);
  expect_no_overlaps(ps);
  EXPECT_EQ(check_error(s, ps), "");
}

TEST(ParticleGeneration, LargeSetCheckIsFast) {
  // 20k particles on a periodic lattice: the grid check is O(N).
  const Scene s = scene_with("{lo: [0, 0, 0], hi: [0.03, 0.03, 0.03], periodic: [true, true, true]}",
                             "  - {material: glass, count: 20000, size: {radius: 0.0005},\n"
                             "     placement: {type: lattice, spacing: 0.001}}\n");
  const ParticleSet ps = generate_particles(s);
  ASSERT_EQ(ps.size(), 20000u);
  EXPECT_EQ(check_error(s, ps), ""); // touching (overlap 0) is not an overlap
}
