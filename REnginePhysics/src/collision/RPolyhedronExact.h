// Private to REnginePhysics: exact signed distances for polyhedra by enumerating features.
//
// GJK and EPA answer almost every query, and say when they have: GJK's lower bound (the
// support plane) meets its upper bound (the point of the Minkowski difference), EPA's
// nearest face meets the support beyond it. Where they do not (a thin simplex with
// coordinates in the thousands whose closest point is lost to rounding, a polytope flat to
// rounding, an iteration cap), these answer instead. They take no iterations and no
// tolerances, so they cannot stall; they cost more (O(F) supports plus O(E_a E_b) edge pairs,
// or O(V F + E^2) for a separated pair), which is why they are the fallback, not the rule.
#pragma once

#include <REnginePhysics/RCollision.h>

namespace REngine {

// Signed distance of polyhedra A (its own frame) and B (posed in A's frame by X_AB), exact
// to rounding, in A's frame: separation, normal (A to B) and witnesses; status is left to the
// caller. Overlapping or touching: the separating axis test over the face normals of both
// and the cross products of the edge pairs that form faces of the Minkowski difference
// (Gregorius, "The separating axis test between convex polyhedra", GDC 2013): its largest
// separation is minus the penetration depth. Apart: the closest pair of features
// (vertex-face both ways, edge-edge), which is the distance.
RDistanceResult ExactPolyhedra(const RConvexPolyhedron& a, const RConvexPolyhedron& b,
                               const RRelativePose& X_AB);

// Closest points of segments [p0, p1] and [q0, q1] (Ericson, Real-Time Collision Detection,
// 5.1.9), a zero-length one taken as a point. Returns whether both are interior to their
// segments.
bool ClosestOnSegments(const RVec3& p0, const RVec3& p1, const RVec3& q0, const RVec3& q1,
                       RVec3& onP, RVec3& onQ);

// Signed distance from point c to the solid polyhedron p (both in p's frame), exact to
// rounding: negative inside. `closest` is the nearest point of the surface, `outward` the
// unit direction from the solid to c (the face normal of least depth when inside).
void ExactPointPolyhedron(const RConvexPolyhedron& p, const RVec3& c, RScalar& signedDistance,
                          RVec3& closest, RVec3& outward);

}  // namespace REngine
