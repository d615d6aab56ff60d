// Private to REnginePhysics: triangle meshes in the narrow phase (RMesh.cpp).
//
// A mesh is static or kinematic geometry; each of its triangles meets a convex shape as a
// convex child of its own (a flat polyhedron, two-sided, in a frame at its centroid with the
// mesh's axes), found through the mesh's tree, and the convex narrow phase answers for the
// pair unchanged. Two things make many triangles behave as one surface:
//  * active edges: a contact on an edge or corner inside a smooth stretch of the mesh takes
//    the triangle's face normal (RTriangleMesh.h);
//  * merging: the manifolds of one convex child against the mesh whose normals agree (to
//    kFaceContactCos) become one manifold of at most four points, as Jolt's manifold
//    reduction does. A box on a tessellated floor gets the four corners it gets on one box,
//    not a set of points per triangle.
#pragma once

#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RQueries.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RTriangleMesh.h>

#include <cstdint>

namespace REngine {

// Checks a mesh (vertices, triangles, as RTriangleMesh does) and fills p's mesh, frame and
// bounds: the body frame B is S moved to the centre of the mesh's box. Throws RBodyError
// naming the field ("shape.vertices[3]", "shape.triangles[12]").
void PrepareMesh(const RShape& shape, RPreparedShape& p);

// At most this many manifolds of one convex child against a mesh (normals farther apart
// than kFaceContactCos each get one; beyond this many the rest join the closest).
constexpr int kMaxMeshManifolds = 8;

// The manifolds of convex child `other` (its pose in the other body's frame) against the
// mesh, in A's frame, naming their children (the triangle of the deepest point on the mesh's
// side, `otherIndex` on the other), with feature ids distinct per triangle: out[0, count).
// meshIsA: the mesh is shape A of the pair X (B's pose in A's frame).
int MeshChildManifolds(const RTriangleMesh& mesh, bool meshIsA, const RShapeChild& other, std::uint32_t otherIndex,
                       const RRelativePose& X, RScalar margin, RContactManifold* out);

// The least distance between a mesh and a convex shape (either side; a compound's children
// each), in A's frame, as RCompound's CompoundDistance gives it for children.
RDistanceResult MeshDistance(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB, RScalar cutoff);

// The deepest of the pair's manifolds (MeshChildManifolds over the convex side's children);
// with none, the query is MeshDistance's within cutoff.
RContactManifold MeshManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB, RScalar margin,
                              RScalar cutoff);

// The manifold of the contact that named children (childA, childB) of a pair with a mesh,
// as MeshChildManifolds gives it for the convex side's child at any depth: the one naming
// them, else the deepest (none: no points).
RContactManifold MeshPartManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB,
                                  std::uint32_t childA, std::uint32_t childB);

// The manifold of a and b along the given unit normal n (A to B, A's frame) instead of the
// one the distance query finds: the separation is the overlap of their supports along n,
// and the reference face is `faceOfA`'s face facing the other (a triangle's own face).
RContactManifold ManifoldAlong(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB,
                               const RVec3& n, bool faceOfA, RScalar margin);

// Calls f(triangle, child) for every triangle whose box overlaps [lo, hi] (the mesh's frame),
// child being the triangle as a convex child; its polyhedron lives until f returns.
template <class F>
void ForEachTriangleChild(const RTriangleMesh& mesh, const RVec3& lo, const RVec3& hi, const F& f);

// A ray against a mesh in its body frame: the first triangle hit.
bool RayCastMesh(const RTriangleMesh& mesh, const RVec3& origin, const RVec3& direction, RScalar maxDistance,
                 RShapeRayHit& hit);

// A convex shape (or compound) cast against a mesh, as ShapeCastShape (RQueries.h) casts a
// compound: the first touch of any triangle, each cast alone; either side may be the mesh.
bool ShapeCastMesh(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB, const RVec3& translation_A,
                   RScalar maxFraction, RShapeCastResult& out);

// --- implementation -----------------------------------------------------------------------

// The polyhedra triangles are built into: one per nesting level and thread, reused (no
// allocation after a thread's first).
RConvexPolyhedron& TriangleScratch(int level);
int& TriangleScratchLevel();

// Triangle t as a convex child, its polyhedron built into `scratch`.
void MakeTriangleChild(const RTriangleMesh& mesh, std::uint32_t t, RConvexPolyhedron& scratch, RShapeChild& out);

// The scratch polyhedron of the next nesting level, held for a scope (the level is given
// back however the scope ends).
class RTriangleScratchScope {
 public:
  RTriangleScratchScope() : m_level(TriangleScratchLevel()), m_scratch(TriangleScratch(m_level)) { ++m_level; }
  ~RTriangleScratchScope() { --m_level; }
  RTriangleScratchScope(const RTriangleScratchScope&) = delete;
  RTriangleScratchScope& operator=(const RTriangleScratchScope&) = delete;
  RConvexPolyhedron& Scratch() { return m_scratch; }

 private:
  int& m_level;
  RConvexPolyhedron& m_scratch;
};

template <class F>
void ForEachTriangleChild(const RTriangleMesh& mesh, const RVec3& lo, const RVec3& hi, const F& f) {
  RTriangleScratchScope scope;
  RConvexPolyhedron& scratch = scope.Scratch();
  mesh.ForEachOverlapping(lo, hi, [&](std::uint32_t t) {
    // The triangle's own box first: a leaf's box holds four.
    const RVec3 &a = mesh.Vertex(t, 0), &b = mesh.Vertex(t, 1), &c = mesh.Vertex(t, 2);
    if ((a.cwiseMin(b).cwiseMin(c).array() > hi.array()).any() || (a.cwiseMax(b).cwiseMax(c).array() < lo.array()).any()) {
      return;
    }
    RShapeChild child;
    MakeTriangleChild(mesh, t, scratch, child);
    f(t, static_cast<const RShapeChild&>(child));
  });
}

}  // namespace REngine
