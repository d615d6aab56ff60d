// The distance and depth of pairs with a cylinder (RCylinder.h); their manifold is in
// RCylinderManifold.cpp.
#include "collision/RCylinder.h"
#include <REngineMath/RFunctions.h>

#include "collision/RGjkEpa.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

namespace {

// EPA's relative gap on a curved surface: each support point lies on the surface, and near
// the answer the polytope's faces shrink until their normals carry rounding of the order of
// 1e-16 of the pair's size over the faces' size; 1e-10 is below what such faces resolve.
constexpr RScalar kCurvedEpaGap = RScalar(1e-9);

// How far B must move along n (A's frame) to clear A: the support of A - B along n, with
// the two support points.
RScalar Overlap(RPairSupport& sup, const RVec3& n, RVec3& onA, RVec3& onB) {
  onA = sup.SupportA(n);
  onB = sup.SupportB(-n);
  return n.dot(onA - onB);
}

// Overlapping shapes where EPA gave no verdict: the least overlap over the directions a
// contact between these shapes can have as its normal (the polyhedra's face normals, the
// cylinders' axes) and those EPA and the centres suggest. Every overlap along a direction
// is at least the depth, so this is a depth and normal that separate the shapes, exact
// where the contact is a face or an end (a cylinder standing on a box).
void LeastOverlap(RPairSupport& sup, const REpaResult& epa, RDistanceResult& r) {
  RScalar best = std::numeric_limits<RScalar>::infinity();
  auto consider = [&](const RVec3& n) {
    RVec3 onA, onB;
    const RScalar depth = Overlap(sup, n, onA, onB);
    if (depth < best) best = depth, r.normal = n, r.witnessA = onA, r.witnessB = onB;
  };
  auto both = [&](const RVec3& n) { consider(n), consider(-n); };
  const RRelativePose& X = sup.X;
  if (epa.upperDepth < best) {
    best = epa.upperDepth, r.normal = epa.upperNormal, r.witnessA = epa.upperA, r.witnessB = epa.upperB;
  }
  if (X.t_AB.squaredNorm() > 0) consider(X.t_AB.normalized());
  for (int k = 0; k < 3; ++k) both(RVec3::Unit(k));
  if (sup.a.cylinderRadius > 0) both(RVec3::UnitY());
  if (sup.b.cylinderRadius > 0) both(X.R_AB.col(1));
  if (sup.a.polyhedron) {
    for (const RFace& f : sup.a.polyhedron->Faces()) consider(f.plane.normal);
  }
  if (sup.b.polyhedron) {
    for (const RFace& f : sup.b.polyhedron->Faces()) consider(-(X.R_AB * f.plane.normal));
  }
  r.separation = -best;  // (negative best: a direction that sets them apart)
}

// Whether p (the shape's frame) lies in the shape's core (a polyhedron, a cylinder, a
// sphere's centre, a capsule's segment) within `tolerance` (m).
bool InCore(const RConvexShape& s, const RVec3& p, RScalar tolerance) {
  if (s.polyhedron) {
    for (const RFace& f : s.polyhedron->Faces()) {
      if (f.plane.SignedDistance(p) > tolerance) return false;
    }
    return true;
  }
  if (s.cylinderRadius > 0) {
    return Hypot(p.x(), p.z()) <= s.cylinderRadius + tolerance && std::abs(p.y()) <= s.halfHeight + tolerance;
  }
  return (p - RVec3(0, std::clamp(p.y(), -s.halfHeight, s.halfHeight), 0)).norm() <= tolerance;
}

// The witnesses of an answer read off a supporting plane (separation s along n, A to B, A's
// frame) from the two support points along it: each is its shape's farthest point along the
// normal, not the point nearest the other shape (a triangle's support along a normal a hair
// off its own is a corner, metres from where it meets a cylinder lying on it). A pair s n
// apart instead, one a support point and the other in the other shape (the normal's
// rounding allowed for: 1e-6 of the pair's size); when neither support gives one, the
// supports as they are.
void PairWitnesses(RPairSupport& sup, RScalar s, const RVec3& n, RVec3& onA, RVec3& onB) {
  const RScalar tolerance = RScalar(1e-6) * (sup.a.boundingRadius + sup.b.boundingRadius);
  const RVec3 fromB = onB - s * n;
  if (InCore(sup.a, fromB, tolerance)) {
    onA = fromB;
    return;
  }
  const RVec3 fromA = onA + s * n;
  const RRelativePose X_BA = Inverse(sup.X);
  if (InCore(sup.b, X_BA.R_AB * fromA + X_BA.t_AB, tolerance)) onB = fromA;
}

// A touching pair's answer (core separation within the band) checked against the
// directions a contact of these shapes can have as its normal (a polyhedron's face normals,
// a cylinder's axis): the separation along any direction is at most the distance. Touching,
// the closest vector is a rounding error long and its direction noise (a cylinder lying on
// a box's face: 3e-14 m, 6 degrees off the face's normal, which then gives no face contact):
// the direction with the largest separation, when that is within the band of the answer,
// is the normal. And a flat polytope can pass for touching where it is not (a cylinder
// standing on a box's plane 1.7 cm beside the box: EPA finds a face 7e-13 m from the
// origin): a direction that separates them by more than the band sets them apart, and GJK
// started from it finds their distance and closest points; where it cannot certify them,
// that direction's separation is the answer (a lower bound of the distance, exact for a
// face against a face, an end or a side) with witnesses from GJK's nearest points (a curved
// rim keeps it from certifying them) or else its support points paired (PairWitnesses).
void SettleTouching(RPairSupport& sup, RScalar band, RScalar stopAbove, RScalar& separation, RVec3& normal, RVec3& onA,
                    RVec3& onB) {
  RScalar best = -std::numeric_limits<RScalar>::infinity();
  RVec3 bestNormal = normal, bestA = onA, bestB = onB;
  auto consider = [&](const RVec3& n) {
    RVec3 a, b;
    const RScalar along = -Overlap(sup, n, a, b);
    if (along > best) best = along, bestNormal = n, bestA = a, bestB = b;
  };
  if (sup.a.cylinderRadius > 0) consider(RVec3::UnitY()), consider(-RVec3::UnitY());
  if (sup.b.cylinderRadius > 0) consider(sup.X.R_AB.col(1)), consider(-sup.X.R_AB.col(1));
  if (sup.a.polyhedron) {
    for (const RFace& f : sup.a.polyhedron->Faces()) consider(f.plane.normal);
  }
  if (sup.b.polyhedron) {
    for (const RFace& f : sup.b.polyhedron->Faces()) consider(-(sup.X.R_AB * f.plane.normal));
  }
  if (best > separation + band) {
    const RVec3 start = -bestNormal;  // GJK's v runs from B to A
    const RGjkResult g = Gjk(sup, false, stopAbove, &start);
    if (!g.beyond && Certified(g, band) && g.distance > band) {
      separation = g.distance, normal = SafeDirection(-g.closest, bestNormal), onA = g.witnessA, onB = g.witnessB;
      return;
    }
    separation = best, normal = bestNormal, onA = bestA, onB = bestB;
    if (!g.beyond && g.distance > 0) {
      // The points GJK got nearest to (a curved rim stalls it), made separation apart
      // along the normal: the flat side's kept (a polyhedron's face holds it).
      if (sup.a.polyhedron) {
        onA = g.witnessA, onB = onA + separation * normal;
      } else if (sup.b.polyhedron) {
        onB = g.witnessB, onA = onB - separation * normal;
      } else {
        const RVec3 mid = RScalar(0.5) * (g.witnessA + g.witnessB);
        onA = mid - RScalar(0.5) * separation * normal, onB = mid + RScalar(0.5) * separation * normal;
      }
    } else {
      PairWitnesses(sup, separation, normal, onA, onB);
    }
  } else if (best >= separation - band) {
    normal = bestNormal;
  }
}

}  // namespace

RDistanceResult CylinderPair(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X,
                             RScalar cutoff) {
  RDistanceResult r;
  RPairSupport sup(a, b, X);
  const RScalar band = Band(a, b);
  // Spheres and capsules take part as their cores: their radii come off the cores' answer.
  const RScalar rounding = a.radius + b.radius;
  const RVec3 centres = SafeDirection(X.t_AB, RVec3::UnitX());
  auto fromCores = [&](RScalar coreSeparation, const RVec3& n, const RVec3& onA, const RVec3& onB) {
    RVec3 normal = n, coreA = onA, coreB = onB;
    if (std::abs(coreSeparation) <= band) {
      SettleTouching(sup, band, cutoff + rounding, coreSeparation, normal, coreA, coreB);
    }
    r.separation = coreSeparation - rounding;
    r.normal = normal;
    r.witnessA = coreA + a.radius * normal;
    r.witnessB = coreB - b.radius * normal;
    r.status = StatusOf(r.separation, band);
    return r;
  };
  RGjkResult g = Gjk(sup, false, cutoff + rounding);
  if (g.overlap && !CertainOverlap(g, band)) {
    // A tetrahedron flat to rounding passed for an enclosure of the origin while a support
    // plane had already set the shapes apart: start again from that plane's direction.
    const RVec3 start = g.lowerNormal;
    const int spent = g.iterations;
    g = Gjk(sup, false, cutoff + rounding, &start);
    g.iterations += spent;
  }
  r.gjkIterations = g.iterations;
  if (g.beyond) {
    r.separation = g.lowerBound - rounding;
    r.normal = SafeDirection(-g.closest, centres);
    r.status = RCollisionStatus::kSeparated;
    return r;
  }
  const RGjkResult refined = Certified(g, band) ? g : RefineOnTrianglePlane(sup, g);
  if (Certified(refined, band)) {
    return fromCores(refined.distance, SafeDirection(-refined.closest, centres), refined.witnessA,
                     refined.witnessB);
  }
  REpaResult e;
  if (CertainOverlap(g, band)) {
    e = EpaPenetration(sup, g, kCurvedEpaGap);
    r.epaIterations = e.iterations;
    if (e.converged) return fromCores(-e.depth, e.normal, e.witnessA, e.witnessB);
  }
  if (!g.overlap && g.distance > 0) {
    // Apart or touching, but GJK's bounds have not met: two curved surfaces touching at a
    // point, where each support point gains less than the last (GJK stalls about 1e-7 of
    // the size away). Push B into A along GJK's normal by a little more than its bracket,
    // so the pair overlaps, and let EPA find that overlap's depth d and normal n: moving B
    // back by s, the separation is s (n . normal) - d, to second order in their angle
    // (exact when the contact's normal does not turn over s).
    const RVec3 guess = SafeDirection(-g.closest, centres);
    const RScalar s = 2 * (g.distance - std::max(RScalar(0), g.lowerBound)) + g.distance + band;
    RRelativePose pushed = X;
    pushed.t_AB -= s * guess;
    RPairSupport supPushed(a, b, pushed);
    const RGjkResult gp = Gjk(supPushed, false);
    if (CertainOverlap(gp, band)) {
      const REpaResult ep = EpaPenetration(supPushed, gp, kCurvedEpaGap);
      r.epaIterations = ep.iterations;
      if (ep.converged) {
        return fromCores(s * guess.dot(ep.normal) - ep.depth, ep.normal, ep.witnessA, ep.witnessB + s * guess);
      }
      // Out of iterations on a doubly curved patch: the least overlap it met, a depth
      // along its normal that is at least the true one, when that beats GJK's bound.
      const RScalar bound = s * guess.dot(ep.upperNormal) - ep.upperDepth;
      if (ep.upperDepth < std::numeric_limits<RScalar>::infinity() && bound < g.distance) {
        RVec3 onA = ep.upperA, onB = ep.upperB + s * guess;
        PairWitnesses(sup, bound, ep.upperNormal, onA, onB);
        return fromCores(bound, ep.upperNormal, onA, onB);
      }
    }
    // Its points are real points of the shapes, the distance between them within
    // distance - lowerBound of the true one.
    return fromCores(g.distance, guess, g.witnessA, g.witnessB);
  }
  LeastOverlap(sup, e, r);
  PairWitnesses(sup, r.separation, r.normal, r.witnessA, r.witnessB);
  return fromCores(r.separation, r.normal, r.witnessA, r.witnessB);
}

}  // namespace REngine
