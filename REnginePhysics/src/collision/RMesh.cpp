// Triangle meshes in the narrow phase: preparation, triangle children, active edges and the
// merging of a convex child's manifolds (RMesh.h).
#include "collision/RMesh.h"

#include "shape/RCompound.h"
#include "collision/RGjkEpa.h"
#include "collision/RManifold.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

void PrepareMesh(const RShape& shape, RPreparedShape& p) {
  RTriangleMesh mesh_S;
  try {
    mesh_S = RTriangleMesh(shape.points, shape.triangles);
  } catch (const RMeshError& e) {
    throw RBodyError("shape." + e.Field(), e.what());
  }
  // B at the centre of the box: the bounding sphere is about the mesh, not the origin its
  // author drew it about, and the triangles' coordinates are as small as they can be.
  const RVec3 centre_S = RScalar(0.5) * (mesh_S.BoxMin() + mesh_S.BoxMax());
  p.q_BS = RQuat::Identity();
  p.p_BS = -centre_S;
  p.unitMass = RMassProperties{};
  p.unitMass.volume = 0;
  p.unitMass.com_S = centre_S;
  p.unitMass.principalMoments = RVec3::Zero();
  p.mesh_B = std::make_shared<const RTriangleMesh>(mesh_S.Translated(-centre_S));
  p.boundingRadius = p.mesh_B->MaxRadius();
  p.boxCenter_B = RVec3::Zero();
  p.boxHalf_B = RScalar(0.5) * (mesh_S.BoxMax() - mesh_S.BoxMin());
}

RConvexPolyhedron& TriangleScratch(int level) {
  // Deep enough for any nesting the engine does (a query inside a query: none today).
  thread_local RConvexPolyhedron scratch[4];
  return scratch[std::min(level, 3)];
}

int& TriangleScratchLevel() {
  thread_local int level = 0;
  return level;
}

void MakeTriangleChild(const RTriangleMesh& mesh, std::uint32_t t, RConvexPolyhedron& scratch, RShapeChild& out) {
  const RVec3 &a = mesh.Vertex(t, 0), &b = mesh.Vertex(t, 1), &c = mesh.Vertex(t, 2);
  const RVec3 centre = (a + b + c) / 3;
  scratch.SetTriangle(a - centre, b - centre, c - centre);
  out.shape = RConvexShape{};
  out.shape.polyhedron = &scratch;
  out.shape.boundingRadius = scratch.MaxRadius();
  out.R_BC = RMat3::Identity();
  out.p_BC = centre;
}

namespace {

// Whether the triangle's point w (its frame, on the triangle) lies on an active feature: an
// active edge or corner, or the face's inside (where any normal the query finds is the
// shapes' own). Barycentric weights within 1e-6 of 0 put w on an edge, of 1 at a corner.
bool OnActiveFeature(const RTriangleMesh& mesh, std::uint32_t t, const RConvexPolyhedron& tri, const RVec3& w) {
  const auto& v = tri.Vertices();
  const RVec3 n = (v[1] - v[0]).cross(v[2] - v[0]);
  const RScalar area = n.squaredNorm();
  RScalar lambda[3];
  for (int k = 0; k < 3; ++k) {
    // Corner k's weight: the sub-triangle opposite it, (w, k+1, k+2), over the whole.
    lambda[k] = (v[(k + 1) % 3] - w).cross(v[(k + 2) % 3] - w).dot(n) / area;
  }
  constexpr RScalar kOn = 1e-6;
  const std::uint8_t active = mesh.ActiveFeatures(t);
  for (int k = 0; k < 3; ++k) {
    if (lambda[k] >= 1 - kOn) return (active >> (3 + k)) & 1u;
  }
  for (int k = 0; k < 3; ++k) {
    // Edge k runs from corner k to corner k+1: the third corner's weight vanishes on it.
    if (lambda[(k + 2) % 3] <= kOn) return (active >> k) & 1u;
  }
  return true;
}

// Whether q (the triangle's frame) lies on the triangle, as ManifoldAlong's clipping puts a
// point on it: within twice kClipTolerance of the triangle's longest edge of its plane and
// of the inside of each edge (the clipping pushes its side planes out by kClipTolerance of
// the face's size, so a point clipped at an edge lies that far outside it).
bool OverTriangle(const RConvexPolyhedron& tri, const RVec3& q) {
  const auto& v = tri.Vertices();
  const RVec3 n = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
  RScalar longest = 0;
  for (int k = 0; k < 3; ++k) longest = std::max(longest, (v[(k + 1) % 3] - v[k]).norm());
  const RScalar tolerance = 2 * kClipTolerance * longest;
  if (std::abs(n.dot(q - v[0])) > tolerance) return false;
  for (int k = 0; k < 3; ++k) {
    // The distance of q inside edge k (from corner k to k + 1), in the plane.
    const RVec3 edge = v[(k + 1) % 3] - v[k];
    if (n.dot(edge.cross(q - v[k])) / edge.norm() < -tolerance) return false;
  }
  return true;
}

// The manifolds of one convex child against a mesh, gathered by normal.
struct MeshGroups {
  static constexpr int kPoints = 16;  // reduced to four whenever full
  struct Group {
    RContactManifold m;  // the deepest member's query, normal and children
    RContactPoint pts[kPoints];
    int n = 0;
  };
  Group groups[kMaxMeshManifolds];
  int count = 0;
  RScalar sameDistance = 0;  // points closer than this are one (two triangles' copies of it)

  void Add(const RContactManifold& m) {
    int g = -1;
    RScalar best = -2;
    for (int k = 0; k < count; ++k) {
      const RScalar c = groups[k].m.normal.dot(m.normal);
      if (c > best) best = c, g = k;
    }
    if (g < 0 || (best < kFaceContactCos && count < kMaxMeshManifolds)) {
      g = count++;
      groups[g].m = m;
      groups[g].n = 0;
    } else if (m.query.separation < groups[g].m.query.separation) {
      RContactManifold& keep = groups[g].m;
      keep.query = m.query, keep.normal = m.normal, keep.childA = m.childA, keep.childB = m.childB;
    }
    Group& G = groups[g];
    for (int i = 0; i < m.pointCount; ++i) {
      const RContactPoint& p = m.points[i];
      bool known = false;
      for (int j = 0; j < G.n && !known; ++j) {
        known = (G.pts[j].position - p.position).squaredNorm() <= sameDistance * sameDistance;
        // Of two copies the deeper stands (rounding apart, from two triangles).
        if (known && p.separation < G.pts[j].separation) G.pts[j] = p;
      }
      if (known) continue;
      if (G.n == kPoints) G.n = ReduceToFour(G.pts, G.n, G.m.normal);
      G.pts[G.n++] = p;
    }
  }

  int Finish(RContactManifold* out) {
    for (int k = 0; k < count; ++k) {
      Group& G = groups[k];
      out[k] = G.m;
      out[k].pointCount = ReduceToFour(G.pts, G.n, G.m.normal);
      for (int i = 0; i < out[k].pointCount; ++i) out[k].points[i] = G.pts[i];
    }
    return count;
  }
};

// The box of convex shape s posed at (R, p) in the mesh's frame, grown by margin: the
// triangles it can touch are those whose boxes meet it (tighter than its bounding sphere's,
// which takes in three times the triangles under a box lying flat).
void BoxInMesh(const RConvexShape& s, const RMat3& R, const RVec3& p, RScalar margin, RVec3& lo, RVec3& hi) {
  RVec3 e;
  if (s.polyhedron) {
    lo = RVec3::Constant(std::numeric_limits<RScalar>::infinity()), hi = -lo;
    for (const RVec3& v : s.polyhedron->Vertices()) {
      const RVec3 w = R * v;
      lo = lo.cwiseMin(w), hi = hi.cwiseMax(w);
    }
    lo = (lo + p).array() - margin, hi = (hi + p).array() + margin;
    return;
  }
  const RVec3 axis = R.col(1);
  if (s.cylinderRadius > 0) {
    e = (s.halfHeight * axis.cwiseAbs()).array() +
        s.cylinderRadius * (RVec3::Ones() - axis.cwiseAbs2()).cwiseMax(RVec3::Zero()).cwiseSqrt().array();
  } else {
    e = (s.halfHeight * axis.cwiseAbs()).array() + s.radius;
  }
  lo = (p - e).array() - margin, hi = (p + e).array() + margin;
}

// Convex child `other`'s frame C in the mesh's frame M.
void OtherInMesh(bool meshIsA, const RShapeChild& other, const RRelativePose& X, RMat3& R_MC, RVec3& p_MC) {
  if (meshIsA) {
    R_MC = X.R_AB * other.R_BC;
    p_MC = X.R_AB * other.p_BC + X.t_AB;
  } else {
    R_MC = X.R_AB.transpose() * other.R_BC;
    p_MC = X.R_AB.transpose() * (other.p_BC - X.t_AB);
  }
}

}  // namespace

int MeshChildManifolds(const RTriangleMesh& mesh, bool meshIsA, const RShapeChild& other, std::uint32_t otherIndex,
                       const RRelativePose& X, RScalar margin, RContactManifold* out) {
  RMat3 R_MC;
  RVec3 p_MC;
  OtherInMesh(meshIsA, other, X, R_MC, p_MC);
  RVec3 lo, hi;
  BoxInMesh(other.shape, R_MC, p_MC, margin, lo, hi);
  MeshGroups groups;
  groups.sameDistance = 1e-6 * other.shape.boundingRadius;
  ForEachTriangleChild(mesh, lo, hi, [&](std::uint32_t t, const RShapeChild& tri) {
    const RVec3 centre_T = p_MC - tri.p_BC;  // other's origin from the triangle's centroid
    if (centre_T.norm() - tri.shape.boundingRadius - other.shape.boundingRadius > margin) return;
    const RShapeChild& ca = meshIsA ? tri : other;
    const RShapeChild& cb = meshIsA ? other : tri;
    const RRelativePose Xc = ChildPose(ca, cb, X);
    RContactManifold m;
    if (!RCollisionSolver::CheckCollisionInA(ca.shape, cb.shape, Xc, RMargin{margin}, m) || m.pointCount == 0) return;
    // In the triangle's frame T (the mesh's axes): the normal from the triangle to the other.
    const RVec3 n_T = meshIsA ? m.normal : RVec3(-(Xc.R_AB.transpose() * m.normal));
    const RVec3& face = tri.shape.polyhedron->Faces()[0].plane.normal;
    const RScalar along = n_T.dot(face);
    // Any normal but the face's own (to rounding) found on an inactive feature: a normal a
    // hair off the face's at a neighbour's edge puts the point beside the one under a ball's
    // centre, and a rolling ball then hops (found by review: within kFaceContactCos, 1.1
    // degrees, it kept its edge point).
    if (std::abs(along) < 1 - 1e-12) {
      const RVec3 w_T = meshIsA ? m.query.witnessA : RVec3(Xc.R_AB.transpose() * (m.query.witnessB - Xc.t_AB));
      if (!OnActiveFeature(mesh, t, *tri.shape.polyhedron, w_T)) {
        // An edge or corner inside a smooth stretch: the face it belongs to answers, on the
        // side the other shape's centre is on (the normal found may lie in the face's plane,
        // its sign along the face rounding noise).
        const RScalar centreSide = centre_T.dot(face);
        const RScalar side = centreSide != 0 ? centreSide : along;
        const RVec3 n_face = side >= 0 ? face : RVec3(-face);
        const RVec3 n = meshIsA ? n_face : RVec3(-(Xc.R_AB * n_face));
        m = ManifoldAlong(ca.shape, cb.shape, Xc, n, meshIsA, margin);
        // Only the points over the triangle are its face's: a shape beside the triangle,
        // within the margin of its inactive edge but past its plane (a ball rolling over
        // the top of a closed mesh's side, near the diagonal that splits it), overlaps the
        // plane, not the face, and the face's normal would throw it off (the other
        // triangles' own contacts hold it).
        int kept = 0;
        for (int k = 0; k < m.pointCount; ++k) {
          const RContactPoint& p = m.points[k];
          const RVec3 q_A = p.position + RScalar(meshIsA ? -0.5 : 0.5) * p.separation * m.normal;
          const RVec3 q_T = meshIsA ? q_A : RVec3(Xc.R_AB.transpose() * (q_A - Xc.t_AB));
          if (OverTriangle(*tri.shape.polyhedron, q_T)) m.points[kept++] = p;
        }
        m.pointCount = kept;
        if (m.pointCount == 0) return;
      }
    }
    ChildToBody(ca, meshIsA ? t : otherIndex, meshIsA ? otherIndex : t, m);
    groups.Add(m);
  });
  return groups.Finish(out);
}

RDistanceResult MeshDistance(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X, RScalar cutoff) {
  RDistanceResult best;
  best.separation = std::numeric_limits<RScalar>::infinity();
  best.status = RCollisionStatus::kSeparated;
  if (a.mesh && b.mesh) return best;  // two meshes never touch
  const bool meshIsA = a.mesh != nullptr;
  const RTriangleMesh& mesh = meshIsA ? *a.mesh : *b.mesh;
  RShapeChild alone;
  std::uint32_t n;
  const RShapeChild* children = ChildrenOf(meshIsA ? b : a, alone, n);
  for (std::uint32_t j = 0; j < n; ++j) {
    const RShapeChild& other = children[j];
    RMat3 R_MC;
    RVec3 p_MC;
    OtherInMesh(meshIsA, other, X, R_MC, p_MC);
    // Every triangle when nothing bounds the answer yet (Distance without a cutoff).
    const RScalar reach = other.shape.boundingRadius + std::min(cutoff, best.separation);
    const RVec3 lo = std::isfinite(reach) ? RVec3(p_MC.array() - reach) : mesh.BoxMin();
    const RVec3 hi = std::isfinite(reach) ? RVec3(p_MC.array() + reach) : mesh.BoxMax();
    ForEachTriangleChild(mesh, lo, hi, [&](std::uint32_t, const RShapeChild& tri) {
      const RScalar bound = std::min(cutoff, best.separation);
      if ((p_MC - tri.p_BC).norm() - tri.shape.boundingRadius - other.shape.boundingRadius > bound) return;
      const RShapeChild& ca = meshIsA ? tri : other;
      const RShapeChild& cb = meshIsA ? other : tri;
      const RDistanceResult r = RCollisionSolver::DistanceWithin(ca.shape, cb.shape, ChildPose(ca, cb, X), bound);
      if (!(r.separation < best.separation)) return;
      best = r;
      best.normal = ca.R_BC * r.normal;
      best.witnessA = ca.R_BC * r.witnessA + ca.p_BC;
      best.witnessB = ca.R_BC * r.witnessB + ca.p_BC;
    });
  }
  return best;
}

RContactManifold MeshManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X, RScalar margin,
                              RScalar cutoff) {
  RContactManifold best;
  bool found = false;
  if (!(a.mesh && b.mesh)) {
    const bool meshIsA = a.mesh != nullptr;
    RShapeChild alone;
    std::uint32_t n;
    const RShapeChild* children = ChildrenOf(meshIsA ? b : a, alone, n);
    RContactManifold ms[kMaxMeshManifolds];
    for (std::uint32_t j = 0; j < n; ++j) {
      const int count = MeshChildManifolds(meshIsA ? *a.mesh : *b.mesh, meshIsA, children[j],
                                           (meshIsA ? b : a).children ? j : 0, X, margin, ms);
      for (int k = 0; k < count; ++k) {
        if (!found || ms[k].query.separation < best.query.separation) best = ms[k], found = true;
      }
    }
  }
  if (!found) {
    best.query = MeshDistance(a, b, X, cutoff);
    best.normal = best.query.normal;
  }
  return best;
}

RContactManifold MeshPartManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X,
                                  std::uint32_t childA, std::uint32_t childB) {
  RContactManifold best;
  if (a.mesh && b.mesh) return best;
  const bool meshIsA = a.mesh != nullptr;
  const RConvexShape& convex = meshIsA ? b : a;
  const std::uint32_t j = meshIsA ? childB : childA;
  RShapeChild alone;
  std::uint32_t n;
  const RShapeChild* children = ChildrenOf(convex, alone, n);
  const RShapeChild& other = children[convex.children ? j : 0];
  // Every triangle within the child's size of it: the impact's geometry at any depth the
  // step reaches (a body moves less than its size a step, or it is a fast body's sweep).
  RContactManifold ms[kMaxMeshManifolds];
  const int count = MeshChildManifolds(meshIsA ? *a.mesh : *b.mesh, meshIsA, other, convex.children ? j : 0, X,
                                       other.shape.boundingRadius, ms);
  for (int k = 0; k < count; ++k) {
    if (ms[k].childA == childA && ms[k].childB == childB) return ms[k];
    if (best.pointCount == 0 || ms[k].query.separation < best.query.separation) best = ms[k];
  }
  return best;
}

bool ShapeCastMesh(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X, const RVec3& translation_A,
                   RScalar maxFraction, RShapeCastResult& out) {
  if (a.mesh && b.mesh) return false;
  const bool meshIsA = a.mesh != nullptr;
  const RTriangleMesh& mesh = meshIsA ? *a.mesh : *b.mesh;
  RShapeChild alone;
  std::uint32_t n;
  const RShapeChild* children = ChildrenOf(meshIsA ? b : a, alone, n);
  // The other shape's path in the mesh's frame (B moves by the translation: the other when
  // the mesh is A, else the mesh, which is the other moving back).
  const RVec3 path_M = meshIsA ? translation_A : RVec3(-(X.R_AB.transpose() * translation_A));
  bool found = false;
  for (std::uint32_t j = 0; j < n; ++j) {
    const RShapeChild& other = children[j];
    RMat3 R_MC;
    RVec3 p_MC;
    OtherInMesh(meshIsA, other, X, R_MC, p_MC);
    const RVec3 end = p_MC + maxFraction * path_M;
    const RScalar r = other.shape.boundingRadius;
    ForEachTriangleChild(mesh, RVec3(p_MC.cwiseMin(end).array() - r), RVec3(p_MC.cwiseMax(end).array() + r),
                         [&](std::uint32_t, const RShapeChild& tri) {
      const RShapeChild& ca = meshIsA ? tri : other;
      const RShapeChild& cb = meshIsA ? other : tri;
      RShapeCastResult hit;
      const RScalar limit = found ? out.fraction : maxFraction;
      if (!ShapeCastShape(ca.shape, cb.shape, ChildPose(ca, cb, X), ca.R_BC.transpose() * translation_A, limit, hit)) {
        return;
      }
      if (found && !(hit.fraction < out.fraction)) return;
      out = hit;
      out.point = ca.R_BC * hit.point + ca.p_BC;
      out.normal = ca.R_BC * hit.normal;
      found = true;
    });
  }
  return found;
}

bool RayCastMesh(const RTriangleMesh& mesh, const RVec3& origin, const RVec3& direction, RScalar maxDistance,
                 RShapeRayHit& hit) {
  RScalar distance;
  std::uint32_t triangle;
  RVec3 normal;
  if (!mesh.RayCast(origin, direction, maxDistance, distance, triangle, normal)) return false;
  hit.distance = distance;
  hit.normal = normal;
  return true;
}

}  // namespace REngine
