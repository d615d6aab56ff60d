// What the cylinder suites (cylinder_test, cylinder_narrowphase_test, cylinder_physics_test)
// share: a cylinder's and a capsule's convex shape, and a cylinder's manifold on a slab's
// top face.
#pragma once

#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RShape.h>

#include "support/RandomPartners.h"

namespace REngine::test {

inline RConvexShape Cylinder(RScalar r, RScalar h) { return CylinderShape(r, h); }
inline RConvexShape Capsule(RScalar r, RScalar h) { return CapsuleShape(r, h); }

inline RConvexPolyhedron Slab() { return RConvexPolyhedron::Box(RVec3(3, 0.5, 3)); }

inline RContactManifold OnSlab(const RConvexPolyhedron& slab, const RConvexShape& c, const RQuat& q,
                               const RVec3& t) {
  RConvexShape a;
  a.polyhedron = &slab, a.boundingRadius = slab.MaxRadius();
  RRelativePose X;
  X.R_AB = q.toRotationMatrix(), X.t_AB = t;
  return RCollisionSolver::Manifold(a, c, X, 1e-3);
}

}  // namespace REngine::test
