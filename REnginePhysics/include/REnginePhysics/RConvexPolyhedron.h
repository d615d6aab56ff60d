// RConvexPolyhedron: a convex polyhedron ready for GJK (support), SAT (face normals and
// unique edges) and contact clipping (ordered face loops), with exact mass properties.
//
// A polyhedron lives in one local frame (the frame its vertices are given in). Bodies keep
// theirs in the body frame B (centre of mass at the origin, principal axes), so that the
// world form is one rotation and one translation away.
#pragma once

#include <REnginePhysics/RError.h>

#include <REnginePhysics/RAbi.h>
#include <REngineMath/RMath.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace REngine {

// Plane n . x = d with n a unit outward normal; d in metres.
struct RPlane {
  RVec3 normal = RVec3::UnitZ();
  RScalar offset = 0;
  RScalar SignedDistance(const RVec3& p) const { return normal.dot(p) - offset; }
};

struct RFace {
  RPlane plane;               // outward unit normal and offset, local frame
  std::uint32_t firstVertex;  // the face's loop is loopVertices[first, first + count)
  std::uint32_t vertexCount;  // counter-clockwise seen from outside
};

struct REdge {
  std::uint32_t v0, v1;  // vertex indices, v0 < v1
  std::uint32_t f0, f1;  // the two faces that share the edge
};

// Thrown when points do not span a solid: fewer than 4, or all (nearly) coplanar. Field()
// is "points"; what() is the problem alone (the caller knows which points it gave).
class RHullError : public RError {
 public:
  explicit RHullError(const std::string& problem) : RError("points", problem, problem) {}
};

// Mass properties of the solid of uniform density 1 kg/m^3, in the polyhedron's frame.
struct RPolyhedronMass {
  RScalar volume = 0;                 // m^3
  RVec3 centroid = RVec3::Zero();     // centre of mass, m
  RMat3 inertia = RMat3::Zero();      // about the centroid, kg m^2 per (kg/m^3)
};

class RConvexPolyhedron {
 public:
  // Box with the given half extents (m), centred at the origin, axis-aligned.
  static RConvexPolyhedron Box(const RVec3& halfExtents);

  // The convex hull of `points` (m). Survives duplicates, coplanar and collinear subsets and
  // clouds far from the origin (the hull is computed about the cloud's centroid). Interior
  // points and points on faces or edges are dropped; coplanar facets are merged into one
  // polygon face. Throws RHullError for points that span no usable solid: fewer than 4, a
  // point beyond 1e12 m, a hull thinner than 1e-4 of its extent along a face normal
  // (coplanar, collinear, needle-like clouds), or any hull that fails the checks of a
  // closed convex polyhedron (unit normals, V - E + F = 2, vertices inside every face
  // plane). Qhull does the hull; this class owns and checks the result.
  static RConvexPolyhedron Hull(const std::vector<RVec3>& points);

  // Makes this the flat triangle (a, b, c) (m): two faces, the front (counter-clockwise
  // seen from its normal) and the back, three edges. Not a solid: no mass properties, and
  // Validate would refuse it; the narrow phase takes it as it takes any polyhedron (a mesh's
  // triangle, RTriangleMesh). Its storage is reused: no allocation after the first call.
  void SetTriangle(const RVec3& a, const RVec3& b, const RVec3& c);

  // The same polyhedron with every vertex mapped x -> R x + t (planes follow).
  RConvexPolyhedron Transformed(const RMat3& R, const RVec3& t) const;

  const std::vector<RVec3>& Vertices() const { return m_vertices; }
  const std::vector<RFace>& Faces() const { return m_faces; }
  const std::vector<std::uint32_t>& LoopVertices() const { return m_loops; }
  const std::vector<REdge>& Edges() const { return m_edges; }
  // Neighbours of vertex i: AdjacencyVertices()[AdjacencyStart()[i] .. AdjacencyStart()[i+1]).
  const std::vector<std::uint32_t>& AdjacencyStart() const { return m_adjStart; }
  const std::vector<std::uint32_t>& AdjacencyVertices() const { return m_adj; }

  // A box made by Box() (and not moved since): its half extents (m), the box axis-aligned
  // about the frame origin. Null for any other polyhedron. The narrow phase proves two boxes
  // apart in closed form with it.
  const RVec3* BoxHalfExtents() const { return m_isBox ? &m_boxHalf : nullptr; }

  // Largest distance of a vertex from the frame origin, m: the bounding sphere about it.
  RScalar MaxRadius() const { return m_maxRadius; }

  // Exact mass properties (divergence theorem over a fan triangulation of each face).
  RPolyhedronMass MassProperties() const;

  // Index of a vertex maximising dot(v, d) over `vertices` (any array laid out like
  // Vertices(), e.g. a world-space copy). Plain loop: the fastest for small hulls.
  static std::uint32_t SupportLinear(const RVec3* vertices, std::uint32_t count, const RVec3& d);
  // The same maximum by hill climbing over vertex adjacency from `start`: O(sqrt n) visits
  // on a round hull. Where several vertices tie exactly (a face or edge facing d), either
  // may be returned; the dot product is the same.
  std::uint32_t SupportHillClimb(const RVec3* vertices, const RVec3& d,
                                 std::uint32_t start = 0) const;
  // Vertex count from which Support() climbs instead of looping. tools/bench/bench_support
  // (random round hulls): the loop costs ~1 ns per vertex, a climb from a cold start wins
  // from ~56 vertices. GJK's successive directions jump too far for warm starts to help
  // much: on 32-vertex pairs (tools/bench/bench_collision) switching them from climbing to
  // the loop made the boolean query 2.8x faster.
  static constexpr std::uint32_t kHillClimbMinVertices = 64;
  std::uint32_t Support(const RVec3* vertices, const RVec3& d, std::uint32_t start = 0) const {
    const auto n = static_cast<std::uint32_t>(m_vertices.size());
    return n < kHillClimbMinVertices ? SupportLinear(vertices, n, d)
                                     : SupportHillClimb(vertices, d, start);
  }

 private:
  // Fills edges, adjacency and the bounding radius from vertices, faces and loops.
  void BuildTopology();
  // Throws RHullError unless the polyhedron is one the engine can use (see the definition).
  void Validate(RScalar extent) const;

  std::vector<RVec3> m_vertices;
  std::vector<RFace> m_faces;
  std::vector<std::uint32_t> m_loops;
  std::vector<REdge> m_edges;
  std::vector<std::uint32_t> m_adjStart;
  std::vector<std::uint32_t> m_adj;
  RScalar m_maxRadius = 0;
  RVec3 m_boxHalf = RVec3::Zero();  // Box()'s half extents (m) while m_isBox
  bool m_isBox = false;
};

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_CONVEX_POLYHEDRON(X) \
  X(RPlane) \
  X(RFace) \
  X(REdge) \
  X(RPolyhedronMass) \
  X(RConvexPolyhedron)
RENGINE_ABI_CHECK(kConvexPolyhedron, RENGINE_ABI_TYPES_CONVEX_POLYHEDRON)
