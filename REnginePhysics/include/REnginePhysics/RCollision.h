// Narrow-phase collision queries between convex shapes: GJK (boolean and distance with
// witness points), EPA (penetration depth and normal), and contact manifolds.
//
// Conventions, everywhere in REngine's collision code:
//  * The normal is a unit vector pointing from shape A to shape B: translating B by
//    +depth * normal separates penetrating shapes; for separated shapes it is the direction
//    of the shortest segment from A to B.
//  * separation = signed distance: > 0 apart (the distance), < 0 overlapping (-depth).
//  * Queries run in a frame local to the pair (A's centre of mass and axes), so a pair 1e7 m
//    from the origin computes exactly what it computes at the origin; only the final
//    world-space points carry the rounding of their large coordinates.
//  * Tolerances scale with the pair's size: the touching band is
//    |separation| <= RCollisionSolver::kTouchingTolerance * (bounding radius of A + of B).
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REngineMath/RMath.h>
#include <REnginePhysics/RConvexPolyhedron.h>

#include <cstdint>

namespace REngine {

class RRigidBody;

// A convex shape as the narrow phase sees it, in its own body frame B: a polyhedron, a
// cylinder, or a core swept by a sphere: a point (a sphere) or the segment from
// (0, -halfHeight, 0) to (0, halfHeight, 0) (a capsule). Cheap to build per query.
struct RConvexShape {
  const RConvexPolyhedron* polyhedron = nullptr;  // null: a sphere, capsule or cylinder about B's origin
  RScalar radius = 0;                             // sphere or capsule radius, m (0 otherwise)
  RScalar boundingRadius = 0;                     // about B's origin, m
  RScalar halfHeight = 0;                         // capsule core's or cylinder's half length along B's y, m
  // > 0: a cylinder of this radius about B's y axis, its flat ends at y = +-halfHeight, m.
  RScalar cylinderRadius = 0;
  // Non-null: a compound, the union of these childCount convex children (the fields above
  // unused but boundingRadius). Every query answers for the union: the least distance over
  // the children's pairs, the manifold of the deepest pair, the first ray hit.
  const struct RShapeChild* children = nullptr;
  std::uint32_t childCount = 0;
  // Non-null: a triangle mesh in B (the fields above unused but boundingRadius). Queries
  // answer for its triangles, each a convex child of its own (RMesh.h); two meshes never
  // touch.
  const class RTriangleMesh* mesh = nullptr;
};

// A compound's child as the narrow phase sees it: its convex shape in its own body frame C,
// and C's pose in the compound's body frame B (p_B = R_BC p_C + p_BC), m.
struct RShapeChild {
  RConvexShape shape;
  RMat3 R_BC = RMat3::Identity();
  RVec3 p_BC = RVec3::Zero();
};

// Pose of shape B's frame in shape A's frame: p_A = R_AB p_B + t_AB. Both in metres.
struct RRelativePose {
  RMat3 R_AB = RMat3::Identity();
  RVec3 t_AB = RVec3::Zero();
};

enum class RCollisionStatus : std::uint8_t {
  kSeparated,     // separation > touching band
  kTouching,      // |separation| within the touching band
  kPenetrating,   // separation < -touching band
  kIterationCap,  // no verdict. No query returns it any more: where GJK or EPA cannot
                  // certify an answer, the exact enumeration answers (RPolyhedronExact).
                  // Kept so that callers written against it still compile.
};

// Result of a distance / penetration query between two shapes.
struct RDistanceResult {
  RCollisionStatus status = RCollisionStatus::kSeparated;
  RScalar separation = 0;          // signed distance, m
  RVec3 normal = RVec3::UnitX();   // unit, from A to B (in the frame the query was posed in)
  RVec3 witnessA = RVec3::Zero();  // closest (or deepest) point on A's surface, m
  RVec3 witnessB = RVec3::Zero();  // closest (or deepest) point on B's surface, m
  int gjkIterations = 0;
  int epaIterations = 0;
};

struct RContactPoint {
  RVec3 position = RVec3::Zero();  // midway between the two surfaces, m
  RScalar separation = 0;          // signed distance along the normal at this point, m
  std::uint32_t featureId = 0;     // the same while the same features touch (warm starting)
};

// Up to four points that keep the deepest one and the contact area.
struct RContactManifold {
  RDistanceResult query;  // status, separation, normal and witnesses of the pair
  // The direction the contact's normal impulses act along, unit, A to B (same frame as the
  // query): for a face against a face, the reference face's outward normal (turned to point
  // from A to B); otherwise the query's normal. Faces that barely touch have closest points
  // a rounding error apart, whose direction is noise (4e-5 rad for two boxes 1e6 m from the
  // origin); the face's normal is exact.
  RVec3 normal = RVec3::Zero();
  int pointCount = 0;
  RContactPoint points[4];
  // A compound's child that touches (its index among the shape's children; 0 otherwise).
  std::uint32_t childA = 0, childB = 0;
};

// A speculative margin, m: a gap this small still counts as a contact. (A type of its own so
// that it is never mistaken for the time step CheckCollision also accepts.)
struct RMargin {
  RScalar metres = 0;
};

class RCollisionSolver {
 public:
  // Touching band, relative to the sum of the two bounding radii.
  static constexpr RScalar kTouchingTolerance = 1e-9;
  static constexpr int kMaxGjkIterations = 64;
  static constexpr int kMaxEpaIterations = 128;

  // Boolean query: do A and B overlap (separation <= touching band)? GJK alone, stops as
  // soon as a separating direction or an enclosing simplex is found.
  static bool Intersect(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB);

  // Signed distance with witness points and normal, all in A's frame: GJK for separated
  // shapes; EPA for overlapping polyhedra; closed forms for sphere pairs and for a sphere
  // whose centre is inside a polyhedron.
  static RDistanceResult Distance(const RConvexShape& a, const RConvexShape& b,
                                  const RRelativePose& X_AB);

  // The contact manifold in A's frame: Distance(), then reference/incident face clipping
  // for face contacts or the closest points of two edges, reduced to at most 4 points.
  // Points whose separation exceeds `margin` (m) are dropped; margin > 0 keeps speculative
  // contacts of shapes that may close the gap within a step.
  static RContactManifold Manifold(const RConvexShape& a, const RConvexShape& b,
                                   const RRelativePose& X_AB, RScalar margin);
  // The same, stopping at a proof that two polyhedra are farther apart than `cutoff` (m):
  // the query's separation is then only a lower bound above it, with no witnesses, and
  // there are no points. CheckCollision's form, with a cutoff just above the margin.
  static RDistanceResult DistanceWithin(const RConvexShape& a, const RConvexShape& b,
                                        const RRelativePose& X_AB, RScalar cutoff);
  // droppedMin, when given: the smallest separation of a clipped point the margin dropped
  // (infinity when none was), which says how far the margin may shrink or grow before the
  // points would be others.
  static RContactManifold ManifoldWithin(const RConvexShape& a, const RConvexShape& b,
                                         const RRelativePose& X_AB, RScalar margin, RScalar cutoff,
                                         RScalar* droppedMin = nullptr);
  // CheckCollision before its last step: the manifold in A's frame for the shapes at X_AB
  // (for callers that keep it: the pair sweep's manifold memory), and droppedMin as
  // ManifoldWithin gives it.
  static bool CheckCollisionInA(const RConvexShape& a, const RConvexShape& b,
                                const RRelativePose& X_AB, RMargin margin, RContactManifold& out_A,
                                RScalar* droppedMin = nullptr);
  // A manifold in A's frame (as Manifold gives it) to world: rotated by A's orientation,
  // translated by its position; CheckCollision's last step.
  static void ToWorld(const RRigidBody& a, RContactManifold& m);

  // The pair of bodies in world terms, the narrow phase CollisionDetection calls: whether
  // they touch now or are within the speculative margin (m) of touching, and if so the
  // manifold with world-space normal and points. The integrator's margin is how far the
  // bodies can approach within the step, from the velocities they will move with (pending
  // impulses and forces included). Returns false (and leaves `out` unspecified) otherwise.
  static bool CheckCollision(const RRigidBody& a, const RRigidBody& b, RMargin margin,
                             RContactManifold& out);
  // The same with the margin bounded from the bodies' current velocities over dt: how far
  // any point of b can approach any point of a.
  static bool CheckCollision(const RRigidBody& a, const RRigidBody& b, RScalar dt,
                             RContactManifold& out);
};

// The shape of a body, as the narrow phase wants it.
RConvexShape ShapeOf(const RRigidBody& body);
// Pose of b's body frame in a's body frame.
RRelativePose RelativePose(const RRigidBody& a, const RRigidBody& b);

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_COLLISION(X) \
  X(RConvexShape) \
  X(RShapeChild) \
  X(RRelativePose) \
  X(RDistanceResult) \
  X(RContactPoint) \
  X(RContactManifold)
RENGINE_ABI_CHECK(kCollision, RENGINE_ABI_TYPES_COLLISION)
