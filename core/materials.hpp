#pragma once
// Mixing of material parameters into per-pair tables (physics.md header): E*, G*, restitution and
// friction of a pair, adhesion parameters. Host only; the tables go to the device once.
#include <vector>
#include "core/scene.hpp"
#include "models/pair_parameters.hpp"

namespace cgdem {

// Parameters of the pair (a, b); b may be a wall material. `adhesive` false zeroes every attractive
// parameter (surface energy, liquid, EEPA pull-off) so the pair is purely repulsive.
models::PairParameters mix_pair(const MaterialSpec& a, const MaterialSpec& b, bool adhesive);

// Full tables (num_materials^2, row-major) with the scene's per-pair overrides applied.
std::vector<models::PairParameters> pair_table(const Scene& scene, bool wall_table);

} // namespace cgdem
