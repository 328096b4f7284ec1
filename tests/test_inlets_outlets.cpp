// Particles entering and leaving a run through the cgdem executable: an inlet places its particles
// without overlaps at its count or mass rate, an outlet removes exactly the particles that crossed it, the
// HDF5 frames and the XDMF follow the changing particle count (ids unique, never reused), and a restart
// continues the insertions and removals bitwise.
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <map>
#include <regex>
#include <set>
#include "tests/cli_support.hpp"

using namespace cgdem::testing;

namespace {

// Beads poured from an inlet box at the top of a periodic column onto a floor; `inlet` and `outlets` are
// substituted by each test.
std::string pour_scene(const std::string& inlet, const std::string& outlets = "") {
  return R"(domain:
  lo: [0, 0, 0]
  hi: [0.01, 0.01, 0.03]
  periodic: [true, true, false]
gravity: [0, 0, -9.81]
materials:
  beads:
    density: 2500
    youngs_modulus: 5.0e6
    poisson_ratio: 0.3
    restitution: 0.5
    friction: 0.4
contact:
  normal: hertz
groups:
  - name: poured
    material: beads
    count: 400
    size: {distribution: normal, mean: 0.0005, std: 0.0001, min: 0.0003, max: 0.0007}
    placement:
      type: inlet
      lo: [0, 0, 0.024]
      hi: [0.01, 0.01, 0.03]
      )" +
         inlet + R"(
      every: 0.0025
      seed: 7
    velocity: [0, 0, -0.5]
walls:
  - name: floor
    type: plane
    material: beads
    point: [0, 0, 0]
    normal: [0, 0, 1]
)" + outlets +
         R"(
time:
  end: 0.04
  step: 5.0e-6
output:
  every: 0.0025
  file: pour.h5
  fields: [id, position, velocity, radius, mass]
)";
}

// An outlet box over the floor's first 4 mm: the landed beads leave through it.
const char* kBoxDrain = R"(outlets:
  - name: drain
    type: box
    lo: [0, 0, 0]
    hi: [0.01, 0.01, 0.004]
)";

struct Frame {
  double time = 0;
  std::vector<double> id, x, r, m;
};

double attribute(hid_t group, const char* name) {
  double v = 0;
  hid_t a = H5Aopen(group, name, H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_DOUBLE, &v);
  H5Aclose(a);
  return v;
}

std::vector<Frame> read_frames(const fs::path& file) {
  std::vector<Frame> out;
  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << file;
  if (f < 0) return out;
  for (int k = 0; k < frame_count(f); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "/frames/%06d", k);
    Frame fr;
    hid_t g = H5Gopen2(f, name, H5P_DEFAULT);
    fr.time = attribute(g, "time");
    H5Gclose(g);
    fr.id = read_doubles(f, std::string(name) + "/id");
    fr.x = read_doubles(f, std::string(name) + "/position");
    fr.r = read_doubles(f, std::string(name) + "/radius");
    fr.m = read_doubles(f, std::string(name) + "/mass");
    out.push_back(std::move(fr));
  }
  H5Fclose(f);
  return out;
}

std::vector<double> series(const fs::path& file, const std::string& name) {
  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  std::vector<double> v = read_doubles(f, "/series/" + name);
  H5Fclose(f);
  return v;
}

// Deepest overlap (m, > 0 when overlapping) of particle i with any other particle of the frame, with the
// periodic images in x and y of the 10 mm column.
double deepest_overlap(const Frame& fr, std::size_t i) {
  double worst = -1;
  for (std::size_t j = 0; j < fr.id.size(); ++j) {
    if (j == i) continue;
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
      double d = fr.x[3 * i + a] - fr.x[3 * j + a];
      if (a < 2) d -= 0.01 * std::round(d / 0.01);
      d2 += d * d;
    }
    worst = std::max(worst, fr.r[i] + fr.r[j] - std::sqrt(d2));
  }
  return worst;
}

} // namespace

TEST_F(CliTest, InletPlacesWithoutOverlapsAtItsCountRate) {
  write("pour.yaml", pour_scene("rate: 6000"));
  const Result r = cgdem("run pour.yaml --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Frame> frames = read_frames(dir / "pour.h5");
  ASSERT_EQ(frames.size(), 17u);
  const auto inserted = series(dir / "pour.h5", "inlet_poured_count");
  const auto particles = series(dir / "pour.h5", "particles");
  ASSERT_EQ(inserted.size(), frames.size());
  std::set<double> seen;
  std::size_t new_total = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const Frame& fr = frames[k];
    // 6000/s from t = 0 in events every 2.5 ms: 15 per event, all placed (the box clears at 0.5 m/s).
    const double due = std::floor(6000 * fr.time + 1e-9);
    EXPECT_EQ(inserted[k], due) << "t = " << fr.time;
    EXPECT_EQ(particles[k], double(fr.id.size()));
    EXPECT_EQ(fr.id.size(), std::size_t(due));
    // The particles that appeared in this frame were placed in it: none overlaps anything.
    for (std::size_t i = 0; i < fr.id.size(); ++i) {
      if (seen.count(fr.id[i])) continue;
      ++new_total;
      EXPECT_LE(deepest_overlap(fr, i), 0) << "new particle " << fr.id[i] << " at t = " << fr.time;
      const double z = fr.x[3 * i + 2];
      EXPECT_GE(z - fr.r[i], 0.024 - 1e-12);
      EXPECT_LE(z + fr.r[i], 0.03 + 1e-12);
    }
    for (double id : fr.id)
      seen.insert(id);
  }
  EXPECT_EQ(new_total, 240u);
}

TEST_F(CliTest, InletMassRateIsFollowedToWithinOneParticle) {
  write("pour.yaml", pour_scene("mass_rate: 0.01"));
  const Result r = cgdem("run pour.yaml --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Frame> frames = read_frames(dir / "pour.h5");
  const auto mass = series(dir / "pour.h5", "inlet_poured_mass");
  ASSERT_EQ(mass.size(), frames.size());
  const double largest = 2500 * 4.0 / 3.0 * M_PI * std::pow(0.0007, 3);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const double due = 0.01 * frames[k].time;
    EXPECT_LE(mass[k], due * (1 + 1e-9)) << "t = " << frames[k].time;
    EXPECT_GT(mass[k], due - largest) << "t = " << frames[k].time;
    double held = 0; // nothing leaves: the mass in the frame is the mass inserted
    for (double m : frames[k].m)
      held += m;
    EXPECT_NEAR(held, mass[k], 1e-12 * (1 + mass[k]));
  }
  EXPECT_GT(mass.back(), 0.9 * 0.01 * 0.04);
}

TEST_F(CliTest, OutletRemovesExactlyTheParticlesThatCrossedIt) {
  // No floor: the poured beads fall through the plane z = 10 mm and are removed there.
  std::string scene = pour_scene("rate: 6000", R"(outlets:
  - name: drain
    type: plane
    point: [0, 0, 0.01]
    normal: [0, 0, 1]
)");
  scene = std::regex_replace(scene, std::regex("walls:\n(  .*\n|    .*\n)*"), "");
  write("pour.yaml", scene);
  const Result r = cgdem("run pour.yaml --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Frame> frames = read_frames(dir / "pour.h5");
  const auto count = series(dir / "pour.h5", "outlet_drain_count");
  const auto mass = series(dir / "pour.h5", "outlet_drain_mass");
  const auto inserted = series(dir / "pour.h5", "inlet_poured_count");
  ASSERT_EQ(count.size(), frames.size());
  std::map<double, std::pair<double, double>> last_seen; // id -> (z, mass) in the previous frame
  std::set<double> removed;
  double removed_mass = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const Frame& fr = frames[k];
    std::map<double, std::pair<double, double>> now;
    for (std::size_t i = 0; i < fr.id.size(); ++i) {
      now[fr.id[i]] = {fr.x[3 * i + 2], fr.m[i]};
      EXPECT_GE(fr.x[3 * i + 2], 0.01)
          << "particle " << fr.id[i] << " below the outlet kept at t = " << fr.time;
      EXPECT_EQ(removed.count(fr.id[i]), 0u) << "removed id " << fr.id[i] << " reappeared";
    }
    // Every particle of the previous frame is either still here or was removed by the outlet; a removed
    // one had not crossed before (it was above the plane then) and moves at most a few mm per event.
    for (const auto& [id, zm] : last_seen) {
      if (now.count(id)) continue;
      removed.insert(id);
      removed_mass += zm.second;
      EXPECT_LT(zm.first - 0.01, 0.003) << "particle " << id << " vanished far above the outlet";
    }
    EXPECT_EQ(count[k], double(removed.size())) << "t = " << fr.time;
    EXPECT_NEAR(mass[k], removed_mass, 1e-15 + 1e-12 * removed_mass);
    EXPECT_EQ(double(fr.id.size()), inserted[k] - count[k]);
    last_seen = std::move(now);
  }
  EXPECT_GT(removed.size(), 50u);
}

TEST_F(CliTest, ChangingParticleCountKeepsTheHdf5AndXdmfContract) {
  std::string scene = pour_scene("rate: 6000", kBoxDrain);
  write("pour.yaml", scene);
  const Result r = cgdem("run pour.yaml --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  hid_t f = H5Fopen((dir / "pour.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const int frames = frame_count(f);
  std::set<hsize_t> sizes;
  double largest_id = 0;
  std::set<double> ever;
  for (int k = 0; k < frames; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "/frames/%06d", k);
    const auto ids = read_doubles(f, std::string(name) + "/id");
    const hsize_t n = ids.size();
    sizes.insert(n);
    for (const char* ds : {"radius", "mass"})
      EXPECT_EQ(shape(f, std::string(name) + "/" + ds), std::vector<hsize_t>{n}) << ds;
    for (const char* ds : {"position", "velocity"})
      EXPECT_EQ(shape(f, std::string(name) + "/" + ds), (std::vector<hsize_t>{n, 3})) << ds;
    // Rows in id order, ids unique; a new id is larger than every id seen before (never reused).
    EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
    EXPECT_EQ(std::set<double>(ids.begin(), ids.end()).size(), ids.size());
    double newest = largest_id;
    for (double id : ids)
      if (!ever.count(id)) {
        EXPECT_GT(id, largest_id);
        newest = std::max(newest, id);
      }
    ever.insert(ids.begin(), ids.end());
    largest_id = newest;
  }
  EXPECT_GE(sizes.size(), 5u) << "the particle count should change from frame to frame";
  // The XDMF names each frame with its own particle count.
  const int checked = expect_xdmf_matches(f, dir / "pour.xdmf", "pour");
  EXPECT_GE(checked, 2 * frames);
  H5Fclose(f);
  EXPECT_GT(series(dir / "pour.h5", "outlet_drain_count").back(), 0);
}

TEST_F(CliTest, RestartContinuesInsertionsAndRemovalsBitwise) {
  const std::string scene = pour_scene("rate: 6000", kBoxDrain);
  write("pour.yaml", scene);
  ASSERT_EQ(cgdem("run pour.yaml --quiet --threads 1 --out full.h5").code, 0);
  ASSERT_EQ(
      cgdem("run pour.yaml --quiet --threads 1 --out mid.h5 --set time.end=0.02 --checkpoint-every 0.02")
          .code,
      0);
  const Result r = cgdem("run pour.yaml --quiet --threads 2 --out cont.h5 --restart mid.checkpoint.h5");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Frame> a = read_frames(dir / "full.h5");
  const std::vector<Frame> b = read_frames(dir / "cont.h5");
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  EXPECT_EQ(a.back().time, b.back().time);
  EXPECT_TRUE(a.back().id == b.back().id);
  EXPECT_TRUE(a.back().x == b.back().x) << "positions differ after restart"; // bitwise
  EXPECT_EQ(series(dir / "full.h5", "outlet_drain_mass").back(),
            series(dir / "cont.h5", "outlet_drain_mass").back());
}

TEST_F(CliTest, InletBoxTooSmallForItsRateIsReported) {
  // 400 particles due in 4 ms into a 1 mm thin box: most cannot be placed, and the run says so.
  std::string scene = pour_scene("rate: 100000");
  scene = std::regex_replace(scene, std::regex("lo: \\[0, 0, 0.024\\]"), "lo: [0, 0, 0.0285]");
  write("pour.yaml", scene);
  const Result r = cgdem("run pour.yaml --quiet --set time.end=0.004");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: inlet of group 'poured' placed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("enlarge the box"), std::string::npos) << r.err;
}

// The recipes of docs/recipes.md start and write their results (their full runs make the committed figures).
TEST_F(CliTest, RecipeScenesRun) {
  for (const char* scene : {"column_collapse", "hopper_discharge", "drum_dynamic_angle", "pour_heap"}) {
    SCOPED_TRACE(scene);
    const std::string path = std::string(CGDEM_SOURCE_DIR) + "/scenes/" + scene + ".yaml";
    const Result r = cgdem("run '" + path + "' --quiet --set time.end=0.02 --out recipe.h5");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(dir / "recipe.h5"));
  }
}
