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
  int owner = 0;          // index of the named wall this part belongs to (force reporting)
  Vec3 point;             // plane: a point on it; cylinder: centre of the base at time 0
  Vec3 axis{0, 0, 1};     // plane: unit normal into the particles; cylinder: unit axis
  Real radius = 0;        // cylinder radius; for a plane > 0 bounds it to a disk around point
  Real length = 0;        // cylinder length along the axis
  Vec3 velocity;          // translation while moving
  Real angular_velocity = 0;  // rad/s about axis through point
  Real motion_start = 0, motion_stop = 1e300;

  // Displacement of the wall from its time-0 position.
  KOKKOS_INLINE_FUNCTION Vec3 offset(Real t) const {
    Real moving = t < motion_start ? 0 : (t < motion_stop ? t - motion_start : motion_stop - motion_start);
    return moving * velocity;
  }
  KOKKOS_INLINE_FUNCTION bool moving(Real t) const { return t >= motion_start && t < motion_stop; }
};

struct WallContact {
  Real overlap = -1;      // > 0 in contact
  Vec3 normal;            // unit, from the particle toward the wall
  Vec3 surface_velocity;  // velocity of the wall surface at the contact point
  bool reachable = false; // the particle is within the wall's extent (otherwise no interaction)
};

KOKKOS_INLINE_FUNCTION WallContact wall_contact(const Wall& w, Real t, const Vec3& x, Real radius) {
  WallContact c;
  const Vec3 base = w.point + w.offset(t);
  const Vec3 rel = x - base;
  const bool moving = w.moving(t);
  if (w.type == Wall::Plane) {
    const Real dist = dot(rel, w.axis);
    if (w.radius > 0) {
      const Vec3 in_plane = rel - dist * w.axis;
      if (norm2(in_plane) > w.radius * w.radius) return c;
    }
    c.reachable = true;
    c.overlap = radius - dist;
    c.normal = -w.axis;
    if (moving) {
      const Vec3 contact_point = rel - dist * w.axis;
      c.surface_velocity = w.velocity + w.angular_velocity * cross(w.axis, contact_point);
    }
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
  if (moving) {
    const Vec3 contact_point = axial * w.axis + w.radius * c.normal;
    c.surface_velocity = w.velocity + w.angular_velocity * cross(w.axis, contact_point);
  }
  return c;
}

} // namespace cgdem
