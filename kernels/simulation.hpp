#pragma once
// Simulation<Law, ExecSpace>: the time loop over the SoA store, for one compiled contact law on one
// Kokkos execution space. Each step (design.md):
//   kick + drift -> (list rebuild with spatial reorder when a particle moved > skin/2) -> forces -> closing
//   kick (the integrate timer holds both kicks and the drift). Inside advance() the closing kick rides on
//   the next step's kick + drift pass, which also zeroes the forces for the next force pass (bitwise the
//   same trajectory; Integrator::kick_drift).
#include <Kokkos_Core.hpp>
#include <algorithm>
#include <cstdio>
#include <numeric>
#include <sstream>
#include "kernels/cell_grid.hpp"
#include "kernels/contact_forces.hpp"
#include "kernels/engine.hpp"
#include "kernels/integrator.hpp"
#include "kernels/neighbor_list.hpp"
#include "kernels/reductions.hpp"
#include "kernels/reorder.hpp"

namespace cgdem::kernels {

template <class Law, class ExecSpace>
class Simulation final : public Engine {
public:
  using Mem = typename ExecSpace::memory_space;
  static constexpr int H = Law::history_size;
  using HistoryView = Kokkos::View<ForceReal**, Kokkos::LayoutRight, Mem>;

  Simulation(const EngineConfig& cfg, std::string physics_name, std::string backend_name)
      : cfg_(cfg), physics_(std::move(physics_name)), backend_(std::move(backend_name)),
        n_(static_cast<int>(cfg.particles.size())), store_(n_) {
    upload_particles();
    cfg_.particles = ParticleSet{}; // on the device now; the host copy would only cost ~100 B per particle
    upload_tables();
    Real rmax = cfg.max_radius; // particles an inlet adds later included
    for (double r : cfg.particles.radius)
      rmax = std::max<Real>(rmax, r);
    max_radius_ = rmax;
    // The longest interaction range of this law over all material pairs (adhesion, bridges) widens
    // the neighbour cut-off; the force kernel uses it to skip pairs quickly.
    cfg_.reach = 0;
    for (std::size_t k = 0; k < cfg.pair_params.size(); ++k)
      cfg_.reach = std::max<double>({cfg_.reach, Law::interaction_range(cfg.pair_params[k], rmax, rmax),
                                     Law::interaction_range(cfg.wall_params[k], rmax, 0)});
    cutoff_extra_ = cfg_.reach + cfg.skin;
    grid_ = CellGrid(cfg.domain, 2 * rmax + cutoff_extra_, std::max<long>(8L * n_, 1L << 16));
    for (int a = 0; a < 3; ++a)
      if (cfg.domain.periodic[a] && grid_.dims[a] < 3) {
        std::ostringstream msg;
        msg << "periodic axis "
            << "xyz"[a] << " is " << cfg.domain.length[a] << " m long, less than 3 neighbour cells of "
            << 2 * rmax + cutoff_extra_ << " m: enlarge the domain along it or reduce the skin";
        throw std::invalid_argument(msg.str());
      }
    if (cfg.force_pass == "blocks")
      force_path_ = ContactForces<ExecSpace, Law>::Path::blocks;
    else if (cfg.force_pass == "pairs")
      force_path_ = ContactForces<ExecSpace, Law>::Path::pairs;
    else if (cfg.force_pass != "auto")
      throw std::invalid_argument("force pass '" + cfg.force_pass + "': use blocks, pairs or auto");
    allocate_per_particle_scratch();
    rebuild(true);
    compute_forces(true);
  }

  void advance(long steps) override {
    Kokkos::Timer timer;
    // The closing kick is left to the next step's kick_drift when nothing reads the velocities in
    // between: not at the health check (it reads them), not after the last step (the caller does).
    bool closing_pending = false;
    for (long s = 0; s < steps; ++s) {
      timer.reset();
      const Real max_d2 = Integrator<ExecSpace>::kick_drift(store_, cfg_.domain, cfg_.gravity, cfg_.dt, n_,
                                                            closing_pending, /*clear_forces=*/true, &blocks_);
      timers_.integrate += timer.seconds();
      if (!(max_d2 < Kokkos::Experimental::infinity<Real>::value))
        throw BlowUpError(diagnose("a position or velocity became NaN or Inf"));
      displacement_since_build_ = std::sqrt(max_d2);
      // The largest since the build, not this step's: a pair the force pass once found within reach is
      // then never skipped again before the next build, so that its history is cleared when it parts
      // (ContactForces skips a slot whole, history included).
      skip_displacement_ = std::max(skip_displacement_, displacement_since_build_);
      // A particle and a mesh may each move skin/2 before a contact could be missing from the lists.
      if (4 * max_d2 > cfg_.skin * cfg_.skin ||
          (!meshes_.empty() && 2 * meshes_.motion_since_build(cfg_.walls, (step_ + 1) * cfg_.dt) > cfg_.skin))
        rebuild(false); // sets it to 0
      ++step_;
      time_ = step_ * cfg_.dt; // not accumulated: a restart reproduces it bitwise
      compute_forces(s == steps - 1, /*cleared=*/true);
      const bool health_check = step_ % health_every_ == 0;
      closing_pending = s < steps - 1 && !health_check;
      if (closing_pending) continue;
      timer.reset();
      Integrator<ExecSpace>::closing_kick(store_, cfg_.gravity, cfg_.dt, n_);
      Kokkos::fence();
      timers_.integrate += timer.seconds();
      if (health_check) check_overlaps();
    }
  }

  Observables observe() override {
    Observables o;
    o.time = time_;
    o.step = step_;
    const SystemSums s = system_sums<ExecSpace>(store_, n_);
    o.kinetic_energy = s.kinetic;
    o.rotational_energy = s.rotational;
    for (int a = 0; a < 3; ++a)
      o.momentum[a] = s.momentum[a];
    o.contacts = s.contacts;
    o.pair_contact_ends = s.pair_slots;
    o.max_speed = s.max_speed;
    o.max_overlap_fraction = max_overlap_fraction();
    // Wall forces recorded by the last force evaluation (the last step of advance(), or construction).
    if (!cfg_.walls.empty()) {
      std::vector<int> owner;
      for (const Wall& w : cfg_.walls)
        owner.push_back(w.owner);
      WallLoads loads = wall_loads<ExecSpace>(wall_force_record_, store_.halo, owner,
                                              static_cast<int>(cfg_.wall_names.size()), n_);
      o.wall_force = std::move(loads.force);
      o.wall_torque = std::move(loads.torque);
    }
    return o;
  }

  void rebuild_neighbors() override {
    builds_ = 0; // the next build reorders whatever reorder_every says
    rebuild(false);
  }

  FrameData frame() override;
  CheckpointData checkpoint() override;
  void restore(const CheckpointData& c) override;
  void exchange(const std::vector<std::int64_t>& remove_ids, const ParticleSet& add) override;
  void end_wall_segment(int wall, int segment, double time) override;

  void read_state_rows(const std::vector<int>& index, std::vector<double>& rows) override;
  void write_state_rows(const std::vector<int>& index, const std::vector<double>& rows) override;
  std::vector<std::int64_t> store_ids() override;
  void flip_pair_history(double* history) const override {
    Real h[H > 0 ? H : 1];
    for (int k = 0; k < H; ++k)
      h[k] = static_cast<Real>(history[k]);
    Law::flip_history(h);
    for (int k = 0; k < H; ++k)
      history[k] = h[k];
  }
  double interaction_cutoff() const override { return 2 * max_radius_ + cutoff_extra_; }
  double displacement_since_build() const override { return displacement_since_build_; }
  double time() const override { return time_; }
  long step() const override { return step_; }
  int size() const override { return n_; }
  StepTimers timers() const override { return timers_; }
  std::size_t bytes() const override {
    return std::size_t(n_) * ParticleStore<Mem>::bytes_per_particle() + nl_.bytes() + blocks_.bytes() +
           wall_history_.span() * sizeof(ForceReal) + reorder_scratch_.span() * sizeof(double) +
           wall_force_record_.span() * sizeof(Real) + bins_.bytes() + meshes_.bytes() +
           (identity_.span() + old_index_.span()) * sizeof(int);
  }
  std::string physics() const override { return physics_; }
  std::string backend() const override { return backend_; }

  // Internal steps, public only because they launch device lambdas: CUDA requires the enclosing member
  // function of an extended lambda to be public.
  void allocate_per_particle_scratch(); // everything sized by n_ beside the store and the list
  void upload_walls();                  // cfg_.walls to the device (at setup, and when a segment ends)
  void stage_state_rows(const std::vector<int>& index); // into row_index_, row_buffer_ grown to fit
  Real max_overlap_fraction();
  void check_overlaps();

private:
  void upload_particles();
  void upload_tables();
  void rebuild(bool first);
  void compute_forces(bool record_wall_forces, bool cleared = false);
  std::string diagnose(const std::string& what);

  EngineConfig cfg_;
  std::string physics_, backend_;
  int n_;
  ParticleStore<Mem> store_;
  Kokkos::View<models::PairParameters**, Mem> pair_params_, wall_params_;
  Kokkos::View<Wall*, Mem> walls_;
  Kokkos::View<PlacedWall*, Mem> placed_walls_; // walls_ at the time of the last force pass
  typename Kokkos::View<PlacedWall*, Mem>::HostMirror placed_walls_host_;
  HistoryView wall_history_; // N x history_width_: each wall part's history (Wall::history_offset)
  int history_width_ = 0;
  MeshWalls<ExecSpace> meshes_;                // the mesh parts' triangles and each particle's candidates
  Kokkos::View<double*, Mem> reorder_scratch_; // one field at a time during a reorder (kernels/reorder.hpp)
  Kokkos::View<Real* [3], Mem> wall_force_record_; // 2 N x wall parts (force, moment), on recording steps
  NeighborList<ExecSpace, Law> nl_;
  ForceBlocks<ExecSpace> blocks_; // the host force pass's schedule, made with each list
  CellBins<ExecSpace> bins_;
  CellGrid grid_;
  Kokkos::View<int*, Mem> identity_;
  Kokkos::View<int*, Mem> old_index_; // new -> old index of the last reorder (history transfer)
  Kokkos::View<int*, Mem> row_index_; // read_state_rows / write_state_rows: the store indices
  Kokkos::View<double**, Kokkos::LayoutRight, Mem> row_buffer_; // and their rows
  // How the force pass shares the pairs among threads (ContactForces::Path); the backend's own by default.
  typename ContactForces<ExecSpace, Law>::Path force_path_ = ContactForces<ExecSpace, Law>::kDefaultPath;
  Real cutoff_extra_ = 0;
  Real max_radius_ = 0; // of the particles now in the store (the force pass's seam test)
  // The largest displacement of a particle from its place at the list's build, at the last kick and drift
  // (the rebuild test, and the MPI ranks' redistribution test).
  Real displacement_since_build_ = 0;
  // Its largest value since the build: the force pass skips the pairs still beyond reach against it
  // (NeighborList::gap).
  Real skip_displacement_ = 0;
  long builds_ = 0;
  long step_ = 0;
  double time_ = 0;
  long health_every_ = 100;
  StepTimers timers_;
};

} // namespace cgdem::kernels

#include "kernels/simulation_impl.hpp"
