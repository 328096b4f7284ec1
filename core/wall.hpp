#pragma once
// Walls as plain device structs: infinite (or disk-bounded) planes and the inner side of finite
// cylinders, with a prescribed translation and a rotation about their own axis (a rotating drum).
// A cylinder's end caps are expanded on the host into two disk-bounded planes that report their
// force to the cylinder (owner), so every wall part has its own contact-history slot.
#include "core/types.hpp"

namespace cgdem {

struct Wall {
  enum Type : int { Plane = 0, Cylinder = 1 };
  int type = Plane;
  int material = 0;
  int owner = 0;             // index of the named wall this part belongs to (force reporting)
  Vec3 point;                // plane: a point on it; cylinder: centre of the base at time 0
  Vec3 axis{0, 0, 1};        // plane: unit normal into the particles; cylinder: unit axis
  Real radius = 0;           // cylinder radius; for a plane > 0 bounds it to a disk around point
  Real length = 0;           // cylinder length along the axis
  Vec3 velocity;             // translation while moving
  Real angular_velocity = 0; // rad/s about axis through point
  Real motion_start = 0, motion_stop = 1e300;
  // Further translation segments (scene motion.then), constant velocity over [start, stop) each.
  static constexpr int kMaxThen = 3;
  Vec3 then_velocity[kMaxThen];
  Real then_start[kMaxThen] = {0, 0, 0}, then_stop[kMaxThen] = {0, 0, 0};
  int num_then = 0;

  KOKKOS_INLINE_FUNCTION static Real span(Real t, Real a, Real b) {
    return t < a ? 0 : (t < b ? t - a : b - a);
  }
  // Displacement of the wall from its time-0 position.
  KOKKOS_INLINE_FUNCTION Vec3 offset(Real t) const {
    Vec3 d = span(t, motion_start, motion_stop) * velocity;
    for (int k = 0; k < num_then; ++k)
      d += span(t, then_start[k], then_stop[k]) * then_velocity[k];
    return d;
  }
  KOKKOS_INLINE_FUNCTION bool moving(Real t) const { return t >= motion_start && t < motion_stop; }
  // Translation velocity at time t (the sum of the active segments).
  KOKKOS_INLINE_FUNCTION Vec3 translation_velocity(Real t) const {
    Vec3 v = moving(t) ? velocity : Vec3{};
    for (int k = 0; k < num_then; ++k)
      if (t >= then_start[k] && t < then_stop[k]) v += then_velocity[k];
    return v;
  }
};

// A wall part at one instant: where its base is and how its surface moves. The force pass places every
// wall once per step (place) instead of once per particle: summing the motion segments was about a
// third of a far particle's wall test.
struct PlacedWall {
  int type = Wall::Plane;
  int material = 0;
  Vec3 base; // plane: a point on it; cylinder: centre of the base
  Vec3 axis{0, 0, 1};
  Real radius = 0, length = 0;
  Vec3 velocity; // translation velocity
  Real spin = 0; // angular velocity about the axis through base
};

KOKKOS_INLINE_FUNCTION PlacedWall place(const Wall& w, Real t) {
  PlacedWall p;
  p.type = w.type;
  p.material = w.material;
  p.base = w.point + w.offset(t);
  p.axis = w.axis;
  p.radius = w.radius;
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
};

// Geometry only: every particle is tested against every wall each step, and most are far from it, so
// the lever arm to the contact point is left to wall_surface_velocity, called for the particles within
// reach.
KOKKOS_INLINE_FUNCTION WallContact wall_contact(const PlacedWall& w, const Vec3& x, Real radius) {
  WallContact c;
  c.rel = x - w.base;
  if (w.type == Wall::Plane) {
    c.along = dot(c.rel, w.axis);
    if (w.radius > 0) {
      const Vec3 in_plane = c.rel - c.along * w.axis;
      if (norm2(in_plane) > w.radius * w.radius) return c;
    }
    c.reachable = true;
    c.overlap = radius - c.along;
    c.normal = -w.axis;
    return c;
  }
  // Inner side of a cylinder.
  c.along = dot(c.rel, w.axis);
  if (c.along < 0 || c.along > w.length) return c;
  const Vec3 radial = c.rel - c.along * w.axis;
  const Real r = norm(radial);
  if (r <= 0) return c;
  c.reachable = true;
  c.normal = (1.0 / r) * radial;
  c.overlap = radius - (w.radius - r);
  return c;
}

// The same for a wall not yet placed (host analyses, one particle at a time).
KOKKOS_INLINE_FUNCTION WallContact wall_contact(const Wall& w, Real t, const Vec3& x, Real radius) {
  return wall_contact(place(w, t), x, radius);
}

// Velocity of the wall's surface at the contact point of `c` (translation plus rotation about the axis),
// with the arm from the axis to the contact point.
KOKKOS_INLINE_FUNCTION Vec3 wall_surface_velocity(const PlacedWall& w, const WallContact& c) {
  const Vec3 arm = w.type == Wall::Plane ? c.rel - c.along * w.axis : c.along * w.axis + w.radius * c.normal;
  return w.velocity + w.spin * cross(w.axis, arm);
}

} // namespace cgdem
