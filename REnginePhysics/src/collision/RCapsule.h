// Private to REnginePhysics: the narrow phase of capsules (RCapsule.cpp).
//
// A capsule is its core, the segment from (0, -h, 0) to (0, h, 0) in its body frame, swept
// by a ball of its radius r; a sphere is the same with h = 0. The distance of a capsule from
// any convex shape is the distance of its core minus r, and where the cores overlap the
// depth is the cores' depth plus r, along the same normal: a rounded shape's surface is its
// core's pushed out by r. So every query here is a query on cores, exact for segments and
// points in closed form, and for a segment against a polyhedron by GJK where GJK certifies
// its answer and by enumeration where it does not or the cores overlap.
#pragma once

#include <REnginePhysics/RCollision.h>

#include "collision/RGjkEpa.h"

#include <limits>

namespace REngine {

// Two shapes without polyhedra, at least one of them a capsule, in A's frame.
RDistanceResult RoundPair(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB);

// Polyhedron A against capsule B, in A's frame. A pair whose cores GJK proves farther apart
// than cutoff + B's radius gets that proof (separation = its lower bound minus the radius,
// no witnesses), as DistanceWithin does for polyhedra.
RDistanceResult PolyhedronCapsule(const RConvexShape& poly, const RConvexShape& capsule,
                                  const RRelativePose& X_AB, RPairSupport& sup,
                                  RScalar cutoff = std::numeric_limits<RScalar>::infinity());

// Exact to rounding: the signed distance of segment [p0, p1] from the solid polyhedron P,
// all in P's frame; normal from P to the segment, onP on P's surface, onSegment on the
// segment (the deepest point of the segment when they overlap).
void ExactSegmentPolyhedron(const RConvexPolyhedron& P, const RVec3& p0, const RVec3& p1,
                            RScalar& signedDistance, RVec3& normal, RVec3& onP, RVec3& onSegment);

// Where a capsule lies along a face of a polyhedron or along another capsule, the contact
// is a line: its two ends, each with its own separation (a capsule tilted on a floor
// touches with one end and hovers with the other). Fills m's points and normal (A's frame)
// and returns true; false when one point describes the contact (an edge, a corner, crossed
// capsules, a sphere). Points farther apart than margin are dropped, the least of them
// kept in *droppedMin as ManifoldWithin does.
bool CapsuleManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB,
                     RScalar margin, RContactManifold& m, RScalar* droppedMin);

}  // namespace REngine
