#pragma once
// Triangle meshes from CAD files for mesh walls, read through Assimp (binary and ASCII STL, OBJ, PLY and
// the other formats it knows), placed in the scene: each vertex x -> R (scale x) + translate, where R
// rotates by rotate[0] degrees about x, then rotate[1] about y, then rotate[2] about z.
#include <array>
#include <string>
#include "core/triangle_mesh_data.hpp"

namespace cgdem {

// Throws std::runtime_error with one line saying what is wrong with the file (unreadable, no triangles,
// faces that are not triangles).
TriangleMeshData load_triangle_mesh(const std::string& file, double scale,
                                    const std::array<double, 3>& rotate_deg,
                                    const std::array<double, 3>& translate);

// The first problem that makes a mesh unusable as a wall, or "": a degenerate triangle (area below 1e-12 of
// the squared size of the mesh: its normal is undefined).
std::string mesh_problem(const TriangleMeshData& mesh);

} // namespace cgdem
