#include "core/time_step.hpp"
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include "core/materials.hpp"

namespace cgdem {

double rayleigh_time(double radius, double density, double youngs_modulus, double poisson_ratio) {
  const double shear = youngs_modulus / (2 * (1 + poisson_ratio));
  return M_PI * radius * std::sqrt(density / shear) / (0.1631 * poisson_ratio + 0.8766);
}

double hertz_contact_time(double m_eff, double r_eff, double e_eff, double speed) {
  return 2.868 * std::pow(m_eff * m_eff / (r_eff * e_eff * e_eff * speed), 0.2);
}

TimeStepEstimate estimate_time_step(const Scene& scene, const ParticleSet& ps) {
  const std::size_t nm = scene.materials.size();
  const double inf = std::numeric_limits<double>::infinity();
  // Smallest radius and its density per material.
  std::vector<double> rmin(nm, inf), rho(nm, 0);
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const int m = ps.material[i];
    if (ps.radius[i] < rmin[m]) {
      rmin[m] = ps.radius[i];
      rho[m] = ps.density[i];
    }
  }
  // Characteristic impact speed: initial speeds, moving walls, free fall over the domain height, 1 m/s floor.
  double speed = 1.0;
  for (const auto& v : ps.velocity) speed = std::max(speed, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  for (const WallSpec& w : scene.walls) {
    speed = std::max(speed, std::sqrt(w.velocity[0] * w.velocity[0] + w.velocity[1] * w.velocity[1] +
                                      w.velocity[2] * w.velocity[2]));
    speed = std::max(speed, std::fabs(w.angular_velocity) * w.radius);
  }
  const double g = std::sqrt(scene.gravity[0] * scene.gravity[0] + scene.gravity[1] * scene.gravity[1] +
                             scene.gravity[2] * scene.gravity[2]);
  double height = 0;
  for (int a = 0; a < 3; ++a) height = std::max(height, scene.domain.hi[a] - scene.domain.lo[a]);
  speed = std::max(speed, std::sqrt(2 * g * height));

  TimeStepEstimate e;
  e.rayleigh_time = inf;
  e.contact_time = inf;
  std::string tr_material, tc_pair;
  const bool linear = scene.contact.normal == "linear";
  const bool eepa = scene.contact.normal == "eepa";
  for (std::size_t a = 0; a < nm; ++a) {
    if (!(rmin[a] < inf)) continue;
    const MaterialSpec& ma = scene.materials[a];
    if (!linear && !eepa && ma.youngs_modulus > 0) {
      const double tr = rayleigh_time(rmin[a], rho[a], ma.youngs_modulus, ma.poisson_ratio);
      if (tr < e.rayleigh_time) {
        e.rayleigh_time = tr;
        tr_material = ma.name;
      }
    }
    auto consider = [&](std::size_t b, bool wall) {
      const MaterialSpec& mb = scene.materials[b];
      const double ra = rmin[a], rb = wall ? inf : rmin[b];
      const double mass_a = rho[a] * 4.0 / 3.0 * M_PI * ra * ra * ra;
      const double mass_b = wall ? inf : rho[b] * 4.0 / 3.0 * M_PI * rb * rb * rb;
      const double m_eff = wall ? mass_a : mass_a * mass_b / (mass_a + mass_b);
      const double r_eff = wall ? ra : ra * rb / (ra + rb);
      const models::PairParameters p = mix_pair(ma, mb, false);
      double tc = inf;
      if (linear && p.k_n > 0) tc = M_PI * std::sqrt(m_eff / p.k_n);
      else if (eepa && std::max(p.eepa_k1, p.eepa_k2) > 0) tc = M_PI * std::sqrt(m_eff / std::max(p.eepa_k1, p.eepa_k2));
      else if (p.E_eff > 0) tc = hertz_contact_time(m_eff, r_eff, p.E_eff, speed);
      if (tc < e.contact_time) {
        e.contact_time = tc;
        tc_pair = ma.name + (wall ? "-wall " : "-") + mb.name;
      }
    };
    for (std::size_t b = 0; b < nm; ++b) {
      if (rmin[b] < inf) consider(b, false);
    }
    for (const WallSpec& w : scene.walls) {
      const int b = scene.material_index(w.material);
      if (b >= 0) consider(static_cast<std::size_t>(b), true);
    }
  }
  const double by_rayleigh = 0.3 * e.rayleigh_time, by_contact = e.contact_time / 10;
  e.limit = std::min(by_rayleigh, by_contact);
  std::ostringstream why;
  if (by_contact <= by_rayleigh)
    why << "contact time / 10 of " << tc_pair << " (" << scene.contact.normal << ", t_c = " << e.contact_time
        << " s" << (linear || eepa ? "" : " at " + std::to_string(speed) + " m/s") << ")";
  else
    why << "0.3 x Rayleigh time of " << tr_material << " (T_R = " << e.rayleigh_time << " s)";
  if (scene.time.step > 0) {
    e.step = scene.time.step;
    std::ostringstream r;
    r << "given in the scene (stable limit " << e.limit << " s from " << why.str() << ")";
    e.reason = r.str();
  } else {
    e.step = scene.time.fraction * e.limit;
    std::ostringstream r;
    r << "auto: " << scene.time.fraction << " x " << e.limit << " s, the " << why.str();
    e.reason = r.str();
  }
  return e;
}

} // namespace cgdem
