#pragma once
// Everything the engine needs to start, resolved on the host from a Scene (drivers/engine_setup.cpp):
// particles with masses, the mixed pair-parameter tables, wall parts, the time step and neighbour skin.
#include <string>
#include <vector>
#include "core/domain.hpp"
#include "core/scene.hpp"
#include "core/wall.hpp"
#include "models/pair_parameters.hpp"

namespace cgdem {

struct EngineConfig {
  ParticleSet particles;
  std::vector<double> scale_factor; // per particle (coarse-graining factor of its group)
  int num_materials = 0;
  std::vector<models::PairParameters> pair_params; // num_materials^2, row-major, symmetric
  std::vector<models::PairParameters> wall_params; // particle material x wall material
  std::vector<Wall> walls;                         // wall parts (cylinder caps expanded)
  std::vector<TriangleMeshData> meshes;            // of the mesh parts (Wall::mesh indexes this)
  std::vector<std::string> wall_names;             // named walls; Wall::owner indexes this
  Domain domain;
  Vec3 gravity;
  double dt = 0;
  double skin = 0;
  double reach = 0;      // longest interaction range beyond touching (adhesion, bridges)
  int reorder_every = 1; // spatial reorder every N list builds (0: never)
  // How the force pass shares the pairs among threads (kernels/contact_forces.hpp): "blocks", "pairs", or
  // "auto" (the backend's own: blocks on host threads, pairs on a device).
  std::string force_pass = "auto";
  double max_overlap_fraction = 0.5;
  ContactSpec contact;
  // For particles added during the run (inlets): each group's material slot and scale factor, and the
  // largest radius any particle will have (the cell grid and the interaction reach are sized for it).
  std::vector<int> group_slot;
  std::vector<double> group_scale;
  double max_radius = 0;
  bool resizable = false; // the particle count may change (restore accepts another count)
};

} // namespace cgdem
