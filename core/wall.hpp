#pragma once
// Walls as plain device structs, each moving by prescribed translation segments and a rotation about its
// own axis (a rotating drum, an impeller's hub, a lifted gate):
//   - Plane: an infinite half-space boundary (a floor); the particles are on the side the normal points to.
//   - Plate: a bounded plane (rectangle, disk, either with a circular orifice): a thin two-sided sheet
//     with edges, touched on either face and at its rim (a gate, a silo floor with an outlet).
//   - Cylinder: the inner side of a finite cylinder (a drum, a die).
//   - Cone: a thin frustum, radius `radius` at `point` and `end_radius` at point + length * axis, touched
//     on either side and at both rims (a hopper whose orifice is the narrow end).
//   - Mesh: a triangle mesh (equipment from CAD), its triangles held by the engine (kernels/mesh_walls.hpp);
//     it moves as a whole by the same translation segments and rotation about axis through point.
// A cylinder's end caps are expanded on the host into two disk plates that report their force to the
// cylinder (owner), so every wall part has its own contact-history slot.
#include "core/types.hpp"

namespace cgdem {

struct Wall {
  enum Type : int { Plane = 0, Cylinder = 1, Plate = 2, Cone = 3, Mesh = 4 };
  int type = Plane;
  int material = 0;
  int owner = 0;             // index of the named wall this part belongs to (force reporting)
  int mesh = -1;             // Mesh: index of its triangle mesh in the engine's meshes
  int history_offset = 0;    // where this part's contact history starts in a particle's wall history row
  Vec3 point;                // plane, plate: a point on it (a plate's centre); cylinder, cone: base centre
  Vec3 axis{0, 0, 1};        // plane, plate: unit normal (into the particles for a plane); others: unit axis
  Vec3 edge{1, 0, 0};        // plate: unit direction of the rectangle's first side (in the plane)
  Real radius = 0;           // cylinder radius; cone radius at point; plate: > 0 bounds it to a disk
  Real end_radius = 0;       // cone radius at point + length * axis
  Real half_width = 0;       // plate: > 0 bounds it to a rectangle 2 half_width (along edge) x ...
  Real half_height = 0;      // ... 2 half_height (along axis x edge)
  Real orifice = 0;          // plate: radius of a circular hole around point
  Real length = 0;           // cylinder, cone: length along the axis
  Vec3 velocity;             // translation while moving
  Real angular_velocity = 0; // rad/s about axis through point
  Real motion_start = 0, motion_stop = 1e300;
  // Further translation segments (scene motion.then), constant velocity over [start, stop) each.
  static constexpr int kMaxThen = 3;
  Vec3 then_velocity[kMaxThen];
  Real then_start[kMaxThen] = {0, 0, 0}, then_stop[kMaxThen] = {0, 0, 0};
  int num_then = 0;
  // Oscillation (scene motion.oscillation), added to the segments: amplitude x sin(omega (t - start)) along
  // a unit direction over [start, stop), held where it is at stop (a vibrated container).
  Vec3 oscillation_direction{0, 0, 1};
  Real oscillation_amplitude = 0, oscillation_omega = 0, oscillation_start = 0, oscillation_stop = 0;

  KOKKOS_INLINE_FUNCTION static Real span(Real t, Real a, Real b) {
    return t < a ? 0 : (t < b ? t - a : b - a);
  }
  // Displacement of the wall from its time-0 position.
  KOKKOS_INLINE_FUNCTION Vec3 offset(Real t) const {
    Vec3 d = span(t, motion_start, motion_stop) * velocity;
    for (int k = 0; k < num_then; ++k)
      d += span(t, then_start[k], then_stop[k]) * then_velocity[k];
    if (oscillation_amplitude != 0)
      d += oscillation_amplitude *
           math::sin(oscillation_omega * span(t, oscillation_start, oscillation_stop)) *
           oscillation_direction;
    return d;
  }
  // Whether the wall moves at any time (a mesh that never does is placed once).
  KOKKOS_INLINE_FUNCTION bool ever_moves() const {
    return angular_velocity != 0 || norm2(velocity) > 0 || num_then > 0 || oscillation_amplitude != 0;
  }
  KOKKOS_INLINE_FUNCTION bool moving(Real t) const { return t >= motion_start && t < motion_stop; }
  // Angle turned about the axis since time 0 (rad).
  KOKKOS_INLINE_FUNCTION Real angle(Real t) const {
    return angular_velocity * span(t, motion_start, motion_stop);
  }
  // Translation velocity at time t (the sum of the active segments).
  KOKKOS_INLINE_FUNCTION Vec3 translation_velocity(Real t) const {
    Vec3 v = moving(t) ? velocity : Vec3{};
    for (int k = 0; k < num_then; ++k)
      if (t >= then_start[k] && t < then_stop[k]) v += then_velocity[k];
    if (oscillation_amplitude != 0 && t >= oscillation_start && t < oscillation_stop)
      v += oscillation_amplitude * oscillation_omega *
           math::cos(oscillation_omega * (t - oscillation_start)) * oscillation_direction;
    return v;
  }
};

// A wall part at one instant: where its base is and how its surface moves. The force pass places every
// wall once per step (place) instead of once per particle: summing the motion segments was about a
// third of a far particle's wall test.
struct PlacedWall {
  int type = Wall::Plane;
  int material = 0;
  int mesh = -1, history_offset = 0;
  Vec3 base; // plane, plate: a point on it; cylinder, cone: centre of the base
  Vec3 axis{0, 0, 1};
  Vec3 edge{1, 0, 0};
  Real radius = 0, end_radius = 0, half_width = 0, half_height = 0, orifice = 0, length = 0;
  Vec3 velocity; // translation velocity
  Real spin = 0; // angular velocity about the axis through base
};

KOKKOS_INLINE_FUNCTION PlacedWall place(const Wall& w, Real t) {
  PlacedWall p;
  p.type = w.type;
  p.material = w.material;
  p.mesh = w.mesh;
  p.history_offset = w.history_offset;
  p.base = w.point + w.offset(t);
  p.axis = w.axis;
  p.edge = w.edge;
  p.radius = w.radius;
  p.end_radius = w.end_radius;
  p.half_width = w.half_width;
  p.half_height = w.half_height;
  p.orifice = w.orifice;
  p.length = w.length;
  p.velocity = w.translation_velocity(t);
  p.spin = w.moving(t) ? w.angular_velocity : 0;
  return p;
}

struct WallContact {
  Real overlap = -1;      // > 0 in contact
  Vec3 normal;            // unit, from the particle toward the wall
  bool reachable = false; // the particle is within the wall's extent (otherwise no interaction)
  Vec3 rel;               // from the wall's base to the particle's centre
  Real along = 0;         // plane: distance of the centre from it; cylinder: axial position
  Vec3 touch;             // plate, cone: the wall's point nearest the centre, from the base
};

// The point of a plate nearest to `rel` (relative to its centre): the in-plane projection clamped to the
// rectangle, the disk and out of the orifice. `on_face` tells whether the projection needed no clamping.
KOKKOS_INLINE_FUNCTION Vec3 plate_nearest(const PlacedWall& w, const Vec3& rel, Real along, bool& on_face) {
  Vec3 q = rel - along * w.axis;
  on_face = true;
  if (w.half_width > 0) {
    const Vec3 second = cross(w.axis, w.edge);
    const Real u = dot(q, w.edge), v = dot(q, second);
    const Real cu = u < -w.half_width ? -w.half_width : (u > w.half_width ? w.half_width : u);
    const Real cv = v < -w.half_height ? -w.half_height : (v > w.half_height ? w.half_height : v);
    if (cu != u || cv != v) {
      on_face = false;
      q = q + (cu - u) * w.edge + (cv - v) * second;
    }
  }
  const Real r2 = norm2(q);
  if (w.radius > 0 && r2 > w.radius * w.radius) {
    on_face = false;
    q = (w.radius / math::sqrt(r2)) * q;
  }
  if (w.orifice > 0 && r2 < w.orifice * w.orifice && r2 > 0) {
    on_face = false;
    q = (w.orifice / math::sqrt(r2)) * q;
  }
  return q;
}

// Geometry only: every particle is tested against every wall each step, and most are far from it, so
// the lever arm to the contact point is left to wall_surface_velocity, called for the particles within
// reach.
KOKKOS_INLINE_FUNCTION WallContact wall_contact(const PlacedWall& w, const Vec3& x, Real radius) {
  WallContact c;
  if (w.type == Wall::Mesh) return c; // its triangles are the mesh terms' (kernels/mesh_walls.hpp)
  c.rel = x - w.base;
  c.along = dot(c.rel, w.axis);
  if (w.type == Wall::Plane) {
    c.reachable = true;
    c.overlap = radius - c.along;
    c.normal = -w.axis;
    return c;
  }
  if (w.type == Wall::Cylinder) { // inner side
    if (c.along < 0 || c.along > w.length) return c;
    const Vec3 radial = c.rel - c.along * w.axis;
    const Real r = norm(radial);
    if (r <= 0) return c;
    c.reachable = true;
    c.normal = (1.0 / r) * radial;
    c.overlap = radius - (w.radius - r);
    return c;
  }
  // Plate and cone: the nearest point of the sheet, on a face or a rim.
  if (w.type == Wall::Plate) {
    bool on_face = false;
    c.touch = plate_nearest(w, c.rel, c.along, on_face);
    if (on_face) { // the nearest point is the foot of the normal: the distance is |along|
      if (c.along == 0) return c;
      c.reachable = true;
      c.overlap = radius - (c.along > 0 ? c.along : -c.along);
      c.normal = c.along > 0 ? -w.axis : w.axis;
      return c;
    }
  } else {
    // In the meridional half-plane (s along the axis, rho from it) the cone is the segment from
    // (0, radius) to (length, end_radius).
    Vec3 radial = c.rel - c.along * w.axis;
    const Real rho = norm(radial);
    if (rho > 0) {
      radial = (1.0 / rho) * radial;
    } else { // on the axis: every direction is as near; take a fixed one
      radial = w.edge;
    }
    const Real ds = w.length, dr = w.end_radius - w.radius;
    Real t = (c.along * ds + (rho - w.radius) * dr) / (ds * ds + dr * dr);
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    c.touch = (t * ds) * w.axis + (w.radius + t * dr) * radial;
  }
  const Vec3 away = c.rel - c.touch; // from the sheet to the centre
  const Real dist = norm(away);
  if (dist <= 0) return c; // the centre on the sheet: no side to push it to
  c.reachable = true;
  c.normal = (-1.0 / dist) * away;
  c.overlap = radius - dist;
  return c;
}

// The same for a wall not yet placed (host analyses, one particle at a time).
KOKKOS_INLINE_FUNCTION WallContact wall_contact(const Wall& w, Real t, const Vec3& x, Real radius) {
  return wall_contact(place(w, t), x, radius);
}

// Velocity of the wall's surface at the contact point of `c` (translation plus rotation about the axis),
// with the arm from the axis to the contact point.
KOKKOS_INLINE_FUNCTION Vec3 wall_surface_velocity(const PlacedWall& w, const WallContact& c) {
  Vec3 arm;
  if (w.type == Wall::Plane) {
    arm = c.rel - c.along * w.axis;
  } else if (w.type == Wall::Cylinder) {
    arm = c.along * w.axis + w.radius * c.normal;
  } else if (w.type == Wall::Plate) {
    arm = c.touch; // in the plane through the base
  } else {
    arm = c.touch - dot(c.touch, w.axis) * w.axis;
  }
  return w.velocity + w.spin * cross(w.axis, arm);
}

} // namespace cgdem
