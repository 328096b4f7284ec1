#include "drivers/resolution_check.hpp"
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cgdem {
namespace {

double dot3(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
double norm3(const Vec3d& a) {
  return std::sqrt(dot3(a, a));
}

// The largest ORIGINAL radius a group's size distribution can produce.
double largest_radius(const SizeSpec& s) {
  if (s.distribution == "mono") return s.radius;
  if (s.max_radius > 0) return s.max_radius;
  return s.mean_radius + 3 * s.std_radius;
}

struct Width {
  double length = 0;
  std::string what;
};

std::string mm(double m) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g mm", m * 1e3);
  return b;
}

// The narrowest bounded width of the container across gravity (any direction without gravity).
Width narrowest(const Scene& scene) {
  const double g = norm3(scene.gravity);
  auto along_gravity = [&](const Vec3d& dir) {
    return g > 0 && std::fabs(dot3(dir, scene.gravity)) > 0.9 * g * norm3(dir);
  };
  Width best{1e300, ""};
  auto consider = [&](double length, const std::string& what) {
    if (length > 0 && length < best.length) best = {length, what};
  };
  const char* axis_name[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    Vec3d e{0, 0, 0};
    e[a] = 1;
    if (scene.domain.periodic[a] && !along_gravity(e))
      consider(scene.domain.hi[a] - scene.domain.lo[a], std::string("periodic length along ") + axis_name[a]);
  }
  for (const WallSpec& w : scene.walls) {
    if (w.type == "cylinder") consider(2 * w.radius, "cylinder '" + w.name + "' diameter");
    if (w.type == "cone") consider(2 * std::min(w.radius, w.end_radius), "orifice of cone '" + w.name + "'");
    if (w.orifice > 0) consider(2 * w.orifice, "orifice of '" + w.name + "'");
  }
  for (std::size_t i = 0; i < scene.walls.size(); ++i)
    for (std::size_t j = i + 1; j < scene.walls.size(); ++j) {
      const WallSpec &a = scene.walls[i], &b = scene.walls[j];
      if (a.type != "plane" || b.type != "plane") continue;
      const double na = norm3(a.normal), nb = norm3(b.normal);
      if (dot3(a.normal, b.normal) > -0.999 * na * nb || along_gravity(a.normal)) continue; // not facing
      const Vec3d d{b.point[0] - a.point[0], b.point[1] - a.point[1], b.point[2] - a.point[2]};
      consider(dot3(d, a.normal) / na, "gap between walls '" + a.name + "' and '" + b.name + "'");
    }
  return best.what.empty() ? Width{} : best;
}

} // namespace

std::vector<std::string> resolution_warnings(const Scene& scene, double min_ratio) {
  std::vector<std::string> out;
  const Width w = narrowest(scene);
  if (w.what.empty()) return out;
  for (const GroupSpec& grp : scene.groups) {
    const double k = grp.coarse_grain.factor;
    const double d = 2 * largest_radius(grp.size);
    if (!(k > 1) || !(d > 0)) continue;
    const double ratio = w.length / (k * d);
    if (ratio >= min_ratio) continue;
    char fix[160], line[512];
    const double k_max = w.length / (min_ratio * d);
    if (k_max > 1)
      std::snprintf(fix, sizeof fix, "use k <= %.3g or widen the container", k_max);
    else
      std::snprintf(fix, sizeof fix, "even the original particles have D/d = %.3g: widen the container",
                    w.length / d);
    std::snprintf(line, sizeof line,
                  "warning: group '%s' (%s, k = %g): the %s is %s = %.3g coarse diameters across; bulk "
                  "results need D/d >= %g (Hu et al. 2022): %s",
                  grp.name.c_str(), grp.coarse_grain.law.c_str(), k, w.what.c_str(), mm(w.length).c_str(),
                  ratio, min_ratio, fix);
    out.emplace_back(line);
  }
  return out;
}

} // namespace cgdem
