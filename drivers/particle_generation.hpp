#pragma once
// Initial particles from a scene's groups (sizes, placement, velocities) and their sanity check.
#include "core/scene.hpp"
#include "drivers/scene_parser.hpp"

namespace cgdem {

// One ParticleSet for the whole scene, groups in scene order, deterministic for the groups' seeds.
// Radii: SizeSpec (of the original particles) times the group's coarse-graining factor
// (group_scale_factor, setup/scaling.hpp, which also scales materials and forces: docs/physics.md 4);
// placement lattice / random_box / random_cylinder (random sequential addition, no overlaps, also none with
// the particles of groups placed before) / file (CSV or cgdem HDF5, taken as they are: no coarse-grain
// factor). Ids are unique: file ids are kept, generated ids continue after the largest file id (from 1).
// Throws SceneError (one line, naming the group) when a group cannot be generated.
ParticleSet generate_particles(const Scene& scene);

// Throws SceneError when a particle is outside the domain (non-periodic axes: centre outside [lo, hi];
// periodic axes: more than one box length outside), or when two particles overlap by more than
// stability.overlap_tolerance times the smaller radius (minimum image on periodic axes; skipped when
// stability.relax_initial_overlaps is true, except for coincident centres). O(N) with a cell grid.
void check_particles(const Scene& scene, const ParticleSet& particles);

// Opt-in (stability.relax_initial_overlaps): move particles apart until no two overlap (positions only,
// no energy injected; walls not considered). Returns the largest overlap / smaller radius before and after.
struct RelaxReport {
  double initial_max_overlap = 0, final_max_overlap = 0;
  int sweeps = 0;
};
RelaxReport relax_overlaps(const Scene& scene, ParticleSet& particles);

} // namespace cgdem
