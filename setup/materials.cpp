#include "setup/materials.hpp"
#include <cmath>
#include "setup/restitution.hpp"
#include "models/component_lists.hpp"
#include "models/jkr_relation.hpp"

namespace cgdem {

namespace {
// Pair value of a per-material coefficient: the mean, so that like pairs keep their own value.
double mean(double x, double y) {
  return models::mix_values(models::Mix::mean, x, y);
}
} // namespace

double damping_coefficient(double restitution, const ContactSpec& contact, double surface_energy) {
  const double beta = restitution_beta(restitution);
  if (models::is_spring_like(contact.normal)) return -2 * beta; // exact for a linear spring
  if (contact.damping == "beta_formula") return -2 * std::sqrt(5.0 / 6.0) * beta;
  const bool jkr = contact.normal == "jkr" && surface_energy > 0;
  // Adhesive pairs rebound with e at the impact speed the scene names (setup/restitution.hpp).
  if (contact.restitution_speed_ratio > 0 && (jkr || (contact.adhesion == "dmt" && surface_energy > 0))) {
    const AdhesiveCollision law = !jkr                                   ? AdhesiveCollision::Dmt
                                  : contact.jkr_separation == "pull_off" ? AdhesiveCollision::JkrPullOff
                                  : contact.jkr_separation == "contact_loss"
                                      ? AdhesiveCollision::JkrContactLoss
                                      : AdhesiveCollision::JkrDeltaS;
    return adhesive_damping_for_restitution(restitution, law, contact.restitution_speed_ratio);
  }
  // Hertz-Tsuji (and DMT on it) holds the normal force at >= 0; full JKR does not.
  const bool unclamped = jkr;
  return hertz_damping_for_restitution(restitution,
                                       unclamped ? HertzContactEnd::Unclamped : HertzContactEnd::Clamped);
}

models::PairParameters mix_pair(const MaterialSpec& a, const MaterialSpec& b, bool adhesive,
                                const ContactSpec& contact) {
  models::PairParameters p;
  const auto compliance = [](const MaterialSpec& m) {
    return m.youngs_modulus > 0 ? (1 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus : 0.0;
  };
  const auto shear_compliance = [](const MaterialSpec& m) {
    return m.youngs_modulus > 0 ? 2 * (2 - m.poisson_ratio) * (1 + m.poisson_ratio) / m.youngs_modulus : 0.0;
  };
  const double c = compliance(a) + compliance(b);
  const double cs = shear_compliance(a) + shear_compliance(b);
  p.E_eff = c > 0 ? 1 / c : 0;
  p.G_eff = cs > 0 ? 1 / cs : 0;
  p.restitution = std::min(a.restitution, b.restitution);
  p.mu_slide = mean(a.friction, b.friction);
  p.mu_roll = mean(a.rolling_friction, b.rolling_friction);
  // Each component's own parameters, by its declarations (models/material_parameters.hpp); attractive
  // ones only where the pair is adhesive.
  models::for_each_component([&](auto component) {
    using C = typename decltype(component)::type;
    models::for_each_material_parameter<C>([&](const char* block, const models::MaterialParameter& d) {
      p.*d.pair = d.attractive && !adhesive ? 0
                                            : models::mix_values(d.mix, models::material_value(a, block, d),
                                                                 models::material_value(b, block, d));
    });
    if constexpr (models::HasFinishPair<C>::value) C::finish_pair(p);
  });
  if (contact.jkr_separation == "pull_off")
    p.jkr_separation_overlap = models::jkr::d_C;
  else if (contact.jkr_separation == "contact_loss")
    p.jkr_separation_overlap = 0;
  else
    p.jkr_separation_overlap = models::jkr::d_S;
  if (adhesive) p.surface_energy = std::sqrt(a.surface_energy * b.surface_energy);
  p.damping = damping_coefficient(p.restitution, contact, p.surface_energy);
  return p;
}

std::string resolved_lever_arm(const Scene& scene) {
  if (scene.contact.lever_arm != "auto") return scene.contact.lever_arm;
  const bool chen = !scene.groups.empty() && scene.groups.front().coarse_grain.law == "chen_elliott";
  return chen ? "radius" : "contact_point";
}

std::vector<models::PairParameters> pair_table(const Scene& scene, bool wall_table) {
  const std::size_t n = scene.materials.size();
  const bool adhesive = !wall_table || scene.contact.wall_adhesion;
  const double lever_share = resolved_lever_arm(scene) == "radius" ? 0.0 : 0.5;
  std::vector<models::PairParameters> t(n * n);
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b) {
      t[a * n + b] = mix_pair(scene.materials[a], scene.materials[b], adhesive, scene.contact);
      t[a * n + b].lever_share = lever_share;
    }
  for (const PairOverrideSpec& o : scene.pair_overrides) {
    const int a = scene.material_index(o.material_a), b = scene.material_index(o.material_b);
    if (a < 0 || b < 0) continue; // the parser has already rejected unknown names
    for (auto [i, j] : {std::pair{a, b}, std::pair{b, a}}) {
      models::PairParameters& p = t[i * n + j];
      if (o.restitution > 0) p.restitution = o.restitution;
      if (o.friction >= 0) p.mu_slide = o.friction;
      if (o.rolling_friction >= 0) p.mu_roll = o.rolling_friction;
      if (o.surface_energy >= 0 && adhesive) p.surface_energy = o.surface_energy;
      p.damping = damping_coefficient(p.restitution, scene.contact, p.surface_energy);
    }
  }
  return t;
}

} // namespace cgdem
