// A ray against one convex shape in its own frame (RayCastShape, RQueries.h).
#include <REnginePhysics/RQueries.h>

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

}  // namespace

bool RayCastShape(const RConvexShape& shape, const RVec3& origin, const RVec3& direction,
                  RScalar maxDistance, RShapeRayHit& hit) {
  return shape.polyhedron ? RayPolyhedron(*shape.polyhedron, origin, direction, maxDistance, hit)
                          : RaySphere(shape.radius, origin, direction, maxDistance, hit);
}

}  // namespace REngine
