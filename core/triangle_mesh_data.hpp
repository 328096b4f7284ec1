#pragma once
// A triangle mesh on the host as a mesh wall uses it: vertices placed in the scene (scale, rotation and
// translation applied) and triangles as three vertex indices each.
#include <array>
#include <vector>

namespace cgdem {

struct TriangleMeshData {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0}; // bounding box of the vertices
};

} // namespace cgdem
