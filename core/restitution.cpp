#include "core/restitution.hpp"
#include <cmath>
#include <map>
#include <mutex>
#include <utility>

namespace cgdem {

double restitution_beta(double restitution) {
  if (restitution >= 1) return 0;
  const double l = std::log(restitution);
  return l / std::sqrt(l * l + M_PI * M_PI);
}

namespace {

// The scaled normal force x^(3/2) + a x^(1/4) x' (a = sqrt(3/2) eta), and the same held at >= 0 in the
// clamped form.
double unclamped_force(double x, double v, double a) {
  const double xp = x > 0 ? x : 0;
  return xp * std::sqrt(xp) + a * std::sqrt(std::sqrt(xp)) * v;
}
double scaled_force(double x, double v, double a, HertzContactEnd end) {
  const double f = unclamped_force(x, v, a);
  return (end == HertzContactEnd::Clamped && f < 0) ? 0 : f;
}

} // namespace

double hertz_restitution(double eta, HertzContactEnd end) {
  if (!(eta > 0)) return 1;
  const double a = std::sqrt(1.5) * eta;
  // Classical RK4 on (x, v) from first touch. The undamped contact lasts 3.2 time units; a step of 1e-4
  // (smaller when the damper is stiff) keeps the error of e near 1e-7, and the end of the contact is located
  // by linear interpolation between the two steps around it.
  const double h = 1e-4 / (1 + a);
  double x = 0, v = 1;
  for (long step = 0; step < 200000000L; ++step) {
    const double k1x = v, k1v = -scaled_force(x, v, a, end);
    const double k2x = v + 0.5 * h * k1v, k2v = -scaled_force(x + 0.5 * h * k1x, v + 0.5 * h * k1v, a, end);
    const double k3x = v + 0.5 * h * k2v, k3v = -scaled_force(x + 0.5 * h * k2x, v + 0.5 * h * k2v, a, end);
    const double k4x = v + h * k3v, k4v = -scaled_force(x + h * k3x, v + h * k3v, a, end);
    const double xn = x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double vn = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (vn < 0) {
      if (end == HertzContactEnd::Clamped) {
        // The surfaces part where the unclamped force first reaches zero.
        const double f0 = unclamped_force(x, v, a), f1 = unclamped_force(xn, vn, a);
        if (f1 <= 0) {
          const double t = f0 > 0 ? f0 / (f0 - f1) : 0;
          return -(v + t * (vn - v));
        }
      } else if (xn <= 0) {
        const double t = x / (x - xn);
        return -(v + t * (vn - v));
      }
    }
    x = xn;
    v = vn;
  }
  return 0; // never separated: fully damped
}

double hertz_damping_for_restitution(double restitution, HertzContactEnd end) {
  if (restitution >= 1) return 0;
  // Without the clamp, Tsuji's coefficient 2 sqrt(5/6) |beta| is exact (the forward map confirms it to
  // 1e-7 for e = 0.05..0.95; tests/test_restitution.cpp): no solve needed.
  if (end == HertzContactEnd::Unclamped) return 2 * std::sqrt(5.0 / 6.0) * -restitution_beta(restitution);
  static std::mutex mutex;
  static std::map<std::pair<double, int>, double> cache;
  const std::pair<double, int> key{restitution, static_cast<int>(end)};
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
  }
  // e(eta) falls monotonically from 1 at eta = 0: bracket the root by doubling, then regula falsi with the
  // Illinois modification until e is within 1e-9 of the target.
  double lo = 0, hi = 1;
  double f_lo = 1 - restitution, f_hi = hertz_restitution(hi, end) - restitution;
  while (f_hi > 0 && hi < 1e6) {
    lo = hi;
    f_lo = f_hi;
    hi *= 2;
    f_hi = hertz_restitution(hi, end) - restitution;
  }
  double eta = hi;
  int side = 0;
  for (int it = 0; it < 100; ++it) {
    eta = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    const double f = hertz_restitution(eta, end) - restitution;
    if (std::fabs(f) < 1e-9 || hi - lo < 1e-12 * hi) break;
    if (f > 0) {
      lo = eta;
      f_lo = f;
      if (side == -1) f_hi *= 0.5;
      side = -1;
    } else {
      hi = eta;
      f_hi = f;
      if (side == 1) f_lo *= 0.5;
      side = 1;
    }
  }
  std::lock_guard<std::mutex> lock(mutex);
  cache[key] = eta;
  return eta;
}

} // namespace cgdem
