#pragma once
// The engine as the drivers see it: one abstract host interface over Simulation<Law, ExecSpace>, so a
// run-time choice (scene YAML, --backend) picks one of a closed list of compiled instantiations
// (drivers/physics_registry.cpp). Virtual calls happen once per batch of steps on the host only.
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>
#include "setup/engine_config.hpp"
#include "core/frame.hpp"

namespace cgdem {

struct StepTimers {
  double integrate = 0, binning = 0, neighbor_list = 0, forces = 0;
  // Between MPI ranks (parallel/distributed_engine.hpp): time in communication (halo, redistribution,
  // waiting for the slowest rank), the ranks' particle counts' spread (largest / mean - 1) at the last
  // redistribution, and how often the bricks were moved to even them out.
  double communication = 0;
  double load_imbalance = 0;
  long rebalances = 0;
  long list_builds = 0;
};

struct Observables {
  double time = 0;
  long step = 0;
  double kinetic_energy = 0, rotational_energy = 0;
  double momentum[3] = {0, 0, 0};
  long contacts = 0;
  long pair_contact_ends = 0; // particle-particle contacts counted from both particles (owned ones only)
  double max_speed = 0;
  double max_overlap_fraction = 0; // largest overlap / smaller radius
  std::vector<double> wall_force;  // 3 per named wall: the particles' force on it
  std::vector<double> wall_torque; // 3 per named wall: their moment on it about its point (its axis's)
};

// Thrown when the state stops being physical; what() is the diagnosis (step, particle, neighbours, cause).
struct BlowUpError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Engine {
public:
  virtual ~Engine() = default;
  // Advance `steps` time steps; throws BlowUpError on a NaN/Inf state or an overlap beyond the limit.
  virtual void advance(long steps) = 0;
  virtual Observables observe() = 0;
  // Rebuild the neighbour list now, with a spatial reorder (tests of history carry-over; restarts).
  virtual void rebuild_neighbors() = 0;
  virtual FrameData frame() = 0;
  virtual CheckpointData checkpoint() = 0;
  // Restore a checkpoint; one holding a different particle count is accepted only when `resizable`
  // (a scene with inlets or outlets).
  virtual void restore(const CheckpointData&) = 0;
  // Remove the particles with the given ids and add `add` (ids new, group and density set; its velocities
  // and positions at the current time), keeping every other particle's state and contact history. Forces
  // on the added particles start at zero; those of the kept ones keep the last evaluation.
  virtual void exchange(const std::vector<std::int64_t>& remove_ids, const ParticleSet& add) = 0;
  // Ends motion segment `segment` (-1: the first motion; k: motion.then[k]) of the named wall `wall` (its
  // index in the scene: every part it owns) at `time`, the current time: the wall holds its position
  // from then on until a later segment starts (a segment that ends when the particles push back).
  virtual void end_wall_segment(int wall, int segment, double time) = 0;
  // The state a halo copy on another rank follows: position, velocity, angular velocity, force and torque
  // (kStateRowWidth values per particle, in that order) of the particles at the given store indices.
  static constexpr int kStateRowWidth = 15;
  virtual void read_state_rows(const std::vector<int>& index, std::vector<double>& rows) = 0;
  virtual void write_state_rows(const std::vector<int>& index, const std::vector<double>& rows) = 0;
  // The store's particle ids in store order (it changes at every list build that reorders).
  virtual std::vector<std::int64_t> store_ids() = 0;
  // One pair's history seen from the other particle (the contact law's flip_history).
  virtual void flip_pair_history(double* history) const = 0;
  // The neighbour cut-off's widest reach between particle centres: twice the largest radius, the law's
  // interaction range and the skin.
  virtual double interaction_cutoff() const = 0;
  // The largest displacement of a particle since the last list build (at the last half kick and drift).
  virtual double displacement_since_build() const = 0;
  virtual double time() const = 0;
  virtual long step() const = 0;
  virtual int size() const = 0;
  virtual StepTimers timers() const = 0;
  virtual std::size_t bytes() const = 0; // device memory held by the store and the lists
  virtual std::string physics() const = 0;
  virtual std::string backend() const = 0;
};

// Physics combinations compiled into this binary, by name ("hertz+mindlin", ...).
std::vector<std::string> compiled_physics();
std::string physics_name(const ContactSpec& c);
std::vector<std::string> compiled_backends();
// Throws std::invalid_argument naming the combinations available when `config.contact` is not compiled.
std::unique_ptr<Engine> make_engine(const EngineConfig& config, const std::string& backend);

} // namespace cgdem
