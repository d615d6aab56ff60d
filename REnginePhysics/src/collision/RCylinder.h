// Private to REnginePhysics: the narrow phase of pairs with a cylinder (RCylinder.cpp).
//
// A cylinder is round and flat at once: no core and radius describe it, so its queries run
// GJK and EPA on its exact support mapping (the rim point farthest along a direction)
// against the other shape's core (a sphere's centre, a capsule's segment, a polyhedron),
// the other's radius added after, as for capsules. GJK's answer is taken where its upper
// and lower bounds meet; EPA's where its polytope's nearest face and the support beyond it
// meet to a part in 1e10. The manifold comes from features: a cylinder's end is a polygon
// on its rim (an octagon fixed in the body, plus the exact deepest rim point when the end
// is tilted), its side a line along the axis.
#pragma once

#include <REnginePhysics/RCollision.h>

#include <limits>

namespace REngine {

// Signed distance, normal and witnesses of a pair with at least one cylinder, in A's frame.
// A pair GJK proves farther apart than cutoff gets that proof (separation = the bound, no
// witnesses), as DistanceWithin does for polyhedra.
RDistanceResult CylinderPair(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB,
                             RScalar cutoff = std::numeric_limits<RScalar>::infinity());

// The contact points of a pair with a cylinder from its query m.query (already filled):
// a face or a cylinder's end against whatever lies on it (clipped to it, each point with its
// own separation: an end standing on a face gives a full manifold, a side lying on it a
// line); two sides along each other a line; anything else the witnesses' single point.
// Points farther apart than margin are dropped, the least of them kept in *droppedMin.
void CylinderManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB,
                      RScalar margin, RContactManifold& m, RScalar* droppedMin);

}  // namespace REngine
