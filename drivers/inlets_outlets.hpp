#pragma once
// Particles entering and leaving during a run: inlet groups (placement type inlet) add their particles at
// a count or mass rate inside a box, outlets remove the particles whose centre crossed a plane or entered a
// box. Both act at fixed steps (every `every` s), on the host, through Engine::exchange; the positions
// they read are the engine's, so the same scene gives the same insertions on any backend and thread
// count, and a restart from a checkpoint taken at any step continues them exactly.
#include <cstdint>
#include <map>
#include <string>
#include <vector>
#include "core/frame.hpp"
#include "core/scene.hpp"
#include "kernels/engine.hpp"

namespace cgdem {

class ParticleExchange {
public:
  // Takes the pending tail of `particles` (the inlets' particles, in insertion order) and leaves the set
  // without it.
  ParticleExchange(const Scene& scene, ParticleSet& particles, double dt);

  bool active() const { return !inlets_.empty() || !outlets_.empty(); }
  // Steps between two exchanges: the shortest `every` of the inlets and outlets, or by default the largest
  // divisor of the output interval up to 100 steps (100 when it has none from 20 up).
  long every_steps() const { return every_steps_; }
  static long default_every_steps(double output_every, double dt);
  // Inlet particles not yet placed.
  std::size_t waiting() const;
  // Remove what the outlets caught and add what the inlets owe by now (the engine's time).
  void apply(Engine& engine);
  // Totals so far, as series columns: inlet_<group>_count/_mass, outlet_<name>_count/_mass (kg), particles.
  void record(std::map<std::string, double>& columns, long particles) const;
  // The inlets still owing particles and why (end of run), one line each.
  std::vector<std::string> shortfalls(double time) const;
  void save(CheckpointData& c) const;
  void load(const CheckpointData& c);

private:
  struct Inlet {
    std::string group;
    PlacementSpec placement;
    ParticleSet queue; // its particles in insertion order
    std::vector<double> cumulative_mass;
    std::size_t inserted = 0;
    double mass = 0;
    long blocked = 0; // events that could not place all it owed (inlet box full)
  };
  struct Outlet {
    OutletSpec spec;
    long count = 0;
    double mass = 0;
  };
  std::size_t owed(const Inlet& in, double time) const;
  ParticleSet place(Inlet& in, std::size_t target, const FrameData& frame, long step, std::size_t index);

  DomainSpec domain_;
  std::vector<Inlet> inlets_;
  std::vector<Outlet> outlets_;
  long every_steps_ = 100;
};

} // namespace cgdem
