// The MPI decomposition's geometry (parallel/decomposition.hpp), without MPI: which rank owns a point,
// which ranks need a copy of it, and the rank grid chosen from the particles' extent.
#include <gtest/gtest.h>
#include <random>
#include "parallel/decomposition.hpp"

namespace cgdem::testing {
namespace {

using parallel::Decomposition;

std::vector<double> uniform_points(int n, const Vec3& lo, const Vec3& hi, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> x;
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a)
      x.push_back(lo[a] + (hi[a] - lo[a]) * u(rng));
  return x;
}

TEST(Decomposition, CutsTheLongAxisOfAFlatBedAndBalancesTheCounts) {
  // A bed 4 x 1 x 0.5 (periodic in x and y): 2 ranks cut x (a 1 x 0.5 face, cut twice through the
  // periodic face: 1.0) rather than y (4 x 0.5 twice: 4) or z (4 x 1 once: 4).
  const Domain d({0, 0, 0}, {4, 1, 2}, true, true, false);
  const std::vector<double> x = uniform_points(4000, {0, 0, 0}, {4, 1, 0.5}, 1);
  const Decomposition dec = Decomposition::make(d, x, 2, 0.1);
  EXPECT_EQ(dec.dims, (std::array<int, 3>{2, 1, 1}));
  std::vector<int> count(2, 0);
  for (std::size_t i = 0; i < x.size() / 3; ++i)
    ++count[dec.rank_of(&x[3 * i])];
  EXPECT_EQ(count[0], 2000);
  EXPECT_EQ(count[1], 2000);
  // 4 ranks: x alone costs 4 faces of 0.5 = 2, against 5 for x and y or x and z, 12 for z alone.
  EXPECT_EQ(Decomposition::make(d, x, 4, 0.1).dims, (std::array<int, 3>{4, 1, 1}));
  // A tall column (0.2 x 0.2 x 4, open): 4 ranks cut z.
  const Domain column({0, 0, 0}, {0.2, 0.2, 4}, false, false, false);
  EXPECT_EQ(Decomposition::make(column, uniform_points(1000, {0, 0, 0}, {0.2, 0.2, 4}, 2), 4, 0.01).dims,
            (std::array<int, 3>{1, 1, 4}));
}

TEST(Decomposition, EveryPointHasOneOwnerAndTheRanksWithinTheHaloWidth) {
  const Domain d({0, 0, 0}, {1, 1, 1}, true, false, false);
  const std::vector<double> x = uniform_points(3000, {0, 0, 0}, {1, 1, 1}, 3);
  const double w = 0.05;
  const Decomposition dec = Decomposition::make(d, x, 6, w);
  ASSERT_EQ(dec.dims[0] * dec.dims[1] * dec.dims[2], 6);
  for (std::size_t i = 0; i < x.size() / 3; ++i) {
    const double* p = &x[3 * i];
    const int owner = dec.rank_of(p);
    ASSERT_TRUE(dec.near(p, owner));
    for (int r = 0; r < 6; ++r) {
      double lo[3], hi[3];
      dec.brick(r, lo, hi);
      // By hand: the gap to the brick along each axis, through the periodic x face.
      bool inside = true, near = true;
      for (int a = 0; a < 3; ++a) {
        inside = inside && p[a] >= lo[a] && p[a] < hi[a];
        double g = std::max({lo[a] - p[a], p[a] - hi[a], 0.0});
        if (a == 0)
          g = std::min({g, std::max({lo[a] - (p[a] - 1), p[a] - 1 - hi[a], 0.0}),
                        std::max({lo[a] - (p[a] + 1), p[a] + 1 - hi[a], 0.0})});
        near = near && g <= w;
      }
      EXPECT_EQ(inside, r == owner) << "point " << i << " rank " << r;
      EXPECT_EQ(near, dec.near(p, r)) << "point " << i << " rank " << r;
    }
  }
}

TEST(Decomposition, APeriodicFaceIsARankBoundary) {
  // Two ranks along periodic x cut at the median: a point just inside x = 0 is near the rank whose brick
  // ends at x = 1, through the face.
  const Domain d({0, 0, 0}, {1, 1, 1}, true, false, false);
  const std::vector<double> x = uniform_points(1000, {0, 0, 0}, {1, 0.2, 0.1}, 4);
  const Decomposition dec = Decomposition::make(d, x, 2, 0.02);
  ASSERT_EQ(dec.dims[0], 2);
  const double at_low_face[3] = {0.01, 0.1, 0.05}, middle[3] = {0.25, 0.1, 0.05};
  EXPECT_EQ(dec.rank_of(at_low_face), 0);
  EXPECT_TRUE(dec.near(at_low_face, 1));
  EXPECT_FALSE(dec.near(middle, 1));
}

} // namespace
} // namespace cgdem::testing
