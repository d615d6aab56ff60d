// Private to REnginePhysics: compound shapes (RCompound.cpp).
//
// A compound is a rigid union of convex children. Its mass properties are the union's
// (each child's at its density, moved to the common centre of mass by the parallel-axis
// theorem); its body frame is the union's principal frame, as for every body, so the exact
// free rotation applies unchanged. The narrow phase works child by child: every child pair
// is a convex pair in the child's frame (the convex narrow phase unchanged), and the
// answers come back to the body's frame. A pair of bodies can then touch at several places
// with different normals: the step gets one contact per touching child pair.
#pragma once

#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RQueries.h>
#include <REnginePhysics/RRigidBody.h>

#include "collision/RMesh.h"

#include <cstdint>

namespace REngine {

// Checks a compound's children (count, types, poses, densities, each child's shape as
// PrepareShape does) and fills p's children, mass properties and bounds. Throws RBodyError
// naming the field ("shape.children[2].density", "shape.children[0].shape.radius").
void PrepareCompound(const RShape& shape, RPreparedShape& p);

// The union's mass properties at its children's densities (RShape.h).
RMassProperties CompoundMassProperties(const RShape& shape);

// The least distance over the child pairs (a non-compound side is its own one child), in
// A's frame; pairs proven beyond cutoff (or beyond the best so far) are not computed.
RDistanceResult CompoundDistance(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB,
                                 RScalar cutoff);

// The manifold of the child pair with the least separation, in A's frame, naming its children.
RContactManifold CompoundManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB,
                                  RScalar margin, RScalar cutoff, RScalar* droppedMin);

// Every child pair's manifold within the margin, in A's frame, in order of A's child then
// B's, each naming its children and with feature ids made distinct per child pair: calls
// emit(const RContactManifold&) for each with points. Returns the number of child pairs
// that got the narrow phase (their bounding spheres within the margin).
template <class Emit>
int ForEachChildManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB, RScalar margin,
                         const Emit& emit);

// The child frame of one child pair: cb's pose in ca's frame, from B's in A's.
inline RRelativePose ChildPose(const RShapeChild& ca, const RShapeChild& cb, const RRelativePose& X) {
  RRelativePose c;
  c.R_AB = ca.R_BC.transpose() * X.R_AB * cb.R_BC;
  c.t_AB = ca.R_BC.transpose() * (X.R_AB * cb.p_BC + X.t_AB - ca.p_BC);
  return c;
}

// A manifold of a child pair (in ca's frame) turned into A's body frame, naming its children.
void ChildToBody(const RShapeChild& ca, std::uint32_t ia, std::uint32_t ib, RContactManifold& m);

// Whether a shape meets others part by part (a compound's children, a mesh's triangles):
// then a pair of bodies can touch at several places, one contact each.
inline bool HasParts(const RConvexShape& s) { return s.children || s.mesh; }

// The shape as a list of children: a compound's own, or the shape alone at the identity.
inline const RShapeChild* ChildrenOf(const RConvexShape& s, RShapeChild& alone, std::uint32_t& count) {
  if (s.children) {
    count = s.childCount;
    return s.children;
  }
  alone.shape = s;
  count = 1;
  return &alone;
}

template <class Emit>
int ForEachChildManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X, RScalar margin,
                         const Emit& emit) {
  RShapeChild aloneA, aloneB;
  std::uint32_t na, nb;
  if (a.mesh || b.mesh) {
    // A mesh against each child of the other shape: that child's manifolds, merged by normal
    // (RMesh.h). Two meshes never touch.
    if (a.mesh && b.mesh) return 0;
    const bool meshIsA = a.mesh != nullptr;
    const RConvexShape& other = meshIsA ? b : a;
    const RShapeChild* c = ChildrenOf(other, aloneA, na);
    RContactManifold ms[kMaxMeshManifolds];
    for (std::uint32_t j = 0; j < na; ++j) {
      const int count = MeshChildManifolds(meshIsA ? *a.mesh : *b.mesh, meshIsA, c[j], other.children ? j : 0, X,
                                           margin, ms);
      for (int k = 0; k < count; ++k) emit(static_cast<const RContactManifold&>(ms[k]));
    }
    return static_cast<int>(na);
  }
  const RShapeChild* ca = ChildrenOf(a, aloneA, na);
  const RShapeChild* cb = ChildrenOf(b, aloneB, nb);
  int tested = 0;
  for (std::uint32_t i = 0; i < na; ++i) {
    for (std::uint32_t j = 0; j < nb; ++j) {
      const RRelativePose Xc = ChildPose(ca[i], cb[j], X);
      // Child bounds: the children's bounding spheres (about their own origins) apart by
      // more than the margin need nothing more.
      if (Xc.t_AB.norm() - ca[i].shape.boundingRadius - cb[j].shape.boundingRadius > margin) continue;
      ++tested;
      RContactManifold m;
      if (!RCollisionSolver::CheckCollisionInA(ca[i].shape, cb[j].shape, Xc, RMargin{margin}, m)) continue;
      if (m.pointCount == 0) continue;
      ChildToBody(ca[i], a.children ? i : 0, b.children ? j : 0, m);
      emit(m);
    }
  }
  return tested;
}

// A ray against a compound in its body frame: the first hit over its children.
bool RayCastCompound(const RConvexShape& shape, const RVec3& origin, const RVec3& direction, RScalar maxDistance,
                     RShapeRayHit& hit);

}  // namespace REngine
