#pragma once
// Incremental tangential spring with Coulomb limit (Mindlin no-slip stiffness from the normal law,
// LAMMPS/LIGGGHTS "history" style). History: the accumulated tangential displacement xi (3 Reals),
// rotated into the current tangent plane each step with its length kept, so a rolling pair does
// not lose or gain spring energy by the rotation of the normal.
//   F_t = -(k_t xi + c_t v_t); if |F_t| > mu * load the force is capped and xi rescaled so that the
//   spring alone gives the capped force (the dashpot is not stored).
#include "models/contact_law.hpp"

namespace cgdem::models {

struct MindlinTangential {
  static constexpr int history_size = 3;
  static constexpr bool history_antisymmetric = true;
  static constexpr const char* name = "mindlin";

  KOKKOS_FORCEINLINE_FUNCTION Vec3 operator()(const PairParameters& p, const PairState& s,
                                              const NormalResult& nr, Real* h) const {
    Vec3 xi{h[0], h[1], h[2]};
    // Rotate the stored displacement into the current tangent plane, keeping its length.
    const Real len2 = norm2(xi);
    if (len2 > 0) {
      xi -= dot(xi, s.normal) * s.normal;
      const Real proj2 = norm2(xi);
      if (proj2 > 0) xi *= math::sqrt(len2 / proj2);
    }
    xi += s.dt * s.tangential_velocity;
    Vec3 ft = (-nr.k_t) * xi - nr.c_t * s.tangential_velocity; // = -(k_t xi + c_t v_t), without the negation
    const Real limit = p.mu_slide * nr.friction_load;
    const Real ft2 = norm2(ft);
    if (ft2 > limit * limit) {
      if (ft2 > 0 && nr.k_t > 0) {
        ft *= limit / math::sqrt(ft2);
        xi = (-1.0 / nr.k_t) * ft;
      } else {
        ft = Vec3{};
        xi = Vec3{};
      }
    }
    h[0] = xi.x;
    h[1] = xi.y;
    h[2] = xi.z;
    return ft;
  }
};

} // namespace cgdem::models
