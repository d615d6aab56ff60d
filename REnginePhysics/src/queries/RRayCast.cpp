// A ray against one convex shape in its own frame (RayCastShape, RQueries.h).
#include <REnginePhysics/RQueries.h>
#include <REngineMath/RFunctions.h>

#include "shape/RCompound.h"

#include <algorithm>
#include <cmath>

namespace REngine {

namespace {

// |o + t d| = r for unit d. The textbook root -b - sqrt(b^2 - c) loses every digit twice:
// b^2 - c cancels when the origin is far (b^2 and |o|^2 agree in their leading digits), and
// -b - sqrt(...) cancels when the origin is near the surface. Instead: the squared distance
// of the line from the centre from the perpendicular p = o - b d itself (Ray Tracing Gems,
// ch. 7), and the near root as c / (far root), the product of the roots being
// c = |o|^2 - r^2 = (|o| - r)(|o| + r).
bool RaySphere(RScalar r, const RVec3& o, const RVec3& d, RScalar maxDistance, RShapeRayHit& hit) {
  const RScalar len = o.norm();
  if (len <= r) {  // inside or on the surface
    hit.distance = 0;
    hit.normal = -d;
    return true;
  }
  const RScalar b = o.dot(d);
  if (b >= 0) return false;  // outside and moving away
  const RVec3 p = o - b * d;
  const RScalar h2 = (r - p.norm()) * (r + p.norm());
  if (h2 < 0) return false;
  const RScalar t = (len - r) * (len + r) / (std::sqrt(h2) - b);
  if (!(t <= maxDistance)) return false;
  hit.distance = t;
  const RVec3 n = o + t * d;
  const RScalar nn = n.norm();
  hit.normal = nn > 0 ? RVec3(n / nn) : RVec3(-d);
  return true;
}

// Clipping against the face planes n . x <= offset: the ray is inside all of them for t in
// [enter, exit]; a plane it crosses inwards (n . d < 0) raises enter, outwards lowers exit.
// Each t is one subtraction and one division from the plane's own numbers, so the answer is
// exact to rounding. Starting inside every plane, enter stays 0 (the start is in the solid).
bool RayPolyhedron(const RConvexPolyhedron& poly, const RVec3& o, const RVec3& d,
                   RScalar maxDistance, RShapeRayHit& hit) {
  RScalar enter = 0, exit = maxDistance;
  const RFace* entered = nullptr;
  for (const RFace& f : poly.Faces()) {
    const RScalar denom = f.plane.normal.dot(d);
    const RScalar gap = f.plane.offset - f.plane.normal.dot(o);  // >= 0: inside this plane
    if (denom == 0) {
      if (gap < 0) return false;  // parallel, outside
      continue;
    }
    const RScalar t = gap / denom;
    if (denom < 0) {
      if (t > enter) enter = t, entered = &f;
    } else if (t < exit) {
      exit = t;
    }
    if (enter > exit) return false;
  }
  hit.distance = enter;
  hit.normal = entered ? entered->plane.normal : RVec3(-d);
  return true;
}

// A capsule (core from (0, -h, 0) to (0, h, 0), radius r) is the union of a finite cylinder
// and two balls, and the first point a ray meets on a union is the first it meets on any
// part: the cylinder's side where it lies within the core's height (its flat ends lie inside
// the balls, met no later), or a ball. Starting within r of the core is starting inside.
bool RayCapsule(RScalar r, RScalar h, const RVec3& o, const RVec3& d, RScalar maxDistance, RShapeRayHit& hit) {
  const RScalar y = std::clamp(o.y(), -h, h);
  if ((o - RVec3(0, y, 0)).norm() <= r) {
    hit.distance = 0;
    hit.normal = -d;
    return true;
  }
  bool found = false;
  // The side: |o_xz + t d_xz| = r, its near root as c / (far root) as for the sphere, the
  // discriminant from the perpendicular to the axis (see RaySphere).
  const RScalar a = d.x() * d.x() + d.z() * d.z();
  const RScalar b = o.x() * d.x() + o.z() * d.z();
  const RScalar len = Hypot(o.x(), o.z());
  if (a > 0 && b < 0 && len > r) {
    const RScalar px = o.x() - b / a * d.x(), pz = o.z() - b / a * d.z();
    const RScalar p = Hypot(px, pz);
    const RScalar h2 = (r - p) * (r + p);  // the half chord squared, over a
    if (h2 >= 0) {
      const RScalar t = (len - r) * (len + r) / (std::sqrt(a * h2) - b);
      const RScalar yt = o.y() + t * d.y();
      if (t <= maxDistance && std::abs(yt) <= h) {
        hit.distance = t;
        const RScalar nx = o.x() + t * d.x(), nz = o.z() + t * d.z(), nn = Hypot(nx, nz);
        hit.normal = nn > 0 ? RVec3(nx / nn, 0, nz / nn) : RVec3(-d);
        found = true;
      }
    }
  }
  for (const RScalar end : {-h, h}) {
    RShapeRayHit ball;
    const RVec3 c(0, end, 0);
    if (RaySphere(r, o - c, d, found ? hit.distance : maxDistance, ball) && (!found || ball.distance < hit.distance)) {
      hit = ball;
      found = true;
    }
  }
  return found;
}

// A cylinder (radius r about y, ends at y = +-h) is the intersection of a slab and an
// infinite round cylinder: as for a polyhedron, the ray is inside both for t in
// [enter, exit], and the constraint that raised enter last gives the normal. The side's
// roots as in RayCapsule, each from the form that does not cancel.
bool RayCylinder(RScalar r, RScalar h, const RVec3& o, const RVec3& d, RScalar maxDistance, RShapeRayHit& hit) {
  RScalar enter = 0, exit = maxDistance;
  RVec3 normal = -d;  // starting inside
  if (d.y() == 0) {
    if (std::abs(o.y()) > h) return false;
  } else {
    const RScalar t0 = (-h - o.y()) / d.y(), t1 = (h - o.y()) / d.y();
    if (std::min(t0, t1) > enter) enter = std::min(t0, t1), normal = RVec3(0, d.y() > 0 ? -1 : 1, 0);
    exit = std::min(exit, std::max(t0, t1));
  }
  const RScalar a = d.x() * d.x() + d.z() * d.z();
  const RScalar len = Hypot(o.x(), o.z());
  if (a == 0) {
    if (len > r) return false;
  } else {
    const RScalar b = o.x() * d.x() + o.z() * d.z();
    const RScalar px = o.x() - b / a * d.x(), pz = o.z() - b / a * d.z();
    const RScalar p = Hypot(px, pz);
    const RScalar h2 = (r - p) * (r + p);
    if (h2 < 0) return false;
    const RScalar s = std::sqrt(a * h2), c = (len - r) * (len + r);
    RScalar tNear, tFar;
    if (b <= 0) {
      tFar = (s - b) / a;
      tNear = s - b > 0 ? c / (s - b) : tFar;
    } else {
      tNear = -(s + b) / a;
      tFar = -c / (s + b);
    }
    if (tNear > enter) {
      enter = tNear;
      const RScalar nx = o.x() + enter * d.x(), nz = o.z() + enter * d.z(), nn = Hypot(nx, nz);
      normal = nn > 0 ? RVec3(nx / nn, 0, nz / nn) : RVec3(-d);
    }
    exit = std::min(exit, tFar);
  }
  if (enter > exit) return false;
  hit.distance = enter;
  hit.normal = normal;
  return true;
}

}  // namespace

bool RayCastShape(const RConvexShape& shape, const RVec3& origin, const RVec3& direction,
                  RScalar maxDistance, RShapeRayHit& hit) {
  if (shape.polyhedron) return RayPolyhedron(*shape.polyhedron, origin, direction, maxDistance, hit);
  if (shape.mesh) return RayCastMesh(*shape.mesh, origin, direction, maxDistance, hit);
  if (shape.children) return RayCastCompound(shape, origin, direction, maxDistance, hit);
  if (shape.cylinderRadius > 0) return RayCylinder(shape.cylinderRadius, shape.halfHeight, origin, direction, maxDistance, hit);
  if (shape.halfHeight > 0) return RayCapsule(shape.radius, shape.halfHeight, origin, direction, maxDistance, hit);
  return RaySphere(shape.radius, origin, direction, maxDistance, hit);
}

}  // namespace REngine
