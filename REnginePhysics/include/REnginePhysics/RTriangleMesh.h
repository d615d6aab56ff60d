// RTriangleMesh: static and kinematic geometry made of triangles (terrain, the inside of a
// station), with a bounding-volume tree over its triangles, built once and shared by every
// body made from it.
//
// Triangles are two-sided: a body meets one from either side. The mesh lives in one local
// frame (the body frame of the body that owns it), metres.
//
// Internal edges. A body sliding over a tessellated flat floor touches the edges between its
// triangles; taken one triangle at a time, such an edge gives a sideways normal (a "bump").
// Each triangle's edges and vertices are therefore marked active or not, once: an edge is
// active when it bends the surface by more than kActiveEdgeAngle (or borders one triangle
// only, or more than two). A contact the narrow phase finds on an inactive feature takes the
// triangle's face normal instead (Jolt calls these active edges).
#pragma once

#include <REnginePhysics/RError.h>

#include <REnginePhysics/RAbi.h>
#include <REngineMath/RMath.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace REngine {

// Thrown for a mesh the engine cannot use; what() says what is wrong and `field` names the
// part ("vertices[3]", "triangles[12]").
class RMeshError : public RError {
 public:
  RMeshError(std::string field, const std::string& what) : RError(std::move(field), what, what) {}
};

class RTriangleMesh {
 public:
  using Triangle = std::array<std::uint32_t, 3>;
  // Edges bent by less than this (rad) are inside a smooth surface: not active.
  static constexpr RScalar kActiveEdgeAngle = RScalar(5 * 3.14159265358979323846 / 180);
  // A triangle thinner than this fraction of its longest edge (its smallest height) is
  // degenerate: its normal is rounding noise.
  static constexpr RScalar kMinThickness = 1e-6;

  RTriangleMesh() = default;
  // Checks and builds: vertices finite and within 1e12 m, at least one triangle, indices in
  // range, no degenerate triangle. Throws RMeshError naming the first bad one.
  RTriangleMesh(std::vector<RVec3> vertices, std::vector<Triangle> triangles);

  // The same mesh with every vertex mapped x -> x + t (the tree follows).
  RTriangleMesh Translated(const RVec3& t) const;

  const std::vector<RVec3>& Vertices() const { return m_vertices; }
  const std::vector<Triangle>& Triangles() const { return m_triangles; }
  std::uint32_t TriangleCount() const { return static_cast<std::uint32_t>(m_triangles.size()); }
  const RVec3& Vertex(std::uint32_t triangle, int k) const { return m_vertices[m_triangles[triangle][k]]; }
  // Unit normal from the winding (counter-clockwise seen from its side); the triangle is
  // two-sided, this only fixes a sign.
  const RVec3& Normal(std::uint32_t triangle) const { return m_normals[triangle]; }
  // Bit k set: edge k (from corner k to corner k+1 mod 3) is active. Bit 3 + k: corner k is
  // active (one of its two edges in this triangle is).
  std::uint8_t ActiveFeatures(std::uint32_t triangle) const { return m_active[triangle]; }

  // The box holding every vertex, m.
  const RVec3& BoxMin() const { return m_boxMin; }
  const RVec3& BoxMax() const { return m_boxMax; }
  // Largest distance of a vertex from the frame origin, m.
  RScalar MaxRadius() const { return m_maxRadius; }

  // Calls f(triangle) for every triangle whose box overlaps [lo, hi], in a fixed order (the
  // tree's, depth first): the same answer for the same mesh and box, run after run.
  template <class F>
  void ForEachOverlapping(const RVec3& lo, const RVec3& hi, const F& f) const;

  // First hit of the ray origin + s direction (direction unit), s in [0, maxDistance]: the
  // distance, the triangle and its normal facing the ray. False when none is hit.
  bool RayCast(const RVec3& origin, const RVec3& direction, RScalar maxDistance, RScalar& distance,
               std::uint32_t& triangle, RVec3& normal) const;

  // Bytes this mesh holds (vertices, triangles, normals, flags, tree).
  std::size_t MemoryBytes() const;

 private:
  struct Node {
    RVec3 lo, hi;
    // count > 0: a leaf of m_order[first, first + count). Otherwise children first, first + 1.
    std::uint32_t first = 0, count = 0;
  };
  static constexpr int kLeafSize = 4;
  static constexpr int kMaxDepth = 64;

  void Build();
  void BuildNode(std::uint32_t self, std::uint32_t begin, std::uint32_t end, const std::vector<RVec3>& centroids,
                 int depth);
  void FindActiveEdges();

  std::vector<RVec3> m_vertices;
  std::vector<Triangle> m_triangles;
  std::vector<RVec3> m_normals;
  std::vector<std::uint8_t> m_active;
  std::vector<Node> m_nodes;
  std::vector<std::uint32_t> m_order;  // triangles in leaf order
  RVec3 m_boxMin = RVec3::Zero(), m_boxMax = RVec3::Zero();
  RScalar m_maxRadius = 0;
};

template <class F>
void RTriangleMesh::ForEachOverlapping(const RVec3& lo, const RVec3& hi, const F& f) const {
  if (m_nodes.empty()) return;
  std::uint32_t stack[kMaxDepth + 2];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = m_nodes[stack[--top]];
    if ((n.lo.array() > hi.array()).any() || (n.hi.array() < lo.array()).any()) continue;
    if (n.count > 0) {
      for (std::uint32_t i = n.first; i < n.first + n.count; ++i) f(m_order[i]);
    } else {
      // The second child below the first on the stack: the first is visited first.
      stack[top++] = n.first + 1;
      stack[top++] = n.first;
    }
  }
}

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_TRIANGLE_MESH(X) \
  X(RTriangleMesh)
RENGINE_ABI_CHECK(kTriangleMesh, RENGINE_ABI_TYPES_TRIANGLE_MESH)
