#include "setup/scaling.hpp"
#include <cmath>
#include <stdexcept>
#include "setup/materials.hpp"
#include "models/component_lists.hpp"
#include "models/scaling/direct_force_scaling.hpp"

namespace cgdem {

namespace {
struct LawName {
  ScalingLaw law;
  const char* name;
};
constexpr LawName kLaws[] = {
    {ScalingLaw::None, "none"},
    {ScalingLaw::ChenElliott, "chen_elliott"},
    {ScalingLaw::Bond, "bond"},
    {ScalingLaw::Cohesion, "cohesion"},
    {ScalingLaw::Thakur, "thakur"},
    {ScalingLaw::ThakurF0Linear, "thakur_f0_linear"},
    {ScalingLaw::ThakurF0Cubic, "thakur_f0_cubic"},
    {ScalingLaw::HuMethod1, "hu_method1"},
    {ScalingLaw::HuMethod2, "hu_method2"},
    {ScalingLaw::HuMethod3, "hu_method3"},
    {ScalingLaw::Sakai, "sakai"},
};
} // namespace

ScalingLaw scaling_law(const std::string& name) {
  for (const LawName& l : kLaws)
    if (name == l.name) return l.law;
  throw std::invalid_argument("unknown coarse-graining law '" + name + "'");
}

const char* scaling_law_name(ScalingLaw law) {
  for (const LawName& l : kLaws)
    if (law == l.law) return l.name;
  return "none";
}

bool is_direct(ScalingLaw law) {
  return law == ScalingLaw::HuMethod1 || law == ScalingLaw::HuMethod2 || law == ScalingLaw::HuMethod3 ||
         law == ScalingLaw::Sakai;
}

bool is_parameter(ScalingLaw law) {
  return law == ScalingLaw::ChenElliott || law == ScalingLaw::Bond || law == ScalingLaw::Cohesion ||
         law == ScalingLaw::Thakur || law == ScalingLaw::ThakurF0Linear || law == ScalingLaw::ThakurF0Cubic;
}

bool scales_surface_energy(ScalingLaw law) {
  return law == ScalingLaw::ChenElliott || law == ScalingLaw::Bond || law == ScalingLaw::Cohesion;
}

ScalingLaw scene_scaling_law(const Scene& scene) {
  return scene.groups.empty() ? ScalingLaw::None : scaling_law(scene.groups.front().coarse_grain.law);
}

double group_scale_factor(const GroupSpec& group) {
  return group.coarse_grain.law == "none" ? 1.0 : group.coarse_grain.factor;
}

double scene_surface_energy_power(const Scene& scene) {
  return scene.groups.empty() ? -1 : scene.groups.front().coarse_grain.surface_energy_power;
}

ParameterScaling parameter_scaling(ScalingLaw law, double k, double surface_energy_power) {
  ParameterScaling s;
  switch (law) {
  case ScalingLaw::ChenElliott: // Chen & Elliott 2020: gamma k^2, E k^2.5
    s.surface_energy = k * k;
    s.youngs_modulus = std::pow(k, 2.5);
    break;
  case ScalingLaw::Bond: // keeps F_c / m g
    s.surface_energy = k * k;
    break;
  case ScalingLaw::Cohesion: // Behjani: keeps (Gamma^5 / (E*^2 R*^8))^(1/3) / (rho g)
    s.surface_energy = std::pow(k, 1.6);
    break;
  case ScalingLaw::Thakur: // Thakur 2016: stiffnesses k, pull-off k^2
    s.stiffness = k;
    s.pull_off = k * k;
    break;
  case ScalingLaw::ThakurF0Linear:
    s.stiffness = k;
    s.pull_off = k;
    break;
  case ScalingLaw::ThakurF0Cubic:
    s.stiffness = k;
    s.pull_off = k * k * k;
    break;
  default:
    break;
  }
  if (scales_surface_energy(law) && surface_energy_power >= 0)
    s.surface_energy = std::pow(k, surface_energy_power);
  return s;
}

namespace {
// The factor of `s` that multiplies a component parameter declared to scale as `scales`.
double factor_of(const ParameterScaling& s, models::Scales scales) {
  switch (scales) {
  case models::Scales::stiffness:
    return s.stiffness;
  case models::Scales::pull_off:
    return s.pull_off;
  case models::Scales::no:
    break;
  }
  return 1;
}

// Calls f(block, declaration) for every component parameter that scales.
template <class F>
void for_each_scaled_parameter(F&& f) {
  models::for_each_component([&](auto component) {
    using C = typename decltype(component)::type;
    models::for_each_material_parameter<C>([&](const char* block, const models::MaterialParameter& d) {
      if (d.scales != models::Scales::no) f(block, d);
    });
  });
}
} // namespace

MaterialSpec scale_material(const MaterialSpec& original, ScalingLaw law, double k,
                            double surface_energy_power) {
  const ParameterScaling s = parameter_scaling(law, k, surface_energy_power);
  MaterialSpec m = original;
  m.surface_energy *= s.surface_energy;
  m.youngs_modulus *= s.youngs_modulus;
  for_each_scaled_parameter([&](const char* block, const models::MaterialParameter& d) {
    const auto it = m.law_parameters.find(models::parameter_path(block, d));
    if (it != m.law_parameters.end()) it->second *= factor_of(s, d.scales);
  });
  return m;
}

models::PairParameters scale_pair(const models::PairParameters& original, ScalingLaw law, double k,
                                  double surface_energy_power) {
  const ParameterScaling s = parameter_scaling(law, k, surface_energy_power);
  models::PairParameters p = original;
  p.surface_energy *= s.surface_energy;
  p.E_eff *= s.youngs_modulus;
  p.G_eff *= s.youngs_modulus;
  for_each_scaled_parameter(
      [&](const char*, const models::MaterialParameter& d) { p.*d.pair *= factor_of(s, d.scales); });
  p.coarse_grain_factor = k;
  return p;
}

double pair_scale_factor(double k_i, double k_j) {
  return k_j > 0 ? 2 * k_i * k_j / (k_i + k_j) : k_i;
}

ScaledTables scaled_tables(const Scene& scene) {
  const int nm = static_cast<int>(scene.materials.size());
  const ScalingLaw law = scene_scaling_law(scene);
  const double gamma_power = scene_surface_energy_power(scene);
  ScaledTables t;
  for (int m = 0; m < nm; ++m)
    t.slots.push_back({m, 1.0});
  for (const GroupSpec& g : scene.groups) {
    const int m = std::max(0, scene.material_index(g.material));
    const double k = group_scale_factor(g);
    int slot = -1;
    for (std::size_t s = 0; s < t.slots.size() && slot < 0; ++s)
      if (t.slots[s].material == m && t.slots[s].factor == k) slot = static_cast<int>(s);
    if (slot < 0) {
      slot = static_cast<int>(t.slots.size());
      t.slots.push_back({m, k});
    }
    t.slot_of_group.push_back(slot);
  }
  const std::vector<models::PairParameters> pairs = pair_table(scene, false), walls = pair_table(scene, true);
  const std::size_t ns = t.slots.size();
  t.pair_params.resize(ns * ns);
  t.wall_params.resize(ns * ns);
  for (std::size_t a = 0; a < ns; ++a)
    for (std::size_t b = 0; b < ns; ++b) {
      const MaterialSlot sa = t.slots[a], sb = t.slots[b];
      const std::size_t orig = static_cast<std::size_t>(sa.material) * nm + sb.material;
      t.pair_params[a * ns + b] =
          scale_pair(pairs[orig], law, pair_scale_factor(sa.factor, sb.factor), gamma_power);
      t.wall_params[a * ns + b] = scale_pair(walls[orig], law, pair_scale_factor(sa.factor, 0), gamma_power);
      if (!scene.groups.empty())
        t.pair_params[a * ns + b].torque_power = t.wall_params[a * ns + b].torque_power =
            scene.groups.front().coarse_grain.torque_power;
    }
  return t;
}

ContactSpec effective_contact(const Scene& scene) {
  ContactSpec c = scene.contact;
  const ScalingLaw law = scene_scaling_law(scene);
  c.scaling = is_direct(law) ? scaling_law_name(law) : "none";
  return c;
}

void check_scaling(const Scene& scene) {
  const ScalingLaw law = scene_scaling_law(scene);
  for (const GroupSpec& g : scene.groups)
    if (scaling_law(g.coarse_grain.law) != law)
      throw std::invalid_argument("coarse_grain law '" + g.coarse_grain.law + "' of group '" + g.name +
                                  "' differs from the scene's '" + scaling_law_name(law) + "'");
  const std::string& normal = scene.contact.normal;
  const bool spring = models::is_spring_like(normal);
  const bool thakur =
      law == ScalingLaw::Thakur || law == ScalingLaw::ThakurF0Linear || law == ScalingLaw::ThakurF0Cubic;
  if (thakur && !spring)
    throw std::invalid_argument(std::string("coarse_grain law ") + scaling_law_name(law) +
                                " scales EEPA / linear spring stiffnesses; the scene's "
                                "normal law is '" +
                                normal + "' (use eepa or linear, or chen_elliott for JKR/DMT/Hertz)");
  if ((law == ScalingLaw::ChenElliott || law == ScalingLaw::Bond || law == ScalingLaw::Cohesion) && spring)
    throw std::invalid_argument(std::string("coarse_grain law ") + scaling_law_name(law) +
                                " scales E and gamma of Hertz-based laws; the scene's normal law is '" +
                                normal + "' (use thakur for eepa / linear)");
  // A parameter law scales E, gamma or the EEPA springs, never a liquid bridge, whose force would then grow
  // as k where the law needs k^3 (and its rupture distance as k).
  if (is_parameter(law) && scene.contact.adhesion == "capillary")
    throw std::invalid_argument(
        std::string("coarse_grain law ") + scaling_law_name(law) +
        " does not scale capillary bridges (their force would grow as k, not k^3); use "
        "a direct force law (hu_method1, hu_method2, hu_method3 or sakai), which "
        "evaluates the original bridge and scales its force");
}

// The device methods' own exponents (models/scaling/direct_force_scaling.hpp): one table for both sides.
template <class Method>
DirectExponents exponents_of() {
  return {Method::overlap_power, Method::force_power, Method::adhesion_power, Method::torque_power};
}

DirectExponents direct_exponents(ScalingLaw law) {
  namespace ms = models::scaling;
  switch (law) {
  case ScalingLaw::HuMethod1:
    return exponents_of<ms::HuMethod1>();
  case ScalingLaw::HuMethod2:
    return exponents_of<ms::HuMethod2>();
  case ScalingLaw::HuMethod3:
    return exponents_of<ms::HuMethod3>();
  case ScalingLaw::Sakai:
    return exponents_of<ms::Sakai>();
  default:
    return {};
  }
}

} // namespace cgdem
