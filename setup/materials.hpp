#pragma once
// Mixing of material parameters into per-pair tables (docs/physics.md section 1): E*, G*, restitution and
// its damping coefficient, friction, the linear and EEPA springs and the adhesion parameters of a pair.
// Host only; the tables go to the device once.
#include <string>
#include <vector>
#include "core/scene.hpp"
#include "models/pair_parameters.hpp"

namespace cgdem {

// Parameters of the pair (a, b); b may be a wall material. `adhesive` false zeroes every attractive
// parameter (surface energy, liquid, EEPA k_adh and pull-off) so the pair is purely repulsive. `contact`
// selects the damping rule for its normal law and the JKR separation rule.
models::PairParameters mix_pair(const MaterialSpec& a, const MaterialSpec& b, bool adhesive,
                                const ContactSpec& contact);

// Damping coefficient eta of a pair with restitution e under the scene's normal law and damping rule. A JKR
// pair without surface energy runs as Hertz-Tsuji (force held >= 0) and gets that law's coefficient. Adhesive
// JKR and DMT pairs under contact.restitution_speed_ratio get the coefficient solved at that impact speed.
double damping_coefficient(double restitution, const ContactSpec& contact, double surface_energy = 1);

// The lever arm the scene uses: contact.lever_arm, with auto resolved (radius under chen_elliott,
// contact_point otherwise).
std::string resolved_lever_arm(const Scene& scene);

// Full tables (num_materials^2, row-major) with the scene's per-pair overrides applied.
std::vector<models::PairParameters> pair_table(const Scene& scene, bool wall_table);

} // namespace cgdem
