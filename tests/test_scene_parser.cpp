// Scene parser: accepted layout, --set overrides, and one message per kind of bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "drivers/particle_generation.hpp"
#include "drivers/scene_parser.hpp"
#include "setup/materials.hpp"
#include "models/component_lists.hpp"

using namespace cgdem;

namespace {

const std::string kBase = R"(description: test scene
domain:
  lo: [0, 0, 0]
  hi: [0.02, 0.02, 0.04]
  periodic: [true, true, false]
gravity: [0, 0, -9.81]
materials:
  glass:
    density: 2500
    youngs_modulus: 5e6
    poisson_ratio: 0.3
    restitution: 0.5
    friction: 0.5
    rolling_friction: 0.1
    capillary: {surface_tension: 0.072, contact_angle: 30, liquid_fraction: 0.004}
  steel:
    density: 7800
    youngs_modulus: 2e8
contact:
  normal: hertz
  rolling: constant_torque
pairs:
  - materials: [glass, steel]
    friction: 0.3
groups:
  - name: beads
    material: glass
    count: 100
    size: {radius: 0.0005}
    placement:
      type: random_box
      lo: [0, 0, 0]
      hi: [0.02, 0.02, 0.02]
      seed: 7
    velocity: [0, 0, -0.1]
  - name: fines
    material: glass
    count: 50
    size: {distribution: uniform, min: 0.0002, max: 0.0003}
    placement: {type: lattice, lo: [0, 0, 0.025], hi: [0.02, 0.02, 0.04]}
walls:
  - name: floor
    type: plane
    material: steel
    point: [0, 0, 0]
    normal: [0, 0, 2]
  - name: drum
    type: cylinder
    material: steel
    point: [0.01, 0.01, 0]
    axis: [0, 0, 1]
    radius: 0.009
    length: 0.04
    motion:
      velocity: [0, 0, 0.05]
      rpm: 60
      start: 0.1
time:
  end: 0.5
  step: auto
output:
  every: 0.05
analyses:
  - type: packing_fraction
    region: [0, 0, 0, 0.02, 0.02, 0.01]
)";

// 1-based line of the first line containing `needle`.
int line_of(const std::string& text, const std::string& needle) {
  const auto pos = text.find(needle);
  EXPECT_NE(pos, std::string::npos) << needle;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n'));
}

std::string replaced(const std::string& text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  std::string out = text;
  out.replace(pos, from.size(), to);
  return out;
}

// The error message of parsing `text`, or "" when it parses.
std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    parse_scene_text(text, "scene.yaml", overrides);
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    return msg;
  }
  return "";
}

// Expects "<scene.yaml>:<line>: <key_path>: ..." containing `what` and `fix`.
void expect_error(const std::string& text, int line, const std::string& key_path, const std::string& what,
                  const std::string& fix) {
  const std::string msg = error_of(text);
  const std::string head = "scene.yaml:" + std::to_string(line) + ": " + key_path + ": ";
  EXPECT_EQ(msg.rfind(head, 0), 0u) << "message: " << msg << "\nexpected start: " << head;
  EXPECT_NE(msg.find(what), std::string::npos) << msg;
  EXPECT_NE(msg.find("; "), std::string::npos) << msg;
  EXPECT_NE(msg.find(fix), std::string::npos) << msg;
}

} // namespace

TEST(SceneParser, ParsesTheFullLayout) {
  const Scene s = parse_scene_text(kBase, "scene.yaml", {});
  EXPECT_EQ(s.source_file, "scene.yaml");
  EXPECT_DOUBLE_EQ(s.domain.hi[2], 0.04);
  EXPECT_TRUE(s.domain.periodic[0]);
  EXPECT_FALSE(s.domain.periodic[2]);
  ASSERT_EQ(s.materials.size(), 2u);
  const MaterialSpec& glass = s.materials[static_cast<size_t>(s.material_index("glass"))];
  EXPECT_DOUBLE_EQ(glass.youngs_modulus, 5e6);
  EXPECT_DOUBLE_EQ(glass.rolling_friction, 0.1);
  EXPECT_NEAR(glass.law_parameter("capillary.contact_angle", 0), M_PI / 6, 1e-12); // degrees -> radians
  // min_separation not given: the component's declared default (1e-6 m) reaches the pair.
  EXPECT_EQ(glass.law_parameters.count("capillary.min_separation"), 0u);
  EXPECT_DOUBLE_EQ(mix_pair(glass, glass, true, s.contact).min_separation, 1e-6);
  EXPECT_EQ(s.contact.normal, "hertz");
  EXPECT_EQ(s.contact.rolling, "constant_torque");
  ASSERT_EQ(s.pair_overrides.size(), 1u);
  EXPECT_DOUBLE_EQ(s.pair_overrides[0].friction, 0.3);
  EXPECT_DOUBLE_EQ(s.pair_overrides[0].restitution, -1);
  ASSERT_EQ(s.groups.size(), 2u);
  EXPECT_EQ(s.groups[0].count, 100);
  EXPECT_EQ(s.groups[0].placement.kind, "random_box");
  EXPECT_EQ(s.groups[0].placement.seed, 7u);
  EXPECT_EQ(s.groups[1].placement.seed, 2u); // default: group index + 1
  EXPECT_EQ(s.groups[1].size.distribution, "uniform");
  EXPECT_EQ(s.groups[0].source_location, "scene.yaml:" + std::to_string(line_of(kBase, "- name: beads")));
  ASSERT_EQ(s.walls.size(), 2u);
  EXPECT_DOUBLE_EQ(s.walls[0].normal[2], 1.0); // normalised
  EXPECT_NEAR(s.walls[1].angular_velocity, 2 * M_PI, 1e-12);
  EXPECT_DOUBLE_EQ(s.walls[1].motion_start, 0.1);
  EXPECT_GT(s.walls[1].motion_stop, 1e299);
  EXPECT_DOUBLE_EQ(s.time.step, 0);
  EXPECT_DOUBLE_EQ(s.output.every, 0.05);
  ASSERT_EQ(s.analyses.size(), 1u);
  EXPECT_EQ(s.analyses[0].name, "packing_fraction");
  EXPECT_EQ(s.analyses[0].params.at("region"), "[0, 0, 0, 0.02, 0.02, 0.01]");
  // The resolved YAML parses to the same scene.
  const Scene again = parse_scene_text(s.resolved_yaml, "resolved.yaml", {});
  EXPECT_EQ(again.groups[1].size.max_radius, s.groups[1].size.max_radius);
  EXPECT_EQ(again.walls[1].angular_velocity, s.walls[1].angular_velocity);
}

TEST(SceneParser, UnknownKeySuggestsClosest) {
  const std::string text = replaced(kBase, "    youngs_modulus: 5e6", "    youngs_modulos: 5e6");
  expect_error(text, line_of(text, "youngs_modulos"), "materials.glass.youngs_modulos",
               "unknown key 'youngs_modulos'", "did you mean 'youngs_modulus'?");
  const std::string top = replaced(kBase, "gravity:", "gravty:");
  expect_error(top, line_of(top, "gravty"), "gravty", "unknown key 'gravty'", "did you mean 'gravity'?");
  // Nothing close: the valid keys are listed.
  const std::string far = replaced(kBase, "  every: 0.05", "  zzzzzzzzzz: 1");
  expect_error(far, line_of(far, "zzzz"), "output.zzzzzzzzzz", "unknown key",
               "valid keys here: every, fields, file");
}

TEST(SceneParser, EditDistance) {
  EXPECT_EQ(edit_distance("youngs_modulos", "youngs_modulus"), 1u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
}

TEST(SceneParser, WrongType) {
  const std::string text = replaced(kBase, "density: 2500", "density: heavy");
  expect_error(text, line_of(text, "heavy"), "materials.glass.density", "expected a number, got 'heavy'",
               "plain number");
  const std::string t2 = replaced(kBase, "gravity: [0, 0, -9.81]", "gravity: [0, -9.81]");
  expect_error(t2, line_of(t2, "gravity"), "gravity", "expected a list of three numbers", "[x, y, z]");
  const std::string t3 = replaced(kBase, "count: 100", "count: 10.5");
  expect_error(t3, line_of(t3, "count: 10.5"), "groups.0.count", "expected a whole number", "integer");
  const std::string t4 = replaced(kBase, "periodic: [true, true, false]", "periodic: [true, maybe, false]");
  expect_error(t4, line_of(t4, "periodic"), "domain.periodic.1", "expected true or false", "true or false");
}

TEST(SceneParser, MissingRequiredKey) {
  const std::string text = replaced(kBase, "    material: glass\n    count: 100", "    count: 100");
  expect_error(text, line_of(text, "- name: beads"), "groups.0.material", "missing required key 'material'",
               "glass, steel");
  const std::string t2 = replaced(kBase, "  end: 0.5\n", "");
  expect_error(t2, line_of(t2, "time:"), "time.end", "missing required key 'end'", "end time");
}

TEST(SceneParser, RadiusAndDensityMustBePositive) {
  const std::string t1 = replaced(kBase, "{radius: 0.0005}", "{radius: 0}");
  expect_error(t1, line_of(t1, "{radius: 0}"), "groups.0.size.radius", "must be > 0", "positive radius");
  const std::string t2 = replaced(kBase, "min: 0.0002", "min: -0.0002");
  expect_error(t2, line_of(t2, "min: -0.0002"), "groups.1.size.min", "must be > 0", "positive radius");
  const std::string t3 = replaced(kBase, "density: 7800", "density: -7800");
  expect_error(t3, line_of(t3, "-7800"), "materials.steel.density", "density must be > 0", "kg/m^3");
}

TEST(SceneParser, MaterialRanges) {
  const std::string p1 = replaced(kBase, "poisson_ratio: 0.3", "poisson_ratio: 0.5");
  expect_error(p1, line_of(p1, "poisson_ratio"), "materials.glass.poisson_ratio", "outside (-1, 0.5)",
               "between -1 and 0.5");
  const std::string p2 = replaced(kBase, "poisson_ratio: 0.3", "poisson_ratio: -1");
  expect_error(p2, line_of(p2, "poisson_ratio"), "materials.glass.poisson_ratio", "outside (-1, 0.5)",
               "-1 and 0.5");
  const std::string e1 = replaced(kBase, "restitution: 0.5", "restitution: 0");
  expect_error(e1, line_of(e1, "restitution"), "materials.glass.restitution", "outside (0, 1]", "at most 1");
  const std::string e2 = replaced(kBase, "restitution: 0.5", "restitution: 1.2");
  expect_error(e2, line_of(e2, "restitution"), "materials.glass.restitution", "outside (0, 1]", "at most 1");
  EXPECT_EQ(error_of(replaced(kBase, "restitution: 0.5", "restitution: 1")), "");
  const std::string f1 = replaced(kBase, "friction: 0.5", "friction: -0.1");
  expect_error(f1, line_of(f1, "friction: -0.1"), "materials.glass.friction", "must be >= 0", "friction");
  const std::string f2 = replaced(kBase, "friction: 0.3", "friction: -0.3");
  expect_error(f2, line_of(f2, "friction: -0.3"), "pairs.0.friction", "must be >= 0", "friction");
}

TEST(SceneParser, UnknownLawsListValidOnes) {
  const std::string t1 = replaced(kBase, "normal: hertz", "normal: hertzz");
  expect_error(t1, line_of(t1, "hertzz"), "contact.normal", "unknown normal law 'hertzz'",
               "use one of hertz, linear, jkr, eepa (did you mean 'hertz'?)");
  const std::string t2 = replaced(kBase, "rolling: constant_torque", "rolling: viscous");
  expect_error(t2, line_of(t2, "viscous"), "contact.rolling", "unknown rolling law 'viscous'",
               "none, constant_torque, spring_dashpot");
  const std::string t3 = replaced(kBase, "type: random_box", "type: random_sphere");
  expect_error(t3, line_of(t3, "random_sphere"), "groups.0.placement.type", "unknown placement type",
               "lattice, random_box, random_cylinder, file");
}

TEST(SceneParser, UnknownMaterialName) {
  const std::string t1 =
      replaced(kBase, "    material: glass\n    count: 100", "    material: glas\n    count: 100");
  expect_error(t1, line_of(t1, "material: glas\n"), "groups.0.material", "material 'glas' is not defined",
               "did you mean 'glass'?");
  const std::string t2 = replaced(kBase, "[glass, steel]", "[glass, iron]");
  expect_error(t2, line_of(t2, "[glass, iron]"), "pairs.0.materials.1", "material 'iron' is not defined",
               "define it under materials");
}

TEST(SceneParser, DomainAndTime) {
  const std::string t1 =
      replaced(kBase, "hi: [0.02, 0.02, 0.04]\n  periodic", "hi: [0.02, 0, 0.04]\n  periodic");
  expect_error(t1, line_of(t1, "hi: [0.02, 0, 0.04]"), "domain.hi", "domain hi y = 0 is not above lo y = 0",
               "larger than lo");
  const std::string t2 = replaced(kBase, "end: 0.5", "end: 0");
  expect_error(t2, line_of(t2, "end: 0"), "time.end", "time.end must be > 0", "end time");
  const std::string t3 = replaced(kBase, "step: auto", "step: fast");
  expect_error(t3, line_of(t3, "step: fast"), "time.step", "expected 'auto' or a number", "step: auto");
}

TEST(SceneParser, CoarseGrain) {
  const std::string ok =
      replaced(kBase, "    velocity: [0, 0, -0.1]",
               "    velocity: [0, 0, -0.1]\n    coarse_grain: {law: chen_elliott, factor: 2}");
  // Both groups must share the law.
  expect_error(ok, line_of(ok, "- name: fines"), "groups.1.coarse_grain.law", "differs from group 0",
               "one scaling law");
  const std::string t1 = replaced(ok, "factor: 2", "factor: 0.5");
  expect_error(t1, line_of(t1, "factor: 0.5"), "groups.0.coarse_grain.factor", "is below 1", ">= 1");
  const std::string t2 = replaced(ok, "chen_elliott", "chen");
  expect_error(t2, line_of(t2, "law: chen"), "groups.0.coarse_grain.law", "unknown coarse_grain law 'chen'",
               "none, chen_elliott, bond, cohesion, thakur, thakur_f0_linear, thakur_f0_cubic, hu_method1, "
               "hu_method2, hu_method3, sakai");
  const Scene s =
      parse_scene_text(ok, "scene.yaml", {"groups.1.coarse_grain={law: chen_elliott, factor: 2}"});
  EXPECT_EQ(s.groups[0].coarse_grain.law, "chen_elliott");
  EXPECT_DOUBLE_EQ(s.groups[1].coarse_grain.factor, 2);
}

TEST(SceneParser, KeysThatDoNotApply) {
  const std::string t1 = replaced(kBase, "    normal: [0, 0, 2]", "    normal: [0, 0, 2]\n    length: 0.01");
  expect_error(t1, line_of(t1, "length: 0.01"), "walls.0.length", "does not apply to a plane wall",
               "remove it");
  const std::string t2 = replaced(kBase, "{radius: 0.0005}", "{radius: 0.0005, std: 0.0001}");
  expect_error(t2, line_of(t2, "std: 0.0001"), "groups.0.size.std", "does not apply to a mono distribution",
               "remove it");
}

TEST(SceneParser, LawRequirementsOnMaterials) {
  const std::string t1 = replaced(kBase, "normal: hertz", "normal: linear");
  expect_error(t1, line_of(t1, "  glass:"), "materials.glass.spring", "no spring.normal", "spring: {normal:");
  const std::string t2 = replaced(kBase, "normal: hertz", "normal: jkr\n  adhesion: dmt");
  expect_error(t2, line_of(t2, "adhesion: dmt"), "contact.adhesion", "cannot be combined", "adhesion: none");
}

TEST(SceneParser, SyntaxErrorHasLine) {
  const std::string text = replaced(kBase, "  end: 0.5", "  end: [0.5");
  const std::string msg = error_of(text);
  EXPECT_NE(msg.find("YAML syntax error"), std::string::npos) << msg;
  EXPECT_EQ(msg.rfind("scene.yaml:", 0), 0u) << msg;
}

TEST(SceneParser, OverridesNestedKeysAndListItems) {
  const Scene s = parse_scene_text(
      kBase, "scene.yaml",
      {"materials.glass.youngs_modulus=1e7", "groups.0.count=500", "walls.1.motion.velocity=[0,0,0.01]",
       "groups.1.name=small", "contact.normal=linear", "materials.glass.spring={normal: 100}",
       "materials.steel.spring={normal: 1000}", "stop={kinetic_energy_below: 1e-9}"});
  EXPECT_DOUBLE_EQ(s.materials[0].youngs_modulus, 1e7);
  EXPECT_EQ(s.groups[0].count, 500);
  EXPECT_DOUBLE_EQ(s.walls[1].velocity[2], 0.01);
  EXPECT_EQ(s.groups[1].name, "small");
  EXPECT_EQ(s.contact.normal, "linear");
  EXPECT_DOUBLE_EQ(s.materials[1].law_parameter("spring.normal", 0), 1000);
  EXPECT_DOUBLE_EQ(s.stop.kinetic_energy_below, 1e-9);
  // The resolved YAML carries the overrides.
  EXPECT_NE(s.resolved_yaml.find("500"), std::string::npos);
  const Scene again = parse_scene_text(s.resolved_yaml, "resolved.yaml", {});
  EXPECT_EQ(again.groups[0].count, 500);
  EXPECT_DOUBLE_EQ(again.materials[0].youngs_modulus, 1e7);
}

TEST(SceneParser, OverrideErrors) {
  // A path that does not exist.
  std::string msg = error_of(kBase, {"materials.glas.density=1"});
  EXPECT_EQ(msg.rfind("scene.yaml:--set 'materials.glas.density=1': materials.glas.density: ", 0), 0u) << msg;
  EXPECT_NE(msg.find("'materials.glas' does not exist"), std::string::npos) << msg;
  EXPECT_NE(msg.find("did you mean 'glass'?"), std::string::npos) << msg;
  msg = error_of(kBase, {"groups.5.count=1"});
  EXPECT_NE(msg.find("'groups.5' does not exist"), std::string::npos) << msg;
  EXPECT_NE(msg.find("use an index from 0 to 1"), std::string::npos) << msg;
  msg = error_of(kBase, {"time.end.x=1"});
  EXPECT_NE(msg.find("single value"), std::string::npos) << msg;
  msg = error_of(kBase, {"groups.0.count"});
  EXPECT_NE(msg.find("key.path=value"), std::string::npos) << msg;
  // A new leaf goes through key validation, and the error names the override instead of a line.
  msg = error_of(kBase, {"materials.glass.youngs_modulos=1e7"});
  EXPECT_EQ(
      msg,
      "scene.yaml:--set 'materials.glass.youngs_modulos=1e7': materials.glass.youngs_modulos: unknown key "
      "'youngs_modulos'; did you mean 'youngs_modulus'?");
  // A bad value set by an override.
  msg = error_of(kBase, {"groups.0.count=-5"});
  EXPECT_EQ(msg.rfind("scene.yaml:--set 'groups.0.count=-5': groups.0.count: count must be > 0", 0), 0u)
      << msg;
  // Errors elsewhere keep their line.
  msg = error_of(replaced(kBase, "end: 0.5", "end: -1"), {"groups.0.count=5"});
  EXPECT_EQ(msg.rfind("scene.yaml:" + std::to_string(line_of(kBase, "end: 0.5")) + ": time.end:", 0), 0u)
      << msg;
}

TEST(SceneParser, RelativeParticleFileIsResolvedAgainstTheSceneDirectory) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "cgdem_scene_parser_test";
  fs::create_directories(dir / "data");
  {
    std::ofstream csv(dir / "data" / "p.csv");
    csv << "# two particles\nid,x,y,z,radius\n10,0.001,0.001,0.001,0.0005\n11,0.003,0.001,0.001,0.0005\n";
    std::ofstream sc(dir / "s.yaml");
    sc << "domain: {lo: [0, 0, 0], hi: [0.01, 0.01, 0.01]}\n"
          "materials: {m: {density: 1000, youngs_modulus: 1e6}}\n"
          "groups:\n  - material: m\n    placement: {type: file, file: data/p.csv}\n"
          "time: {end: 1}\n";
  }
  const Scene s = parse_scene_file((dir / "s.yaml").string(), {});
  EXPECT_EQ(fs::path(s.groups[0].placement.file), (dir / "data" / "p.csv").lexically_normal());
  const ParticleSet ps = generate_particles(s);
  EXPECT_EQ(ps.size(), 2u);
  EXPECT_EQ(ps.id[1], 11);
  // A missing file is reported with its path and line.
  const std::string msg =
      error_of(replaced(kBase, "type: random_box", "type: file\n      file: /nonexistent/p.csv"));
  EXPECT_NE(msg.find("does not apply to placement type file"), std::string::npos) << msg; // lo/hi given
  std::string t =
      "domain: {lo: [0, 0, 0], hi: [1, 1, 1]}\nmaterials: {m: {density: 1, youngs_modulus: 1}}\n"
      "groups:\n  - material: m\n    placement: {type: file, file: /nonexistent/p.csv}\ntime: {end: 1}\n";
  expect_error(t, 5, "groups.0.placement.file", "cannot read particle file '/nonexistent/p.csv'",
               "check the path");
  fs::remove_all(dir);
}

// Every example scene and every validation case of sweeps/ parses, generates its particles, and passes
// the particle check.
TEST(SceneParser, ExampleScenesAreValid) {
  namespace fs = std::filesystem;
  int n = 0;
  for (const char* sub : {"scenes", "sweeps"}) {
    const fs::path dir = fs::path(CGDEM_SOURCE_DIR) / sub;
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.path().extension() != ".yaml") continue;
      SCOPED_TRACE(entry.path().string());
      ++n;
      try {
        const Scene s = parse_scene_file(entry.path().string(), {});
        const ParticleSet ps = generate_particles(s);
        EXPECT_GT(ps.size(), 0u);
        check_particles(s, ps);
      } catch (const SceneError& e) {
        ADD_FAILURE() << e.what();
      }
    }
  }
  EXPECT_GE(n, 15);
}

// Hu's simplified JKR is the full JKR law with contact loss: the old adhesion name points there.
TEST(SceneParser, JkrSimplifiedPointsToContactLoss) {
  const std::string t = replaced(kBase, "normal: hertz", "normal: hertz\n  adhesion: jkr_simplified");
  expect_error(t, line_of(t, "adhesion: jkr_simplified"), "contact.adhesion", "Hu's JKR",
               "normal: jkr with jkr_separation: contact_loss");
  const Scene s = parse_scene_text(
      replaced(kBase, "normal: hertz", "normal: jkr\n  jkr_separation: contact_loss"), "scene.yaml");
  EXPECT_EQ(s.contact.jkr_separation, "contact_loss");
}

// A parameter law does not scale liquid bridges: refused at the law's key, pointing to the direct laws.
TEST(SceneParser, CapillaryWithParameterLawIsRefused) {
  const std::string capillary =
      replaced(kBase, "normal: hertz", "normal: hertz\n  adhesion: capillary\n  wall_adhesion: false");
  EXPECT_EQ(error_of(capillary), ""); // the steel walls need no liquid without wall adhesion
  for (const char* law : {"chen_elliott", "bond", "cohesion"}) {
    const std::string t = replaced(
        replaced(capillary, "    velocity: [0, 0, -0.1]",
                 std::string("    velocity: [0, 0, -0.1]\n    coarse_grain: {law: ") + law + ", factor: 2}"),
        "    placement: {type: lattice",
        std::string("    coarse_grain: {law: ") + law + ", factor: 2}\n    placement: {type: lattice");
    expect_error(t, line_of(t, std::string("law: ") + law), "groups.0.coarse_grain.law",
                 "does not scale capillary bridges", "hu_method1, hu_method2, hu_method3 or sakai");
  }
  const std::string direct =
      replaced(replaced(capillary, "    velocity: [0, 0, -0.1]",
                        "    velocity: [0, 0, -0.1]\n    coarse_grain: {law: hu_method1, factor: 2}"),
               "    placement: {type: lattice",
               "    coarse_grain: {law: hu_method1, factor: 2}\n    placement: {type: lattice");
  EXPECT_EQ(error_of(direct), "");
}

TEST(SceneParser, TorquePowerDampingAndLeverArm) {
  const std::string hu = replaced(
      replaced(kBase, "    velocity: [0, 0, -0.1]",
               "    velocity: [0, 0, -0.1]\n    coarse_grain: {law: hu_method1, factor: 2, torque_power: 3}"),
      "    placement: {type: lattice",
      "    coarse_grain: {law: hu_method1, factor: 2, torque_power: 3}\n    placement: {type: lattice");
  const Scene s = parse_scene_text(hu, "scene.yaml");
  EXPECT_EQ(s.groups[0].coarse_grain.torque_power, 3);
  const std::string t1 = replaced(hu, "torque_power: 3", "torque_power: 4");
  expect_error(t1, line_of(t1, "torque_power: 4"), "groups.0.coarse_grain.torque_power", "is not 2 or 3",
               "rotational similarity");
  const std::string t2 = replaced(kBase, "normal: hertz", "normal: hertz\n  damping: tsuji");
  expect_error(t2, line_of(t2, "damping: tsuji"), "contact.damping", "unknown damping rule", "beta_formula");
  const Scene d = parse_scene_text(replaced(kBase, "normal: hertz", "normal: hertz\n  damping: beta_formula"),
                                   "scene.yaml");
  EXPECT_EQ(d.contact.damping, "beta_formula");
  EXPECT_EQ(parse_scene_text(kBase, "scene.yaml").contact.damping, "restitution");
  EXPECT_EQ(parse_scene_text(kBase, "scene.yaml").contact.lever_arm, "auto");
  // The impact speed (in sticking velocities) at which adhesive pairs rebound with e: above 1 only.
  EXPECT_EQ(parse_scene_text(kBase, "scene.yaml").contact.restitution_speed_ratio, 0);
  const Scene r = parse_scene_text(
      replaced(kBase, "normal: hertz", "normal: jkr\n  restitution_speed_ratio: 20"), "scene.yaml");
  EXPECT_EQ(r.contact.restitution_speed_ratio, 20);
  const std::string t3 = replaced(kBase, "normal: hertz", "normal: jkr\n  restitution_speed_ratio: 0.5");
  expect_error(t3, line_of(t3, "restitution_speed_ratio: 0.5"), "contact.restitution_speed_ratio",
               "must be > 1", "sticking velocities");
}

TEST(SceneParser, SurfaceEnergyPowerOnlyOnLawsThatScaleGamma) {
  const auto with = [](const std::string& first, const std::string& second) {
    return replaced(replaced(kBase, "    velocity: [0, 0, -0.1]",
                             "    velocity: [0, 0, -0.1]\n    coarse_grain: " + first),
                    "    placement: {type: lattice",
                    "    coarse_grain: " + second + "\n    placement: {type: lattice");
  };
  const std::string p1 = "{law: chen_elliott, factor: 2, surface_energy_power: 1}";
  const Scene s = parse_scene_text(with(p1, p1), "scene.yaml");
  EXPECT_EQ(s.groups[0].coarse_grain.surface_energy_power, 1);
  EXPECT_EQ(s.groups[1].coarse_grain.surface_energy_power, 1);
  const std::string own = "{law: chen_elliott, factor: 2}";
  EXPECT_LT(parse_scene_text(with(own, own), "scene.yaml").groups[0].coarse_grain.surface_energy_power, 0);
  const std::string hu = "{law: hu_method1, factor: 2, surface_energy_power: 1}";
  const std::string t1 = with(hu, hu);
  expect_error(t1, line_of(t1, "law: hu_method1"), "groups.0.coarse_grain.surface_energy_power",
               "applies to the laws that scale the surface energy", "remove surface_energy_power");
  const std::string big = "{law: bond, factor: 2, surface_energy_power: 4}";
  const std::string t2 = with(big, big);
  expect_error(t2, line_of(t2, "law: bond"), "groups.0.coarse_grain.surface_energy_power", "is outside 0-3",
               "e.g. 1 to keep the pull-off force per cross-section");
  const std::string t3 = with(p1, own);
  expect_error(t3, line_of(t3, "- name: fines"), "groups.1.coarse_grain.surface_energy_power",
               "differs from group 0's", "one surface_energy_power for the whole scene");
}

TEST(SceneParser, BoundedPlatesConesInletsAndOutlets) {
  const std::string gate =
      "  - name: gate\n    type: plane\n    material: steel\n    point: [0.01, 0.01, 0.01]\n"
      "    normal: [1, 0, 0]\n    size: [0.005, 0.008]\n    edge: [0, 1, 0]\n";
  const std::string hopper =
      "  - name: hopper\n    type: cone\n    material: steel\n    point: [0.01, 0.01, 0.01]\n"
      "    axis: [0, 0, 1]\n    radius: 0.002\n    end_radius: 0.009\n    length: 0.01\n";
  const std::string inlet =
      "    placement:\n      type: inlet\n      lo: [0, 0, 0.03]\n      hi: [0.02, 0.02, 0.04]\n"
      "      mass_rate: 0.01\n      start: 0.1\n      every: 0.002\n";
  std::string t = replaced(kBase, "walls:\n", "walls:\n" + gate + hopper);
  t = replaced(t, "    placement: {type: lattice, lo: [0, 0, 0.025], hi: [0.02, 0.02, 0.04]}\n", inlet);
  t = replaced(
      t, "time:\n",
      "outlets:\n  - name: drain\n    type: plane\n    point: [0, 0, 0.001]\n"
      "    normal: [0, 0, 2]\n  - {name: bin, type: box, lo: [0, 0, 0], hi: [0.02, 0.02, 0.001]}\ntime:\n");
  const Scene s = parse_scene_text(t, "scene.yaml", {});
  ASSERT_EQ(s.walls.size(), 4u);
  EXPECT_TRUE(s.walls[0].bounded());
  EXPECT_DOUBLE_EQ(s.walls[0].size[1], 0.008);
  EXPECT_EQ(s.walls[1].type, "cone");
  EXPECT_DOUBLE_EQ(s.walls[1].end_radius, 0.009);
  EXPECT_EQ(s.groups[1].placement.kind, "inlet");
  EXPECT_DOUBLE_EQ(s.groups[1].placement.mass_rate, 0.01);
  EXPECT_DOUBLE_EQ(s.groups[1].placement.start, 0.1);
  ASSERT_EQ(s.outlets.size(), 2u);
  EXPECT_DOUBLE_EQ(s.outlets[0].normal[2], 1.0); // normalised
  EXPECT_EQ(s.outlets[1].type, "box");

  const std::string both = replaced(t, "      mass_rate: 0.01\n", "      mass_rate: 0.01\n      rate: 100\n");
  EXPECT_NE(error_of(both).find("both rate and mass_rate are given"), std::string::npos) << error_of(both);
  const std::string none = replaced(t, "      mass_rate: 0.01\n", "");
  EXPECT_NE(error_of(none).find("the inlet has no rate"), std::string::npos) << error_of(none);
  const std::string box_key =
      replaced(t, "    normal: [0, 0, 2]\n  - {name: bin", "    lo: [0, 0, 0]\n  - {name: bin");
  expect_error(box_key, line_of(box_key, "    lo: [0, 0, 0]\n  - {name: bin"), "outlets.0.lo",
               "does not apply to a plane outlet", "remove it");
  const std::string flat = replaced(t, "hi: [0.02, 0.02, 0.001]", "hi: [0.02, 0.02, 0]");
  EXPECT_NE(error_of(flat).find("is not above lo z"), std::string::npos) << error_of(flat);
  const std::string pinched =
      replaced(t, "    radius: 0.002\n    end_radius: 0.009\n", "    radius: 0\n    end_radius: 0\n");
  EXPECT_NE(error_of(pinched).find("both radii are 0"), std::string::npos) << error_of(pinched);
  const std::string cone_caps =
      replaced(t, "    end_radius: 0.009\n", "    end_radius: 0.009\n    caps: true\n");
  EXPECT_NE(error_of(cone_caps).find("does not apply to a cone wall"), std::string::npos)
      << error_of(cone_caps);
}

// Every material parameter a contact-law component declares (models/material_parameters.hpp) is a YAML
// key the parser accepts, in the component's block, converted to SI, and it reaches the pair table by
// its declared mixing rule; a value outside its declared range is refused naming the key. Driven by the
// declarations, so a new component's parameters are checked without editing this test.
TEST(SceneParser, EveryDeclaredComponentParameterIsParsedCheckedAndMixed) {
  int checked = 0;
  models::for_each_component([&](auto component) {
    using C = typename decltype(component)::type;
    models::for_each_material_parameter<C>([&](const char* block, const models::MaterialParameter& d) {
      SCOPED_TRACE(models::parameter_path(block, d));
      // A value inside the range, away from its ends: 0.3 of the way, or 1.5 x a one-sided bound.
      const double lo = std::isinf(d.lowest) ? d.highest - 2 : d.lowest,
                   hi = std::isinf(d.highest) ? lo + 2 : d.highest;
      const double v = lo + 0.3 * (hi - lo);
      const std::string key =
          std::string("materials.glass.") + block + "=" + "{" + d.key + ": " + models::short_number(v) + "}";
      const Scene s = parse_scene_text(kBase, "scene.yaml", {key});
      const MaterialSpec& glass = s.materials[static_cast<std::size_t>(s.material_index("glass"))];
      const double si = d.degrees ? v * M_PI / 180.0 : v;
      EXPECT_NEAR(glass.law_parameter(models::parameter_path(block, d), -1), si, 1e-12 * std::fabs(si));
      // Like pairs (adhesive, so attractive parameters are kept) get the mixing rule of two equal values.
      const models::PairParameters p = mix_pair(glass, glass, true, s.contact);
      EXPECT_NEAR(p.*d.pair, models::mix_values(d.mix, si, si), 1e-12 * std::fabs(si));
      // Attractive parameters are zero on a non-adhesive pair.
      if (d.attractive) EXPECT_EQ(mix_pair(glass, glass, false, s.contact).*d.pair, 0);
      // Outside the range: one line naming the key.
      const double bad = std::isinf(d.lowest) ? d.highest + 1 : d.lowest - 1;
      const std::string msg = error_of(kBase, {std::string("materials.glass.") + block + "={" + d.key + ": " +
                                               models::short_number(bad) + "}"});
      EXPECT_NE(msg.find(std::string("materials.glass.") + block + "." + d.key), std::string::npos) << msg;
      EXPECT_NE(msg.find(d.help), std::string::npos) << msg;
      ++checked;
    });
  });
  EXPECT_GE(checked, 11); // spring (2), eepa (4), capillary (5) at least
}

// until_force: a positive force on a segment that moves; its segment keeps its times.
TEST(SceneParser, UntilForceEndsAMovingSegment) {
  const std::string ok =
      replaced(kBase, "      start: 0.1\n",
               "      start: 0.1\n      until_force: 2.5\n      then: [{velocity: [0, 0, -0.01], "
               "start: 0.2, stop: 0.4, until_force: 30}]\n");
  const Scene s = parse_scene_text(ok, "scene.yaml");
  EXPECT_DOUBLE_EQ(s.walls[1].motion_until_force, 2.5);
  ASSERT_EQ(s.walls[1].then.size(), 1u);
  EXPECT_DOUBLE_EQ(s.walls[1].then[0].until_force, 30);
  EXPECT_DOUBLE_EQ(s.walls[1].segment(0).stop, 0.4);
  EXPECT_DOUBLE_EQ(s.walls[1].segment(-1).until_force, 2.5);
  const std::string negative = replaced(ok, "until_force: 30", "until_force: -30");
  expect_error(negative, line_of(negative, "until_force: -30"), "walls.1.motion.then.0.until_force",
               "must be > 0", "target stress x the loaded area");
  const std::string still = replaced(ok, "velocity: [0, 0, -0.01]", "velocity: [0, 0, 0]");
  expect_error(still, line_of(still, "until_force: 30"), "walls.1.motion.then.0.until_force",
               "needs the segment's velocity", "give the segment a velocity");
}
