#pragma once
// Coarse-graining scaling laws on the host (docs/physics.md 4, docs/coarse_graining.md).
//
// A scene names one law for all its groups (the parser enforces it); each group has its own factor k.
// Parameter laws (chen_elliott, bond, cohesion, thakur) change the contact parameters once, here; direct
// laws (hu_method1/2/3, sakai) keep the original parameters and wrap the compiled contact law in a device
// functor (models/scaling/direct_force_scaling.hpp) that evaluates the original pair and scales its force.
//
// Pair rule (mixed factors and walls): the pair's parameters are mixed from the two ORIGINAL materials as
// usual (setup/materials.cpp), then scaled as a contact with the pair factor
//   k_ij = 2 k_i k_j / (k_i + k_j)  (particle-particle: the ratio R*_coarse / R*_original for equal sizes),
//   k_iw = k_i                       (particle-wall: R* = R_i; the wall itself is never scaled).
// Equal factors give exactly the law applied to each material and then mixed (compliances add, gamma is a
// geometric mean, springs in series); but scaling the materials first would leave the wall pair out of the
// law (E* of a particle on a stiff wall not ~ k^2.5, gamma ~ k instead of k^2), breaking Chen's invariance
// of wall impacts. The direct wrappers use the same k_ij as their l.
//
// Particles of group g use material slot slot_of_group[g]: (original material, factor). Slots 0..nm-1 are
// the scene's materials at factor 1 (walls index these), further slots one per other (material, factor).
#include <string>
#include <vector>
#include "core/scene.hpp"
#include "models/pair_parameters.hpp"

namespace cgdem {

// ThakurF0Linear and ThakurF0Cubic are Thakur's law with the pull-off force scaled as k and k^3: the
// alternatives his paper rejects, kept so that a sweep can show why.
enum class ScalingLaw {
  None,
  ChenElliott,
  Bond,
  Cohesion,
  Thakur,
  ThakurF0Linear,
  ThakurF0Cubic,
  HuMethod1,
  HuMethod2,
  HuMethod3,
  Sakai
};

// Throws std::invalid_argument for an unknown name.
ScalingLaw scaling_law(const std::string& name);
const char* scaling_law_name(ScalingLaw law);
bool is_direct(ScalingLaw law);    // hu_method1/2/3, sakai
bool is_parameter(ScalingLaw law); // chen_elliott, bond, cohesion, thakur
// The laws that scale the surface energy (chen_elliott, bond, cohesion): coarse_grain.surface_energy_power
// applies to them only.
bool scales_surface_energy(ScalingLaw law);

// The scene's law (group 0's; "none" without groups).
ScalingLaw scene_scaling_law(const Scene& scene);
// Effective factor of a group: 1 under law none.
double group_scale_factor(const GroupSpec& group);

// Multipliers a parameter law applies at factor k (all 1 for none and the direct laws).
struct ParameterScaling {
  double surface_energy = 1; // gamma (JKR, DMT)
  double youngs_modulus = 1; // E, hence E* and G*
  double stiffness = 1;      // EEPA k1, k2, k_adh (and k_t = 2/7 k1); linear spring k_n, k_t
  double pull_off = 1;       // EEPA f0
};
// surface_energy_power >= 0 replaces the exponent of gamma of the laws that scale it (chen_elliott, bond,
// cohesion: coarse_grain.surface_energy_power); < 0 keeps the law's own.
ParameterScaling parameter_scaling(ScalingLaw law, double k, double surface_energy_power = -1);
// The scene's coarse_grain.surface_energy_power (group 0's; the parser makes every group's the same).
double scene_surface_energy_power(const Scene& scene);

// The law applied to one material (what a coarse particle of factor k is made of).
MaterialSpec scale_material(const MaterialSpec& original, ScalingLaw law, double k,
                            double surface_energy_power = -1);
// The law applied to the mixed parameters of an original pair at pair factor k; also records k in
// coarse_grain_factor (for every law).
models::PairParameters scale_pair(const models::PairParameters& original, ScalingLaw law, double k,
                                  double surface_energy_power = -1);
// k_ij of the pair rule above; k_j <= 0 is a wall.
double pair_scale_factor(double k_i, double k_j);

struct MaterialSlot {
  int material = 0; // index into scene.materials
  double factor = 1;
};

struct ScaledTables {
  std::vector<MaterialSlot> slots;
  std::vector<int> slot_of_group;                  // per scene group
  std::vector<models::PairParameters> pair_params; // slots^2, row-major
  std::vector<models::PairParameters> wall_params; // slots^2: (particle slot, wall material slot)
};
ScaledTables scaled_tables(const Scene& scene);

// The scene's contact spec with `scaling` set to the direct method (or "none").
ContactSpec effective_contact(const Scene& scene);

// Refuses laws that do not fit the scene's contact law (thakur needs eepa or linear; chen_elliott, bond and
// cohesion need a Hertz-based law: hertz, jkr; no parameter law scales capillary bridges). Throws
// std::invalid_argument with the reason.
void check_scaling(const Scene& scene);

// Exponents of the direct methods (docs/physics.md 4.2): original overlap = coarse overlap / l^overlap_power,
// coarse force = l^force_power original force; and what they mean for an equivalent coarse contact
// (time step): a Hertz law with E* l^hertz_modulus_power, a linear spring with k l^spring_power.
struct DirectExponents {
  int overlap_power = 0, force_power = 0, adhesion_power = 0, torque_power = 0;
  double hertz_modulus_power() const { return force_power - 0.5 - 1.5 * overlap_power; }
  double spring_power() const { return force_power - overlap_power; }
};
DirectExponents direct_exponents(ScalingLaw law);

} // namespace cgdem
