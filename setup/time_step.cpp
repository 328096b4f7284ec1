#include "setup/time_step.hpp"
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include "setup/materials.hpp"
#include "setup/scaling.hpp"
#include "models/component_lists.hpp"

namespace cgdem {

double rayleigh_time(double radius, double density, double youngs_modulus, double poisson_ratio) {
  const double shear = youngs_modulus / (2 * (1 + poisson_ratio));
  return M_PI * radius * std::sqrt(density / shear) / (0.1631 * poisson_ratio + 0.8766);
}

double hertz_contact_time(double m_eff, double r_eff, double e_eff, double speed) {
  return 2.868 * std::pow(m_eff * m_eff / (r_eff * e_eff * e_eff * speed), 0.2);
}

TimeStepEstimate estimate_time_step(const Scene& scene, const ParticleSet& ps) {
  const double inf = std::numeric_limits<double>::infinity();
  const ScalingLaw law = scene_scaling_law(scene);
  const double gamma_power = scene_surface_energy_power(scene);
  // How the limit is evaluated under coarse-graining: on the original particles (chen_elliott: times 1,
  // hu_method1: times l), or on the coarse particles with the scaled (parameter laws) or equivalent
  // (hu_method2/3, sakai) contact.
  const bool on_originals = law == ScalingLaw::ChenElliott || law == ScalingLaw::HuMethod1;
  const DirectExponents ex = direct_exponents(law);
  const ScaledTables tables = scaled_tables(scene);
  const std::vector<MaterialSlot>& slots = tables.slots;
  const std::size_t ns = slots.size();
  // Smallest radius and its density per material slot (material, factor).
  std::vector<double> rmin(ns, inf), rho(ns, 0);
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const int g = i < ps.group.size() ? ps.group[i] : -1;
    const int m = g >= 0 && g < static_cast<int>(tables.slot_of_group.size()) ? tables.slot_of_group[g]
                                                                              : ps.material[i];
    if (ps.radius[i] < rmin[m]) {
      rmin[m] = ps.radius[i];
      rho[m] = ps.density[i];
    }
  }
  // Characteristic impact speed: initial speeds, moving walls, free fall over the domain height, 1 m/s floor.
  double speed = 1.0;
  for (const auto& v : ps.velocity)
    speed = std::max(speed, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  for (const WallSpec& w : scene.walls) {
    speed = std::max(speed, std::sqrt(w.velocity[0] * w.velocity[0] + w.velocity[1] * w.velocity[1] +
                                      w.velocity[2] * w.velocity[2]));
    speed = std::max(speed, std::fabs(w.angular_velocity) * w.reach_radius());
    speed = std::max(speed, 2 * M_PI * w.oscillation.frequency * w.oscillation.amplitude);
  }
  const double g = std::sqrt(scene.gravity[0] * scene.gravity[0] + scene.gravity[1] * scene.gravity[1] +
                             scene.gravity[2] * scene.gravity[2]);
  double height = 0;
  for (int a = 0; a < 3; ++a)
    height = std::max(height, scene.domain.hi[a] - scene.domain.lo[a]);
  speed = std::max(speed, std::sqrt(2 * g * height));

  TimeStepEstimate e;
  e.rayleigh_time = inf;
  e.contact_time = inf;
  std::string tr_material, tc_pair, accuracy_pair;
  double accuracy = inf;
  // Spring-like normal laws (linear, EEPA) have a contact time from their stiffness and no Rayleigh limit.
  const bool spring = models::is_spring_like(scene.contact.normal);
  double (*spring_stiffness)(const models::PairParameters&) = nullptr;
  models::for_each_type(models::NormalLaws{}, [&](auto normal) {
    using C = typename decltype(normal)::type;
    if constexpr (models::IsSpringLike<C>::value)
      if (scene.contact.normal == C::name)
        spring_stiffness = [](const models::PairParameters& p) { return double(C::spring_stiffness(p)); };
  });
  // Parameters the limit is evaluated with, for an original pair P at pair factor k.
  const auto evaluated = [&](const models::PairParameters& P, double k) {
    if (on_originals) return P;
    if (!is_direct(law)) return scale_pair(P, law, k, gamma_power);
    models::PairParameters q = P;
    const double hp = std::pow(k, ex.hertz_modulus_power()), sp = std::pow(k, ex.spring_power());
    q.E_eff *= hp;
    q.G_eff *= hp;
    models::for_each_component([&](auto component) {
      using C = typename decltype(component)::type;
      models::for_each_material_parameter<C>([&](const char*, const models::MaterialParameter& d) {
        if (d.scales == models::Scales::stiffness) q.*d.pair *= sp;
      });
    });
    return q;
  };
  const auto slot_name = [&](std::size_t a) {
    std::string n = scene.materials[slots[a].material].name;
    if (slots[a].factor != 1) n += "@k=" + std::to_string(slots[a].factor).substr(0, 4);
    return n;
  };
  for (std::size_t a = 0; a < ns; ++a) {
    if (!(rmin[a] < inf)) continue;
    const MaterialSpec& ma = scene.materials[slots[a].material];
    const double ka = slots[a].factor;
    if (!spring && ma.youngs_modulus > 0) {
      double tr;
      if (on_originals)
        tr = rayleigh_time(rmin[a] / ka, rho[a], ma.youngs_modulus, ma.poisson_ratio) *
             (law == ScalingLaw::HuMethod1 ? ka : 1.0);
      else if (is_direct(law))
        tr = rayleigh_time(rmin[a], rho[a], ma.youngs_modulus * std::pow(ka, ex.hertz_modulus_power()),
                           ma.poisson_ratio);
      else {
        const MaterialSpec sm = scale_material(ma, law, ka, gamma_power);
        tr = rayleigh_time(rmin[a], rho[a], sm.youngs_modulus, sm.poisson_ratio);
      }
      if (tr < e.rayleigh_time) {
        e.rayleigh_time = tr;
        tr_material = slot_name(a);
      }
    }
    auto consider = [&](std::size_t b, bool wall) {
      const MaterialSpec& mb = scene.materials[slots[b].material];
      const double k = pair_scale_factor(ka, wall ? 0.0 : slots[b].factor);
      const double ra = rmin[a], rb = wall ? inf : rmin[b];
      const double mass_a = rho[a] * 4.0 / 3.0 * M_PI * ra * ra * ra;
      const double mass_b = wall ? inf : rho[b] * 4.0 / 3.0 * M_PI * rb * rb * rb;
      double m_eff = wall ? mass_a : mass_a * mass_b / (mass_a + mass_b);
      double r_eff = wall ? ra : ra * rb / (ra + rb);
      if (on_originals) {
        m_eff /= k * k * k;
        r_eff /= k;
      }
      const models::PairParameters p = evaluated(mix_pair(ma, mb, false, scene.contact), k);
      double tc = inf;
      if (spring) {
        const double stiffness = spring_stiffness(p);
        if (stiffness > 0) tc = M_PI * std::sqrt(m_eff / stiffness);
      } else if (p.E_eff > 0)
        tc = hertz_contact_time(m_eff, r_eff, p.E_eff, speed);
      if (law == ScalingLaw::HuMethod1) tc *= k;
      const models::PairParameters adh =
          evaluated(mix_pair(ma, mb, !wall || scene.contact.wall_adhesion, scene.contact), k);
      if (scene.contact.normal == "jkr" && adh.surface_energy > 0 && adh.E_eff > 0) {
        // JKR length scale u = (pi^2 gamma^2 R* / E*^2)^(1/3); relative speeds reach twice a particle's.
        const double u = std::cbrt(M_PI * M_PI * adh.surface_energy * adh.surface_energy * r_eff /
                                   (adh.E_eff * adh.E_eff));
        const double step = 2e-3 * u / (2 * speed) * (law == ScalingLaw::HuMethod1 ? k : 1.0);
        if (step < accuracy) {
          accuracy = step;
          accuracy_pair = slot_name(a) + (wall ? "-wall " + mb.name : "-" + slot_name(b));
        }
      }
      if (tc < e.contact_time) {
        e.contact_time = tc;
        tc_pair = slot_name(a) + (wall ? "-wall " + mb.name : "-" + slot_name(b));
      }
    };
    for (std::size_t b = 0; b < ns; ++b) {
      if (rmin[b] < inf) consider(b, false);
    }
    for (const WallSpec& w : scene.walls) {
      const int b = scene.material_index(w.material);
      if (b >= 0) consider(static_cast<std::size_t>(b), true);
    }
  }
  if (law != ScalingLaw::None) {
    std::ostringstream r;
    r << scaling_law_name(law) << " (k =";
    std::vector<double> seen;
    for (const GroupSpec& gs : scene.groups)
      if (std::find(seen.begin(), seen.end(), group_scale_factor(gs)) == seen.end()) {
        seen.push_back(group_scale_factor(gs));
        r << (seen.size() > 1 ? ", " : " ") << seen.back();
      }
    r << "): ";
    if (law == ScalingLaw::ChenElliott && gamma_power >= 0)
      r << "the original particles' step (the Hertz contact time is invariant under the law; surface energy "
           "~ k^"
        << gamma_power << " changes the adhesive part)";
    else if (law == ScalingLaw::ChenElliott)
      r << "the original particles' step (contact time invariant under the law)";
    else if (law == ScalingLaw::HuMethod1)
      r << "l x the original particles' step (Hu eqs 38-41)";
    else if (is_direct(law))
      r << "the scaled contact's step (equivalent coarse contact, E* x l^" << ex.hertz_modulus_power()
        << ", springs x l^" << ex.spring_power() << ")";
    else
      r << "the scaled contact's step (parameters scaled by the law on the coarse particles)";
    e.rule = r.str();
  }
  const double by_rayleigh = 0.3 * e.rayleigh_time, by_contact = e.contact_time / 10;
  e.limit = std::min(by_rayleigh, by_contact);
  e.accuracy_step = accuracy;
  std::ostringstream why;
  if (by_contact <= by_rayleigh)
    why << "contact time / 10 of " << tc_pair << " (" << scene.contact.normal << ", t_c = " << e.contact_time
        << " s" << (spring ? "" : " at " + std::to_string(speed) + " m/s") << ")";
  else
    why << "0.3 x Rayleigh time of " << tr_material << " (T_R = " << e.rayleigh_time << " s)";
  if (!e.rule.empty()) why << "; coarse-graining " << e.rule;
  if (scene.time.step > 0) {
    e.step = scene.time.step;
    std::ostringstream r;
    r << "given in the scene (stable limit " << e.limit << " s from " << why.str() << ")";
    e.reason = r.str();
  } else {
    e.step = scene.time.fraction * e.limit;
    std::ostringstream r;
    r << "auto: " << scene.time.fraction << " x " << e.limit << " s, the " << why.str();
    if (scene.time.resolve_adhesion && accuracy < e.step) {
      e.step = accuracy;
      r.str("");
      r << "auto: JKR snap-in/snap-off resolution of " << accuracy_pair << " (v dt = 2e-3 u at " << 2 * speed
        << " m/s; stable limit " << e.limit << " s from " << why.str() << ")";
    }
    e.reason = r.str();
  }
  return e;
}

} // namespace cgdem
