#include "drivers/engine_setup.hpp"
#include <algorithm>
#include <cmath>
#include "setup/materials.hpp"
#include "setup/scaling.hpp"

namespace cgdem {

namespace {
Vec3 to_vec(const Vec3d& v) {
  return Vec3{v[0], v[1], v[2]};
}
Vec3 unit(const Vec3d& v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return Vec3{v[0] / n, v[1] / n, v[2] / n};
}
// A unit direction perpendicular to `normal`: `wanted` with its normal part removed, or when that is zero
// the coordinate axis least aligned with the normal, projected (a plate's first side, a cone's reference
// radial).
Vec3 in_plane_direction(const Vec3& normal, Vec3 wanted) {
  if (norm2(wanted) == 0) {
    const double ax = std::fabs(normal.x), ay = std::fabs(normal.y), az = std::fabs(normal.z);
    wanted = ax <= ay && ax <= az ? Vec3{1, 0, 0} : (ay <= az ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  }
  const Vec3 e = wanted - dot(wanted, normal) * normal;
  return (1.0 / norm(e)) * e;
}
} // namespace

EngineConfig make_engine_config(const Scene& scene, const ParticleSet& particles,
                                const TimeStepEstimate& dt) {
  EngineConfig c;
  c.particles = particles;
  // Particles an inlet adds later (the set's pending tail) are not in the engine at the start.
  const std::size_t placed = particles.size() - particles.pending;
  c.resizable = !scene.outlets.empty() || particles.pending > 0;
  if (particles.pending > 0) {
    auto cut = [placed](auto& v) { v.resize(placed); };
    ParticleSet& q = c.particles;
    cut(q.id), cut(q.position), cut(q.velocity), cut(q.angular_velocity), cut(q.radius), cut(q.density);
    cut(q.material), cut(q.group);
    q.pending = 0;
  }
  // Coarse-graining (setup/scaling.hpp): pair tables over material slots (material, factor), parameter
  // laws applied per pair with the pair factor; particles use their group's slot, walls the factor-1 slots.
  check_scaling(scene);
  ScaledTables tables = scaled_tables(scene);
  c.scale_factor.resize(placed, 1.0);
  for (std::size_t i = 0; i < placed; ++i) {
    const int g = particles.group[i];
    c.scale_factor[i] = group_scale_factor(scene.groups[g]);
    c.particles.material[i] = tables.slot_of_group[g];
  }
  for (std::size_t g = 0; g < scene.groups.size(); ++g) {
    c.group_slot.push_back(tables.slot_of_group[g]);
    c.group_scale.push_back(group_scale_factor(scene.groups[g]));
  }
  c.num_materials = static_cast<int>(tables.slots.size());
  c.pair_params = std::move(tables.pair_params);
  c.wall_params = std::move(tables.wall_params);
  c.domain = Domain(to_vec(scene.domain.lo), to_vec(scene.domain.hi), scene.domain.periodic[0],
                    scene.domain.periodic[1], scene.domain.periodic[2]);
  c.gravity = to_vec(scene.gravity);
  c.dt = dt.step;
  double rmax = 0;
  for (double r : particles.radius)
    rmax = std::max(rmax, r);
  c.max_radius = rmax;
  c.skin = scene.neighbour.skin >= 0 ? scene.neighbour.skin : scene.neighbour.skin_fraction * 2 * rmax;
  c.reorder_every = scene.neighbour.reorder_every;
  c.force_pass = scene.neighbour.force_pass;
  c.max_overlap_fraction = scene.stability.max_overlap_fraction;
  c.contact = effective_contact(scene);
  for (std::size_t w = 0; w < scene.walls.size(); ++w) {
    const WallSpec& s = scene.walls[w];
    c.wall_names.push_back(s.name);
    Wall wall;
    wall.type = s.type == "cylinder" ? Wall::Cylinder
                : s.type == "cone"   ? Wall::Cone
                : s.type == "mesh"   ? Wall::Mesh
                : s.bounded()        ? Wall::Plate
                                     : Wall::Plane;
    if (wall.type == Wall::Mesh) {
      wall.mesh = static_cast<int>(c.meshes.size());
      c.meshes.push_back(*s.mesh);
    }
    wall.material = std::max(0, scene.material_index(s.material));
    wall.owner = static_cast<int>(w);
    wall.point = to_vec(s.point);
    wall.axis = s.type == "plane" ? unit(s.normal) : unit(s.axis);
    wall.radius = s.radius;
    wall.end_radius = s.end_radius;
    wall.length = s.length;
    wall.orifice = s.orifice;
    wall.edge = in_plane_direction(wall.axis, to_vec(s.edge));
    wall.half_width = 0.5 * s.size[0];
    wall.half_height = 0.5 * s.size[1];
    wall.velocity = to_vec(s.velocity);
    wall.angular_velocity = s.angular_velocity;
    wall.motion_start = s.motion_start;
    wall.motion_stop = s.motion_stop;
    wall.oscillation_direction = to_vec(s.oscillation.direction);
    wall.oscillation_amplitude = s.oscillation.amplitude;
    wall.oscillation_omega = 2 * M_PI * s.oscillation.frequency;
    wall.oscillation_start = s.oscillation.start;
    wall.oscillation_stop = s.oscillation.stop;
    wall.num_then = static_cast<int>(s.then.size());
    for (int k = 0; k < wall.num_then && k < Wall::kMaxThen; ++k) {
      wall.then_velocity[k] = to_vec(s.then[k].velocity);
      wall.then_start[k] = s.then[k].start;
      wall.then_stop[k] = s.then[k].stop;
    }
    c.walls.push_back(wall);
    if (wall.type == Wall::Cylinder && s.caps) {
      // End caps: disks at both ends facing inward, moving with the cylinder.
      Wall bottom = wall;
      bottom.type = Wall::Plate;
      bottom.length = 0;
      Wall top = bottom;
      top.point = wall.point + wall.length * wall.axis;
      top.axis = -wall.axis;
      c.walls.push_back(bottom);
      c.walls.push_back(top);
    }
  }
  return c;
}

} // namespace cgdem
