#pragma once
// Sphere-triangle contact geometry for mesh walls, host and device.
//
// closest_on_triangle: the point of triangle (a, b, c) nearest to p and the feature it lies on (the face's
// interior, one of its edges, one of its vertices), by the Voronoi regions of the triangle (Ericson,
// Real-Time Collision Detection, 5.1.5).
//
// One sphere near a tessellated surface finds a nearest point on every triangle within reach, but touches
// the surface once: on a flat floor cut into triangles, the triangle under its centre gives a face contact
// and its neighbours give edge and vertex points on the same plane, which are not contacts of the surface.
// MeshContactFilter keeps the contacts of the surface, fed the triangles' nearest points faces first:
//   - a face point is kept unless it coincides with a kept point (a centre right above a shared edge
//     projects into both triangles);
//   - an edge or vertex point is kept unless it lies on the plane of a kept face (every edge and vertex of
//     a flat or concave neighbourhood does) or coincides with a kept point (the two triangles of a convex
//     edge both find it).
// So a sphere on a tessellated plane feels exactly one face contact, the plane's; on a convex edge or
// vertex exactly one contact; in a concave crease one face contact per face it touches.
#include "core/types.hpp"

namespace cgdem {

struct TrianglePoint {
  enum Feature : int { Face = 0, Edge = 1, Vertex = 2 };
  Vec3 point;
  int feature = Face;
  int index = 0; // Edge: 0 (a-b), 1 (b-c), 2 (c-a); Vertex: 0 (a), 1 (b), 2 (c)
};

KOKKOS_INLINE_FUNCTION TrianglePoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                                         const Vec3& c) {
  TrianglePoint r;
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {a, TrianglePoint::Vertex, 0};
  const Vec3 bp = p - b;
  const Real d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {b, TrianglePoint::Vertex, 1};
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const Real v = d1 / (d1 - d3);
    return {a + v * ab, TrianglePoint::Edge, 0};
  }
  const Vec3 cp = p - c;
  const Real d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {c, TrianglePoint::Vertex, 2};
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const Real w = d2 / (d2 - d6);
    return {a + w * ac, TrianglePoint::Edge, 2};
  }
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const Real w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), TrianglePoint::Edge, 1};
  }
  const Real denom = 1 / (va + vb + vc);
  const Real v = vb * denom, w = vc * denom;
  r.point = a + v * ab + w * ac;
  r.feature = TrianglePoint::Face;
  return r;
}

// The contacts one sphere keeps with the mesh surfaces around it (see the top of this file). Capacity
// kMax: more contacts than that at once are left out (`overflow` counts them).
struct MeshContactFilter {
  static constexpr int kMax = 8;
  Vec3 point[kMax], face_normal[kMax];
  bool is_face[kMax] = {};
  int tag[kMax] = {}; // the caller's (its triangle)
  int n = 0, overflow = 0;
  Real tolerance = 0; // coincidence and on-plane distance (m)

  KOKKOS_INLINE_FUNCTION explicit MeshContactFilter(Real tol) : tolerance(tol) {}

  // Offers a nearest point, every face before any edge or vertex; `normal` is the face's unit normal
  // pointing to the sphere's side (used for faces). Returns the slot it was kept in, or -1.
  KOKKOS_INLINE_FUNCTION int offer(const TrianglePoint& tp, const Vec3& normal, int caller_tag = 0) {
    for (int k = 0; k < n; ++k) {
      if (norm2(tp.point - point[k]) <= tolerance * tolerance) return -1;
      if (tp.feature != TrianglePoint::Face && is_face[k]) {
        // On the kept face's plane, or behind it (a convex surface's farther edges).
        const Real off = dot(tp.point - point[k], face_normal[k]);
        if (off <= tolerance) return -1;
      }
    }
    if (n == kMax) {
      ++overflow;
      return -1;
    }
    point[n] = tp.point;
    face_normal[n] = normal;
    tag[n] = caller_tag;
    is_face[n] = tp.feature == TrianglePoint::Face;
    return n++;
  }
};

// Whether the nearest point p acts as a face contact: inside the face, or on its rim with the sphere's
// centre right above it (`toward`, from p to the centre, along the face normal): a centre above a shared
// edge or vertex of a flat region projects onto the rim of every triangle around it, none inside.
KOKKOS_INLINE_FUNCTION bool acts_as_face(const TrianglePoint& p, const Vec3& toward, const Vec3& normal) {
  return p.feature == TrianglePoint::Face || norm2(cross(toward, normal)) <= 1e-16 * norm2(toward);
}

// Unit normal of triangle (a, b, c) (right-handed); zero for a degenerate triangle.
KOKKOS_INLINE_FUNCTION Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = cross(b - a, c - a);
  const Real len = norm(n);
  return len > 0 ? (1 / len) * n : Vec3{};
}

// Rotation of v by angle theta about the unit axis k (Rodrigues).
KOKKOS_INLINE_FUNCTION Vec3 rotate_about(const Vec3& v, const Vec3& k, Real theta) {
  const Real c = math::cos(theta), s = math::sin(theta);
  return c * v + s * cross(k, v) + ((1 - c) * dot(k, v)) * k;
}

} // namespace cgdem
