#include "parallel/decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace cgdem::parallel {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// Distance from coordinate x to the interval [lo, hi) along one axis, through the periodic images.
double axis_gap(double x, double lo, double hi, bool periodic, double length) {
  auto gap = [&](double y) { return std::max({lo - y, y - hi, 0.0}); };
  double g = gap(x);
  if (periodic) g = std::min({g, gap(x - length), gap(x + length)});
  return g;
}
} // namespace

Decomposition Decomposition::make(const Domain& domain, const std::vector<double>& positions, int ranks,
                                  double halo_width) {
  if (ranks < 1) throw std::invalid_argument("decomposition over " + std::to_string(ranks) + " ranks");
  Decomposition d;
  d.domain = domain;
  d.ranks = ranks;
  d.halo_width = halo_width;
  const std::size_t n = positions.size() / 3;
  // Extent of the particles (the box's length on a periodic axis, where the faces are cut too).
  double extent[3];
  for (int a = 0; a < 3; ++a) {
    double lo = kInf, hi = -kInf;
    for (std::size_t i = 0; i < n; ++i) {
      lo = std::min(lo, positions[3 * i + a]);
      hi = std::max(hi, positions[3 * i + a]);
    }
    extent[a] = domain.periodic[a] ? domain.length[a] : (n > 0 ? std::max(hi - lo, 0.0) : domain.length[a]);
    if (!(extent[a] > 0) || !std::isfinite(extent[a])) extent[a] = 1e-300;
  }
  // The rank grid with the least cut area (each cut of an axis costs the particles' cross-section across
  // it); among equal ones the one that cuts x most, then y.
  double best = kInf;
  for (int px = ranks; px >= 1; --px) {
    if (ranks % px) continue;
    for (int py = ranks / px; py >= 1; --py) {
      if ((ranks / px) % py) continue;
      const int pz = ranks / px / py;
      const int p[3] = {px, py, pz};
      double area = 0;
      for (int a = 0; a < 3; ++a) {
        const int faces = p[a] > 1 ? p[a] - (domain.periodic[a] ? 0 : 1) : 0;
        area += faces * extent[(a + 1) % 3] * extent[(a + 2) % 3];
      }
      if (area < best * (1 - 1e-12)) {
        best = area;
        d.dims = {px, py, pz};
      }
    }
  }
  // Cuts at the quantiles of the coordinates along each axis.
  for (int a = 0; a < 3; ++a) {
    std::vector<double> x(n);
    for (std::size_t i = 0; i < n; ++i)
      x[i] = positions[3 * i + a];
    std::sort(x.begin(), x.end());
    for (int k = 1; k < d.dims[a]; ++k) {
      double c;
      if (n == 0)
        c = domain.lo[a] + domain.length[a] * k / d.dims[a];
      else
        c = x[std::min(n - 1, n * std::size_t(k) / std::size_t(d.dims[a]))];
      if (!d.cuts[a].empty()) c = std::max(c, d.cuts[a].back());
      d.cuts[a].push_back(c);
    }
  }
  return d;
}

std::array<int, 3> Decomposition::coordinates(int rank) const {
  return {rank % dims[0], (rank / dims[0]) % dims[1], rank / (dims[0] * dims[1])};
}

int Decomposition::rank_of(const double* x) const {
  int c[3];
  for (int a = 0; a < 3; ++a)
    c[a] = static_cast<int>(std::upper_bound(cuts[a].begin(), cuts[a].end(), x[a]) - cuts[a].begin());
  return c[0] + dims[0] * (c[1] + dims[1] * c[2]);
}

void Decomposition::brick(int rank, double lo[3], double hi[3]) const {
  const auto c = coordinates(rank);
  for (int a = 0; a < 3; ++a) {
    const double outer_lo = domain.periodic[a] ? domain.lo[a] : -kInf;
    const double outer_hi = domain.periodic[a] ? domain.hi[a] : kInf;
    lo[a] = c[a] == 0 ? outer_lo : cuts[a][c[a] - 1];
    hi[a] = c[a] == dims[a] - 1 ? outer_hi : cuts[a][c[a]];
  }
}

bool Decomposition::near(const double* x, int rank) const {
  double lo[3], hi[3];
  brick(rank, lo, hi);
  for (int a = 0; a < 3; ++a)
    if (axis_gap(x[a], lo[a], hi[a], domain.periodic[a], domain.length[a]) > halo_width) return false;
  return true;
}

std::string Decomposition::describe() const {
  std::ostringstream s;
  s << dims[0] << " x " << dims[1] << " x " << dims[2] << " ranks, halo " << halo_width << " m";
  for (int a = 0; a < 3; ++a)
    if (!cuts[a].empty()) {
      s << "; "
        << "xyz"[a] << " cut at";
      for (double c : cuts[a])
        s << " " << c;
    }
  return s.str();
}

} // namespace cgdem::parallel
