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

struct WallContact {
  Real overlap = -1;      // > 0 in contact
  Vec3 normal;            // unit, from the particle toward the wall
  Vec3 arm;               // from the wall's axis to the contact point (for the surface velocity)
  bool reachable = false; // the particle is within the wall's extent (otherwise no interaction)
};

// Geometry only: every particle is tested against every wall each step, and most are far from it, so
// the surface velocity (the motion segments summed again) is left to wall_surface_velocity, called for
// the particles within reach.
KOKKOS_INLINE_FUNCTION WallContact wall_contact(const Wall& w, Real t, const Vec3& x, Real radius) {
  WallContact c;
  const Vec3 base = w.point + w.offset(t);
  const Vec3 rel = x - base;
  if (w.type == Wall::Plane) {
    const Real dist = dot(rel, w.axis);
    if (w.radius > 0) {
      const Vec3 in_plane = rel - dist * w.axis;
      if (norm2(in_plane) > w.radius * w.radius) return c;
    }
    c.reachable = true;
    c.overlap = radius - dist;
    c.normal = -w.axis;
    c.arm = rel - dist * w.axis;
    return c;
  }
  // Inner side of a cylinder.
  const Real axial = dot(rel, w.axis);
  if (axial < 0 || axial > w.length) return c;
  const Vec3 radial = rel - axial * w.axis;
  const Real r = norm(radial);
  if (r <= 0) return c;
  c.reachable = true;
  c.normal = (1.0 / r) * radial;
  c.overlap = radius - (w.radius - r);
  c.arm = axial * w.axis + w.radius * c.normal;
  return c;
}

// Velocity of the wall's surface at the contact point of `c` (translation plus rotation about the axis).
KOKKOS_INLINE_FUNCTION Vec3 wall_surface_velocity(const Wall& w, Real t, const WallContact& c) {
  const Real spin = w.moving(t) ? w.angular_velocity : 0;
  return w.translation_velocity(t) + spin * cross(w.axis, c.arm);
}

} // namespace cgdem
