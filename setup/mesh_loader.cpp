#include "setup/mesh_loader.hpp"
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cgdem {

namespace {

using A3 = std::array<double, 3>;

A3 rotate(const A3& v, int axis, double degrees) {
  const double t = degrees * M_PI / 180, c = std::cos(t), s = std::sin(t);
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  A3 r = v;
  r[a] = c * v[a] - s * v[b];
  r[b] = s * v[a] + c * v[b];
  return r;
}

A3 sub(const A3& a, const A3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

} // namespace

TriangleMeshData load_triangle_mesh(const std::string& file, double scale, const A3& rotate_deg,
                                    const A3& translate) {
  Assimp::Importer importer;
  // Triangulate polygons, merge the vertices an STL repeats per face (shared edges become shared indices),
  // bake node transforms of multi-part files into the vertices. Degenerate triangles are kept, to be
  // reported rather than dropped silently.
  const aiScene* scene = importer.ReadFile(file, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                     aiProcess_PreTransformVertices);
  if (!scene) throw std::runtime_error("cannot read mesh file '" + file + "': " + importer.GetErrorString());
  TriangleMeshData m;
  long not_triangles = 0;
  for (unsigned k = 0; k < scene->mNumMeshes; ++k) {
    const aiMesh* mesh = scene->mMeshes[k];
    const int base = static_cast<int>(m.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      A3 x{scale * p.x, scale * p.y, scale * p.z};
      for (int axis = 0; axis < 3; ++axis)
        if (rotate_deg[axis] != 0) x = rotate(x, axis, rotate_deg[axis]);
      m.vertices.push_back({x[0] + translate[0], x[1] + translate[1], x[2] + translate[2]});
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) {
        ++not_triangles;
        continue;
      }
      m.triangles.push_back(
          {base + int(face.mIndices[0]), base + int(face.mIndices[1]), base + int(face.mIndices[2])});
    }
  }
  if (not_triangles > 0)
    throw std::runtime_error("mesh file '" + file + "' has " + std::to_string(not_triangles) +
                             " faces that are points or lines, not triangles");
  if (m.triangles.empty()) throw std::runtime_error("mesh file '" + file + "' holds no triangles");
  m.lo = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max()};
  m.hi = {-m.lo[0], -m.lo[1], -m.lo[2]};
  for (const A3& v : m.vertices)
    for (int a = 0; a < 3; ++a) {
      m.lo[a] = std::min(m.lo[a], v[a]);
      m.hi[a] = std::max(m.hi[a], v[a]);
    }
  return m;
}

std::string mesh_problem(const TriangleMeshData& mesh) {
  const A3 d = sub(mesh.hi, mesh.lo);
  const double size2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const A3 ab = sub(mesh.vertices[tri[1]], mesh.vertices[tri[0]]);
    const A3 ac = sub(mesh.vertices[tri[2]], mesh.vertices[tri[0]]);
    const A3 n{ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]};
    const double area2 = 0.25 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(area2 > 1e-24 * size2 * size2))
      return "triangle " + std::to_string(t) + " (vertices " + std::to_string(tri[0]) + ", " +
             std::to_string(tri[1]) + ", " + std::to_string(tri[2]) + ") is degenerate (zero area)";
  }
  return "";
}

} // namespace cgdem
