#pragma once
// Host-side snapshots that the engine hands to the output writer (core/result_writer.hpp) and the
// checkpoint files (core/checkpoint.hpp). Plain std containers: the writer runs as a oneTBB host task
// while the device keeps stepping, so it owns copies, never views.
#include <cstdint>
#include <map>
#include <string>
#include <vector>
#include "core/triangle_mesh_data.hpp"
#include "core/wall.hpp"

namespace cgdem {

struct FrameData {
  double time = 0;
  std::int64_t step = 0;
  std::vector<std::int64_t> id;         // N
  std::vector<double> position;         // 3N, row-major (N x 3)
  std::vector<double> velocity;         // 3N
  std::vector<double> angular_velocity; // 3N
  std::vector<double> radius;           // N
  std::vector<double> mass;             // N
  std::vector<std::int32_t> group;      // N
  std::size_t size() const { return id.size(); }
  // Host bytes one frame takes per particle (what `cgdem check` reports per output frame).
  static constexpr std::size_t bytes_per_particle() {
    return sizeof(std::int64_t) + 3 * 3 * sizeof(double) + 2 * sizeof(double) + sizeof(std::int32_t);
  }
};

struct SeriesRow {
  double time = 0;
  std::int64_t step = 0;
  double kinetic_energy = 0;
  double rotational_energy = 0;
  std::int64_t contacts = 0;
  std::vector<double> wall_force;         // 3 per wall, in RunInfo::wall_names order
  std::vector<double> wall_torque;        // 3 per wall: moment about its point (empty: not known)
  std::map<std::string, double> analyses; // each analysis output, one column each
};

struct RunInfo {
  std::string cgdem_version;
  std::string scene_yaml; // resolved scene after overrides
  std::string backend;    // "openmp" | "serial" | ...
  int threads = 1;
  double time_step = 0;
  std::string scaling_law = "none";
  double scale_factor = 1;
  std::vector<std::string> wall_names;
  // Mesh walls, drawn in the XDMF beside the particles: triangles, vertices at time 0, and the wall's
  // motion (each frame then stores the vertices where they are, /frames/<k>/mesh_<name>).
  struct Mesh {
    std::string name;
    TriangleMeshData data;
    Wall motion;
    bool moves() const { return motion.ever_moves(); }
  };
  std::vector<Mesh> meshes;
};

// Full restart state: every per-particle field, the neighbour list's contact history and ids, wall
// history, the time and step. Named arrays so that the engine decides what it needs.
struct CheckpointData {
  double time = 0;
  std::int64_t step = 0;
  std::map<std::string, std::vector<double>> reals;
  std::map<std::string, std::vector<std::int64_t>> ints;
  std::map<std::string, double> scalars;
  std::string scene_yaml;
};

} // namespace cgdem
