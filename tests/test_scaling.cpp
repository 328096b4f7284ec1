// Coarse-graining laws without running the engine: parameter multipliers, the mixed-factor / wall pair
// rule, each direct force scaling method against the original pair force for a static overlap (the
// functor called directly), the tangential displacement rule, the reach, the time-step rules and names.
#include <gtest/gtest.h>
#include <cmath>
#include <type_traits>
#include "setup/materials.hpp"
#include "setup/scaling.hpp"
#include "drivers/resolution_check.hpp"
#include "drivers/scene_parser.hpp"
#include "models/capillary_bridge.hpp"
#include "models/hertz_tsuji.hpp"
#include "models/jkr_full.hpp"
#include "models/mindlin_tangential.hpp"
#include "models/scaling/direct_force_scaling.hpp"
#include "tests/test_support.hpp"

using namespace cgdem;
using namespace cgdem::testing;
namespace sc = cgdem::models::scaling;

namespace {

MaterialSpec sticky(const std::string& name, double E, double gamma) {
  MaterialSpec m = material(name, 2500, E, 0.3, 0.9, 0.4);
  m.surface_energy = gamma;
  m.rolling_friction = 0.1;
  return m;
}

Scene two_group_scene(const std::string& law, double k1, double k2) {
  Scene s = basic_scene({sticky("a", 1e7, 0.1), sticky("steel", 2e11, 0.05)}, "jkr");
  s.groups[0].coarse_grain = {law, k1};
  GroupSpec g = s.groups[0];
  g.name = "second";
  g.coarse_grain = {law, k2};
  s.groups.push_back(g);
  WallSpec w;
  w.name = "floor";
  w.material = "steel";
  s.walls.push_back(w);
  return s;
}

} // namespace

TEST(ScalingLaws, ParameterMultipliersMatchPhysicsTable) {
  MaterialSpec m = sticky("a", 1e7, 0.1);
  m.law_parameters["eepa.k1"] = 100;
  m.law_parameters["eepa.k2"] = 500;
  m.law_parameters["eepa.k_adh"] = 50;
  m.law_parameters["eepa.f0"] = -1e-3;
  const double k = 3;
  const MaterialSpec ce = scale_material(m, ScalingLaw::ChenElliott, k);
  EXPECT_DOUBLE_EQ(ce.surface_energy, 0.1 * 9);
  EXPECT_NEAR(ce.youngs_modulus / (1e7 * std::pow(3.0, 2.5)), 1, 1e-14);
  EXPECT_DOUBLE_EQ(scale_material(m, ScalingLaw::Bond, k).surface_energy, 0.9);
  EXPECT_DOUBLE_EQ(scale_material(m, ScalingLaw::Bond, k).youngs_modulus, 1e7);
  EXPECT_NEAR(scale_material(m, ScalingLaw::Cohesion, k).surface_energy, 0.1 * std::pow(3.0, 1.6), 1e-15);
  const MaterialSpec th = scale_material(m, ScalingLaw::Thakur, k);
  EXPECT_DOUBLE_EQ(th.law_parameter("eepa.k1", 0), 300);
  EXPECT_DOUBLE_EQ(th.law_parameter("eepa.k2", 0), 1500);
  EXPECT_DOUBLE_EQ(th.law_parameter("eepa.k_adh", 0), 150);
  EXPECT_DOUBLE_EQ(th.law_parameter("eepa.f0", 0), -9e-3);
  EXPECT_DOUBLE_EQ(th.youngs_modulus, 1e7);
  // Thakur's rejected alternatives: the same stiffnesses, f0 as k and k^3.
  const MaterialSpec lin = scale_material(m, ScalingLaw::ThakurF0Linear, k);
  const MaterialSpec cub = scale_material(m, ScalingLaw::ThakurF0Cubic, k);
  EXPECT_DOUBLE_EQ(lin.law_parameter("eepa.k1", 0), 300);
  EXPECT_DOUBLE_EQ(cub.law_parameter("eepa.k_adh", 0), 150);
  EXPECT_DOUBLE_EQ(lin.law_parameter("eepa.f0", 0), -3e-3);
  EXPECT_NEAR(cub.law_parameter("eepa.f0", 0), -27e-3, 1e-17);
  for (ScalingLaw law : {ScalingLaw::None, ScalingLaw::ChenElliott, ScalingLaw::Bond, ScalingLaw::Cohesion,
                         ScalingLaw::Thakur, ScalingLaw::HuMethod1, ScalingLaw::Sakai}) {
    const MaterialSpec s = scale_material(m, law, k); // rho, nu, mu, mu_r, e unchanged by every law
    EXPECT_EQ(s.density, m.density);
    EXPECT_EQ(s.poisson_ratio, m.poisson_ratio);
    EXPECT_EQ(s.friction, m.friction);
    EXPECT_EQ(s.rolling_friction, m.rolling_friction);
    EXPECT_EQ(s.restitution, m.restitution);
  }
  // Direct laws keep every original parameter.
  EXPECT_EQ(scale_material(m, ScalingLaw::HuMethod1, k).youngs_modulus, m.youngs_modulus);
  EXPECT_EQ(scale_material(m, ScalingLaw::HuMethod1, k).surface_energy, m.surface_energy);
}

TEST(ScalingLaws, SurfaceEnergyPowerReplacesTheLawsExponentOfGammaOnly) {
  MaterialSpec m = sticky("a", 1e7, 0.1);
  m.law_parameters["eepa.f0"] = -1e-3;
  const double k = 3;
  for (ScalingLaw law : {ScalingLaw::ChenElliott, ScalingLaw::Bond, ScalingLaw::Cohesion}) {
    const MaterialSpec own = scale_material(m, law, k), p1 = scale_material(m, law, k, 1),
                       p0 = scale_material(m, law, k, 0);
    EXPECT_NEAR(p1.surface_energy, 0.1 * 3, 1e-15) << scaling_law_name(law);
    EXPECT_EQ(p0.surface_energy, 0.1) << scaling_law_name(law);
    EXPECT_EQ(p1.youngs_modulus, own.youngs_modulus) << scaling_law_name(law); // E keeps the law's k^2.5 or 1
    EXPECT_EQ(scale_material(m, law, k, -1).surface_energy, own.surface_energy) << scaling_law_name(law);
  }
  // Laws that do not scale gamma are not changed by it.
  for (ScalingLaw law : {ScalingLaw::None, ScalingLaw::Thakur, ScalingLaw::HuMethod1}) {
    const MaterialSpec s = scale_material(m, law, k, 1);
    EXPECT_EQ(s.surface_energy, 0.1) << scaling_law_name(law);
    EXPECT_EQ(s.law_parameter("eepa.f0", 0), scale_material(m, law, k).law_parameter("eepa.f0", 0));
  }
  // The scene's value reaches the pair tables, walls included.
  Scene s = two_group_scene("chen_elliott", 2, 2);
  const ScaledTables own = scaled_tables(s);
  for (GroupSpec& g : s.groups)
    g.coarse_grain.surface_energy_power = 1;
  const ScaledTables p1 = scaled_tables(s);
  const int a = p1.slot_of_group[0];
  const std::size_t ns = p1.slots.size();
  EXPECT_NEAR(p1.pair_params[a * ns + a].surface_energy / own.pair_params[a * ns + a].surface_energy, 0.5,
              1e-14);
  EXPECT_NEAR(p1.wall_params[a * ns + 1].surface_energy / own.wall_params[a * ns + 1].surface_energy, 0.5,
              1e-14);
  EXPECT_EQ(p1.pair_params[a * ns + a].E_eff, own.pair_params[a * ns + a].E_eff);
}

TEST(ScalingLaws, EqualFactorsPairEqualsMixingScaledMaterials) {
  const Scene s = two_group_scene("chen_elliott", 2, 2);
  const ScaledTables t = scaled_tables(s);
  ASSERT_EQ(t.slot_of_group[0], t.slot_of_group[1]);
  const int a = t.slot_of_group[0];
  const std::size_t ns = t.slots.size();
  const MaterialSpec ma = scale_material(s.materials[0], ScalingLaw::ChenElliott, 2);
  const models::PairParameters ref = mix_pair(ma, ma, true, s.contact);
  const models::PairParameters& p = t.pair_params[a * ns + a];
  EXPECT_NEAR(p.E_eff / ref.E_eff, 1, 1e-14);
  EXPECT_NEAR(p.G_eff / ref.G_eff, 1, 1e-14);
  EXPECT_NEAR(p.surface_energy / ref.surface_energy, 1, 1e-14);
  EXPECT_EQ(p.damping, ref.damping);
  EXPECT_EQ(p.mu_slide, ref.mu_slide);
  EXPECT_EQ(p.coarse_grain_factor, 2);
}

TEST(ScalingLaws, MixedFactorsUseHarmonicPairFactorAndWallsTheParticles) {
  const Scene s = two_group_scene("chen_elliott", 2, 4);
  const ScaledTables t = scaled_tables(s);
  const std::size_t ns = t.slots.size();
  ASSERT_EQ(ns, 4u); // two factor-1 slots (walls) + (a, 2) + (a, 4)
  const int a = t.slot_of_group[0], b = t.slot_of_group[1];
  const models::PairParameters orig = mix_pair(s.materials[0], s.materials[0], true, s.contact);
  const double kab = 2.0 * 2 * 4 / (2 + 4);
  EXPECT_DOUBLE_EQ(pair_scale_factor(2, 4), kab);
  const models::PairParameters& p = t.pair_params[a * ns + b];
  EXPECT_NEAR(p.E_eff / (orig.E_eff * std::pow(kab, 2.5)), 1, 1e-14);
  EXPECT_NEAR(p.surface_energy / (orig.surface_energy * kab * kab), 1, 1e-14);
  EXPECT_EQ(t.pair_params[b * ns + a].E_eff, p.E_eff); // symmetric
  // Particle-wall: mixed with the unscaled wall material, then scaled with the particle's own factor, so
  // E* ~ k^2.5 and gamma ~ k^2 hold for the contact even though the wall is never scaled.
  const int steel = s.material_index("steel");
  const models::PairParameters w_orig = mix_pair(s.materials[0], s.materials[steel], true, s.contact);
  const models::PairParameters& w = t.wall_params[b * ns + steel];
  EXPECT_NEAR(w.E_eff / (w_orig.E_eff * std::pow(4.0, 2.5)), 1, 1e-14);
  EXPECT_NEAR(w.surface_energy / (w_orig.surface_energy * 16), 1, 1e-14);
  EXPECT_EQ(w.coarse_grain_factor, 4);
}

TEST(ScalingLaws, EngineConfigUsesSlotsAndRejectsMismatchedLaws) {
  Scene s = two_group_scene("chen_elliott", 2, 4);
  ParticleSet p;
  add_particle(p, {0, 0, 0.01}, {0, 0, 0}, 2e-3, 2500);
  add_particle(p, {0, 0, 0.03}, {0, 0, 0}, 4e-3, 2500);
  p.group[1] = 1;
  TimeStepEstimate e = estimate_time_step(s, p);
  const EngineConfig c = make_engine_config(s, p, e);
  EXPECT_EQ(c.num_materials, 4);
  EXPECT_EQ(c.particles.material[0], 2);
  EXPECT_EQ(c.particles.material[1], 3);
  EXPECT_EQ(c.scale_factor[1], 4);
  EXPECT_EQ(c.contact.scaling, "none");
  Scene th = s;
  th.groups[0].coarse_grain.law = th.groups[1].coarse_grain.law = "thakur";
  EXPECT_THROW(make_engine_config(th, p, e), std::invalid_argument);
  Scene hu = s;
  hu.groups[0].coarse_grain.law = hu.groups[1].coarse_grain.law = "hu_method1";
  EXPECT_EQ(make_engine_config(hu, p, e).contact.scaling, "hu_method1");
  EXPECT_EQ(physics_name(effective_contact(hu)), "jkr+mindlin@hu_method1");
}

TEST(ScalingLaws, DirectCombinationsAreCompiled) {
  const std::vector<std::string> all = compiled_physics();
  for (const char* m : {"hu_method1", "hu_method2", "hu_method3", "sakai"})
    for (const char* law : {"hertz+mindlin", "jkr+mindlin", "hertz+capillary", "hertz+capillary+mindlin"}) {
      const std::string name = std::string(law) + "@" + m;
      EXPECT_NE(std::find(all.begin(), all.end(), name), all.end()) << name;
    }
}

// The wrappers' torque factor: the exponent chosen and l^n formed without a selection, bit for bit the
// products l * l (* l (* l)) for every exponent in use and scale factors from 1 to 100.
TEST(ScalingLaws, TorquePowerWithoutSelectionIsExact) {
  EXPECT_EQ(sc::effective_torque_power(0, 2), 2.0);
  EXPECT_EQ(sc::effective_torque_power(0, 4), 4.0);
  EXPECT_EQ(sc::effective_torque_power(2, 4), 2.0);
  EXPECT_EQ(sc::effective_torque_power(3, 2), 3.0);
  for (double l = 1; l <= 100; l += 0.37) {
    const double l2 = l * l, l3 = l2 * l, l4 = l3 * l;
    EXPECT_EQ(sc::power_2_to_4(l, 2), l2) << l;
    EXPECT_EQ(sc::power_2_to_4(l, 3), l3) << l;
    EXPECT_EQ(sc::power_2_to_4(l, 4), l4) << l;
    for (int n = 0; n <= 4; ++n)
      EXPECT_EQ(sc::power(l, n), n == 0 ? 1 : n == 1 ? l : n == 2 ? l2 : n == 3 ? l3 : l4) << l;
  }
}

TEST(ScalingLaws, HostExponentsMirrorDeviceMethods) {
  const auto same = [](ScalingLaw law, auto tag) {
    using M = decltype(tag);
    const DirectExponents e = direct_exponents(law);
    EXPECT_EQ(e.overlap_power, M::overlap_power) << M::name;
    EXPECT_EQ(e.force_power, M::force_power) << M::name;
    EXPECT_EQ(e.adhesion_power, M::adhesion_power) << M::name;
    EXPECT_EQ(e.torque_power, M::torque_power) << M::name;
    EXPECT_STREQ(scaling_law_name(law), M::name);
  };
  same(ScalingLaw::HuMethod1, sc::HuMethod1{});
  same(ScalingLaw::HuMethod2, sc::HuMethod2{});
  same(ScalingLaw::HuMethod3, sc::HuMethod3{});
  same(ScalingLaw::Sakai, sc::Sakai{});
}

// ---------------------------------------------------------------------------------------------------
// Direct force scaling: a static overlap (no rate), with a tangential velocity so that the tangential
// spring and the torque are exercised; the reference is the original pair built by hand.
namespace {

using HertzMindlin = models::ContactLaw<models::HertzTsuji, models::NoAdhesion, models::MindlinTangential>;
using JkrMindlin = models::ContactLaw<models::JkrFull, models::NoAdhesion, models::MindlinTangential>;
using HertzCapillary = models::ContactLaw<models::HertzTsuji, models::CapillaryBridge>;
using HertzCapillaryMindlin =
    models::ContactLaw<models::HertzTsuji, models::CapillaryBridge, models::MindlinTangential>;

models::PairParameters original_params() {
  MaterialSpec m = sticky("a", 1e7, 0.2);
  m.restitution = 1; // static: no damping either way
  m.law_parameters["capillary.surface_tension"] = 0.072;
  m.law_parameters["capillary.liquid_fraction"] = 0.083 * 0.05;
  m.law_parameters["capillary.min_separation"] = 1e-7;
  return mix_pair(m, m, true, ContactSpec{});
}

// Coarse state of two equal spheres of coarse radius R (factor l each, or a wall when wall = true).
models::PairState coarse_state(double R, double l, double overlap, bool wall) {
  models::PairState s;
  s.overlap = overlap;
  s.normal = Vec3{1, 0, 0};
  s.tangential_velocity = Vec3{0, 0.01, 0};
  s.relative_rotation = Vec3{0, 0, 3};
  s.omega_i = Vec3{0, 0, 3};
  const double m = 2500 * 4.0 / 3.0 * M_PI * R * R * R;
  s.radius_i = R;
  s.radius_j = wall ? 0 : R;
  s.radius_eff = wall ? R : R / 2;
  s.mass_eff = wall ? m : m / 2;
  s.volume_i = 4.0 / 3.0 * M_PI * R * R * R;
  s.volume_j = wall ? 0 : s.volume_i;
  s.dt = 1e-7;
  s.scale_i = l;
  s.scale_j = wall ? 0 : l;
  return s;
}

// The original pair (radius R / l) at overlap `overlap_O`, built independently of the wrapper.
models::PairState by_hand_original(double R, double l, double overlap_O, double dt_O, bool wall) {
  models::PairState s = coarse_state(R / l, 1, overlap_O, wall);
  s.relative_rotation = Vec3{0, 0, 3 * l};
  s.omega_i = Vec3{0, 0, 3 * l};
  s.dt = dt_O;
  return s;
}

template <class Method, class Law>
void check_method(const char* law_name, double l, double overlap_S, bool wall) {
  const models::PairParameters p = original_params();
  const double R = 1e-3 * l;
  const sc::DirectForceScaling<Method, Law> scaled{};
  const Law law{};
  const double g = std::pow(l, -Method::overlap_power);
  constexpr int H = Law::history_size > 0 ? Law::history_size : 1;
  Real h_s[H] = {}, h_o[H] = {};
  // Two steps: the second sees the tangential spring (and JKR warm start) from the first.
  models::ContactForce fs, fo;
  for (int step = 0; step < 2; ++step) {
    fs = scaled(p, coarse_state(R, l, overlap_S, wall), h_s);
    fo = law(p, by_hand_original(R, l, g * overlap_S, g * 1e-7, wall), h_o);
  }
  for (int k = 0; k < Law::history_size; ++k)
    EXPECT_NEAR(h_s[k], h_o[k], 1e-12 * (1 + std::fabs(h_o[k])));
  const double F = std::pow(l, Method::force_power), M = std::pow(l, Method::torque_power);
  const double tol = 1e-12;
  EXPECT_TRUE(fo.active);
  EXPECT_EQ(fs.active, fo.active);
  EXPECT_NEAR(fs.force.x, F * fo.force.x, tol * std::fabs(F * fo.force.x)) << Method::name << " " << law_name;
  EXPECT_NEAR(fs.force.y, F * fo.force.y, tol * std::fabs(F * fo.force.y) + 1e-30)
      << Method::name << " " << law_name;
  EXPECT_NEAR(fs.torque.z, M * fo.torque.z, tol * std::fabs(M * fo.torque.z) + 1e-30)
      << Method::name << " " << law_name;
  EXPECT_NE(fo.force.y, 0.0);
}

template <class Method>
void check_all_laws() {
  for (double l : {2.0, 4.0, 8.0, 16.0}) // 8 and 16: the large factors of the hard-case suite
    for (bool wall : {false, true}) {
      const double ov = 2e-6 * l; // coarse overlap
      check_method<Method, HertzMindlin>("hertz+mindlin", l, ov, wall);
      check_method<Method, JkrMindlin>("jkr+mindlin", l, ov, wall);
      // Hu's mixer law. Sakai scales contact and adhesion by different powers (checked apart below).
      if constexpr (!std::is_same_v<Method, sc::Sakai>)
        check_method<Method, HertzCapillaryMindlin>("hertz+capillary+mindlin", l, ov, wall);
    }
}

} // namespace

TEST(DirectForceScaling, HuMethod1IsOriginalForceAtOverlapOverLTimesLSquared) {
  check_all_laws<sc::HuMethod1>();
}
TEST(DirectForceScaling, HuMethod2IsOriginalForceAtSameOverlapTimesLSquared) {
  check_all_laws<sc::HuMethod2>();
}
TEST(DirectForceScaling, HuMethod3IsOriginalForceAtOverlapOverLTimesLCubed) {
  check_all_laws<sc::HuMethod3>();
}
TEST(DirectForceScaling, SakaiIsOriginalContactForceTimesLCubedTorqueLToTheFourth) {
  check_all_laws<sc::Sakai>();
}

TEST(DirectForceScaling, HertzMindlinAnalyticPowersPerMethod) {
  // F_S = l^f 4/3 E* sqrt(R*/l) (delta_S / l^o)^1.5, the table of docs/physics.md 4.2 in closed form.
  const models::PairParameters p = original_params();
  const double l = 4, R = 1e-3 * l, ov = 3e-6 * l;
  const auto hertz = [&](double r_eff, double d) {
    return 4.0 / 3.0 * p.E_eff * std::sqrt(r_eff) * std::pow(d, 1.5);
  };
  Real h[3] = {};
  const models::PairState s = coarse_state(R, l, ov, false);
  const double f1 = sc::DirectForceScaling<sc::HuMethod1, HertzMindlin>{}(p, s, h).force.x;
  EXPECT_NEAR(-f1 / (16 * hertz(R / 2 / l, ov / l)), 1, 1e-12);
  EXPECT_NEAR(-f1 / hertz(R / 2, ov), 1, 1e-12); // method 1 = Hertz of the coarse pair, unscaled E*
  const double f2 = sc::DirectForceScaling<sc::HuMethod2, HertzMindlin>{}(p, s, h).force.x;
  EXPECT_NEAR(-f2 / (16 * hertz(R / 2 / l, ov)), 1, 1e-12);
  const double f3 = sc::DirectForceScaling<sc::HuMethod3, HertzMindlin>{}(p, s, h).force.x;
  EXPECT_NEAR(-f3 / (64 * hertz(R / 2 / l, ov / l)), 1, 1e-12);
  const double f4 = sc::DirectForceScaling<sc::Sakai, HertzMindlin>{}(p, s, h).force.x;
  EXPECT_NEAR(-f4 / (64 * hertz(R / 2 / l, ov)), 1, 1e-12);
}

TEST(DirectForceScaling, CapillaryBridgeUsesOriginalVolumeAndSeparation) {
  // A bridge across a gap: S_O = S_S / l (methods 1, 3) or S_S (2, Sakai); V_O = V_S / l^3; the bridge is
  // adhesion, so Sakai scales it by l^2 while methods 1/2/3 use their single power.
  const models::PairParameters p = original_params();
  const double l = 2, R = 1e-3 * l, gap = 4e-6 * l;
  const auto run = [&](auto scaled, double gap_O, double powr) {
    Real hs[1] = {1}, ho[1] = {1}; // a bridge formed earlier
    const double fs = scaled(p, coarse_state(R, l, -gap, false), hs).force.x;
    const double fo = HertzCapillary{}(p, by_hand_original(R, l, -gap_O, 1e-7, false), ho).force.x;
    EXPECT_GT(fo, 0); // attraction pulls i toward j (+x)
    EXPECT_NEAR(fs / (powr * fo), 1, 1e-12);
  };
  run(sc::DirectForceScaling<sc::HuMethod1, HertzCapillary>{}, gap / l, l * l);
  run(sc::DirectForceScaling<sc::HuMethod2, HertzCapillary>{}, gap, l * l);
  run(sc::DirectForceScaling<sc::HuMethod3, HertzCapillary>{}, gap / l, l * l * l);
  run(sc::DirectForceScaling<sc::Sakai, HertzCapillary>{}, gap, l * l);
}

TEST(DirectForceScaling, TangentialDisplacementFollowsOverlapRule) {
  // History holds the original contact's spring: xi_O = xi_S / l under geometric similarity (methods 1, 3),
  // xi_O = xi_S under methods 2 and Sakai; xi_S = v_t dt after one step.
  const models::PairParameters p = original_params();
  const double l = 4, R = 1e-3 * l;
  const models::PairState s = coarse_state(R, l, 1e-6, false);
  Real h1[3] = {}, h2[3] = {};
  sc::DirectForceScaling<sc::HuMethod1, HertzMindlin>{}(p, s, h1);
  sc::DirectForceScaling<sc::HuMethod2, HertzMindlin>{}(p, s, h2);
  EXPECT_NEAR(h1[1], 0.01 * 1e-7 / l, 1e-22);
  EXPECT_NEAR(h2[1], 0.01 * 1e-7, 1e-22);
  EXPECT_EQ((sc::DirectForceScaling<sc::HuMethod1, JkrMindlin>::history_size), JkrMindlin::history_size);
}

TEST(DirectForceScaling, ReachIsOriginalReachStretchedByGeometry) {
  models::PairParameters p = original_params();
  p.coarse_grain_factor = 2;
  const double R = 2e-3;
  const double orig = models::JkrFull::interaction_range(p, R / 2, R / 2);
  using M1 = sc::DirectForceScaling<sc::HuMethod1, JkrMindlin>;
  using M2 = sc::DirectForceScaling<sc::HuMethod2, JkrMindlin>;
  EXPECT_NEAR(M1::interaction_range(p, R, R), 2 * orig, 1e-18);
  EXPECT_NEAR(M2::interaction_range(p, R, R), orig, 1e-18);
  EXPECT_GT(orig, 0);
}

// ---------------------------------------------------------------------------------------------------
namespace {
TimeStepEstimate estimate_for(const std::string& law, double k) {
  Scene s = basic_scene({sticky("a", 1e7, 0.1)}, "jkr");
  s.groups[0].coarse_grain = {law, k};
  WallSpec w;
  w.name = "floor";
  w.material = "a";
  s.walls.push_back(w);
  ParticleSet p;
  add_particle(p, {0, 0, 0.01}, {0, 0, 0}, 1e-3 * (law == "none" ? 1 : k), 2500);
  add_particle(p, {0, 0, 0.05}, {0, 0, 0}, 1e-3 * (law == "none" ? 1 : k), 2500);
  return estimate_time_step(s, p);
}
} // namespace

TEST(ScalingTimeStep, RulePerLaw) {
  const TimeStepEstimate orig = estimate_for("none", 1);
  EXPECT_TRUE(orig.rule.empty());
  const TimeStepEstimate ce = estimate_for("chen_elliott", 4);
  EXPECT_NEAR(ce.limit / orig.limit, 1, 1e-12); // the original particles' step
  EXPECT_NE(ce.reason.find("chen_elliott"), std::string::npos);
  EXPECT_NE(ce.reason.find("original particles"), std::string::npos);
  const TimeStepEstimate hu1 = estimate_for("hu_method1", 4);
  EXPECT_NEAR(hu1.limit / orig.limit, 4, 1e-12); // l times the original's
  EXPECT_NE(hu1.reason.find("hu_method1"), std::string::npos);
  // Bond: unscaled E on a k times larger particle: Hertz time ~ k, Rayleigh time ~ k.
  const TimeStepEstimate bond = estimate_for("bond", 4);
  EXPECT_NEAR(bond.limit / orig.limit, 4, 1e-9);
  EXPECT_NE(bond.reason.find("scaled contact"), std::string::npos);
  // Sakai: equivalent E* l^2.5 on l times larger particles: Hertz time invariant, Rayleigh l^-0.25.
  const TimeStepEstimate sk = estimate_for("sakai", 4);
  EXPECT_NEAR(sk.contact_time / orig.contact_time, 1, 1e-9);
  // Chen-Elliott's scaled contact itself also has an invariant Hertz time (E* k^2.5).
  const TimeStepEstimate hu2 = estimate_for("hu_method2", 4);
  EXPECT_NEAR(hu2.contact_time / orig.contact_time, std::pow(4.0, (6 - 1 - 3.0) / 5), 1e-9);
}

TEST(ScalingLaws, WarnsWhenTheContainerHoldsFewerThanFortyCoarseDiameters) {
  auto warnings = [](const std::string& body, const std::string& group) {
    const std::string text = R"(materials: {m: {density: 1000, youngs_modulus: 1e6, eepa: {k1: 1e4, k2: 2e4}}}
gravity: [0, 0, -9.81]
time: {end: 1}
)" + body + "groups: [" + group +
                             "]\n";
    return resolution_warnings(parse_scene_text(text, "w.yaml"));
  };
  const std::string hu_box =
      "domain: {lo: [0, 0, 0], hi: [0.01, 0.01, 0.03], periodic: [true, true, false]}\n"
      "walls: [{name: floor, material: m}, {name: piston, material: m, point: [0, 0, 0.03],"
      " normal: [0, 0, -1]}]\n";
  auto group = [](double r, const std::string& law, double k) {
    return "{name: g, material: m, count: 1, size: {radius: " + std::to_string(r) +
           "}, placement: {type: lattice}, coarse_grain: {law: " + law + ", factor: " + std::to_string(k) +
           "}}";
  };
  // Hu's shrunk compression box at l = 4: 10 mm / 2 mm = 5 across (the floor-piston height, along gravity,
  // is not a width); even the originals have only 20.
  auto w = warnings(hu_box, group(0.00025, "hu_method1", 4));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("periodic length along x is 10 mm = 5 coarse diameters"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("even the original particles have D/d = 20"), std::string::npos) << w[0];
  EXPECT_TRUE(warnings(hu_box, group(0.00025, "none", 1)).empty()); // no coarse-graining, no warning
  // Chen's drum, 84 mm across: 0.5 mm originals at k = 2 have D/d = 42 (fine), at k = 4 only 21.
  const std::string drum = "domain: {lo: [-0.05, -0.05, 0], hi: [0.05, 0.05, 0.02]}\n"
                           "walls: [{name: drum, type: cylinder, material: m, axis: [1, 0, 0],"
                           " point: [-0.01, 0, 0.01], radius: 0.042, length: 0.02}]\n";
  EXPECT_TRUE(warnings(drum, group(0.0005, "chen_elliott", 2)).empty());
  w = warnings(drum, group(0.0005, "chen_elliott", 4));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("cylinder 'drum' diameter is 84 mm = 21 coarse diameters"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("use k <= 2.1"), std::string::npos) << w[0];
  // Thakur's box: side walls 50 mm apart, R 3.75 mm coarse particles: 6.67 across.
  const std::string box = "contact: {normal: eepa}\n"
                          "domain: {lo: [-0.08, -0.08, 0], hi: [0.08, 0.08, 0.16]}\n"
                          "walls: [{name: left, material: m, point: [-0.025, 0, 0], normal: [1, 0, 0]},"
                          " {name: right, material: m, point: [0.025, 0, 0], normal: [-1, 0, 0]}]\n";
  w = warnings(box, group(0.0025, "thakur", 1.5));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("gap between walls 'left' and 'right' is 50 mm = 6.67 coarse diameters"),
            std::string::npos)
      << w[0];
}
