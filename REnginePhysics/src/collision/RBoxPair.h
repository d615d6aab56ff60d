// Private to REnginePhysics: two boxes proven apart in closed form, the narrow phase's
// shortcut before GJK for Box() polyhedra (RCollisionSolver::DistanceWithin).
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RCollision.h>

namespace REngine {

// Two boxes (half extents ha, hb, each axis-aligned in its own frame; B's pose in A's X)
// proven farther apart than `cutoff` (m) by one of their 15 separating axes: the three
// face normals of each and the nine edge-edge crosses (Gottschalk's OBB test). The
// separation along any axis is a lower bound of the distance, so a proof is certain; a pair
// that no axis proves apart goes on to GJK. Returns the axis's lower bound in `bound` and
// its direction (A's frame, from A to B) in `axis`. Thirty-odd products and no vertex:
// most pairs the broad phase passes in a cloud of boxes are proven apart here. A pose whose
// matrix is not a rotation (to 1e-9) is never proven apart.
bool BoxesApart(const RVec3& ha, const RVec3& hb, const RRelativePose& X, RScalar cutoff, RScalar& bound,
                RVec3& axis);

}  // namespace REngine
