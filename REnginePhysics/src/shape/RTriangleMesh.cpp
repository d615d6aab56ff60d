// Triangle meshes: checks, the bounding-volume tree, active edges and rays (RTriangleMesh.h).
#include <REnginePhysics/RTriangleMesh.h>
#include <REngineMath/RFunctions.h>
#include <REnginePhysics/RLimits.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace REngine {

namespace {


std::string At(const char* list, std::size_t i) { return std::string(list) + "[" + std::to_string(i) + "]"; }

}  // namespace

RTriangleMesh::RTriangleMesh(std::vector<RVec3> vertices, std::vector<Triangle> triangles)
    : m_vertices(std::move(vertices)), m_triangles(std::move(triangles)) {
  for (std::size_t i = 0; i < m_vertices.size(); ++i) {
    const RVec3& v = m_vertices[i];
    if (!AllFinite(v) || v.cwiseAbs().maxCoeff() > kMaxCoordinate) {
      throw RMeshError(At("vertices", i), "must be finite and within 1e12 m");
    }
  }
  if (m_triangles.empty()) throw RMeshError("triangles", "must hold at least one triangle");
  if (m_triangles.size() > std::numeric_limits<std::uint32_t>::max() / 2) {
    throw RMeshError("triangles", "has too many triangles");
  }
  m_normals.resize(m_triangles.size());
  for (std::size_t t = 0; t < m_triangles.size(); ++t) {
    const Triangle& tri = m_triangles[t];
    for (std::uint32_t k : tri) {
      if (k >= m_vertices.size()) {
        throw RMeshError(At("triangles", t), "has vertex index " + std::to_string(k) + ", beyond the " +
                                                 std::to_string(m_vertices.size()) + " vertices");
      }
    }
    const RVec3 &a = m_vertices[tri[0]], &b = m_vertices[tri[1]], &c = m_vertices[tri[2]];
    const RVec3 n = (b - a).cross(c - a);
    const RScalar longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    // Twice the area over the longest edge is the smallest height.
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0] || !(n.norm() > kMinThickness * longest * longest)) {
      throw RMeshError(At("triangles", t), "is degenerate: its corners coincide or lie on one line "
                                           "(thinner than 1e-6 of its longest edge)");
    }
    m_normals[t] = n.normalized();
  }
  Build();
}

RTriangleMesh RTriangleMesh::Translated(const RVec3& t) const {
  RTriangleMesh m = *this;
  for (RVec3& v : m.m_vertices) v += t;
  for (Node& n : m.m_nodes) n.lo += t, n.hi += t;
  m.m_boxMin += t, m.m_boxMax += t;
  m.m_maxRadius = 0;
  for (const RVec3& v : m.m_vertices) m.m_maxRadius = std::max(m.m_maxRadius, v.norm());
  return m;
}

void RTriangleMesh::Build() {
  m_boxMin = RVec3::Constant(std::numeric_limits<RScalar>::infinity()), m_boxMax = -m_boxMin;
  m_maxRadius = 0;
  for (const Triangle& tri : m_triangles) {
    for (std::uint32_t k : tri) {
      m_boxMin = m_boxMin.cwiseMin(m_vertices[k]), m_boxMax = m_boxMax.cwiseMax(m_vertices[k]);
      m_maxRadius = std::max(m_maxRadius, m_vertices[k].norm());
    }
  }
  std::vector<RVec3> centroids(m_triangles.size());
  m_order.resize(m_triangles.size());
  for (std::uint32_t t = 0; t < m_triangles.size(); ++t) {
    centroids[t] = (Vertex(t, 0) + Vertex(t, 1) + Vertex(t, 2)) / 3;
    m_order[t] = t;
  }
  m_nodes.clear();
  m_nodes.reserve(2 * m_triangles.size() / kLeafSize + 2);
  m_nodes.emplace_back();
  BuildNode(0, 0, static_cast<std::uint32_t>(m_triangles.size()), centroids, 0);
  m_nodes.shrink_to_fit();
  FindActiveEdges();
}

// Median split of m_order[begin, end) along the longest axis of its centroids' box, into
// node `self`; its two children go to the back of m_nodes, side by side. (nth_element with
// a total order, ties broken by index: the same tree from the same mesh on every machine.)
void RTriangleMesh::BuildNode(std::uint32_t self, std::uint32_t begin, std::uint32_t end,
                              const std::vector<RVec3>& centroids, int depth) {
  RVec3 lo = RVec3::Constant(std::numeric_limits<RScalar>::infinity()), hi = -lo;
  RVec3 clo = lo, chi = hi;
  for (std::uint32_t i = begin; i < end; ++i) {
    const std::uint32_t t = m_order[i];
    for (int k = 0; k < 3; ++k) lo = lo.cwiseMin(Vertex(t, k)), hi = hi.cwiseMax(Vertex(t, k));
    clo = clo.cwiseMin(centroids[t]), chi = chi.cwiseMax(centroids[t]);
  }
  m_nodes[self].lo = lo, m_nodes[self].hi = hi;
  if (end - begin <= kLeafSize || depth >= kMaxDepth) {
    m_nodes[self].first = begin, m_nodes[self].count = end - begin;
    return;
  }
  int axis;
  (chi - clo).maxCoeff(&axis);
  const std::uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(m_order.begin() + begin, m_order.begin() + mid, m_order.begin() + end,
                   [&](std::uint32_t x, std::uint32_t y) {
                     const RScalar cx = centroids[x][axis], cy = centroids[y][axis];
                     return cx < cy || (cx == cy && x < y);
                   });
  const std::uint32_t left = static_cast<std::uint32_t>(m_nodes.size());
  m_nodes[self].first = left, m_nodes[self].count = 0;
  m_nodes.emplace_back();
  m_nodes.emplace_back();
  BuildNode(left, begin, mid, centroids, depth + 1);
  BuildNode(left + 1, mid, end, centroids, depth + 1);
}

void RTriangleMesh::FindActiveEdges() {
  // Every edge once per triangle, keyed by its sorted corners; sorted, the triangles that
  // share an edge are neighbours in the list.
  struct EdgeUse {
    std::uint32_t lo, hi, triangle, k;
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * m_triangles.size());
  for (std::uint32_t t = 0; t < m_triangles.size(); ++t) {
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t a = m_triangles[t][k], b = m_triangles[t][(k + 1) % 3];
      uses.push_back({std::min(a, b), std::max(a, b), t, k});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.triangle != y.triangle ? x.triangle < y.triangle : x.k < y.k;
  });
  m_active.assign(m_triangles.size(), 0);
  const RScalar flat = Cos(kActiveEdgeAngle);
  // The direction across edge k inside triangle t: from the edge towards the third corner,
  // perpendicular to the edge. Two triangles lie flat across their edge when these point
  // opposite ways (half-planes at 180 degrees), whatever their windings: triangles are
  // two-sided, so a fold and a crease are told apart by the corners, not the normals.
  const auto across = [&](std::uint32_t t, std::uint32_t k) {
    const RVec3 &a = Vertex(t, k), &b = Vertex(t, (k + 1) % 3), &c = Vertex(t, (k + 2) % 3);
    const RVec3 e = (b - a).normalized();
    const RVec3 u = (c - a) - e * e.dot(c - a);
    return RVec3(u.normalized());
  };
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
    const bool smooth = j - i == 2 && across(uses[i].triangle, uses[i].k).dot(across(uses[i + 1].triangle, uses[i + 1].k)) <= -flat;
    if (!smooth) {
      for (std::size_t u = i; u < j; ++u) m_active[uses[u].triangle] |= std::uint8_t(1u << uses[u].k);
    }
    i = j;
  }
  for (std::uint8_t& f : m_active) {
    // Corner k lies on edges k and k + 2 (mod 3).
    for (int k = 0; k < 3; ++k) {
      if (f & ((1u << k) | (1u << ((k + 2) % 3)))) f |= std::uint8_t(1u << (3 + k));
    }
  }
}

bool RTriangleMesh::RayCast(const RVec3& origin, const RVec3& direction, RScalar maxDistance, RScalar& distance,
                            std::uint32_t& triangle, RVec3& normal) const {
  if (m_nodes.empty()) return false;
  bool found = false;
  RScalar best = maxDistance;
  // (A component of 0 is never divided by: the slab test takes that axis apart.)
  const RVec3 inv(direction.x() != 0 ? 1 / direction.x() : 0, direction.y() != 0 ? 1 / direction.y() : 0,
                  direction.z() != 0 ? 1 / direction.z() : 0);
  // The slab test of a node's box: the ray's parameter range inside it.
  const auto enters = [&](const Node& n) {
    RScalar t0 = 0, t1 = best;
    for (int k = 0; k < 3; ++k) {
      if (direction[k] == 0) {
        if (origin[k] < n.lo[k] || origin[k] > n.hi[k]) return false;
        continue;
      }
      RScalar a = (n.lo[k] - origin[k]) * inv[k], b = (n.hi[k] - origin[k]) * inv[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a), t1 = std::min(t1, b);
      if (t0 > t1) return false;
    }
    return true;
  };
  std::uint32_t stack[kMaxDepth + 2];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = m_nodes[stack[--top]];
    if (!enters(n)) continue;
    if (n.count == 0) {
      stack[top++] = n.first + 1;
      stack[top++] = n.first;
      continue;
    }
    for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
      const std::uint32_t t = m_order[i];
      // The ray against the triangle's plane, then the hit point's barycentric signs
      // (Moller-Trumbore, two-sided).
      const RVec3 &a = Vertex(t, 0), &b = Vertex(t, 1), &c = Vertex(t, 2);
      const RVec3 e1 = b - a, e2 = c - a;
      const RVec3 p = direction.cross(e2);
      const RScalar det = e1.dot(p);
      if (det == 0) continue;  // along the plane: a two-sided triangle has no thickness to hit
      const RScalar invDet = 1 / det;
      const RVec3 s = origin - a;
      const RScalar u = s.dot(p) * invDet;
      if (u < 0 || u > 1) continue;
      const RVec3 q = s.cross(e1);
      const RScalar v = direction.dot(q) * invDet;
      if (v < 0 || u + v > 1) continue;
      const RScalar d = e2.dot(q) * invDet;
      if (d < 0 || d > best || (found && d == best && t > triangle)) continue;
      best = d, triangle = t, found = true;
    }
  }
  if (!found) return false;
  distance = best;
  normal = Normal(triangle).dot(direction) <= 0 ? Normal(triangle) : RVec3(-Normal(triangle));
  return true;
}

std::size_t RTriangleMesh::MemoryBytes() const {
  return sizeof(*this) + m_vertices.capacity() * sizeof(RVec3) + m_triangles.capacity() * sizeof(Triangle) +
         m_normals.capacity() * sizeof(RVec3) + m_active.capacity() + m_nodes.capacity() * sizeof(Node) +
         m_order.capacity() * sizeof(std::uint32_t);
}

}  // namespace REngine
