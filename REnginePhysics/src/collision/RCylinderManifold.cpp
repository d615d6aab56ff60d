// The contact manifold of pairs with a cylinder, from features (RCylinder.h).
#include "collision/RCylinder.h"
#include <REngineMath/RFunctions.h>

#include "collision/RGjkEpa.h"
#include "collision/RManifold.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

namespace {

// The rim polygon of a cylinder's end: eight points fixed in the body (cos, sin of k 45
// degrees), counter-clockwise about the end's outward normal.
constexpr RScalar kH = RScalar(0.70710678118654752440);
constexpr RScalar kRimCos[8] = {1, kH, 0, -kH, -1, -kH, 0, kH};
constexpr RScalar kRimSin[8] = {0, kH, 1, kH, 0, -kH, -1, -kH};
constexpr int kRim = 8;

// Feature codes (bits 16-29 of a point's feature id) of the features that are not faces.
constexpr std::uint32_t kTopEnd = 0x7f, kBottomEnd = 0x7e, kSide = 0x7d, kCore = 0x7c;

// One of the pair placed in A's frame (B by X, A by the identity).
struct Placed {
  const RConvexShape& s;
  const RRelativePose* X;  // null: A itself
  RVec3 Point(const RVec3& p) const { return X ? RVec3(X->R_AB * p + X->t_AB) : p; }
  RVec3 Direction(const RVec3& d) const { return X ? RVec3(X->R_AB * d) : d; }
  RVec3 Local(const RVec3& d) const { return X ? RVec3(X->R_AB.transpose() * d) : d; }
};

// Rim point k of a cylinder's end sigma (+1: y = h), in its frame, counter-clockwise about
// sigma y.
RVec3 RimPoint(const RConvexShape& c, RScalar sigma, int k) {
  return RVec3(c.cylinderRadius * kRimCos[k], sigma * c.halfHeight, -sigma * c.cylinderRadius * kRimSin[k]);
}

// A face to clip against: a polyhedron's face or a cylinder's end, in A's frame.
struct Reference {
  bool found = false;
  bool isA = true;
  int priority = 0;  // a polyhedron's face (2) before a cylinder's end (1)
  RScalar alignment = -2;
  RVec3 normal = RVec3::UnitY();  // outward, toward the other shape
  RVec3 v[kMaxClip];
  std::uint32_t count = 0;
  std::uint32_t code = 0;
};

// The reference face that `shape` offers along its outward direction d (A's frame), if it
// is aligned with d within the face-contact angle.
void OfferReference(const Placed& shape, bool isA, const RVec3& d, Reference& ref) {
  const RConvexShape& s = shape.s;
  const RVec3 dl = shape.Local(d);
  Reference c;
  c.isA = isA;
  if (s.polyhedron) {
    const std::uint32_t f = MostAlignedFace(*s.polyhedron, nullptr, dl, c.alignment);
    const RFace& F = s.polyhedron->Faces()[f];
    c.priority = 2, c.code = f & 0x7fu;
    c.normal = shape.Direction(F.plane.normal);
    c.count = std::min<std::uint32_t>(F.vertexCount, kMaxClip);
    for (std::uint32_t i = 0; i < c.count; ++i) {
      c.v[i] = shape.Point(s.polyhedron->Vertices()[s.polyhedron->LoopVertices()[F.firstVertex + i]]);
    }
  } else if (s.cylinderRadius > 0) {
    const RScalar sigma = dl.y() >= 0 ? 1 : -1;
    c.alignment = std::abs(dl.y());
    c.priority = 1, c.code = sigma > 0 ? kTopEnd : kBottomEnd;
    c.normal = shape.Direction(RVec3(0, sigma, 0));
    c.count = kRim;
    for (int k = 0; k < kRim; ++k) c.v[k] = shape.Point(RimPoint(s, sigma, k));
  } else {
    return;
  }
  if (c.alignment < kFaceContactCos) return;
  const bool better = !ref.found || c.priority > ref.priority ||
                      (c.priority == ref.priority && c.alignment > ref.alignment + kReferenceBias);
  if (better) c.found = true, ref = c;
}

// What the incident shape puts against the reference face (outward normal refN): its points
// in A's frame, in order around a polygon when there are three or more, and how far its
// surface lies beyond them toward the face (a sphere's or capsule's radius).
struct Incident {
  ClipPoint p[kMaxClip];
  int count = 0;
  std::uint32_t code = 0;
};

void IncidentOf(const Placed& shape, const RVec3& refN, Incident& inc) {
  const RConvexShape& s = shape.s;
  const RVec3 toward = -refN;  // from the incident shape toward the reference face
  const RVec3 dl = shape.Local(toward);
  if (s.polyhedron) {
    RScalar alignment;
    const std::uint32_t f = MostAlignedFace(*s.polyhedron, nullptr, dl, alignment);
    const RFace& F = s.polyhedron->Faces()[f];
    inc.code = f & 0x7fu;
    inc.count = static_cast<int>(std::min<std::uint32_t>(F.vertexCount, kMaxClip));
    for (int i = 0; i < inc.count; ++i) {
      inc.p[i] = {shape.Point(s.polyhedron->Vertices()[s.polyhedron->LoopVertices()[F.firstVertex + i]]),
                  0x8000u | static_cast<std::uint32_t>(i)};
    }
    return;
  }
  if (s.cylinderRadius > 0) {
    const RScalar sigma = dl.y() >= 0 ? 1 : -1;
    const RVec3 deepest = CylinderSupport(s.cylinderRadius, s.halfHeight, dl);
    if (std::abs(dl.y()) > std::sqrt(dl.x() * dl.x() + dl.z() * dl.z())) {
      // The end faces the reference more than the side does (tilted by less than 45
      // degrees): its rim octagon, and where the end is tilted by more than 1e-6 of the
      // radius the exact deepest rim point between its two neighbours, so the depth is
      // exact; the points the tilt lifts beyond the margin drop out later. (Every other
      // octagon point alone when flat, a square that a wobble of rounding could not trade
      // for the other four, made an eight-cylinder stack drift 10 cm: switching between the
      // square and the tilted octagon changed all the points at once.)
      inc.code = sigma > 0 ? kTopEnd : kBottomEnd;
      RScalar octagonMost = -std::numeric_limits<RScalar>::infinity();
      for (int k = 0; k < kRim; ++k) octagonMost = std::max(octagonMost, RimPoint(s, sigma, k).dot(dl));
      const bool tilted = deepest.dot(dl) - octagonMost > RScalar(1e-6) * s.cylinderRadius;
      int after = -1;  // the deepest point's place in the order: after rim point floor(angle / 45)
      if (tilted) {
        RScalar angle = Atan2(-sigma * deepest.z(), deepest.x());
        if (angle < 0) angle += 2 * kPi;
        after = std::min(kRim - 1, static_cast<int>(angle / (kPi / 4)));
      }
      for (int k = 0; k < kRim; ++k) {
        inc.p[inc.count++] = {shape.Point(RimPoint(s, sigma, k)), 0x8000u | static_cast<std::uint32_t>(k)};
        if (k == after) inc.p[inc.count++] = {shape.Point(deepest), 0x8000u | kRim};
      }
      return;
    }
    // The side: the line along the axis through the deepest rim point (each end's feature
    // named by the end, whichever is deeper).
    inc.code = kSide;
    const RVec3 other(deepest.x(), -deepest.y(), deepest.z());
    inc.p[0] = {shape.Point(deepest), deepest.y() > 0 ? 0x8001u : 0x8000u};
    inc.p[1] = {shape.Point(other), deepest.y() > 0 ? 0x8000u : 0x8001u};
    inc.count = 2;
    return;
  }
  // A capsule's core (a sphere's centre), moved by its radius to its surface.
  inc.code = kCore;
  const RVec3 out = s.radius * toward;
  inc.p[0] = {shape.Point(RVec3(0, -s.halfHeight, 0)) + out, 0x8000u};
  inc.count = 1;
  if (s.halfHeight > 0) inc.p[inc.count++] = {shape.Point(RVec3(0, s.halfHeight, 0)) + out, 0x8001u};
}

// A segment (two points) clipped by the reference's side planes; false when nothing is left.
bool ClipSegment(const Reference& ref, RScalar tolerance, ClipPoint* p) {
  for (std::uint32_t e = 0; e < ref.count; ++e) {
    const RVec3& v0 = ref.v[e];
    const RVec3& v1 = ref.v[(e + 1) % ref.count];
    const RVec3 outward = (v1 - v0).cross(ref.normal).normalized();
    const RScalar d0 = outward.dot(p[0].p - v0) - tolerance, d1 = outward.dot(p[1].p - v0) - tolerance;
    if (d0 > 0 && d1 > 0) return false;
    if (d0 > 0) p[0] = {p[0].p + d0 / (d0 - d1) * (p[1].p - p[0].p), 2 + 2 * e};
    if (d1 > 0) p[1] = {p[1].p + d1 / (d1 - d0) * (p[0].p - p[1].p), 3 + 2 * e};
  }
  return true;
}

// Whether a point lies within the reference's side planes.
bool Inside(const Reference& ref, RScalar tolerance, const RVec3& p) {
  for (std::uint32_t e = 0; e < ref.count; ++e) {
    const RVec3& v0 = ref.v[e];
    const RVec3 outward = (ref.v[(e + 1) % ref.count] - v0).cross(ref.normal).normalized();
    if (outward.dot(p - v0) > tolerance) return false;
  }
  return true;
}

// The surface line a cylinder's side or a capsule offers along its outward direction d (A's
// frame), when its axis lies across d; false otherwise.
bool SideLine(const Placed& shape, const RVec3& d, RVec3& p0, RVec3& p1) {
  const RConvexShape& s = shape.s;
  if (s.polyhedron || !(s.halfHeight > 0)) return false;
  const RVec3 dl = shape.Local(d);
  if (std::abs(dl.y()) > std::sqrt(1 - kFaceContactCos * kFaceContactCos)) return false;
  RVec3 out = s.radius * dl;  // a capsule: its core pushed out by its radius
  if (s.cylinderRadius > 0) {
    const RVec3 rim = CylinderSupport(s.cylinderRadius, s.halfHeight, dl);
    out = RVec3(rim.x(), 0, rim.z());
  }
  p0 = shape.Point(RVec3(0, -s.halfHeight, 0) + out);
  p1 = shape.Point(RVec3(0, s.halfHeight, 0) + out);
  return true;
}

// Two sides along each other (logs side by side): B's line clipped to the stretch of A's
// that faces it, each end with its own separation along n. False when they only cross or
// meet end to end.
bool SideAlongSide(const Placed& A, const Placed& B, const RVec3& n, RScalar margin,
                   RContactManifold& m, RScalar* droppedMin) {
  RVec3 a0, a1, b0, b1;
  if (!SideLine(A, n, a0, a1) || !SideLine(B, -n, b0, b1)) return false;
  if (std::abs(B.Direction(RVec3::UnitY()).y()) < kFaceContactCos) return false;
  // A's axis is A's y: clip B's line to A's stretch of y.
  const RScalar lo = std::max(a0.y(), std::min(b0.y(), b1.y()));
  const RScalar hi = std::min(a1.y(), std::max(b0.y(), b1.y()));
  const RScalar size = A.s.boundingRadius + B.s.boundingRadius;
  if (!(hi - lo > RScalar(1e-4) * size)) return false;
  const RScalar ys[2] = {lo, hi};
  for (int k = 0; k < 2; ++k) {
    const RScalar t = (ys[k] - b0.y()) / (b1.y() - b0.y());
    const RVec3 pb = b0 + t * (b1 - b0);
    // Measured from A's line at pb's height (n may lean along A's axis by the face-contact
    // angle, and a plane through a0 would count that lean over the height between them).
    const RScalar sep = n.dot(pb - a0) - n.y() * (pb.y() - a0.y());
    KeepWithin(margin, droppedMin, m, pb - RScalar(0.5) * sep * n, sep, 0x10000000u | static_cast<std::uint32_t>(k));
  }
  if (m.pointCount == 0) return false;
  m.normal = n;
  return true;
}

}  // namespace

void CylinderManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X,
                      RScalar margin, RContactManifold& m, RScalar* droppedMin) {
  const RDistanceResult& q = m.query;
  const RVec3 n = q.normal;
  const Placed A{a, nullptr}, B{b, &X};
  auto single = [&]() {
    m.pointCount = 1;
    m.points[0].position = RScalar(0.5) * (q.witnessA + q.witnessB);
    m.points[0].separation = q.separation;
    m.points[0].featureId = 0;
    m.normal = n;
  };
  Reference ref;
  OfferReference(A, true, n, ref);
  OfferReference(B, false, -n, ref);
  if (!ref.found) {
    if (!SideAlongSide(A, B, n, margin, m, droppedMin)) single();
    return;
  }
  Incident inc;
  IncidentOf(ref.isA ? B : A, ref.normal, inc);
  RScalar faceSize = 0;
  for (std::uint32_t e = 0; e < ref.count; ++e) faceSize = std::max(faceSize, (ref.v[e] - ref.v[0]).norm());
  const RScalar tolerance = kClipTolerance * faceSize;
  ClipPoint scratch[kMaxClip];
  ClipPoint* clipped = inc.p;
  int count = inc.count;
  if (count >= 3) {
    count = ClipBySides([&](std::uint32_t e) { return ref.v[e]; }, ref.count, ref.normal, tolerance, inc.p,
                        count, scratch, &clipped);
  } else if (count == 2) {
    if (!ClipSegment(ref, tolerance, inc.p)) count = 0;
  } else if (!Inside(ref, tolerance, inc.p[0].p)) {
    count = 0;
  }
  const std::uint32_t faceBits = (ref.isA ? 0x40000000u : 0u) | (ref.code << 23) | (inc.code << 16);
  RContactPoint pts[kMaxClip];
  int np = 0;
  for (int i = 0; i < count; ++i) {
    const RScalar s = ref.normal.dot(clipped[i].p - ref.v[0]);
    if (s > margin) {
      if (droppedMin) *droppedMin = std::min(*droppedMin, s);
      continue;
    }
    RContactPoint& c = pts[np++];
    c.position = clipped[i].p - RScalar(0.5) * s * ref.normal;
    c.separation = s;
    c.featureId = faceBits | (clipped[i].feature & 0xffffu);
  }
  if (np == 0) {
    single();
    return;
  }
  // A cylinder's end as the reference clips to its inscribed octagon, and an end as the
  // incident polygon is its octagon's chords where a face's edge cuts it: the deepest point
  // can fall between octagon and rim. Then the query's witnesses give it, at its depth.
  RScalar deepest = std::numeric_limits<RScalar>::infinity();
  for (int i = 0; i < np; ++i) deepest = std::min(deepest, pts[i].separation);
  if (deepest > q.separation + RScalar(1e-6) * (a.boundingRadius + b.boundingRadius) && np < kMaxClip) {
    RContactPoint& c = pts[np++];
    c.position = RScalar(0.5) * (q.witnessA + q.witnessB);
    c.separation = q.separation;
    c.featureId = faceBits | 0x7fffu;
  }
  m.pointCount = ReduceToFour(pts, np, ref.normal);
  for (int i = 0; i < m.pointCount; ++i) m.points[i] = pts[i];
  m.normal = ref.isA ? ref.normal : RVec3(-ref.normal);
}

}  // namespace REngine
