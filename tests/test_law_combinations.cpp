// Every combination of contact-law components a scene can name either runs or is refused with its reason:
// the registry generated from the component lists (models/component_lists.hpp) holds exactly the
// combinations that make sense, the parser refuses the others in one line, and every compiled law (direct
// scaling methods included) runs a two-particle oblique impact that conserves momentum and creates no
// energy.
#include <gtest/gtest.h>
#include <algorithm>
#include <fstream>
#include <cmath>
#include <set>
#include <sstream>
#include "setup/time_step.hpp"
#include "drivers/commands.hpp"
#include "drivers/scene_parser.hpp"
#include "models/component_lists.hpp"
#include "tests/test_support.hpp"

using namespace cgdem;
using namespace cgdem::testing;

namespace {

template <class List>
std::vector<std::string> names_of(List list) {
  std::vector<std::string> out;
  models::for_each_type(list, [&](auto t) { out.emplace_back(decltype(t)::type::name); });
  return out;
}

struct Combination {
  std::string normal, adhesion = "none", tangential = "none", rolling = "none", method = "none";
};

// "jkr+mindlin+spring_dashpot@hu_method1" into its components.
Combination parse_name(const std::string& name) {
  Combination c;
  const auto at = name.find('@');
  if (at != std::string::npos) c.method = name.substr(at + 1);
  std::stringstream parts(name.substr(0, at));
  std::getline(parts, c.normal, '+');
  for (std::string part; std::getline(parts, part, '+');) {
    if (part == "dmt" || part == "capillary")
      c.adhesion = part;
    else if (part == "mindlin")
      c.tangential = part;
    else
      c.rolling = part;
  }
  return c;
}

// A material with the parameters of every law.
MaterialSpec all_parameters(const std::string& name) {
  MaterialSpec m = material(name, 2500, 1e7, 0.3, 0.5, 0.4);
  m.rolling_friction = 0.1;
  m.surface_energy = 0.02;
  m.law_parameters["eepa.k1"] = 2e3;
  m.law_parameters["eepa.k2"] = 1e4;
  m.law_parameters["eepa.k_adh"] = 5e2;
  m.law_parameters["eepa.f0"] = -1e-5;
  m.law_parameters["spring.normal"] = 2e3;
  m.law_parameters["spring.tangential"] = 2e3 * 2.0 / 7.0;
  m.law_parameters["capillary.surface_tension"] = 0.072;
  m.law_parameters["capillary.contact_angle"] = 0.3;
  m.law_parameters["capillary.liquid_fraction"] = 0.01;
  return m;
}

const char* kScene = R"(domain: {lo: [-0.01, -0.01, -0.01], hi: [0.01, 0.01, 0.01]}
gravity: [0, 0, 0]
materials:
  grains:
    density: 2500
    youngs_modulus: 1e7
    restitution: 0.5
    friction: 0.4
    rolling_friction: 0.1
    surface_energy: 0.02
    eepa: {k1: 2e3, k2: 1e4, k_adh: 5e2, f0: -1e-5}
    spring: {normal: 2e3, tangential: 571}
    capillary: {surface_tension: 0.072, contact_angle: 20, liquid_fraction: 0.01}
contact: {normal: NORMAL, adhesion: ADHESION, tangential: TANGENTIAL, rolling: ROLLING}
groups:
  - {name: g, material: grains, count: 2, size: {radius: 0.001}, placement: {type: lattice}}
time: {end: 0.01}
)";

std::string scene_with(const Combination& c) {
  std::string s = kScene;
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"NORMAL", c.normal},
                                   {"ADHESION", c.adhesion},
                                   {"TANGENTIAL", c.tangential},
                                   {"ROLLING", c.rolling}})
    s.replace(s.find(key), key.size(), value);
  return s;
}

} // namespace

TEST(LawCombinations, EverySensibleCombinationIsCompiledAndEveryOtherRefusedWithItsReason) {
  const std::vector<std::string> compiled = compiled_physics();
  const std::set<std::string> unique(compiled.begin(), compiled.end());
  EXPECT_EQ(unique.size(), compiled.size()) << "a law is registered twice";
  int sensible = 0, refused = 0;
  for (const std::string& n : names_of(models::NormalLaws{}))
    for (const std::string& a : names_of(models::AdhesionLaws{}))
      for (const std::string& t : names_of(models::TangentialLaws{}))
        for (const std::string& r : names_of(models::RollingLaws{})) {
          const std::string name = models::law_name(n, a, t, r);
          SCOPED_TRACE(name);
          const std::string_view problem = models::combination_problem(n, a, t, r);
          std::string error;
          try {
            parse_scene_text(scene_with({n, a, t, r}), "combo.yaml", {});
          } catch (const SceneError& e) {
            error = e.what();
          }
          if (problem.empty()) {
            ++sensible;
            EXPECT_TRUE(unique.count(name)) << "not compiled";
            EXPECT_EQ(error, "");
          } else {
            ++refused;
            EXPECT_FALSE(unique.count(name)) << "compiled although it makes no sense";
            EXPECT_NE(error.find(std::string(problem)), std::string::npos) << error;
            EXPECT_EQ(error.find('\n'), std::string::npos) << error;
          }
        }
  // hertz x {none, dmt, capillary}, linear/jkr/eepa x {none, capillary}; without friction only no rolling.
  EXPECT_EQ(sensible, 9 * 4);
  EXPECT_EQ(refused, 4 * 3 * 2 * 3 - 36);
  // The rest of the registry: the four direct scaling methods around Hu et al.'s four laws
  // (DirectlyScaledLaws in drivers/physics_factory.hpp).
  EXPECT_EQ(compiled.size(), std::size_t(sensible + 4 * 4));
}

TEST(LawCombinations, EveryCompiledLawRunsATwoParticleImpact) {
  for (const std::string& name : compiled_physics()) {
    SCOPED_TRACE(name);
    const Combination c = parse_name(name);
    const MaterialSpec m = all_parameters("grains");
    Scene s = basic_scene({m}, c.normal, c.tangential);
    s.contact.adhesion = c.adhesion;
    s.contact.rolling = c.rolling;
    if (c.method != "none") {
      s.groups[0].coarse_grain.law = c.method;
      s.groups[0].coarse_grain.factor = 2;
    }
    // An oblique impact with spin, 0.5 m/s apart along x, so that every component acts.
    const double R = 1e-3, gap = 1e-6;
    ParticleSet p;
    add_particle(p, {-R - gap, 0, 0}, {0.25, 0.05, 0}, R, m.density);
    add_particle(p, {R + gap, 0, 0}, {-0.25, -0.05, 0}, R, m.density);
    p.angular_velocity[0] = {0, 0, 20};
    const double dt = estimate_time_step(s, p).step;
    auto engine = make(s, p, dt, "serial");
    ASSERT_EQ(engine->physics(), name);
    const FrameData before = engine->frame();
    auto kinetic = [](const FrameData& f) {
      double e = 0;
      for (std::size_t i = 0; i < f.size(); ++i)
        for (int a = 0; a < 3; ++a)
          e += 0.5 * f.mass[i] * f.velocity[3 * i + a] * f.velocity[3 * i + a];
      return e;
    };
    auto rotational = [&](const FrameData& f) {
      double e = 0;
      for (std::size_t i = 0; i < f.size(); ++i)
        for (int a = 0; a < 3; ++a)
          e += 0.5 * 0.4 * f.mass[i] * f.radius[i] * f.radius[i] * f.angular_velocity[3 * i + a] *
               f.angular_velocity[3 * i + a];
      return e;
    };
    const double e0 = kinetic(before) + rotational(before);
    double largest_change = 0;
    FrameData f = before;
    for (int chunk = 0; chunk < 40; ++chunk) {
      engine->advance(100);
      f = engine->frame();
      for (double v : f.velocity)
        ASSERT_TRUE(std::isfinite(v)) << "at step " << engine->step();
      largest_change = std::max(largest_change, std::fabs(f.velocity[0] - before.velocity[0]));
    }
    // The particles met (the approach speed changed by more than a tenth), momentum is conserved to
    // round-off, and no law created energy (e = 0.5: the impact dissipates, adhesion can only bind).
    EXPECT_GT(largest_change, 0.025);
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(f.mass[0] * f.velocity[a] + f.mass[1] * f.velocity[3 + a], 0, 1e-12 * f.mass[0]) << a;
    EXPECT_LT(kinetic(f) + rotational(f), e0);
  }
}

TEST(LawCombinations, DirectScalingAroundAnotherLawIsRefusedWithTheLawsItWraps) {
  const std::string text = std::string(kScene).replace(std::string(kScene).find("NORMAL"), 6, "linear");
  std::string t = text;
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"ADHESION", "none"},
                                   {"TANGENTIAL", "mindlin"},
                                   {"ROLLING", "none"}})
    t.replace(t.find(key), key.size(), value);
  t.replace(t.find("placement: {type: lattice}}"), 27,
            "placement: {type: lattice}, coarse_grain: {law: hu_method1, factor: 2}}");
  EXPECT_NO_THROW(parse_scene_text(t, "combo.yaml", {}));
  const std::string path = ::testing::TempDir() + "combo_direct.yaml";
  std::ofstream(path) << t;
  try {
    check_run(path, {});
    ADD_FAILURE() << "linear+mindlin@hu_method1 was accepted";
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_NE(
        msg.find("contact: direct force scaling hu_method1 is compiled around hertz+mindlin, jkr+mindlin, "
                 "hertz+capillary"),
        std::string::npos)
        << msg;
    EXPECT_NE(msg.find("not around linear+mindlin"), std::string::npos) << msg;
    EXPECT_NE(msg.find("coarse_grain.law: chen_elliott"), std::string::npos) << msg;
  }
}
