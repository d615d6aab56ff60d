// The distance and depth of pairs with a cylinder (RCylinder.h); their manifold is in
// RCylinderManifold.cpp.
#include "collision/RCylinder.h"

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
    r.separation = coreSeparation - rounding;
    r.normal = n;
    r.witnessA = onA + a.radius * n;
    r.witnessB = onB - b.radius * n;
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
        return fromCores(bound, ep.upperNormal, ep.upperA, ep.upperB + s * guess);
      }
    }
    // Its points are real points of the shapes, the distance between them within
    // distance - lowerBound of the true one.
    return fromCores(g.distance, guess, g.witnessA, g.witnessB);
  }
  LeastOverlap(sup, e, r);
  return fromCores(r.separation, r.normal, r.witnessA, r.witnessB);
}

}  // namespace REngine
