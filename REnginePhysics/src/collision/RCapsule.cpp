// The narrow phase of capsules: queries on their cores (RCapsule.h).
#include "collision/RCapsule.h"

#include "collision/RManifold.h"
#include "collision/RPolyhedronExact.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

namespace {

// A unit vector across d (any, when d is zero).
RVec3 Across(const RVec3& d) {
  const RVec3 c = std::abs(d.x()) < std::abs(d.y()) ? RVec3(0, -d.z(), d.y()) : RVec3(-d.z(), 0, d.x());
  const RScalar n = c.norm();
  return n > 0 ? RVec3(c / n) : RVec3::UnitZ();
}

// B's core ends in A's frame.
void CoreOfB(const RConvexShape& b, const RRelativePose& X, RVec3& p0, RVec3& p1) {
  const RVec3 half = X.R_AB.col(1) * b.halfHeight;
  p0 = X.t_AB - half, p1 = X.t_AB + half;
}


}  // namespace

RDistanceResult RoundPair(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X) {
  const RVec3 a0(0, -a.halfHeight, 0), a1(0, a.halfHeight, 0);
  RVec3 b0, b1;
  CoreOfB(b, X, b0, b1);
  RVec3 ca, cb;
  ClosestOnSegments(a0, a1, b0, b1, ca, cb);
  const RVec3 d = cb - ca;
  const RScalar dist = d.norm();
  RDistanceResult r;
  // Cores that cross (or a centre on a core) are a rounding error apart, in no direction:
  // then the depth r_a + r_b is along any direction across both cores. Two crossing
  // segments: their common perpendicular. A point on a segment, or parallel segments: across
  // the segment, towards B's centre where that has a part across it.
  const RScalar size = a.boundingRadius + b.boundingRadius;
  if (dist > RScalar(1e-12) * size) {
    r.normal = d / dist;
  } else {
    const RVec3 axisA = RVec3::UnitY(), axisB = X.R_AB.col(1);
    const bool segA = a.halfHeight > 0, segB = b.halfHeight > 0;
    const RVec3 both = axisA.cross(axisB);
    if (segA && segB && both.squaredNorm() > 1e-12) {
      r.normal = both.normalized();
    } else {
      const RVec3 axis = segA ? axisA : axisB;
      const RVec3 aside = X.t_AB - X.t_AB.dot(axis) * axis;
      r.normal = aside.norm() > RScalar(1e-12) * size ? RVec3(aside.normalized()) : Across(axis);
    }
    if (r.normal.dot(X.t_AB) < 0) r.normal = -r.normal;
  }
  r.separation = dist - a.radius - b.radius;
  r.witnessA = ca + a.radius * r.normal;
  r.witnessB = cb - b.radius * r.normal;
  r.status = StatusOf(r.separation, Band(a, b));
  return r;
}

void ExactSegmentPolyhedron(const RConvexPolyhedron& P, const RVec3& p0, const RVec3& p1,
                            RScalar& signedDistance, RVec3& normal, RVec3& onP, RVec3& onSegment) {
  // The separating axis test over the faces of the Minkowski difference of P and the
  // segment: P's face normals, and the cross products of the segment with P's edges. Where
  // none separates, the least overlap is the depth, exactly (the depth is the least support
  // of the difference over its face normals, and these are all of them).
  const RVec3 seg = p1 - p0;
  RScalar least = std::numeric_limits<RScalar>::infinity();
  RVec3 axis = RVec3::UnitX();
  bool apart = false;
  const RFace* leastFace = nullptr;  // the axis's face, or
  const REdge* leastEdge = nullptr;  // its edge
  for (const RFace& f : P.Faces()) {
    const RScalar o = f.plane.offset - std::min(f.plane.normal.dot(p0), f.plane.normal.dot(p1));
    if (o < 0) {
      apart = true;
      break;
    }
    if (o < least) least = o, axis = f.plane.normal, leastFace = &f;
  }
  const std::vector<RVec3>& v = P.Vertices();
  for (std::size_t k = 0; !apart && k < P.Edges().size(); ++k) {
    const REdge& e = P.Edges()[k];
    const RVec3 edge = v[e.v1] - v[e.v0];
    RVec3 n = edge.cross(seg);
    // Parallel to the segment: no face of the difference (its faces' normals are P's).
    if (!(n.squaredNorm() > 1e-20 * edge.squaredNorm() * seg.squaredNorm())) continue;
    n.normalize();
    RScalar lo = std::numeric_limits<RScalar>::infinity(), hi = -lo;
    for (const RVec3& x : v) lo = std::min(lo, n.dot(x)), hi = std::max(hi, n.dot(x));
    const RScalar s0 = n.dot(p0), s1 = n.dot(p1);
    const RScalar up = hi - std::min(s0, s1), down = std::max(s0, s1) - lo;  // along +n, -n
    if (up < 0 || down < 0) {
      apart = true;
      break;
    }
    // A face of the difference only where this edge is P's support along the axis: the
    // parallel edges elsewhere give the same overlap (P's support is P's, not the edge's),
    // and the witnesses must be at the edge that touches.
    const RScalar at = n.dot(v[e.v0]), slack = RScalar(1e-12) * (std::abs(hi) + std::abs(lo));
    if (up < least && at >= hi - slack) least = up, axis = n, leastEdge = &e, leastFace = nullptr;
    if (down < least && at <= lo + slack) least = down, axis = -n, leastEdge = &e, leastFace = nullptr;
  }
  if (!apart) {
    signedDistance = -least;
    normal = axis;
    // The witnesses where the shapes touch along the axis. An edge's axis: the segment's
    // point nearest that edge (the axis is across the segment, so its two ends are equally
    // deep, and either could be metres from the contact). A face's: the segment's deepest
    // point within the face's side planes (the middle of that part when it lies along the
    // face), or its deepest end where no part of it is.
    if (leastEdge) {
      RVec3 onEdge;
      ClosestOnSegments(p0, p1, v[leastEdge->v0], v[leastEdge->v1], onSegment, onEdge);
    } else {
      RVec3 q0 = p0, q1 = p1;
      bool inside = true;
      if (leastFace) {
        const std::vector<std::uint32_t>& loop = P.LoopVertices();
        for (std::uint32_t k = 0; k < leastFace->vertexCount && inside; ++k) {
          const RVec3& v0 = v[loop[leastFace->firstVertex + k]];
          const RVec3& v1 = v[loop[leastFace->firstVertex + (k + 1) % leastFace->vertexCount]];
          const RVec3 outward = (v1 - v0).cross(axis);
          const RScalar d0 = outward.dot(q0 - v0), d1 = outward.dot(q1 - v0);
          if (d0 > 0 && d1 > 0) inside = false;
          else if (d0 > 0) q0 = q0 + d0 / (d0 - d1) * (q1 - q0);
          else if (d1 > 0) q1 = q1 + d1 / (d1 - d0) * (q0 - q1);
        }
      }
      if (!inside) q0 = p0, q1 = p1;
      const RScalar s0 = axis.dot(q0), s1 = axis.dot(q1);
      onSegment = s0 < s1 ? q0 : s1 < s0 ? q1 : RVec3(RScalar(0.5) * (q0 + q1));
    }
    onP = onSegment + least * axis;
    return;
  }
  // Apart: the closest pair is an end of the segment against P, or the segment against an
  // edge of P (where the segment is closest to a face's inside it lies along the face, and
  // an end is as close).
  RScalar best = std::numeric_limits<RScalar>::infinity();
  for (const RVec3& end : {p0, p1}) {
    RScalar sd;
    RVec3 closest, outward;
    ExactPointPolyhedron(P, end, sd, closest, outward);
    if (sd < best) best = sd, normal = outward, onP = closest, onSegment = end;
  }
  for (const REdge& e : P.Edges()) {
    RVec3 cs, cp;
    ClosestOnSegments(p0, p1, v[e.v0], v[e.v1], cs, cp);
    const RScalar d = (cs - cp).norm();
    if (d < best && d > 0) best = d, normal = (cs - cp) / d, onP = cp, onSegment = cs;
  }
  signedDistance = best;
}

RDistanceResult PolyhedronCapsule(const RConvexShape& poly, const RConvexShape& capsule,
                                  const RRelativePose& X, RPairSupport& sup, RScalar cutoff) {
  RDistanceResult r;
  const RScalar band = Band(poly, capsule);
  const RGjkResult g = Gjk(sup, false, cutoff + capsule.radius);
  r.gjkIterations = g.iterations;
  if (g.beyond) {
    r.separation = g.lowerBound - capsule.radius;
    const RScalar n = g.closest.norm();
    r.normal = n > 0 ? RVec3(-g.closest / n) : RVec3::UnitX();
    r.status = RCollisionStatus::kSeparated;
    return r;
  }
  if (Certified(g, band) && g.distance > band) {
    // The cores apart, by a certain distance: the capsule's surface is r nearer.
    r.normal = -g.closest / g.distance;
    r.separation = g.distance - capsule.radius;
    r.witnessA = g.witnessA;
    r.witnessB = g.witnessB - capsule.radius * r.normal;
  } else {
    RVec3 p0, p1, onSegment;
    CoreOfB(capsule, X, p0, p1);
    RScalar sd;
    ExactSegmentPolyhedron(*poly.polyhedron, p0, p1, sd, r.normal, r.witnessA, onSegment);
    r.separation = sd - capsule.radius;
    r.witnessB = onSegment - capsule.radius * r.normal;
  }
  r.status = StatusOf(r.separation, band);
  return r;
}

namespace {

// Polyhedron A, capsule B: B's core clipped to the side planes of A's face along the normal.
bool FaceAndCapsule(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X,
                    const RVec3& n, RScalar margin, RContactManifold& m, RScalar* droppedMin) {
  const RConvexPolyhedron& P = *a.polyhedron;
  std::uint32_t face = 0;
  RScalar alignment = -2;
  for (std::uint32_t f = 0; f < P.Faces().size(); ++f) {
    const RScalar x = P.Faces()[f].plane.normal.dot(n);
    if (x > alignment) alignment = x, face = f;
  }
  if (alignment < kFaceContactCos) return false;
  const RFace& F = P.Faces()[face];
  const RVec3& fn = F.plane.normal;
  RVec3 p[2];
  CoreOfB(b, X, p[0], p[1]);
  std::uint32_t ids[2] = {0, 1};
  // Clip the segment by each side plane of the face (pushed out by 1e-4 of the face's size,
  // as the polyhedra's clipping is, so that an end on an edge keeps its feature).
  const std::vector<RVec3>& v = P.Vertices();
  const std::vector<std::uint32_t>& loop = P.LoopVertices();
  RScalar faceSize = 0;
  for (std::uint32_t e = 0; e < F.vertexCount; ++e) {
    faceSize = std::max(faceSize, (v[loop[F.firstVertex + e]] - v[loop[F.firstVertex]]).norm());
  }
  const RScalar tolerance = RScalar(1e-4) * faceSize;
  for (std::uint32_t e = 0; e < F.vertexCount; ++e) {
    const RVec3& v0 = v[loop[F.firstVertex + e]];
    const RVec3& v1 = v[loop[F.firstVertex + (e + 1) % F.vertexCount]];
    const RVec3 outward = (v1 - v0).cross(fn).normalized();
    const RScalar d0 = outward.dot(p[0] - v0) - tolerance, d1 = outward.dot(p[1] - v0) - tolerance;
    if (d0 > 0 && d1 > 0) return false;  // beside the face: an edge or corner touches
    if (d0 > 0) p[0] = p[0] + d0 / (d0 - d1) * (p[1] - p[0]), ids[0] = 2 + 2 * e;
    if (d1 > 0) p[1] = p[1] + d1 / (d1 - d0) * (p[0] - p[1]), ids[1] = 3 + 2 * e;
  }
  const std::uint32_t faceBits = 0x20000000u | ((face & 0x7fu) << 16);
  int count = 0;
  for (int k = 0; k < 2; ++k) {
    const RScalar s = F.plane.SignedDistance(p[k]) - b.radius;
    if (s > margin) {
      if (droppedMin) *droppedMin = std::min(*droppedMin, s);
      continue;
    }
    RContactPoint& c = m.points[count++];
    c.position = p[k] - (b.radius + RScalar(0.5) * s) * fn;
    c.separation = s;
    c.featureId = faceBits | ids[k];
  }
  // The two ends over one spot of the face (a capsule standing on its end, within the
  // margin): the deeper one.
  if (count == 2) {
    const RVec3 apart = m.points[0].position - m.points[1].position;
    if ((apart - apart.dot(fn) * fn).squaredNorm() <= tolerance * tolerance) {
      if (m.points[1].separation < m.points[0].separation) m.points[0] = m.points[1];
      count = 1;
    }
  }
  if (count == 0) return false;
  m.pointCount = count;
  m.normal = fn;
  return true;
}

// Two capsules along each other: the ends of the stretch of A's core that B's faces.
bool CapsuleAlongCapsule(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X,
                         const RVec3& n, RScalar margin, RContactManifold& m, RScalar* droppedMin) {
  const RVec3 axisB = X.R_AB.col(1);
  if (std::abs(axisB.y()) < kFaceContactCos) return false;
  RVec3 b0, b1;
  CoreOfB(b, X, b0, b1);
  const RScalar lo = std::max(-a.halfHeight, std::min(b0.y(), b1.y()));
  const RScalar hi = std::min(a.halfHeight, std::max(b0.y(), b1.y()));
  const RScalar size = a.boundingRadius + b.boundingRadius;
  if (!(hi - lo > RScalar(1e-4) * size)) return false;  // end to end: one point
  const RScalar ys[2] = {lo, hi};
  for (int k = 0; k < 2; ++k) {
    const RVec3 ca(0, ys[k], 0);
    RVec3 onA, cb;
    ClosestOnSegments(ca, ca, b0, b1, onA, cb);
    const RScalar sep = (cb - ca).dot(n) - a.radius - b.radius;
    KeepWithin(margin, droppedMin, m, ca + (a.radius + RScalar(0.5) * sep) * n, sep, 0x10000000u | static_cast<std::uint32_t>(k));
  }
  if (m.pointCount == 0) return false;
  m.normal = n;
  return true;
}

}  // namespace

bool CapsuleManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X,
                     RScalar margin, RContactManifold& m, RScalar* droppedMin) {
  const RVec3 n = m.query.normal;
  if (a.polyhedron && b.halfHeight > 0) return FaceAndCapsule(a, b, X, n, margin, m, droppedMin);
  if (b.polyhedron && a.halfHeight > 0) {
    // In B's frame with the roles swapped, then back: positions by X, the normal flipped.
    const RRelativePose X_BA = Inverse(X);
    RContactManifold swapped;
    if (!FaceAndCapsule(b, a, X_BA, -(X.R_AB.transpose() * n), margin, swapped, droppedMin)) return false;
    m.pointCount = swapped.pointCount;
    for (int k = 0; k < swapped.pointCount; ++k) {
      m.points[k] = swapped.points[k];
      m.points[k].position = X.R_AB * swapped.points[k].position + X.t_AB;
      m.points[k].featureId |= 0x40000000u;  // the face is B's
    }
    m.normal = -(X.R_AB * swapped.normal);
    return true;
  }
  if (!a.polyhedron && !b.polyhedron && a.halfHeight > 0 && b.halfHeight > 0) {
    return CapsuleAlongCapsule(a, b, X, n, margin, m, droppedMin);
  }
  return false;
}

}  // namespace REngine
