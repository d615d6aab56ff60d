// Covered features across immovable bodies: the rule that makes flush tiles one surface
// (RCoveredFeatures.h).
#include "collision/RCoveredFeatures.h"
#include <REngineMath/RFunctions.h>

#include "collision/RGjkEpa.h"
#include "collision/RManifold.h"
#include "collision/RMesh.h"
#include "shape/RCompound.h"

#include <REnginePhysics/RTriangleMesh.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

RCoverTolerances CoverTolerances(RScalar slop, RScalar radiusB, RScalar radiusM) {
  RCoverTolerances t;
  t.flush = slop + RCollisionSolver::kTouchingTolerance * (radiusB + radiusM);
  t.inPlane = t.flush + 2 * kClipTolerance * std::max(radiusB, radiusM);
  return t;
}

namespace {

// A contact's normal is a face's own when it is that face's normal to the rounding of the
// rotations between frames (rad, |n x face|): anything more is an edge's normal, however
// little off (a ball touching a seam's edge 1e5 m from the origin, where the tiles' tops
// differ by the rounding of their poses, 1e-11 m, gets a normal 1e-10 rad off and drifts up
// at 1e-10 m/s for ever).
constexpr RScalar kSameNormal = RScalar(1e-14);
bool SameNormal(const RVec3& n, const RVec3& face) { return n.dot(face) > 0 && n.cross(face).norm() <= kSameNormal; }

// Whether q lies within `tolerance` of the convex polygon vertex(0 .. count), counter-clockwise
// about its unit normal n (q's height above the polygon's plane is not looked at).
template <class Vertex>
bool InPolygon(const Vertex& vertex, std::uint32_t count, const RVec3& n, const RVec3& q, RScalar tolerance) {
  for (std::uint32_t e = 0; e < count; ++e) {
    const RVec3 v0 = vertex(e), v1 = vertex((e + 1) % count);
    const RVec3 outward = (v1 - v0).cross(n).normalized();
    if (outward.dot(q - v0) > tolerance) return false;
  }
  return true;
}

bool InFace(const RConvexPolyhedron& P, std::uint32_t f, const RVec3& q, RScalar tolerance) {
  const RFace& F = P.Faces()[f];
  const auto& v = P.Vertices();
  const auto& loop = P.LoopVertices();
  return InPolygon([&](std::uint32_t e) { return v[loop[F.firstVertex + e]]; }, F.vertexCount, F.plane.normal, q,
                   tolerance);
}

bool InTriangle(const RTriangleMesh& mesh, std::uint32_t t, const RVec3& q, RScalar tolerance) {
  return InPolygon([&](std::uint32_t e) { return mesh.Vertex(t, static_cast<int>(e)); }, 3, mesh.Normal(t), q,
                   tolerance);
}

// Whether q (the mesh's frame) lies on a triangle of the mesh in the plane of normal n
// (either side): within flush of its plane, within inPlane of its polygon. A contact's
// points against a mesh come from every triangle under the other shape (merged by normal),
// not only from the triangle the contact names.
bool OnMesh(const RTriangleMesh& mesh, const RVec3& q, const RVec3& n, const RCoverTolerances& tol) {
  bool on = false;
  const RVec3 reach = RVec3::Constant(tol.inPlane);
  mesh.ForEachOverlapping(q - reach, q + reach, [&](std::uint32_t t) {
    const RVec3& nt = mesh.Normal(t);
    on = on || (std::abs(nt.dot(n)) >= kFaceContactCos && std::abs(nt.dot(q - mesh.Vertex(t, 0))) <= tol.flush &&
                InTriangle(mesh, t, q, tol.inPlane));
  });
  return on;
}

bool InBox(const RCoverSurface& s, const RVec3& q_W, RScalar grow) {
  return !((q_W.array() < s.boxMin_W.array() - grow).any() || (q_W.array() > s.boxMax_W.array() + grow).any());
}

// A face of a covering body, in the world: its polygon, counter-clockwise about its normal.
struct CoverPolygon {
  static constexpr std::uint32_t kMax = 16;
  RVec3 v[kMax];
  std::uint32_t count = 0;
  RVec3 normal = RVec3::Zero();
};

// Whether A holds a face against B's face at q_W (B's outward normal there n_W): a face of A
// facing it, its plane within flush of q, q within inPlane of its polygon; that face into
// *face when given (none: a face of more than CoverPolygon::kMax corners). A mesh's
// triangle faces the way its normal points (a closed mesh's outward): a flat piece lying in
// B's plane beside it covers none of B's faces, it continues them (ContinuesPlane).
bool PressedAgainst(const RCoverSurface& a, const RVec3& q_W, const RVec3& n_W, const RCoverTolerances& tol,
                    CoverPolygon* face = nullptr) {
  if (!InBox(a, q_W, tol.inPlane)) return false;
  const RVec3 q = a.R_WB.transpose() * (q_W - a.x_W);
  const RVec3 n = a.R_WB.transpose() * n_W;
  auto keep = [&](std::uint32_t count, const auto& vertex, const RVec3& normal) {
    if (!face) return;
    face->count = count <= CoverPolygon::kMax ? count : 0;
    for (std::uint32_t k = 0; k < face->count; ++k) face->v[k] = a.R_WB * vertex(k) + a.x_W;
    face->normal = a.R_WB * normal;
  };
  if (a.shape.polyhedron) {
    const RConvexPolyhedron& P = *a.shape.polyhedron;
    for (std::uint32_t f = 0; f < P.Faces().size(); ++f) {
      const RFace& F = P.Faces()[f];
      if (F.plane.normal.dot(n) <= -kFaceContactCos && std::abs(F.plane.SignedDistance(q)) <= tol.flush &&
          InFace(P, f, q, tol.inPlane)) {
        keep(F.vertexCount, [&](std::uint32_t k) { return P.Vertices()[P.LoopVertices()[F.firstVertex + k]]; },
             F.plane.normal);
        return true;
      }
    }
    return false;
  }
  const RTriangleMesh& mesh = *a.shape.mesh;
  bool pressed = false;
  const RVec3 reach = RVec3::Constant(tol.inPlane);
  mesh.ForEachOverlapping(q - reach, q + reach, [&](std::uint32_t t) {
    const RVec3& nt = mesh.Normal(t);
    if (pressed || !(nt.dot(n) <= -kFaceContactCos && std::abs(nt.dot(q - mesh.Vertex(t, 0))) <= tol.flush &&
                     InTriangle(mesh, t, q, tol.inPlane))) {
      return;
    }
    pressed = true;
    keep(3, [&](std::uint32_t k) { return mesh.Vertex(t, static_cast<int>(k)); }, nt);
  });
  return pressed;
}

// Whether A's surface continues B's plane (unit normal n_W, either side) at probe_W: a face
// of A in that plane (within flush) holds the probe.
bool ContinuesPlane(const RCoverSurface& a, const RVec3& probe_W, const RVec3& n_W, const RCoverTolerances& tol) {
  if (!InBox(a, probe_W, tol.flush)) return false;
  const RVec3 q = a.R_WB.transpose() * (probe_W - a.x_W);
  const RVec3 n = a.R_WB.transpose() * n_W;
  if (a.shape.polyhedron) {
    const RConvexPolyhedron& P = *a.shape.polyhedron;
    for (std::uint32_t f = 0; f < P.Faces().size(); ++f) {
      const RPlane& plane = P.Faces()[f].plane;
      if (std::abs(plane.normal.dot(n)) >= kFaceContactCos && std::abs(plane.SignedDistance(q)) <= tol.flush &&
          InFace(P, f, q, 0)) {
        return true;
      }
    }
    return false;
  }
  const RTriangleMesh& mesh = *a.shape.mesh;
  bool continues = false;
  const RVec3 reach = RVec3::Constant(tol.flush);
  mesh.ForEachOverlapping(q - reach, q + reach, [&](std::uint32_t t) {
    const RVec3& nt = mesh.Normal(t);
    continues = continues || (std::abs(nt.dot(n)) >= kFaceContactCos &&
                              std::abs(nt.dot(q - mesh.Vertex(t, 0))) <= tol.flush && InTriangle(mesh, t, q, 0));
  });
  return continues;
}

// The other immovable surfaces' answers for one point: any but B itself (another body, or
// another child of B's compound), moving with it.
struct Coverers {
  const RCoverSurface* s;
  int count;
  const RCoverSurface& self;
  bool Other(int k) const { return !s[k].Same(self) && s[k].Takes() && s[k].MovesWith(self); }
  bool Pressed(const RVec3& q_W, const RVec3& n_W, const RCoverTolerances& tol, CoverPolygon* face = nullptr) const {
    for (int k = 0; k < count; ++k) {
      if (Other(k) && PressedAgainst(s[k], q_W, n_W, tol, face)) return true;
    }
    return false;
  }
  bool Continued(const RVec3& probe_W, const RVec3& n_W, const RCoverTolerances& tol) const {
    for (int k = 0; k < count; ++k) {
      if (Other(k) && ContinuesPlane(s[k], probe_W, n_W, tol)) return true;
    }
    return false;
  }
  bool Near(const RVec3& q_W, RScalar grow) const {
    for (int k = 0; k < count; ++k) {
      if (Other(k) && InBox(s[k], q_W, grow)) return true;
    }
    return false;
  }
};

// A contact whose points lie on a face of B (f_W the face's outward normal, q_W the points
// on it) partly where another body covers it (a raised tile's side above its lower
// neighbour: a box that hits it and tips dips its edge below the neighbour's top): the
// manifold's polygon clipped to the uncovered part, when one edge of the covering face
// bounds that part (every uncovered point beyond that edge and within the others): the
// points beyond it, and those where the polygon crosses it, positions and separations
// interpolated (linear across a flat face). False: no point is covered, or every one is, or
// the covered part is not bounded so (then left as it is).
bool ClipToUncovered(const Coverers& others, const RVec3& f_W, const RCoverTolerances& tol, const RVec3* q_W,
                     RContactManifold& m) {
  const int points = m.pointCount;
  if (points < 2) return false;
  bool covered[4];
  int nCovered = 0;
  CoverPolygon face;
  for (int k = 0; k < points; ++k) {
    CoverPolygon g;
    covered[k] = others.Pressed(q_W[k], f_W, tol, &g);
    if (covered[k] && nCovered++ == 0) face = g;
  }
  if (nCovered == 0 || nCovered == points || face.count == 0) return false;
  int edge = -1;
  RVec3 out = RVec3::Zero(), on = RVec3::Zero();
  for (std::uint32_t e = 0; e < face.count; ++e) {
    const RVec3 &v0 = face.v[e], &v1 = face.v[(e + 1) % face.count];
    const RVec3 outward = (v1 - v0).cross(face.normal).normalized();
    int beyond = 0;
    for (int k = 0; k < points; ++k) beyond += !covered[k] && outward.dot(q_W[k] - v0) > tol.inPlane;
    if (beyond == 0) continue;
    if (beyond < points - nCovered || edge >= 0) return false;
    edge = static_cast<int>(e), out = outward, on = v0;
  }
  if (edge < 0) return false;
  // The points as a polygon about their centroid in the face's plane, then clipped to the
  // side of the edge's line away from the covering face (Sutherland-Hodgman, one plane).
  struct Corner {
    RContactPoint p;
    RVec3 q;
    RScalar angle;
  } in[4];
  RVec3 centre = RVec3::Zero();
  for (int k = 0; k < points; ++k) centre += q_W[k];
  centre /= points;
  RVec3 u, w;
  OrthonormalBasis(f_W, u, w);
  for (int k = 0; k < points; ++k) {
    in[k] = {m.points[k], q_W[k], Atan2((q_W[k] - centre).dot(w), (q_W[k] - centre).dot(u))};
  }
  std::sort(in, in + points, [](const Corner& a, const Corner& b) { return a.angle < b.angle; });
  const int sides = points == 2 ? 1 : points;  // a segment is one side, not a closed polygon
  RContactPoint kept[5];
  int n = 0;
  for (int k = 0; k < points; ++k) {
    const Corner &a = in[k], &b = in[(k + 1) % points];
    const RScalar ha = out.dot(a.q - on), hb = out.dot(b.q - on);
    if (ha >= 0) kept[n++] = a.p;
    if (k < sides && (ha < 0) != (hb < 0)) {
      const RScalar t = ha / (ha - hb);
      RContactPoint& c = kept[n++];
      c.position = a.p.position + t * (b.p.position - a.p.position);
      c.separation = a.p.separation + t * (b.p.separation - a.p.separation);
      c.featureId = (a.p.featureId * 0x9e3779b1u) ^ (b.p.featureId * 0x85ebca6bu) ^ static_cast<std::uint32_t>(edge);
    }
  }
  if (n == 0) return false;
  m.pointCount = ReduceToFour(kept, n, f_W);
  for (int k = 0; k < m.pointCount; ++k) m.points[k] = kept[k];
  return true;
}

// The manifold of B's piece (its shape P posed in the world at R_WP, x_WP) and M's, along
// the piece's unit outward normal n (P's frame) instead of the normal the distance query
// finds, in P's frame (normal from P to M), with the points that lie on the piece's face
// (onFace, given the point on P's surface in P's frame): none left, false.
template <class OnFace>
bool AlongFace(const RConvexShape& P, const RMat3& R_WP, const RVec3& x_WP, const RPosedShape& m, const RVec3& n,
               RScalar margin, const OnFace& onFace, RContactManifold& along) {
  RRelativePose X;
  X.R_AB = R_WP.transpose() * m.R_W;
  X.t_AB = R_WP.transpose() * (m.x_W - x_WP);
  along = ManifoldAlong(P, m.shape, X, n, true, margin);
  int kept = 0;
  for (int k = 0; k < along.pointCount; ++k) {
    const RContactPoint& p = along.points[k];
    if (onFace(RVec3(p.position - RScalar(0.5) * p.separation * along.normal))) along.points[kept++] = p;
  }
  along.pointCount = kept;
  return kept > 0;
}

// A manifold of B and M in B's body frame (normal from B to M) as the contact's, in the world
// (normal from the contact's a to its b), naming the contact's children (feature ids made
// distinct per child pair, as the narrow phase makes them).
void ToContact(const RCoverSurface& b, bool bIsA, const RShapeChild& piece, std::uint32_t childA, std::uint32_t childB,
               RContactManifold& m) {
  ChildToBody(piece, childA, childB, m);
  m.query.normal = b.R_WB * m.query.normal;
  m.normal = b.R_WB * m.normal;
  m.query.witnessA = b.R_WB * m.query.witnessA + b.x_W;
  m.query.witnessB = b.R_WB * m.query.witnessB + b.x_W;
  for (int k = 0; k < m.pointCount; ++k) m.points[k].position = b.R_WB * m.points[k].position + b.x_W;
  if (!bIsA) {
    m.normal = -m.normal, m.query.normal = -m.query.normal;
    std::swap(m.query.witnessA, m.query.witnessB);
  }
}

RCoverResult CoverPolyhedron(const RCoverSurface& b, bool bIsA, const RPosedShape& m, const Coverers& others,
                             const RCoverTolerances& tol, RScalar margin, const RVec3& n_W, const RVec3* q_W,
                             int points, RContactManifold& manifold_W) {
  const RConvexPolyhedron& P = *b.shape.polyhedron;
  const RMat3 R_BW = b.R_WB.transpose();
  RVec3 q[4];
  for (int k = 0; k < points; ++k) q[k] = R_BW * (q_W[k] - b.x_W);
  // B's faces through every point (a face's own, an edge's two, a corner's) and which of
  // them another body covers at every point.
  constexpr int kMaxThrough = 8;
  std::uint32_t through[kMaxThrough];
  bool covered[kMaxThrough];
  int nThrough = 0;
  bool anyCovered = false;
  for (std::uint32_t f = 0; f < P.Faces().size(); ++f) {
    const RPlane& plane = P.Faces()[f].plane;
    bool on = true;
    for (int k = 0; k < points && on; ++k) on = std::abs(plane.SignedDistance(q[k])) <= tol.flush;
    if (!on) continue;
    if (nThrough == kMaxThrough) return RCoverResult::kKept;  // a corner of many faces: left as it is
    bool c = true;
    for (int k = 0; k < points && c; ++k) c = others.Pressed(q_W[k], b.R_WB * plane.normal, tol);
    through[nThrough] = f, covered[nThrough++] = c;
    anyCovered = anyCovered || c;
  }
  if (!anyCovered) {
    // Points on a face, partly on its covered part.
    for (int i = 0; i < nThrough; ++i) {
      if (ClipToUncovered(others, b.R_WB * P.Faces()[through[i]].plane.normal, tol, q_W, manifold_W)) {
        return RCoverResult::kReplaced;
      }
    }
    return RCoverResult::kKept;
  }
  // A normal that is an uncovered face's own is that face's contact.
  const RVec3 n = R_BW * n_W;
  for (int i = 0; i < nThrough; ++i) {
    if (!covered[i] && SameNormal(n, P.Faces()[through[i]].plane.normal)) return RCoverResult::kKept;
  }
  // The uncovered face through the points that M's piece overlaps least: the union's
  // surface there. Every face through them covered: the points are inside the union (a
  // corner under a neighbour and beside another), where the other bodies' contacts hold M.
  RRelativePose X;
  X.R_AB = R_BW * m.R_W;
  X.t_AB = R_BW * (m.x_W - b.x_W);
  RPairSupport support(b.shape, m.shape, X);
  std::uint32_t best = 0;
  RScalar bestSeparation = -std::numeric_limits<RScalar>::infinity();
  for (int i = 0; i < nThrough; ++i) {
    if (covered[i]) continue;
    const RPlane& plane = P.Faces()[through[i]].plane;
    const RScalar separation = plane.SignedDistance(support.SupportB(-plane.normal)) - m.shape.radius;
    if (separation > bestSeparation) bestSeparation = separation, best = through[i];
  }
  if (!(bestSeparation > -std::numeric_limits<RScalar>::infinity())) return RCoverResult::kDropped;
  RContactManifold along;
  const bool kept = AlongFace(b.shape, b.R_WB, b.x_W, m, P.Faces()[best].plane.normal, margin,
                              [&](const RVec3& onB) { return InFace(P, best, onB, tol.inPlane); }, along);
  if (!kept) return RCoverResult::kDropped;
  ToContact(b, bIsA, RShapeChild{}, manifold_W.childA, manifold_W.childB, along);
  manifold_W = along;
  return RCoverResult::kReplaced;
}

RCoverResult CoverMeshPiece(const RCoverSurface& b, bool bIsA, const RPosedShape& m, const Coverers& others,
                            const RCoverTolerances& tol, RScalar margin, const RVec3& n_W, const RVec3* q_W,
                            int points, RContactManifold& manifold_W) {
  const RTriangleMesh& mesh = *b.shape.mesh;
  const std::uint32_t t = bIsA ? manifold_W.childA : manifold_W.childB;
  if (t >= mesh.TriangleCount()) return RCoverResult::kKept;
  const RMat3 R_BW = b.R_WB.transpose();
  const RVec3& nt = mesh.Normal(t);
  const RVec3 nt_W = b.R_WB * nt;
  const RVec3 n = R_BW * n_W;
  if (SameNormal(n, nt) || SameNormal(n, -nt)) {
    // The piece's own face. A point of it off the mesh (the mesh's inactive edges put a
    // face contact's point where the moving shape's support is, which may lie past the
    // piece's edge) on another body's surface in the plane is that body's contact.
    int kept = 0;
    for (int k = 0; k < points; ++k) {
      if (OnMesh(mesh, R_BW * (q_W[k] - b.x_W), nt, tol) || !others.Continued(q_W[k], nt_W, tol)) {
        manifold_W.points[kept++] = manifold_W.points[k];
      }
    }
    if (kept == points) return RCoverResult::kKept;
    manifold_W.pointCount = kept;
    return kept == 0 ? RCoverResult::kDropped : RCoverResult::kReplaced;
  }
  // The triangle's edges through the contact's point on it (the query's witness: a normal
  // in the piece's plane comes from an edge or corner, while the manifold's points may
  // spread over the face beside it): each must be inside a smooth stretch of the piece's
  // own mesh (not active) or continued by another body just beyond it, there and at every
  // point of the manifold on it.
  const RVec3 witness_W = bIsA ? manifold_W.query.witnessA : manifold_W.query.witnessB;
  const RVec3 w = R_BW * (witness_W - b.x_W);
  bool onEdge = false;
  for (int e = 0; e < 3; ++e) {
    const RVec3 &v0 = mesh.Vertex(t, e), &v1 = mesh.Vertex(t, (e + 1) % 3), &v2 = mesh.Vertex(t, (e + 2) % 3);
    const RVec3 along = (v1 - v0).normalized();
    auto onLine = [&](const RVec3& p) {
      const RVec3 d = p - v0;
      return (d - d.dot(along) * along).norm() <= tol.flush;
    };
    if (!onLine(w)) continue;
    onEdge = true;
    if (!((mesh.ActiveFeatures(t) >> e) & 1u)) continue;
    RVec3 out = along.cross(nt);
    if (out.dot(v2 - v0) > 0) out = -out;
    const RVec3 beyond_W = tol.flush * (b.R_WB * out);
    if (!others.Continued(witness_W + beyond_W, nt_W, tol)) return RCoverResult::kKept;
    for (int k = 0; k < points; ++k) {
      if (onLine(R_BW * (q_W[k] - b.x_W)) && !others.Continued(q_W[k] + beyond_W, nt_W, tol)) {
        return RCoverResult::kKept;
      }
    }
  }
  if (!onEdge) return RCoverResult::kKept;
  // The piece's own face, on M's side, as the mesh's inactive edges take it.
  RTriangleScratchScope scope;
  RConvexPolyhedron& scratch = scope.Scratch();
  RShapeChild tri;
  MakeTriangleChild(mesh, t, scratch, tri);
  const RVec3 face = (R_BW * (m.x_W - b.x_W) - tri.p_BC).dot(nt) >= 0 ? nt : RVec3(-nt);
  // That face covered too (a body standing on the piece at the seam): inside the union.
  bool inside = true;
  for (int k = 0; k < points && inside; ++k) inside = others.Pressed(q_W[k], b.R_WB * face, tol);
  if (inside) return RCoverResult::kDropped;
  RContactManifold along;
  const bool kept = AlongFace(tri.shape, b.R_WB, b.x_W + b.R_WB * tri.p_BC, m, face, margin,
                              [&](const RVec3& onT) { return OnMesh(mesh, RVec3(onT + tri.p_BC), nt, tol); },
                              along);
  if (!kept) return RCoverResult::kDropped;
  ToContact(b, bIsA, tri, manifold_W.childA, manifold_W.childB, along);
  manifold_W = along;
  return RCoverResult::kReplaced;
}

}  // namespace

RCoverResult CoverContact(const RCoverSurface& b, bool bIsA, const RPosedShape& m, const RCoverSurface* coverers,
                          int count, const RCoverTolerances& tol, RScalar margin, RContactManifold& manifold_W) {
  const int points = manifold_W.pointCount;
  if (!b.Takes() || points == 0) return RCoverResult::kKept;
  const Coverers others{coverers, count, b};
  // The points on B's surface: each point's midway position moved back half its separation
  // along the normal (from B to M).
  const RVec3 n_W = bIsA ? manifold_W.normal : RVec3(-manifold_W.normal);
  RVec3 q_W[4];
  for (int k = 0; k < points; ++k) {
    const RContactPoint& p = manifold_W.points[k];
    q_W[k] = p.position - RScalar(0.5) * p.separation * n_W;
  }
  // Points no other body's box reaches cannot be covered: the cheap answer for nearly every
  // contact (a body on one tile away from its seams, a pile on the ground). (A mesh piece's
  // feature is at the query's witness.)
  bool near = b.shape.mesh && others.Near(bIsA ? manifold_W.query.witnessA : manifold_W.query.witnessB, tol.inPlane);
  for (int k = 0; k < points && !near; ++k) near = others.Near(q_W[k], tol.inPlane);
  if (!near) return RCoverResult::kKept;
  if (b.shape.mesh) return CoverMeshPiece(b, bIsA, m, others, tol, margin, n_W, q_W, points, manifold_W);
  return CoverPolyhedron(b, bIsA, m, others, tol, margin, n_W, q_W, points, manifold_W);
}

}  // namespace REngine
