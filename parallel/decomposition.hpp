#pragma once
// Spatial decomposition of the domain into one brick per MPI rank (parallel/distributed_engine.hpp).
//
// The ranks form a px x py x pz grid chosen from the particles' extent so that the cut faces are as small
// as possible; along each axis the cuts sit at quantiles of the particles' coordinates, so each slab of
// the grid starts with the same number of particles. A brick is half-open, [cut_k, cut_k+1); the outer
// bricks of an open axis reach to infinity (a particle leaving the box stays with a rank), those of a
// periodic axis end at the box faces. Pure geometry: no MPI, so it is tested on its own.
#include <array>
#include <string>
#include <vector>
#include "core/domain.hpp"

namespace cgdem::parallel {

struct Decomposition {
  Domain domain;
  int ranks = 1;
  std::array<int, 3> dims{1, 1, 1};
  std::array<std::vector<double>, 3> cuts; // dims[a] - 1 interior cuts per axis, ascending
  double halo_width = 0;                   // how far beyond its brick a rank holds copies of particles

  // positions: 3 per particle (row-major). Throws std::invalid_argument when ranks < 1.
  static Decomposition make(const Domain& domain, const std::vector<double>& positions, int ranks,
                            double halo_width);

  // The rank whose brick holds x.
  int rank_of(const double* x) const;
  // Whether x lies within halo_width of `rank`'s brick (through the periodic faces too): that rank then
  // needs the particle, as its own or as a halo copy.
  bool near(const double* x, int rank) const;
  // The brick's bounds along each axis (infinite on the outer side of an open axis).
  void brick(int rank, double lo[3], double hi[3]) const;
  std::array<int, 3> coordinates(int rank) const;
  std::string describe() const; // "2 x 1 x 1 ranks; x cuts at ..."
};

} // namespace cgdem::parallel
