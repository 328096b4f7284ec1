#include "setup/materials.hpp"
#include <cmath>
#include "setup/restitution.hpp"
#include "models/jkr_relation.hpp"

namespace cgdem {

namespace {
// Pair value of a per-material coefficient: the mean, so that like pairs keep their own value.
double mean(double x, double y) {
  return 0.5 * (x + y);
}
// Per-contact value of a per-contact stiffness given by each material (EEPA): the harmonic mean, i.e. two
// half-contacts in series; like pairs keep their own value, and a zero of either side gives zero.
double harmonic_mean(double x, double y) {
  return x > 0 && y > 0 ? 2 * x * y / (x + y) : 0.0;
}
} // namespace

double damping_coefficient(double restitution, const ContactSpec& contact, double surface_energy) {
  const double beta = restitution_beta(restitution);
  if (contact.normal == "linear" || contact.normal == "eepa") return -2 * beta; // exact for a linear spring
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
  // Linear spring-dashpot: each material's spring in series; k_t = 2/7 k_n by default.
  const auto series = [](double x, double y) { return x > 0 && y > 0 ? x * y / (x + y) : std::max(x, y); };
  p.k_n = series(a.spring_normal, b.spring_normal);
  p.k_t = series(a.spring_tangential, b.spring_tangential);
  if (p.k_t <= 0) p.k_t = 2.0 / 7.0 * p.k_n;
  // EEPA: Thakur's stiffnesses and pull-off are per contact.
  p.eepa_k1 = harmonic_mean(a.eepa_k1, b.eepa_k1);
  p.eepa_k2 = harmonic_mean(a.eepa_k2, b.eepa_k2);
  p.min_separation = std::max(a.min_separation, b.min_separation);
  if (contact.jkr_separation == "pull_off")
    p.jkr_separation_overlap = models::jkr::d_C;
  else if (contact.jkr_separation == "contact_loss")
    p.jkr_separation_overlap = 0;
  else
    p.jkr_separation_overlap = models::jkr::d_S;
  if (adhesive) {
    p.surface_energy = std::sqrt(a.surface_energy * b.surface_energy);
    p.eepa_k_adh = harmonic_mean(a.eepa_k_adh, b.eepa_k_adh);
    p.eepa_f0 = -std::sqrt(a.eepa_f0 * b.eepa_f0); // both <= 0: geometric mean, like the surface energy
    p.surface_tension = std::sqrt(a.surface_tension * b.surface_tension);
    p.contact_angle = mean(a.contact_angle, b.contact_angle);
    p.liquid_volume = std::max(a.liquid_volume, b.liquid_volume);
    p.liquid_fraction = std::max(a.liquid_fraction, b.liquid_fraction);
  }
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
