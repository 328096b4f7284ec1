#pragma once
// A host-side cell grid for placing particles without overlaps (random placement, inlets, the initial
// overlap check): a hash of cells over the domain, so that memory follows the particles and not the
// domain's size, with periodic wrap and minimum image on periodic axes. Cells are at least `cell` wide.
// (The engine's own grid is kernels/cell_grid.hpp.)
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <unordered_map>
#include <vector>
#include "core/scene.hpp"

namespace cgdem {

struct CellKey {
  int x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    return static_cast<std::size_t>(k.x) * 73856093u ^ static_cast<std::size_t>(k.y) * 19349663u ^
           static_cast<std::size_t>(k.z) * 83492791u;
  }
};

class HostCellGrid {
public:
  HostCellGrid(const DomainSpec& d, double cell) : d_(d) {
    for (int a = 0; a < 3; ++a) {
      len_[a] = d.hi[a] - d.lo[a];
      if (d.periodic[a]) {
        n_[a] = std::max(1, static_cast<int>(std::floor(len_[a] / cell)));
        size_[a] = len_[a] / n_[a];
      } else {
        n_[a] = 0;
        size_[a] = cell;
      }
      // With fewer than 3 cells along a periodic axis the 27-cell stencil wraps onto itself.
      stencil_wraps_ = stencil_wraps_ || (d.periodic[a] && n_[a] < 3);
    }
  }
  CellKey key(const Vec3d& x) const {
    int c[3];
    for (int a = 0; a < 3; ++a) {
      double u = x[a] - d_.lo[a];
      if (d_.periodic[a]) u -= len_[a] * std::floor(u / len_[a]);
      // A particle file may put a particle anywhere (check_particles rejects it later, naming it): clamp
      // before the conversion, which is undefined for a value beyond int (found by fuzzing, 1e60 m).
      const double cell = std::floor(u / size_[a]);
      c[a] = cell > -1e9 ? (cell < 1e9 ? static_cast<int>(cell) : 1000000000) : -1000000000;
      if (d_.periodic[a]) c[a] = std::min(std::max(c[a], 0), n_[a] - 1);
    }
    return {c[0], c[1], c[2]};
  }
  void insert(int index, const Vec3d& x) { cells_[key(x)].push_back(index); }
  // Calls f(j) for every stored index in the 27 cells around x (each cell once).
  template <class F>
  void for_neighbours(const Vec3d& x, F&& f) const {
    any_neighbour(x, [&](int j) {
      f(j);
      return false;
    });
  }
  // Whether pred(j) holds for a stored index in the 27 cells around x; stops at the first that does
  // (random placement rejects a try at its first overlap).
  template <class Pred>
  bool any_neighbour(const Vec3d& x, Pred&& pred) const {
    const CellKey k = key(x);
    CellKey seen[27];
    int nseen = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int c[3] = {k.x + dx, k.y + dy, k.z + dz};
          for (int a = 0; a < 3; ++a)
            if (d_.periodic[a]) c[a] = ((c[a] % n_[a]) + n_[a]) % n_[a];
          const CellKey nk{c[0], c[1], c[2]};
          if (stencil_wraps_) {
            if (std::find(seen, seen + nseen, nk) != seen + nseen) continue;
            seen[nseen++] = nk;
          }
          const auto it = cells_.find(nk);
          if (it == cells_.end()) continue;
          for (int j : it->second)
            if (pred(j)) return true;
        }
    return false;
  }
  // x_b - x_a, minimum image on periodic axes.
  Vec3d delta(const Vec3d& a, const Vec3d& b) const {
    Vec3d r;
    for (int k = 0; k < 3; ++k) {
      r[k] = b[k] - a[k];
      if (d_.periodic[k]) r[k] -= len_[k] * std::round(r[k] / len_[k]);
    }
    return r;
  }

private:
  DomainSpec d_;
  double len_[3], size_[3];
  int n_[3];
  bool stencil_wraps_ = false;
  std::unordered_map<CellKey, std::vector<int>, CellKeyHash> cells_;
};

} // namespace cgdem
