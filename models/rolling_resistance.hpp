#pragma once
// Rolling resistance components (docs/physics.md 3). Both return the torque on i; the (j, i) view of a pair
// sees the negated relative rotation. The normal load |F_n| is taken as nr.friction_load: it equals the
// normal force for the non-adhesive laws and is the effective (Coulomb) load of the adhesive ones
// (Thornton & Yin's |F_JKR + 2 F_c|, EEPA's |f_hys + k_adh delta - f0|), so sliding and rolling resistance
// see the same load and an adhesive contact at zero net force still resists rolling.
#include "models/contact_law.hpp"

namespace cgdem::models {

// Constant directional torque, EDEM type A (Thakur eq 11):
//   tau_r,i = -mu_r |F_n| R_i omega_i / |omega_i|
// using the particle's OWN angular velocity omega_i (PairState::omega_i), as docs/physics.md 3.8 states, not the
// relative rotation omega_i - omega_j of the common CDT variant. Zero when omega_i = 0. No history.
struct RollingConstantTorque {
  static constexpr int history_size = 0;
  static constexpr bool history_antisymmetric = false;
  static constexpr const char* name = "constant_torque";

  KOKKOS_INLINE_FUNCTION RollingTorque operator()(const PairParameters& p, const PairState& s, const NormalResult& nr,
                                                  Real*) const {
    // Each particle's torque opposes its own rotation (not antisymmetric: computed for both sides).
    RollingTorque t;
    const Real load = p.mu_roll * nr.friction_load;
    const Real wi = norm(s.omega_i), wj = norm(s.omega_j);
    if (wi > 0) t.on_i = (-load * s.radius_i / wi) * s.omega_i;
    if (wj > 0) t.on_j = (-load * s.radius_j / wj) * s.omega_j;
    return t;
  }
};

// Elastic-plastic spring (Ai, Chen, Rotter & Ooi 2011, type C), spring part only:
//   M_r = -k_r theta_r, k_r = 2.25 k_n mu_r^2 R*^2 (k_n = nr.stiffness), |M_r| <= mu_r R* |F_n|,
// theta_r the accumulated relative rolling rotation, integrated from (omega_i - omega_j) with its
// component along n removed (twisting is not rolling). Like MindlinTangential, the stored angle is kept
// in the current tangent plane with its length preserved, and when the cap is reached it is rescaled so
// that the spring alone gives the capped torque (full mobilisation, where Ai's damper is switched off).
// Ai's viscous damper M_d = -eta_r 2 sqrt(I_r k_r) omega_r is NOT included: it needs each particle's
// moment of inertia (I_r from I_i + m_i R_i^2 and I_j + m_j R_j^2), which PairState does not carry, and a
// separate damping ratio eta_r; the rolling spring is then undamped in the pre-mobilisation regime.
//
// History (3 Reals): accumulated relative rolling rotation theta_r (rad, a tangent-plane vector).
struct RollingSpringDashpot {
  static constexpr int history_size = 3;
  static constexpr bool history_antisymmetric = true;  // a relative rotation angle
  static constexpr const char* name = "spring_dashpot";

  KOKKOS_INLINE_FUNCTION RollingTorque operator()(const PairParameters& p, const PairState& s, const NormalResult& nr,
                                                  Real* h) const {
    const Real k_r = 2.25 * nr.stiffness * p.mu_roll * p.mu_roll * s.radius_eff * s.radius_eff;
    const Real limit = p.mu_roll * s.radius_eff * nr.friction_load;
    Vec3 theta{h[0], h[1], h[2]};
    const Real len2 = norm2(theta);
    if (len2 > 0) {
      theta -= dot(theta, s.normal) * s.normal;
      const Real proj2 = norm2(theta);
      if (proj2 > 0) theta *= math::sqrt(len2 / proj2);
    }
    const Vec3 w = s.relative_rotation - dot(s.relative_rotation, s.normal) * s.normal;
    theta += s.dt * w;
    Vec3 torque = -k_r * theta;
    const Real t2 = norm2(torque);
    if (t2 > limit * limit) {
      if (k_r > 0) {
        torque *= limit / math::sqrt(t2);
        theta = (-1.0 / k_r) * torque;
      } else {
        torque = Vec3{};
        theta = Vec3{};
      }
    }
    if (!(k_r > 0)) theta = Vec3{};
    h[0] = theta.x;
    h[1] = theta.y;
    h[2] = theta.z;
    return RollingTorque{torque, -torque};  // acts on the relative rotation: equal and opposite
  }
};

} // namespace cgdem::models
