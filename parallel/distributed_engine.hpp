#pragma once
// One engine spread over the MPI ranks by spatial decomposition (parallel/decomposition.hpp).
//
// Each rank runs an ordinary engine (the Kokkos kernels unchanged, OpenMP threads or a device) on the
// particles of its brick, its own, plus halo copies of every particle within the halo width of the brick
// (twice the largest radius, the law's interaction range, the skin, and half a skin more). Pairs across
// a rank boundary are evaluated by both ranks, each keeping the force on its own particle: no reverse
// communication, and each rank holds the pair's history, which stays the same on both sides because both
// integrate it from the same states (a halo copy is given its owner's position, velocity, angular velocity,
// force and torque before every step, so its kick and drift are its owner's, bit for bit). The price is
// the pair computed twice at the seams, small beside a reverse communication every step on a CPU cluster.
//
// Whenever any rank's list is rebuilt (a particle moved more than half the skin), the ranks redistribute:
// each particle goes to the rank whose brick now holds it and as a copy to every rank it is near, with its
// contact history (each pair's history sent by the owner of its lower-id particle, the one rank that is
// sure to hold it since the pair formed). The owner's particle fields, wall history and last forces
// travel with it. Output and checkpoints gather the owned particles into the single-process form (rows in
// id order, the list under the lower index): a checkpoint of N ranks restarts on M, or on one process.
#include <memory>
#include "kernels/engine.hpp"

namespace cgdem::parallel {

// `whole` holds every particle of the scene (built with EngineConfig::resizable); the result shares them
// out over MPI_COMM_WORLD and is collective from then on: every rank calls every method in the same
// order. Throws std::runtime_error when cgdem was built without MPI.
// `domain` and `skin` are the engine's (EngineConfig).
std::unique_ptr<Engine> make_distributed_engine(std::unique_ptr<Engine> whole, const Domain& domain,
                                                double skin);

} // namespace cgdem::parallel
