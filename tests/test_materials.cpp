// Mixing of materials into pair parameters (setup/materials.cpp, docs/physics.md section 1): Thakur's EEPA
// values per contact, adhesion off on walls when asked, the damping rule and the lever arm in use.
#include <gtest/gtest.h>
#include <cmath>
#include "setup/materials.hpp"
#include "setup/restitution.hpp"
#include "models/linear_eepa.hpp"
#include "tests/test_support.hpp"

using namespace cgdem;
using namespace cgdem::testing;

namespace {

MaterialSpec eepa_material(const std::string& name, double k1, double k2, double k_adh, double f0) {
  MaterialSpec m = material(name, 2000, 0, 0.3, 0.5, 0.5);
  m.law_parameters["eepa.k1"] = k1;
  m.law_parameters["eepa.k2"] = k2;
  m.law_parameters["eepa.k_adh"] = k_adh;
  m.law_parameters["eepa.f0"] = f0;
  return m;
}

Scene eepa_scene(bool wall_adhesion) {
  // Thakur Table 1: k1 1e4, k2 5e4, k_adh 5e3 N/m, f0 -0.4 N; a steel wall with springs only.
  Scene s =
      basic_scene({eepa_material("powder", 1e4, 5e4, 5e3, -0.4), eepa_material("steel", 1e4, 5e4, 0, 0)},
                  "eepa", "mindlin");
  s.contact.wall_adhesion = wall_adhesion;
  return s;
}

} // namespace

TEST(Materials, EepaPairOfOneMaterialKeepsThakursPerContactValues) {
  const Scene s = eepa_scene(true);
  const models::PairParameters p = mix_pair(s.materials[0], s.materials[0], true, s.contact);
  EXPECT_EQ(p.eepa_k1, 1e4);
  EXPECT_EQ(p.eepa_k2, 5e4);
  EXPECT_EQ(p.eepa_k_adh, 5e3);
  EXPECT_EQ(p.eepa_f0, -0.4);
  // Unlike materials: harmonic mean of the stiffnesses, geometric mean of f0; zero is zero.
  const MaterialSpec a = eepa_material("a", 1e4, 4e4, 2e3, -0.1), b = eepa_material("b", 3e4, 6e4, 0, -0.4);
  const models::PairParameters q = mix_pair(a, b, true, s.contact);
  EXPECT_DOUBLE_EQ(q.eepa_k1, 2 * 1e4 * 3e4 / 4e4);
  EXPECT_DOUBLE_EQ(q.eepa_k2, 2 * 4e4 * 6e4 / 1e5);
  EXPECT_EQ(q.eepa_k_adh, 0);
  EXPECT_DOUBLE_EQ(q.eepa_f0, -0.2);
  EXPECT_EQ(mix_pair(a, eepa_material("c", 1e4, 4e4, 2e3, 0), true, s.contact).eepa_f0, 0);
}

TEST(Materials, NonAdhesiveWallPullsOnNothing) {
  for (bool wall_adhesion : {true, false}) {
    const Scene s = eepa_scene(wall_adhesion);
    const std::vector<models::PairParameters> walls = pair_table(s, true);
    // The powder against the powder-coated wall (same material): adhesive only when the scene says so.
    const models::PairParameters& w = walls[0];
    EXPECT_EQ(w.eepa_k_adh, wall_adhesion ? 5e3 : 0);
    EXPECT_EQ(w.eepa_f0, wall_adhesion ? -0.4 : 0);
    EXPECT_EQ(w.eepa_k1, 1e4);
    // Load and unload the wall contact: without wall adhesion the force never pulls.
    models::PairState st;
    st.normal = Vec3{1, 0, 0};
    st.radius_i = st.radius_eff = 2.5e-3;
    st.mass_eff = 1e-4;
    Real h[1] = {0};
    Real least = 0;
    for (int k = 0; k <= 400; ++k) {
      st.overlap = 1e-4 * (k <= 200 ? k : 400 - k) / 200.0 + 1e-12;
      least = std::min(least, models::LinearEepa{}(w, st, h).force);
    }
    if (wall_adhesion)
      EXPECT_LT(least, -0.3);
    else
      EXPECT_GE(least, 0);
  }
}

TEST(Materials, DampingRuleFollowsTheNormalLaw) {
  ContactSpec c;
  const double e = 0.5, beta = -restitution_beta(e);
  c.normal = "hertz";
  EXPECT_DOUBLE_EQ(damping_coefficient(e, c), hertz_damping_for_restitution(e, HertzContactEnd::Clamped));
  c.normal = "jkr";
  EXPECT_DOUBLE_EQ(damping_coefficient(e, c), 2 * std::sqrt(5.0 / 6.0) * beta);
  for (const char* spring : {"linear", "eepa"}) {
    c.normal = spring;
    EXPECT_DOUBLE_EQ(damping_coefficient(e, c), 2 * beta);
  }
  c.normal = "hertz";
  c.damping = "beta_formula";
  EXPECT_DOUBLE_EQ(damping_coefficient(e, c), 2 * std::sqrt(5.0 / 6.0) * beta);
  EXPECT_EQ(damping_coefficient(1.0, c), 0);
}

TEST(Materials, LeverArmAutoIsRadiusUnderChenElliott) {
  Scene s = basic_scene({material("glass", 2500, 5e6, 0.3, 0.5, 0.3)});
  EXPECT_EQ(resolved_lever_arm(s), "contact_point");
  EXPECT_EQ(pair_table(s, false)[0].lever_share, 0.5);
  s.groups[0].coarse_grain.law = "chen_elliott";
  s.groups[0].coarse_grain.factor = 2;
  EXPECT_EQ(resolved_lever_arm(s), "radius");
  EXPECT_EQ(pair_table(s, false)[0].lever_share, 0);
  s.contact.lever_arm = "contact_point";
  EXPECT_EQ(resolved_lever_arm(s), "contact_point");
}
