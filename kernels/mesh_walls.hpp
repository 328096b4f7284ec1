#pragma once
// Triangle-mesh walls on the device: the triangles of every mesh part, where they are at this step, and
// for each particle the triangles near enough to touch it before the next list build.
//
//   place(): every vertex from its rest position (the mesh as read and placed in the scene) by its part's
//     motion at time t: x = point + offset(t) + R(axis, angle(t)) (x_rest - point).
//   build(): at each neighbour-list build, the triangles are binned into the particle grid's cells over
//     their bounding boxes grown by the largest radius plus the cut-off extra (reach + skin), each cell's
//     list sorted by triangle index; each particle then keeps, from its own cell's list, the triangles
//     within its radius plus that extra, in index order (so the same on every backend and thread count).
//     A particle moving less than skin/2 and a mesh moving less than skin/2 since the build keep every
//     contact on the list (Simulation::advance checks both).
//   MeshContacts: the force terms of one particle with one mesh part (contact_forces.hpp's WallTerms calls
//     it): nearest points on the candidates, filtered to the surface's contacts (core/triangle_mesh.hpp),
//     each evaluated by the law with the wall's material, its history kept in the particle's slots.
//
// Contact history: a mesh part has kSlots slots in a particle's wall-history row, each [triangle + 1 (0:
// free), contact point x, y, z, the law's H values]. A contact takes the slot of its triangle; a contact
// on a new triangle takes over the slot of last step's contact at (nearly) the same point, which is how a
// sphere rolling from one triangle of a flat floor onto the next keeps its tangential spring; otherwise a
// free slot, starting from zero. Slots no contact took are cleared. The rows move with the particles
// (reorder, checkpoint, inlets and outlets) like every wall history.
#include <Kokkos_Core.hpp>
#include <vector>
#include "core/triangle_mesh.hpp"
#include "core/triangle_mesh_data.hpp"
#include "core/wall.hpp"
#include "kernels/cell_grid.hpp"

namespace cgdem::kernels {

struct MeshSlots {
  static constexpr int kSlots = 6;
  static constexpr int kHeader = 4; // triangle + 1, contact point
  static constexpr int width(int H) { return kSlots * (kHeader + H); }
};

template <class Mem>
struct MeshGeometry {
  Kokkos::View<Real* [3], Mem> current;    // vertices at the last place()
  Kokkos::View<int* [3], Mem> triangles;   // vertex indices
  Kokkos::View<int*, Mem> triangle_part;   // wall part of each triangle
  Kokkos::View<int*, Mem> candidate_start; // per particle, CSR into candidates
  Kokkos::View<int*, Mem> candidates;      // triangle indices

  KOKKOS_INLINE_FUNCTION Vec3 vertex(int v) const { return {current(v, 0), current(v, 1), current(v, 2)}; }
};

template <class ExecSpace>
class MeshWalls {
public:
  // The cells, inclusive, that a triangle's box grown by the reach covers (build's binning). At class scope:
  // a device lambda's return type cannot be local to the function that holds it (CUDA).
  struct CellRange {
    int lo[3], hi[3];
  };
  using Mem = typename ExecSpace::memory_space;

  bool empty() const { return num_triangles_ == 0; }
  Real built_at() const { return built_at_; } // time of the last build()
  int num_triangles() const { return num_triangles_; }
  const MeshGeometry<Mem>& geometry() const { return geo_; }
  std::size_t bytes() const {
    return (rest_.span() + geo_.current.span()) * sizeof(Real) +
           (geo_.triangles.span() + geo_.triangle_part.span() + vertex_part_.span() + cell_start_.span() +
            cell_fill_.span() + cell_triangles_.span() + geo_.candidate_start.span() +
            geo_.candidates.span()) *
               sizeof(int);
  }

  // The meshes of the wall parts whose type is Mesh (walls[w].mesh indexes meshes).
  void upload(const std::vector<TriangleMeshData>& meshes, const std::vector<Wall>& walls) {
    std::vector<std::array<double, 3>> vertices;
    std::vector<std::array<int, 3>> triangles;
    std::vector<int> vertex_part, triangle_part;
    parts_.clear();
    for (std::size_t w = 0; w < walls.size(); ++w) {
      if (walls[w].type != Wall::Mesh) continue;
      const TriangleMeshData& m = meshes.at(walls[w].mesh);
      const int base = static_cast<int>(vertices.size());
      double r2 = 0;
      for (const auto& v : m.vertices) {
        vertices.push_back(v);
        vertex_part.push_back(static_cast<int>(w));
        const Vec3 rel = Vec3{v[0], v[1], v[2]} - walls[w].point;
        const Vec3 radial = rel - dot(rel, walls[w].axis) * walls[w].axis;
        r2 = std::max<double>(r2, norm2(radial));
      }
      for (const auto& t : m.triangles) {
        triangles.push_back({base + t[0], base + t[1], base + t[2]});
        triangle_part.push_back(static_cast<int>(w));
      }
      parts_.push_back({static_cast<int>(w), std::sqrt(r2)});
    }
    num_vertices_ = static_cast<int>(vertices.size());
    num_triangles_ = static_cast<int>(triangles.size());
    rest_ = Kokkos::View<Real* [3], Mem>("cgdem::kernels::mesh_rest", num_vertices_);
    geo_.current = Kokkos::View<Real* [3], Mem>("cgdem::kernels::mesh_vertices", num_vertices_);
    geo_.triangles = Kokkos::View<int* [3], Mem>("cgdem::kernels::mesh_triangles", num_triangles_);
    geo_.triangle_part = Kokkos::View<int*, Mem>("cgdem::kernels::mesh_triangle_part", num_triangles_);
    vertex_part_ = Kokkos::View<int*, Mem>("cgdem::kernels::mesh_vertex_part", num_vertices_);
    auto hr = Kokkos::create_mirror_view(rest_);
    auto ht = Kokkos::create_mirror_view(geo_.triangles);
    auto htp = Kokkos::create_mirror_view(geo_.triangle_part);
    auto hvp = Kokkos::create_mirror_view(vertex_part_);
    for (int v = 0; v < num_vertices_; ++v) {
      for (int a = 0; a < 3; ++a)
        hr(v, a) = vertices[v][a];
      hvp(v) = vertex_part[v];
    }
    for (int t = 0; t < num_triangles_; ++t) {
      for (int a = 0; a < 3; ++a)
        ht(t, a) = triangles[t][a];
      htp(t) = triangle_part[t];
    }
    Kokkos::deep_copy(rest_, hr);
    Kokkos::deep_copy(geo_.current, hr);
    Kokkos::deep_copy(geo_.triangles, ht);
    Kokkos::deep_copy(geo_.triangle_part, htp);
    Kokkos::deep_copy(vertex_part_, hvp);
  }

  // Moves the vertices to time t (nothing to do for meshes that never move).
  void place(const Kokkos::View<Wall*, Mem>& walls, const std::vector<Wall>& host_walls, Real t) {
    bool any = false;
    for (const auto& p : parts_) {
      const Wall& w = host_walls[p.part];
      any = any || w.ever_moves();
    }
    if (!any || num_vertices_ == 0) return;
    const auto rest = rest_;
    const auto current = geo_.current;
    const auto part = vertex_part_;
    Kokkos::parallel_for(
        "cgdem::kernels::mesh_place", Kokkos::RangePolicy<ExecSpace>(0, num_vertices_), KOKKOS_LAMBDA(int v) {
          const Wall& w = walls(part(v));
          const Vec3 x0{rest(v, 0), rest(v, 1), rest(v, 2)};
          const Vec3 x = w.point + w.offset(t) + rotate_about(x0 - w.point, w.axis, w.angle(t));
          current(v, 0) = x.x;
          current(v, 1) = x.y;
          current(v, 2) = x.z;
        });
  }

  // How far any vertex may have moved since the last build (translation plus the chord of the rotation
  // at the part's largest distance from its axis), on the host from the parts' motion.
  Real motion_since_build(const std::vector<Wall>& host_walls, Real t) const {
    Real worst = 0;
    for (const auto& p : parts_) {
      const Wall& w = host_walls[p.part];
      const Real moved = norm(w.offset(t) - w.offset(built_at_));
      const Real turned = math::fabs(w.angle(t) - w.angle(built_at_));
      const Real chord = 2 * p.radius * math::sin(turned < math::pi ? 0.5 * turned : 0.5 * math::pi);
      worst = std::max(worst, moved + chord);
    }
    return worst;
  }

  // The candidate triangles of every particle (see the top of this file); `extra` = reach + skin.
  template <class PositionView, class RadiusView>
  void build(const CellGrid& grid, const PositionView& position, const RadiusView& radius, int n,
             Real max_radius, Real extra, Real t) {
    built_at_ = t;
    if (static_cast<int>(geo_.candidate_start.extent(0)) != n + 1)
      geo_.candidate_start = Kokkos::View<int*, Mem>("cgdem::kernels::mesh_candidate_start", n + 1);
    if (num_triangles_ == 0) return;
    const int ncell = grid.count();
    if (static_cast<int>(cell_start_.extent(0)) != ncell + 1) {
      cell_start_ = Kokkos::View<int*, Mem>("cgdem::kernels::mesh_cell_start", ncell + 1);
      cell_fill_ = Kokkos::View<int*, Mem>("cgdem::kernels::mesh_cell_fill", ncell);
    }
    const MeshGeometry<Mem> geo = geo_;
    const auto cell_start = cell_start_;
    const auto cell_fill = cell_fill_;
    const Real grow = max_radius + extra;
    // The cells a triangle's grown box covers (clamped to the grid like the particles).
    auto range_of = [=] KOKKOS_FUNCTION(int t) {
      CellRange r;
      const Vec3 a = geo.vertex(geo.triangles(t, 0)), b = geo.vertex(geo.triangles(t, 1)),
                 c = geo.vertex(geo.triangles(t, 2));
      for (int k = 0; k < 3; ++k) {
        const Real lo = math::fmin(a[k], math::fmin(b[k], c[k])) - grow;
        const Real hi = math::fmax(a[k], math::fmax(b[k], c[k])) + grow;
        Vec3 plo, phi;
        plo[k] = lo;
        phi[k] = hi;
        r.lo[k] = grid.axis_cell(plo, k);
        r.hi[k] = grid.axis_cell(phi, k);
      }
      return r;
    };
    Kokkos::deep_copy(cell_start, 0);
    Kokkos::parallel_for(
        "cgdem::kernels::mesh_bin_count", Kokkos::RangePolicy<ExecSpace>(0, num_triangles_),
        KOKKOS_LAMBDA(int t) {
          const CellRange r = range_of(t);
          for (int z = r.lo[2]; z <= r.hi[2]; ++z)
            for (int y = r.lo[1]; y <= r.hi[1]; ++y)
              for (int x = r.lo[0]; x <= r.hi[0]; ++x)
                Kokkos::atomic_increment(&cell_start(1 + x + grid.dims[0] * (y + grid.dims[1] * z)));
        });
    const int total = counts_to_offsets<ExecSpace>(cell_start, ncell, "cgdem::kernels::mesh_bin_offsets");
    if (static_cast<int>(cell_triangles_.extent(0)) < total)
      cell_triangles_ = Kokkos::View<int*, Mem>("cgdem::kernels::mesh_cell_triangles", total);
    const auto cell_triangles = cell_triangles_;
    Kokkos::deep_copy(cell_fill, 0);
    Kokkos::parallel_for(
        "cgdem::kernels::mesh_bin_fill", Kokkos::RangePolicy<ExecSpace>(0, num_triangles_),
        KOKKOS_LAMBDA(int t) {
          const CellRange r = range_of(t);
          for (int z = r.lo[2]; z <= r.hi[2]; ++z)
            for (int y = r.lo[1]; y <= r.hi[1]; ++y)
              for (int x = r.lo[0]; x <= r.hi[0]; ++x) {
                const int c = x + grid.dims[0] * (y + grid.dims[1] * z);
                cell_triangles(cell_start(c) + Kokkos::atomic_fetch_add(&cell_fill(c), 1)) = t;
              }
        });
    // The fill order depends on the threads: index order within each cell.
    Kokkos::parallel_for(
        "cgdem::kernels::mesh_bin_sort", Kokkos::RangePolicy<ExecSpace>(0, ncell), KOKKOS_LAMBDA(int c) {
          for (int k = cell_start(c) + 1; k < cell_start(c + 1); ++k) {
            const int v = cell_triangles(k);
            int j = k - 1;
            for (; j >= cell_start(c) && cell_triangles(j) > v; --j)
              cell_triangles(j + 1) = cell_triangles(j);
            cell_triangles(j + 1) = v;
          }
        });
    // Each particle's candidates: counted, then written in the same order.
    auto near = [=] KOKKOS_FUNCTION(int t, const Vec3& x, Real reach) {
      const TrianglePoint p =
          closest_on_triangle(x, geo.vertex(geo.triangles(t, 0)), geo.vertex(geo.triangles(t, 1)),
                              geo.vertex(geo.triangles(t, 2)));
      return norm2(p.point - x) < reach * reach;
    };
    const auto start = geo_.candidate_start;
    Kokkos::parallel_for(
        "cgdem::kernels::mesh_candidate_count", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const Vec3 x{position(i, 0), position(i, 1), position(i, 2)};
          const int c = grid.cell_of(x);
          int count = 0;
          for (int k = cell_start(c); k < cell_start(c + 1); ++k)
            count += near(cell_triangles(k), x, radius(i) + extra) ? 1 : 0;
          start(i + 1) = count;
        });
    const int listed = counts_to_offsets<ExecSpace>(start, n, "cgdem::kernels::mesh_candidate_offsets");
    if (static_cast<int>(geo_.candidates.extent(0)) < listed)
      geo_.candidates = Kokkos::View<int*, Mem>("cgdem::kernels::mesh_candidates", listed + listed / 4 + 16);
    const auto candidates = geo_.candidates;
    Kokkos::parallel_for(
        "cgdem::kernels::mesh_candidate_fill", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const Vec3 x{position(i, 0), position(i, 1), position(i, 2)};
          const int c = grid.cell_of(x);
          int s = start(i);
          for (int k = cell_start(c); k < cell_start(c + 1); ++k)
            if (near(cell_triangles(k), x, radius(i) + extra)) candidates(s++) = cell_triangles(k);
        });
  }

private:
  struct Part {
    int part;      // wall part index
    double radius; // largest distance of its vertices from its rotation axis
  };
  std::vector<Part> parts_;
  int num_vertices_ = 0, num_triangles_ = 0;
  Real built_at_ = 0;
  Kokkos::View<Real* [3], Mem> rest_;
  Kokkos::View<int*, Mem> vertex_part_;
  Kokkos::View<int*, Mem> cell_start_, cell_fill_, cell_triangles_;
  MeshGeometry<Mem> geo_;
};

} // namespace cgdem::kernels
