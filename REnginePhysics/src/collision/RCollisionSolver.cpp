#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RRigidBody.h>

#include "collision/RCapsule.h"
#include "shape/RCompound.h"
#include "collision/RCylinder.h"
#include "collision/RMesh.h"
#include "collision/RManifold.h"
#include "collision/RBoxPair.h"
#include "collision/RGjkEpa.h"
#include "collision/RPolyhedronExact.h"

#include <algorithm>
#include <limits>
#include <cmath>
#include "body/RBodyAccess.h"

namespace REngine {

namespace {

// Sphere (radius ra, at the origin of A) against sphere (radius rb, at t).
RDistanceResult SphereSphere(const RConvexShape& a, const RConvexShape& b, const RVec3& t) {
  RDistanceResult r;
  const RScalar d = t.norm();
  r.normal = SafeDirection(t, RVec3::UnitX());
  r.separation = d - a.radius - b.radius;
  r.witnessA = a.radius * r.normal;
  r.witnessB = t - b.radius * r.normal;
  r.status = StatusOf(r.separation, Band(a, b));
  return r;
}

// Point c (a sphere's centre, in the polyhedron's frame) inside polyhedron P: the face with
// the largest signed distance is the exact minimum translation of a point out of P.
void PointInsidePolyhedron(const RConvexPolyhedron& p, const RVec3& c, RVec3& outward,
                           RScalar& signedDistance) {
  signedDistance = -std::numeric_limits<RScalar>::infinity();
  for (const RFace& f : p.Faces()) {
    const RScalar s = f.plane.SignedDistance(c);
    if (s > signedDistance) signedDistance = s, outward = f.plane.normal;
  }
}

// Polyhedron A against sphere B (radius rb, centre t in A's frame).
RDistanceResult PolyhedronSphere(const RConvexShape& poly, const RConvexShape& sphere,
                                 const RRelativePose& X, RPairSupport& sup) {
  RDistanceResult r;
  const RGjkResult g = Gjk(sup, false);
  r.gjkIterations = g.iterations;
  const RVec3 c = X.t_AB;
  const RScalar band = Band(poly, sphere);
  RScalar s = 0;
  RVec3 outward = RVec3::UnitX();
  if (Certified(g, band) && g.distance > band) {
    s = g.distance;
    outward = SafeDirection(c - g.witnessA, RVec3::UnitX());
    r.witnessA = g.witnessA;
  } else if (CertainOverlap(g, band) || Certified(g, band)) {
    // The centre is inside or within the band.
    PointInsidePolyhedron(*poly.polyhedron, c, outward, s);
    s = std::min(s, RScalar(0));
    r.witnessA = c - s * outward;  // the centre's projection onto that face
  } else {  // GJK could not certify its answer: the closest feature by enumeration
    ExactPointPolyhedron(*poly.polyhedron, c, s, r.witnessA, outward);
  }
  r.normal = outward;
  r.separation = s - sphere.radius;
  r.witnessB = c - sphere.radius * outward;
  r.status = StatusOf(r.separation, band);
  return r;
}

RDistanceResult Mirror(RDistanceResult r, const RRelativePose& X_AB) {
  // A result computed with the roles swapped (in B's frame, normal from B to A) expressed
  // in A's frame with the normal from A to B.
  RDistanceResult m = r;
  m.normal = -(X_AB.R_AB * r.normal);
  m.witnessA = X_AB.R_AB * r.witnessB + X_AB.t_AB;
  m.witnessB = X_AB.R_AB * r.witnessA + X_AB.t_AB;
  return m;
}

}  // namespace

bool RCollisionSolver::Intersect(const RConvexShape& a, const RConvexShape& b,
                                 const RRelativePose& X_AB) {
  const RScalar band = Band(a, b);
  if (!a.polyhedron && !b.polyhedron && a.halfHeight == 0 && b.halfHeight == 0 && !a.children && !b.children &&
      !a.mesh && !b.mesh) {
    return X_AB.t_AB.norm() - a.radius - b.radius <= band;
  }
  if (a.polyhedron && b.polyhedron) {
    // GJK's early answers are certain: a plane that separates them by more than the band,
    // or a simplex that encloses the origin. Anything else gets the full query, so that
    // Intersect and Distance never disagree.
    RPairSupport sup(a, b, X_AB);
    const RGjkResult g = Gjk(sup, true);
    if (CertainOverlap(g, band)) return true;
    if (g.converged && g.lowerBound > band) return false;
  }
  // (A mesh: only its triangles within the band of the other shape, not all of them.)
  if (a.mesh || b.mesh) return MeshDistance(a, b, X_AB, band).separation <= band;
  return Distance(a, b, X_AB).separation <= band;
}

RDistanceResult RCollisionSolver::Distance(const RConvexShape& a, const RConvexShape& b,
                                           const RRelativePose& X_AB) {
  return DistanceWithin(a, b, X_AB, std::numeric_limits<RScalar>::infinity());
}

// Distance, except that two polyhedra GJK proves farther apart than `cutoff` (m) get that
// proof instead of their distance: separation is then GJK's lower bound, above the cutoff,
// and the witnesses are not computed. The narrow phase asks no more of a pair beyond its
// margin, and most pairs the broad phase passes are (a debris cloud's, ~70%): they cost a
// few GJK iterations instead of the full answer (and, for some, its enumeration).
RDistanceResult RCollisionSolver::DistanceWithin(const RConvexShape& a, const RConvexShape& b,
                                                 const RRelativePose& X_AB, RScalar cutoff) {
  if (a.mesh || b.mesh) return MeshDistance(a, b, X_AB, cutoff);
  if (a.children || b.children) return CompoundDistance(a, b, X_AB, cutoff);
  if (a.cylinderRadius > 0 || b.cylinderRadius > 0) return CylinderPair(a, b, X_AB, cutoff);
  if (!a.polyhedron && !b.polyhedron) {
    return a.halfHeight == 0 && b.halfHeight == 0 ? SphereSphere(a, b, X_AB.t_AB) : RoundPair(a, b, X_AB);
  }
  if (!a.polyhedron) {
    const RRelativePose X_BA = Inverse(X_AB);
    RPairSupport sup(b, a, X_BA);
    return Mirror(a.halfHeight == 0 ? PolyhedronSphere(b, a, X_BA, sup) : PolyhedronCapsule(b, a, X_BA, sup, cutoff), X_AB);
  }
  RPairSupport sup(a, b, X_AB);
  if (!b.polyhedron) return b.halfHeight == 0 ? PolyhedronSphere(a, b, X_AB, sup) : PolyhedronCapsule(a, b, X_AB, sup, cutoff);

  RDistanceResult r;
  const RVec3* boxA = a.polyhedron->BoxHalfExtents();
  const RVec3* boxB = b.polyhedron->BoxHalfExtents();
  if (boxA && boxB && a.radius == 0 && b.radius == 0 && std::isfinite(cutoff) &&
      BoxesApart(*boxA, *boxB, X_AB, cutoff, r.separation, r.normal)) {
    r.status = RCollisionStatus::kSeparated;
    return r;
  }
  const RScalar band = Band(a, b);
  const RGjkResult g = Gjk(sup, false, cutoff);
  r.gjkIterations = g.iterations;
  if (g.beyond) {
    r.separation = g.lowerBound;
    r.normal = SafeDirection(-g.closest, SafeDirection(X_AB.t_AB, RVec3::UnitX()));
    r.status = RCollisionStatus::kSeparated;
    return r;
  }
  const RGjkResult refined = Certified(g, band) ? g : RefineOnTrianglePlane(sup, g);
  if (Certified(refined, band)) {
    r.separation = refined.distance;
    r.normal = SafeDirection(-refined.closest, SafeDirection(X_AB.t_AB, RVec3::UnitX()));
    r.witnessA = refined.witnessA;
    r.witnessB = refined.witnessB;
    r.status = StatusOf(r.separation, band);
    return r;
  }
  if (CertainOverlap(g, band)) {
    const REpaResult e = EpaPenetration(sup, g);
    r.epaIterations = e.iterations;
    if (e.converged) {
      r.separation = -e.depth;
      r.normal = e.normal;
      r.witnessA = e.witnessA;
      r.witnessB = e.witnessB;
      r.status = StatusOf(r.separation, band);
      return r;
    }
  }
  // Neither GJK nor EPA could certify an answer (EPA found no face: boxes resting face on
  // face overlap by 1e-13 m and the polytope is flat to rounding; GJK's simplex lost the
  // closest point to rounding on a thin triangle with coordinates in the thousands; an
  // iteration cap): the exact answer by enumeration.
  const int gjkIterations = r.gjkIterations, epaIterations = r.epaIterations;
  r = ExactPolyhedra(*a.polyhedron, *b.polyhedron, X_AB);
  r.gjkIterations = gjkIterations, r.epaIterations = epaIterations;
  r.status = StatusOf(r.separation, band);
  return r;
}

namespace {

struct FaceRef {
  const RConvexPolyhedron* poly;
  const RMat3* R;  // to A's frame (null: identity)
  const RVec3* t;
  std::uint32_t face;
  RVec3 Vertex(std::uint32_t i) const {
    const RVec3& v = poly->Vertices()[poly->LoopVertices()[poly->Faces()[face].firstVertex + i]];
    return R ? RVec3(*R * v + *t) : v;
  }
  RVec3 Normal() const {
    const RVec3& n = poly->Faces()[face].plane.normal;
    return R ? RVec3(*R * n) : n;
  }
  std::uint32_t Count() const { return poly->Faces()[face].vertexCount; }
};

}  // namespace

std::uint32_t MostAlignedFace(const RConvexPolyhedron& p, const RMat3* R, const RVec3& d,
                              RScalar& alignment) {
  const RVec3 dLocal = R ? RVec3(R->transpose() * d) : d;
  std::uint32_t best = 0;
  alignment = -2;
  for (std::uint32_t f = 0; f < p.Faces().size(); ++f) {
    const RScalar x = p.Faces()[f].plane.normal.dot(dLocal);
    if (x > alignment) alignment = x, best = f;
  }
  return best;
}

int ReduceToFour(RContactPoint* pts, int n, const RVec3& normal) {
  if (n <= 4) return n;
  int keep[4];
  keep[0] = 0;
  for (int i = 1; i < n; ++i) {
    if (pts[i].separation < pts[keep[0]].separation) keep[0] = i;
  }
  RScalar best = -1;
  keep[1] = keep[0];
  for (int i = 0; i < n; ++i) {
    const RScalar d = (pts[i].position - pts[keep[0]].position).squaredNorm();
    if (d > best) best = d, keep[1] = i;
  }
  const RVec3 p0 = pts[keep[0]].position, p1 = pts[keep[1]].position;
  auto area = [&](const RVec3& a, const RVec3& b, const RVec3& c) {
    return (b - a).cross(c - a).dot(normal);
  };
  best = 0;
  keep[2] = -1;
  RScalar sign = 1;
  for (int i = 0; i < n; ++i) {
    const RScalar s = area(p0, p1, pts[i].position);
    if (std::abs(s) > best) best = std::abs(s), keep[2] = i, sign = s > 0 ? 1 : -1;
  }
  if (keep[2] < 0) {  // collinear: the two ends are all there is
    const RContactPoint p0c = pts[keep[0]], p1c = pts[keep[1]];
    pts[0] = p0c, pts[1] = p1c;
    return 2;
  }
  // The fourth point: the one outside the triangle that adds the most area.
  const RVec3 p2 = pts[keep[2]].position;
  best = 0;
  keep[3] = -1;
  for (int i = 0; i < n; ++i) {
    const RVec3& p = pts[i].position;
    const RScalar gain = std::max({-sign * area(p0, p1, p), -sign * area(p1, p2, p),
                                   -sign * area(p2, p0, p)});
    if (gain > best) best = gain, keep[3] = i;
  }
  RContactPoint out[4];
  int m = 0;
  for (int k : keep) {
    if (k >= 0) out[m++] = pts[k];
  }
  for (int i = 0; i < m; ++i) pts[i] = out[i];
  return m;
}

namespace {
void FinishManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB, RScalar margin,
                    RContactManifold& m, RScalar* droppedMin);
}  // namespace

RContactManifold RCollisionSolver::Manifold(const RConvexShape& a, const RConvexShape& b,
                                            const RRelativePose& X_AB, RScalar margin) {
  return ManifoldWithin(a, b, X_AB, margin, std::numeric_limits<RScalar>::infinity());
}

RContactManifold RCollisionSolver::ManifoldWithin(const RConvexShape& a, const RConvexShape& b,
                                                  const RRelativePose& X_AB, RScalar margin,
                                                  RScalar cutoff, RScalar* droppedMin) {
  if (a.mesh || b.mesh) {
    if (droppedMin) *droppedMin = std::numeric_limits<RScalar>::infinity();
    return MeshManifold(a, b, X_AB, margin, cutoff);
  }
  if (a.children || b.children) {
    if (droppedMin) *droppedMin = std::numeric_limits<RScalar>::infinity();
    return CompoundManifold(a, b, X_AB, margin, cutoff, droppedMin);
  }
  RContactManifold m;
  if (droppedMin) *droppedMin = std::numeric_limits<RScalar>::infinity();
  m.query = DistanceWithin(a, b, X_AB, cutoff);
  m.normal = m.query.normal;
  if (m.query.status == RCollisionStatus::kIterationCap || m.query.separation > margin) return m;
  FinishManifold(a, b, X_AB, margin, m, droppedMin);
  return m;
}

RContactManifold ManifoldAlong(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB,
                               const RVec3& n, bool faceOfA, RScalar margin) {
  // The overlap of the two supports along n: for n a face normal of the face side, the
  // separation of the other shape's deepest point from that face's plane.
  RContactManifold m;
  RPairSupport sup(a, b, X_AB);
  const RVec3 sA = sup.SupportA(n) + a.radius * n;
  const RVec3 sB = sup.SupportB(-n) - b.radius * n;
  RDistanceResult& q = m.query;
  q.separation = n.dot(sB - sA);
  q.normal = n;
  if (faceOfA) {
    q.witnessB = sB, q.witnessA = sB - q.separation * n;
  } else {
    q.witnessA = sA, q.witnessB = sA + q.separation * n;
  }
  q.status = StatusOf(q.separation, Band(a, b));
  m.normal = n;
  if (q.separation <= margin) FinishManifold(a, b, X_AB, margin, m, nullptr);
  return m;
}

namespace {

// The manifold's points from its query (normal, separation, witnesses): clipping for face
// contacts, the closest points of two edges, the round shapes' own.
void FinishManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB, RScalar margin,
                    RContactManifold& m, RScalar* droppedMin) {
  const RDistanceResult& q = m.query;
  const RVec3 n = q.normal;

  auto single = [&](std::uint32_t id) {
    m.pointCount = 1;
    m.points[0].position = RScalar(0.5) * (q.witnessA + q.witnessB);
    m.points[0].separation = q.separation;
    m.points[0].featureId = id;
  };
  if (a.cylinderRadius > 0 || b.cylinderRadius > 0) {
    CylinderManifold(a, b, X_AB, margin, m, droppedMin);
    return;
  }
  if (!a.polyhedron || !b.polyhedron) {
    // A capsule along a face or another capsule touches along a line (RCapsule.cpp).
    if ((a.halfHeight > 0 || b.halfHeight > 0) &&
        CapsuleManifold(a, b, X_AB, margin, m, droppedMin)) {
      return;
    }
    single(0);
    return;
  }

  RScalar alignA, alignB;
  const std::uint32_t faceA = MostAlignedFace(*a.polyhedron, nullptr, n, alignA);
  const std::uint32_t faceB = MostAlignedFace(*b.polyhedron, &X_AB.R_AB, -n, alignB);
  if (std::max(alignA, alignB) < kFaceContactCos) {
    // Edge against edge: the witnesses are the closest points of the two edges.
    single(0x80000000u | (faceA << 16) | faceB);
    return;
  }
  const bool refIsA = alignA + kReferenceBias >= alignB;
  const RVec3 t0 = RVec3::Zero();
  FaceRef ref{refIsA ? a.polyhedron : b.polyhedron, refIsA ? nullptr : &X_AB.R_AB,
              refIsA ? &t0 : &X_AB.t_AB, refIsA ? faceA : faceB};
  const RVec3 refN = ref.Normal();
  // Incident face: the other shape's face most anti-parallel to the reference normal.
  RScalar dummy;
  const RConvexPolyhedron* incPoly = refIsA ? b.polyhedron : a.polyhedron;
  const RMat3* incR = refIsA ? &X_AB.R_AB : nullptr;
  const std::uint32_t incFace = MostAlignedFace(*incPoly, incR, -refN, dummy);
  FaceRef inc{incPoly, incR, refIsA ? &X_AB.t_AB : &t0, incFace};

  // Sutherland-Hodgman: clip the incident polygon by the reference face's side planes.
  ClipPoint bufA[kMaxClip], bufB[kMaxClip];
  ClipPoint* in = bufA;
  ClipPoint* out = bufB;
  int nIn = 0;
  for (std::uint32_t i = 0; i < inc.Count() && nIn < kMaxClip; ++i) {
    in[nIn++] = {inc.Vertex(i), 0x8000u | i};
  }
  const std::uint32_t refCount = ref.Count();
  // Side planes are pushed out by 1e-4 of the face's size: an incident vertex exactly on a
  // reference edge (equal boxes stacked) stays one feature instead of flickering between
  // "inside" and "clipped" with rounding, which would lose its warm start every other step.
  RScalar faceSize = 0;
  for (std::uint32_t e = 0; e < refCount; ++e) {
    faceSize = std::max(faceSize, (ref.Vertex(e) - ref.Vertex(0)).norm());
  }
  const RScalar clipTolerance = kClipTolerance * faceSize;
  nIn = ClipBySides([&](std::uint32_t e) { return ref.Vertex(e); }, refCount, refN, clipTolerance,
                     in, nIn, out, &in);

  const RScalar refOffset = refN.dot(ref.Vertex(0));
  RContactPoint pts[kMaxClip];
  int np = 0;
  const std::uint32_t faceBits =
      (refIsA ? 0x40000000u : 0u) | ((ref.face & 0x7fu) << 23) | ((incFace & 0x7fu) << 16);
  for (int i = 0; i < nIn; ++i) {
    const RScalar s = refN.dot(in[i].p) - refOffset;  // incident point above the reference
    if (s > margin) {
      if (droppedMin) *droppedMin = std::min(*droppedMin, s);
      continue;
    }
    RContactPoint& c = pts[np++];
    c.position = in[i].p - RScalar(0.5) * s * refN;
    c.separation = s;
    c.featureId = faceBits | (in[i].feature & 0xffffu);
  }
  if (np == 0) {
    // Clipping can lose a touching vertex to rounding: fall back on the witnesses.
    single(faceBits);
    return;
  }
  m.pointCount = ReduceToFour(pts, np, refN);
  for (int i = 0; i < m.pointCount; ++i) m.points[i] = pts[i];
  m.normal = refIsA ? refN : RVec3(-refN);
}

}  // namespace

RConvexShape ShapeOf(const RRigidBody& b) {
  const RBodyCore& body = Core(b);
  RConvexShape s;
  s.polyhedron = body.m_polyhedron_B;  // Polyhedron_B()'s, without reaching the prepared shape
  s.radius = body.m_coreRadius;
  s.halfHeight = body.m_coreHalfHeight;
  s.cylinderRadius = body.m_cylinderRadius;
  s.children = body.m_children, s.childCount = body.m_childCount;
  s.mesh = body.m_mesh;
  s.boundingRadius = b.BoundingRadius();
  return s;
}

RRelativePose RelativePose(const RRigidBody& a, const RRigidBody& b) {
  // x_B - x_A first: for two bodies near each other far from the origin this difference
  // is exact, which is what makes the pair frame as good as the origin.
  RRelativePose X;
  const RQuat q_AW = a.Orientation_WB().conjugate();
  X.R_AB = (q_AW * b.Orientation_WB()).toRotationMatrix();
  X.t_AB = q_AW * (b.Position_W() - a.Position_W());
  return X;
}

bool RCollisionSolver::CheckCollision(const RRigidBody& a, const RRigidBody& b, RScalar dt,
                                      RContactManifold& out) {
  // How fast any point of B can approach any point of A: a bound for the speculative
  // margin, so a contact that may close within this step is kept.
  const RScalar approach = (b.Velocity_W() - a.Velocity_W()).norm() +
                           a.AngularVelocity_B().norm() * a.BoundingRadius() +
                           b.AngularVelocity_B().norm() * b.BoundingRadius();
  return CheckCollision(a, b, RMargin{approach * dt}, out);
}

bool RCollisionSolver::CheckCollision(const RRigidBody& a, const RRigidBody& b, RMargin margin,
                                      RContactManifold& out) {
  if (!CheckCollisionInA(ShapeOf(a), ShapeOf(b), RelativePose(a, b), margin, out)) return false;
  ToWorld(a, out);
  return true;
}

bool RCollisionSolver::CheckCollisionInA(const RConvexShape& sa, const RConvexShape& sb,
                                         const RRelativePose& X, RMargin margin,
                                         RContactManifold& out, RScalar* droppedMin) {
  // A pair proven farther apart than the margin needs no more: the cutoff sits above the
  // margin by more than the rounding of GJK's lower bound, so every pair within the margin
  // gets the full answer, bit for bit the same as without it.
  const RScalar within = margin.metres + Band(sa, sb);
  out = ManifoldWithin(sa, sb, X, within, within * (1 + 1e-9) + 1e-12 * (sa.boundingRadius + sb.boundingRadius),
                       droppedMin);
  return !(out.query.status == RCollisionStatus::kSeparated && out.pointCount == 0);
}

void RCollisionSolver::ToWorld(const RRigidBody& a, RContactManifold& m) {
  // Rotate by A's orientation, then translate by its position.
  const RMat3 R = a.Orientation_WB().toRotationMatrix();
  const RVec3& x = a.Position_W();
  m.query.normal = R * m.query.normal;
  m.normal = R * m.normal;
  m.query.witnessA = R * m.query.witnessA + x;
  m.query.witnessB = R * m.query.witnessB + x;
  for (int i = 0; i < m.pointCount; ++i) m.points[i].position = R * m.points[i].position + x;
}

}  // namespace REngine
