#pragma once
// Small scenes built in code for the physics tests (no YAML), and helpers to run them.
#include <cmath>
#include <cstdlib>
#include <memory>
#include <random>
#include "setup/time_step.hpp"
#include "drivers/engine_setup.hpp"
#include "kernels/engine.hpp"

namespace cgdem::testing {

inline MaterialSpec material(const std::string& name, double density, double E, double nu, double e,
                             double mu) {
  MaterialSpec m;
  m.name = name;
  m.density = density;
  m.youngs_modulus = E;
  m.poisson_ratio = nu;
  m.restitution = e;
  m.friction = mu;
  return m;
}

inline Scene basic_scene(const std::vector<MaterialSpec>& materials, const std::string& normal = "hertz",
                         const std::string& tangential = "mindlin") {
  Scene s;
  s.source_file = "<test>";
  s.domain.lo = {-0.1, -0.1, -0.1};
  s.domain.hi = {0.1, 0.1, 0.1};
  s.gravity = {0, 0, 0};
  s.materials = materials;
  s.contact.normal = normal;
  s.contact.tangential = tangential;
  GroupSpec g;
  g.name = "all";
  g.material = materials.front().name;
  s.groups.push_back(g);
  return s;
}

inline void add_particle(ParticleSet& p, const Vec3d& x, const Vec3d& v, double radius, double density,
                         int material = 0) {
  p.id.push_back(static_cast<std::int64_t>(p.id.size()) + 1);
  p.position.push_back(x);
  p.velocity.push_back(v);
  p.angular_velocity.push_back({0, 0, 0});
  p.radius.push_back(radius);
  p.density.push_back(density);
  p.material.push_back(material);
  p.group.push_back(0);
}

// Backend "auto": Serial for a few particles (a handful of pairs gains nothing from threads and pays a
// barrier per kernel), OpenMP otherwise, with the backend's own force pass. Trajectories are identical
// either way. CGDEM_TEST_BACKEND and CGDEM_TEST_FORCE_PASS, when set, override both (even a test's explicit
// backend): ctest runs the engine and physics suites once more on every compiled backend with every force
// pass (CMakeLists.txt).
inline std::unique_ptr<Engine> make(const Scene& scene, const ParticleSet& p, double dt,
                                    const std::string& backend = "auto", double skin = -1) {
  TimeStepEstimate e = estimate_time_step(scene, p);
  e.step = dt;
  EngineConfig c = make_engine_config(scene, p, e);
  if (skin >= 0) c.skin = skin;
  if (const char* pass = std::getenv("CGDEM_TEST_FORCE_PASS")) c.force_pass = pass;
  if (const char* forced = std::getenv("CGDEM_TEST_BACKEND")) return make_engine(c, forced);
  return make_engine(c, backend != "auto" ? backend : (p.size() < 1000 ? "serial" : "openmp"));
}

// Random non-overlapping spheres in a periodic cube (simple rejection with a brute-force check; tests only).
inline ParticleSet random_periodic(int n, double box, double rmin, double rmax, double density, double speed,
                                   unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  ParticleSet p;
  int tries = 0;
  while (static_cast<int>(p.size()) < n && tries < 200 * n) {
    ++tries;
    const double r = rmin + (rmax - rmin) * u(rng);
    const Vec3d x{box * u(rng), box * u(rng), box * u(rng)};
    bool ok = true;
    for (std::size_t k = 0; k < p.size() && ok; ++k) {
      double d2 = 0;
      for (int a = 0; a < 3; ++a) {
        double d = x[a] - p.position[k][a];
        d -= box * std::round(d / box);
        d2 += d * d;
      }
      const double rr = r + p.radius[k];
      ok = d2 > rr * rr;
    }
    if (!ok) continue;
    const double cz = 2 * u(rng) - 1, phi = 2 * M_PI * u(rng), sz = std::sqrt(1 - cz * cz);
    add_particle(p, x, {speed * sz * std::cos(phi), speed * sz * std::sin(phi), speed * cz}, r, density);
  }
  return p;
}

} // namespace cgdem::testing
