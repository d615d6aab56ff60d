// Private to REnginePhysics: covered features across immovable bodies (RCoveredFeatures.cpp),
// the rule that makes flush tiles one surface.
//
// Separate immovable bodies laid edge to edge (a platform of boxes, hulls or mesh pieces)
// have faces and edges inside their union: a tile's side face pressed against its
// neighbour's, a flat piece's open edge that the next piece continues. Such a feature is no
// surface of the world, yet the narrow phase, which sees one pair at a time, can find a
// contact's normal on it: a body resting on the tiles (sunk by up to the slop) whose leading
// edge has just crossed a seam overlaps the next tile less along the motion than downwards,
// so that tile's side face (its top edge, for a round body) gives the normal, and the body is
// thrown back and up. The rule, as Jolt's internal edge removal and Box2D's ghost vertices
// do within one shape, across bodies:
//  * a face of B is covered at a point when another immovable body A holds a face against it
//    there: facing it (normals opposed within kFaceContactCos), its plane within `flush` of
//    the point, the point within `inPlane` of its polygon;
//  * an open edge of a mesh piece B is covered at a point when A continues B's plane there:
//    just beyond the edge (flush further out) lies a face of A in B's plane;
//  * a contact on B whose points lie on a covered feature, and whose normal is not the
//    normal of an uncovered face through them, is not a surface contact: it takes the
//    normal of the uncovered face through them that the moving shape overlaps least (a mesh
//    piece: its own face, on the moving shape's side), with the manifold's points and
//    depths computed along it (ManifoldAlong), kept where they lie on that face of B; none
//    left (the body is over A, whose own contact holds it), or no face through them
//    uncovered (a corner inside the union): the contact is dropped.
// Everything else is kept as the narrow phase gave it, bit for bit.
#pragma once

#include <REnginePhysics/RCollision.h>

#include <cstdint>

namespace REngine {

// An immovable body's surface as the rule reads it: its shape in its body frame B (a
// polyhedron or a mesh; any other shape neither covers nor is covered), its pose in the
// world (p_W = R_WB p_B + x_W, m), its world box (m) and which body it is.
struct RCoverSurface {
  RConvexShape shape;
  RMat3 R_WB = RMat3::Identity();
  RVec3 x_W = RVec3::Zero();
  RVec3 boxMin_W = RVec3::Zero(), boxMax_W = RVec3::Zero();
  std::uint32_t id = 0;  // which body (the caller's index): a body does not cover itself
  // Which of the body's compound children this is (kWhole: the body's own shape). A
  // compound's children are surfaces of their own: a deck built of boxes in one body has
  // its seams between children, and its children cover each other as separate bodies do.
  static constexpr std::uint32_t kWhole = 0xffffffffu;
  std::uint32_t child = kWhole;
  bool Same(const RCoverSurface& o) const { return id == o.id && child == o.child; }
  // Its motion, world, m/s and rad/s: bodies cover each other only while they move as one,
  // without turning (static ones; kinematic ones still, or translating at one velocity): a
  // kinematic paddle sweeping over the ground covers nothing of it. The children of one
  // body always move as one, however it turns (a spinning station's deck of boxes).
  RVec3 v_W = RVec3::Zero(), w_W = RVec3::Zero();
  bool Takes() const { return (shape.polyhedron != nullptr || shape.mesh != nullptr) && shape.children == nullptr; }
  bool MovesWith(const RCoverSurface& o) const {
    return id == o.id || (w_W.isZero(0) && o.w_W.isZero(0) && v_W == o.v_W);
  }
};

// The moving body's convex piece in the contact (the body's shape, or a compound's child),
// posed in the world: p_W = R_W p + x_W (m).
struct RPosedShape {
  RConvexShape shape;
  RMat3 R_W = RMat3::Identity();
  RVec3 x_W = RVec3::Zero();
};

// The rule's tolerances, m. flush: how far apart two facing planes may be and still be
// pressed together (a gap or step this small is none); inPlane: how far beyond a face's
// polygon a point may lie and still be on the face (flush plus the clipping's outward push,
// up to kClipTolerance of a face's size).
struct RCoverTolerances {
  RScalar flush = 0;
  RScalar inPlane = 0;
};

// The tolerances for a contact: flush is the contact slop plus the touching band of the pair
// (kTouchingTolerance of its size: the rounding of poses far from the origin); inPlane adds
// twice kClipTolerance of the larger body's radius (a face is at most its body's diameter).
RCoverTolerances CoverTolerances(RScalar slop, RScalar radiusB, RScalar radiusM);

enum class RCoverResult : std::uint8_t { kKept, kReplaced, kDropped };

// The rule for one contact between immovable body B and moving piece M, its manifold in the
// world (normal from the contact's a to its b; bIsA: B is a), against the other immovable
// bodies M touches this step (coverers, count of them). margin (m): the pair's speculative
// margin, as the narrow phase used it. Replaced: the manifold is rewritten (normal, query,
// points; children kept). Dropped: the contact is no surface contact.
RCoverResult CoverContact(const RCoverSurface& b, bool bIsA, const RPosedShape& m, const RCoverSurface* coverers,
                          int count, const RCoverTolerances& tol, RScalar margin, RContactManifold& manifold_W);

}  // namespace REngine
