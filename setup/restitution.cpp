#include "setup/restitution.hpp"
#include <cmath>
#include <map>
#include <mutex>
#include <tuple>
#include "models/jkr_relation.hpp"

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

// Primitive of F/F_c d(delta/u) along the JKR branch, in x: with d(x) = x^2 - 2 sqrt(x) and
// f(x) = 4/9 x^3 - 4/3 x^1.5, f d'(x) = 8/9 x^4 - 28/9 x^2.5 + 4/3 x.
double jkr_potential(double x) {
  return 8.0 / 45 * std::pow(x, 5) - 8.0 / 9 * std::pow(x, 3.5) + 2.0 / 3 * x * x;
}

// The eta >= 0 at which a restitution that falls monotonically with eta reaches `target` (0 if it is below
// the target already at eta = 0): bracket the root by doubling, then regula falsi with the Illinois
// modification until e is within 1e-9 of the target. Results are cached per key: a scene asks for the same
// few values once per material pair.
struct RootKey {
  double restitution;
  int form;
  double speed_ratio;
  bool operator<(const RootKey& o) const {
    return std::tie(restitution, form, speed_ratio) < std::tie(o.restitution, o.form, o.speed_ratio);
  }
};

template <class RestitutionOfEta>
double cached_root(const RootKey& key, RestitutionOfEta e_of) {
  static std::mutex mutex;
  static std::map<RootKey, double> cache;
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
  }
  const double target = key.restitution;
  double lo = 0, hi = 1;
  double f_lo = e_of(0.0) - target;
  double eta = 0;
  if (f_lo > 0) {
    double f_hi = e_of(hi) - target;
    while (f_hi > 0 && hi < 1e6) {
      lo = hi;
      f_lo = f_hi;
      hi *= 2;
      f_hi = e_of(hi) - target;
    }
    eta = hi;
    int side = 0;
    for (int it = 0; it < 100; ++it) {
      eta = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
      const double f = e_of(eta) - target;
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
  }
  std::lock_guard<std::mutex> lock(mutex);
  cache[key] = eta;
  return eta;
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
  return cached_root({restitution, static_cast<int>(end), 0.0},
                     [&](double eta) { return hertz_restitution(eta, end); });
}

double jkr_sticking_speed() {
  // W_s / (F_c u): the work against the attraction from A (snap-in, d = 0) out to S.
  const double w = jkr_potential(models::jkr::x_S) - jkr_potential(models::jkr::x_A);
  return std::sqrt(2 * w);
}

double adhesive_restitution(double eta, AdhesiveCollision law, double speed_ratio) {
  const double v0 = speed_ratio * jkr_sticking_speed();
  const double a = std::sqrt(2.0 / 3.0) * (eta > 0 ? eta : 0);
  const bool dmt = law == AdhesiveCollision::Dmt;
  // Where the contact ends on the way out: the separation overlap of the JKR rule, or touching (DMT).
  const double d_end = law == AdhesiveCollision::JkrDeltaS    ? models::jkr::d_S
                       : law == AdhesiveCollision::JkrPullOff ? models::jkr::d_C
                                                              : 0.0;
  double x_guess = models::jkr::x_A;
  const auto accel = [&](double d, double v) {
    if (dmt) {
      const double dp = d > 0 ? d : 0;
      const double repulsion = 4.0 / 9.0 * dp * std::sqrt(dp) + a * std::sqrt(std::sqrt(dp)) * v;
      return -(repulsion > 0 ? repulsion : 0) + 4.0 / 3.0;
    }
    const double x = models::jkr::solve_x(d, x_guess);
    x_guess = x;
    return -models::jkr::force_of(x) - a * std::sqrt(x) * v;
  };
  // Potential of the conservative force (dU/dd = -accel without damper): P(x) along the JKR branch (see
  // jkr_sticking_speed), 8/45 d^2.5 - 4/3 d for DMT. The damper only takes energy (the clamp too), so a pair
  // whose energy 1/2 v^2 + U has fallen below U at the end of the contact never gets there: it sticks.
  const auto potential = [&](double d) {
    if (dmt) return d > 0 ? 8.0 / 45 * std::pow(d, 2.5) - 4.0 / 3 * d : 0.0;
    return jkr_potential(models::jkr::solve_x(d, x_guess));
  };
  const double u_end = potential(d_end);
  // Classical RK4 on (d, v) from first touch, as hertz_restitution. h: as there, the contact's Hertzian part
  // (d up to d_max) lasting a few time units, smaller when the damper is stiff.
  const double d_max = std::pow(45.0 / 16.0 * v0 * v0, 0.4);
  const double h = 1e-4 / (1 + a * std::sqrt(1 + std::sqrt(d_max)));
  double d = 0, v = v0;
  for (long step = 0; step < 1000000000L; ++step) {
    const double k1d = v, k1v = accel(d, v);
    const double k2d = v + 0.5 * h * k1v, k2v = accel(d + 0.5 * h * k1d, v + 0.5 * h * k1v);
    const double k3d = v + 0.5 * h * k2v, k3v = accel(d + 0.5 * h * k2d, v + 0.5 * h * k2v);
    const double k4d = v + h * k3v, k4v = accel(d + h * k3d, v + h * k3v);
    const double dn = d + h / 6 * (k1d + 2 * k2d + 2 * k3d + k4d);
    const double vn = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (vn < 0 && dn < d_end) {
      const double t = (d - d_end) / (d - dn);
      return -(v + t * (vn - v)) / v0;
    }
    d = dn;
    v = vn;
    if (0.5 * v * v + potential(d) < u_end) return 0;
  }
  return 0;
}

double adhesive_damping_for_restitution(double restitution, AdhesiveCollision law, double speed_ratio) {
  return cached_root({restitution, 10 + static_cast<int>(law), speed_ratio},
                     [&](double eta) { return adhesive_restitution(eta, law, speed_ratio); });
}

} // namespace cgdem
