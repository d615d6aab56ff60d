// Private to REnginePhysics: what every kind of pair builds its contact manifold with
// (defined in RCollisionSolver.cpp): the reference face, clipping by its sides, and the
// four points kept.
#pragma once

#include <REnginePhysics/RCollision.h>

#include <cstdint>

namespace REngine {

// The reference face is A's unless B's is clearly better aligned: the bias keeps the
// choice, hence the feature ids, from flickering between equally good faces.
constexpr RScalar kReferenceBias = RScalar(1e-3);
// Clipping tolerance, relative to the reference face's size.
constexpr RScalar kClipTolerance = RScalar(1e-4);

// A polygon being clipped: points in A's frame with the feature each came from.
struct ClipPoint {
  RVec3 p;
  std::uint32_t feature;
};
constexpr int kMaxClip = 64;

// The face of `p` whose normal (mapped by R) is most aligned with d; returns the alignment.
std::uint32_t MostAlignedFace(const RConvexPolyhedron& p, const RMat3* R, const RVec3& d,
                              RScalar& alignment);

// Sutherland-Hodgman: clips the polygon in[0, nIn) by the side planes of the convex polygon
// whose vertex e (of nRef, counter-clockwise about refN) is vertex(e), each plane pushed out
// by `tolerance` (m). `in` and `out` are both scratch of kMaxClip points; *result points at
// the one holding the answer, and the count is returned.
template <class Vertex>
int ClipBySides(const Vertex& vertex, std::uint32_t nRef, const RVec3& refN, RScalar tolerance,
                ClipPoint* in, int nIn, ClipPoint* out, ClipPoint** result) {
  for (std::uint32_t e = 0; e < nRef && nIn > 0; ++e) {
    const RVec3 v0 = vertex(e), v1 = vertex((e + 1) % nRef);
    const RVec3 outward = (v1 - v0).cross(refN).normalized();  // CCW about refN: points out
    int nOut = 0;
    for (int i = 0; i < nIn; ++i) {
      const ClipPoint& p = in[i];
      const ClipPoint& q = in[(i + 1) % nIn];
      const RScalar dp = outward.dot(p.p - v0) - tolerance;
      const RScalar dq = outward.dot(q.p - v0) - tolerance;
      if (dp <= 0 && nOut < kMaxClip) out[nOut++] = p;
      if ((dp < 0) != (dq < 0) && dp != dq && nOut < kMaxClip) {
        const RScalar t = dp / (dp - dq);
        // A new point's feature: the segment's two ends' features and the clipping edge,
        // mixed into 15 bits; stable while the same features are involved.
        const std::uint32_t mix = (p.feature * 0x9e3779b1u) ^ (q.feature * 0x85ebca6bu) ^ e;
        out[nOut++] = {p.p + t * (q.p - p.p), (mix >> 17) & 0x7fffu};
      }
    }
    ClipPoint* swap = in;
    in = out, out = swap;
    nIn = nOut;
  }
  *result = in;
  return nIn;
}

// Adds a point to m (at its next free place) unless its separation lies beyond the margin:
// then it is dropped, and the least separation dropped kept in *droppedMin.
inline void KeepWithin(RScalar margin, RScalar* droppedMin, RContactManifold& m, const RVec3& position,
                       RScalar separation, std::uint32_t featureId) {
  if (separation > margin) {
    if (droppedMin && separation < *droppedMin) *droppedMin = separation;
    return;
  }
  RContactPoint& c = m.points[m.pointCount++];
  c.position = position;
  c.separation = separation;
  c.featureId = featureId;
}

// Keeps at most 4 of n points: the deepest, the farthest from it, then the two that add
// the most area (so the manifold spans the contact patch). Returns the count kept.
int ReduceToFour(RContactPoint* pts, int n, const RVec3& normal);

}  // namespace REngine
