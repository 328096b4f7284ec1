#pragma once
// Structure-of-arrays particle store: one Kokkos View per field, in the execution space's memory.
// Everything per particle lives here so that a spatial reorder can permute all of it in one place
// (kernels/reorder.hpp); contact history lives with the neighbour list.
#include <Kokkos_Core.hpp>
#include <cstdint>
#include <string>
#include <type_traits>
#include "core/types.hpp"

namespace cgdem {

template <class MemorySpace>
struct ParticleStore {
  template <class T>
  using View = Kokkos::View<T, MemorySpace>;

  View<std::int64_t*> id; // stable identity across reorders (output, checkpoints, history)
  View<Real* [3]> position;
  View<Real* [3]> velocity;
  View<Real* [3]> angular_velocity;
  // Totals stay double under the precision knob too: the per-pair shares are rounded antisymmetrically,
  // a rounded total would not conserve momentum.
  View<Real* [3]> force;
  View<Real* [3]> torque;
  View<Real* [3]> position_at_build; // where each particle was at the last neighbour-list build
  View<Real*> radius;
  View<Real*> mass;
  View<Real*> inertia;      // moment of inertia of a solid sphere, 2/5 m R^2
  View<Real*> scale_factor; // coarse-graining factor k of the particle's group (1: original)
  View<int*> material;
  View<int*> group;
  View<int*> contacts;      // active particle-particle contacts at the last force evaluation
  View<int*> wall_contacts; // active wall contacts at the last force evaluation
  // 1: a copy of a particle that another MPI rank owns (parallel/distributed_engine.hpp), integrated here
  // only to be overwritten by its owner's state each step and left out of the system's sums; 0: owned.
  View<int*> halo;

  int size() const { return static_cast<int>(id.extent(0)); }

  ParticleStore() = default; // no fields allocated
  explicit ParticleStore(int n) { allocate(n); }

  // Calls visit(name, view) for every per-particle field, in one fixed order. Everything that handles all
  // fields alike (allocation, spatial reorder, checkpoint and restore, adding and removing particles)
  // walks this list, so a new field is declared above and listed here, nowhere else.
  template <class Store, class Visitor>
  static void for_each_field(Store& s, Visitor&& visit) {
    visit("id", s.id);
    visit("position", s.position);
    visit("velocity", s.velocity);
    visit("angular_velocity", s.angular_velocity);
    visit("force", s.force);
    visit("torque", s.torque);
    visit("position_at_build", s.position_at_build);
    visit("radius", s.radius);
    visit("mass", s.mass);
    visit("inertia", s.inertia);
    visit("scale_factor", s.scale_factor);
    visit("material", s.material);
    visit("group", s.group);
    visit("contacts", s.contacts);
    visit("wall_contacts", s.wall_contacts);
    visit("halo", s.halo);
  }

  // Values per particle of a field's view type: 1 or the fixed column count.
  template <class FieldView>
  static constexpr int columns() {
    return FieldView::rank == 1 ? 1 : static_cast<int>(FieldView::static_extent(1));
  }

  void allocate(int n) {
    for_each_field(*this, [n](const char* name, auto& view) {
      using FieldView = std::decay_t<decltype(view)>;
      view = FieldView(std::string("cgdem::core::") + name, n);
    });
  }

  // Bytes per particle held by the store (for the memory estimate and benchmarks).
  static std::size_t bytes_per_particle() {
    std::size_t bytes = 0;
    ParticleStore unallocated;
    for_each_field(unallocated, [&bytes](const char*, const auto& view) {
      using FieldView = std::decay_t<decltype(view)>;
      bytes += sizeof(typename FieldView::value_type) * columns<FieldView>();
    });
    return bytes;
  }
};

// n x 3 fields whose rows are 3 apart by construction. A LayoutRight View<T*[3]> keeps its row stride as a
// runtime value (Kokkos allows padding there), so v(i, c) costs a load of the stride and a multiply at
// every access: ~15 % of the force kernel's instructions (perf/README.md). Our fields are allocated
// unpadded, so for them load3/store3 compute the row's address from the constant 3. Other layouts
// (LayoutLeft, the CUDA default) go through the View's own indexing.
template <class View>
constexpr bool packed_rows3() {
  using Layout = typename View::array_layout;
  return std::is_same<Layout, Kokkos::LayoutRight>::value && View::rank == 2 && View::rank_dynamic == 1 &&
         View::static_extent(1) == 3;
}

// Address of v(i, 0): row i of an n x 3 field (for loads, stores and prefetches).
template <class View>
KOKKOS_INLINE_FUNCTION typename View::value_type* row3(const View& v, int i) {
  if constexpr (packed_rows3<View>()) {
    KOKKOS_ASSERT(v.stride(0) == 3);
    return v.data() + 3 * static_cast<std::size_t>(i);
  } else {
    return &v(i, 0);
  }
}

template <class View>
KOKKOS_INLINE_FUNCTION Vec3 load3(const View& v, int i) {
  if constexpr (packed_rows3<View>()) {
    const auto* r = row3(v, i);
    return Vec3{r[0], r[1], r[2]};
  } else {
    return Vec3{v(i, 0), v(i, 1), v(i, 2)};
  }
}

template <class View>
KOKKOS_INLINE_FUNCTION void store3(const View& v, int i, const Vec3& a) {
  using T = typename View::value_type; // rounds to ForceReal where the view stores it
  if constexpr (packed_rows3<View>()) {
    T* r = row3(v, i);
    r[0] = static_cast<T>(a.x);
    r[1] = static_cast<T>(a.y);
    r[2] = static_cast<T>(a.z);
  } else {
    v(i, 0) = static_cast<T>(a.x);
    v(i, 1) = static_cast<T>(a.y);
    v(i, 2) = static_cast<T>(a.z);
  }
}

// Zero particle i's force and torque sums and its contact count, before a force pass adds to them: done by
// the force pass itself, or by the integrator's pass that reads them last (ContactForces::compute's
// `cleared`).
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void clear_force_sums(const ParticleStore<MemorySpace>& p, int i) {
  store3(p.force, i, Vec3{});
  store3(p.torque, i, Vec3{});
  p.contacts(i) = 0;
}

} // namespace cgdem
