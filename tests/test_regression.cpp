// Regression reference: a few scenes that together run every part of the engine a restructuring could
// disturb (each kind of normal law, adhesion, rolling resistance, parameter and direct scaling laws, walls,
// list rebuilds and reorders, both force passes) must reproduce, bit for bit, the trajectories recorded in
// tests/regression/reference.txt. A change that is meant to alter results (new physics, another summation
// order) regenerates the file on purpose:
//
//   CGDEM_UPDATE_REGRESSION=1 build/cgdem_tests --gtest_filter='Regression.*'
//
// and says in its commit why the trajectories moved. The digests hold for one compiler and one CGDEM_ARCH
// (floating-point contraction differs between targets); the test prints the build it expects.
#include <cinttypes>
#include <cstring>
#include <map>
#include "tests/bed_scene.hpp"
#include "tests/cli_support.hpp"

namespace cgdem::testing {
namespace {

const fs::path kReference = fs::path(CGDEM_SOURCE_DIR) / "tests" / "regression" / "reference.txt";

struct Case {
  const char* name;
  std::string overrides; // --set arguments on top of kBedScene
};

std::vector<Case> cases() {
  const std::string adhesive = " --set contact.wall_adhesion=false";
  return {
      {"hertz_mindlin", ""},
      {"hertz_mindlin_pairs_pass", " --set 'neighbour={force_pass: pairs}'"},
      {"jkr_rolling_chen_elliott", " --set contact.normal=jkr --set contact.rolling=spring_dashpot --set "
                                   "materials.beads.surface_energy=0.05"
                                   " --set materials.beads.rolling_friction=0.1 --set "
                                   "'groups.0.coarse_grain={law: chen_elliott, factor: 2}'"
                                   " --set time.step=5.0e-6" +
                                       adhesive},
      {"dmt_bond", " --set contact.adhesion=dmt --set materials.beads.surface_energy=0.05"
                   " --set 'groups.0.coarse_grain={law: bond, factor: 2}'" +
                       adhesive},
      {"eepa_thakur",
       " --set contact.normal=eepa --set 'materials.beads.eepa={k1: 80, k2: 300, k_adh: 40, f0: -1.0e-5}'"
       " --set 'groups.0.coarse_grain={law: thakur, factor: 2}'" +
           adhesive},
      {"capillary_hu_method2",
       " --set contact.adhesion=capillary --set contact.tangential=none"
       " --set 'materials.beads.capillary={surface_tension: 0.02, liquid_fraction: 0.001}'"
       " --set 'groups.0.coarse_grain={law: hu_method2, factor: 2}' --set time.step=5.0e-6" +
           adhesive},
      {"linear_constant_torque",
       " --set contact.normal=linear --set 'materials.beads.spring={normal: 500}'"
       " --set contact.rolling=constant_torque --set materials.beads.rolling_friction=0.1"},
  };
}

// FNV-1a over the bytes of the doubles: equal digests mean equal bits (up to a 2^-64 accident).
std::uint64_t digest(const std::vector<double>& values) {
  std::uint64_t h = 1469598103934665603ull;
  for (double v : values) {
    unsigned char bytes[sizeof v];
    std::memcpy(bytes, &v, sizeof v);
    for (unsigned char b : bytes)
      h = (h ^ b) * 1099511628211ull;
  }
  return h;
}

struct Record {
  std::uint64_t digest = 0;
  double mean_height = 0, kinetic = 0; // readable summaries for a mismatch's message
};

std::map<std::string, Record> read_reference() {
  std::map<std::string, Record> refs;
  std::ifstream in(kReference);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string name, hex;
    Record r;
    s >> name >> hex >> r.mean_height >> r.kinetic;
    r.digest = std::stoull(hex, nullptr, 16);
    refs[name] = r;
  }
  return refs;
}

class Regression : public CliTest {};

TEST_F(Regression, ScenesReproduceTheirReferenceTrajectoriesBitwise) {
  write("bed.yaml", kBedScene);
  const bool update = std::getenv("CGDEM_UPDATE_REGRESSION") != nullptr;
  const std::map<std::string, Record> refs = update ? std::map<std::string, Record>{} : read_reference();
  std::ostringstream table;
  table << "# name  digest(position, velocity, angular_velocity of the last frame, id order)  mean z (m)  "
           "kinetic energy (J)\n# build: CGDEM_ARCH=" CGDEM_ARCH "\n";
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Result r = cgdem("run bed.yaml --quiet --threads 2 --out run.h5" + c.overrides);
    ASSERT_EQ(r.code, 0) << r.err;
    hid_t f = H5Fopen((dir / "run.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const std::string frame = last_frame(f);
    std::vector<double> state;
    for (const char* field : {"position", "velocity", "angular_velocity"}) {
      const auto v = read_doubles(f, frame + "/" + field);
      state.insert(state.end(), v.begin(), v.end());
    }
    const auto z = read_doubles(f, frame + "/position"), v = read_doubles(f, frame + "/velocity"),
               m = read_doubles(f, frame + "/mass");
    H5Fclose(f);
    ASSERT_EQ(state.size(), 90000u);
    Record now;
    now.digest = digest(state);
    for (std::size_t i = 0; i < m.size(); ++i) {
      now.mean_height += z[3 * i + 2] / double(m.size());
      now.kinetic +=
          0.5 * m[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
    }
    char line[160];
    std::snprintf(line, sizeof line, "%s %016" PRIx64 " %.17g %.17g\n", c.name, now.digest, now.mean_height,
                  now.kinetic);
    table << line;
    if (update) continue;
    const auto it = refs.find(c.name);
    ASSERT_NE(it, refs.end()) << "no reference for " << c.name << " in " << kReference
                              << "; regenerate with CGDEM_UPDATE_REGRESSION=1";
    EXPECT_EQ(now.digest, it->second.digest)
        << c.name << " left its reference trajectory: mean height " << now.mean_height << " m (reference "
        << it->second.mean_height << "), kinetic energy " << now.kinetic << " J (reference "
        << it->second.kinetic
        << "). Intended? Regenerate with CGDEM_UPDATE_REGRESSION=1 and say why in the commit.";
  }
  if (update) {
    std::ofstream(kReference) << table.str();
    std::printf("wrote %s\n", kReference.c_str());
  }
}

} // namespace
} // namespace cgdem::testing
