// Private to REnginePhysics: GJK and EPA on a pair of convex shapes in A's frame.
#pragma once

#include <REnginePhysics/RCollision.h>

#include <cmath>
#include <limits>

namespace REngine {

// Support mapping of the pair in A's frame, with the last support vertex of each shape kept
// as the next hill-climbing start (consecutive GJK/EPA directions are close).
struct RPairSupport {
  const RConvexShape& a;
  const RConvexShape& b;
  const RRelativePose& X;
  RPairSupport(const RConvexShape& a_, const RConvexShape& b_, const RRelativePose& X_)
      : a(a_), b(b_), X(X_) {}
  // Support point of A (its core: a sphere's centre, a capsule's segment end) in direction d
  // (A's frame).
  RVec3 SupportA(const RVec3& d);
  // Support point of B in direction d, given and returned in A's frame.
  RVec3 SupportB(const RVec3& d_A);

 private:
  std::uint32_t m_lastA = 0, m_lastB = 0;
};

// A face contact when the normal is within ~1.1 degrees of a face normal of either shape
// (and two capsules lie along each other within that); otherwise two edges (or an edge and
// a vertex) touch and one point describes the contact.
constexpr RScalar kFaceContactCos = RScalar(0.9998);

// The touching band of a pair, m, and the status of a separation against it.
inline RScalar Band(const RConvexShape& a, const RConvexShape& b) {
  return RCollisionSolver::kTouchingTolerance * (a.boundingRadius + b.boundingRadius);
}
inline RCollisionStatus StatusOf(RScalar separation, RScalar band) {
  if (separation > band) return RCollisionStatus::kSeparated;
  if (separation < -band) return RCollisionStatus::kPenetrating;
  return RCollisionStatus::kTouching;
}

// v's direction, or the fallback when v is zero.
inline RVec3 SafeDirection(const RVec3& v, const RVec3& fallback) {
  const RScalar n = v.norm();
  return n > 0 ? RVec3(v / n) : fallback;
}

// The support point of a cylinder (radius r about y, ends at y = +-h) in direction d, both in
// its frame: the rim point farthest along d's part across the axis, on the end d points to
// (the end's centre when d is along the axis: any point of the end is a support point).
inline RVec3 CylinderSupport(RScalar r, RScalar h, const RVec3& d) {
  const RScalar y = d.y() >= 0 ? h : -h;
  const RScalar across = std::sqrt(d.x() * d.x() + d.z() * d.z());
  if (!(across > 0)) return RVec3(0, y, 0);
  return RVec3(r * (d.x() / across), y, r * (d.z() / across));
}

// The pose of A in B's frame, from B's in A's.
inline RRelativePose Inverse(const RRelativePose& X) {
  RRelativePose inv;
  inv.R_AB = X.R_AB.transpose();
  inv.t_AB = -(inv.R_AB * X.t_AB);
  return inv;
}

struct RSimplexPoint {
  RVec3 w, a, b;  // w = a - b: a point of the Minkowski difference and its two origins
};

struct RGjkResult {
  bool overlap = false;    // the origin is inside D (or within rounding of it)
  bool converged = false;  // false: the iteration cap was hit
  RScalar distance = 0;    // |v| when apart: an upper bound on the distance
  // The largest v.w / |v| seen: the support plane of D normal to v, a lower bound on the
  // distance. The answer is certain to within distance - lowerBound.
  RScalar lowerBound = -std::numeric_limits<RScalar>::infinity();
  RVec3 lowerNormal = RVec3::UnitX();  // the direction (A to B) of that support plane
  RVec3 closest = RVec3::Zero();  // v = witnessA - witnessB
  RVec3 witnessA = RVec3::Zero(), witnessB = RVec3::Zero();
  int iterations = 0;
  bool beyond = false;  // stopped early: lowerBound is above the band or stopAbove
  int simplexSize = 0;
  RSimplexPoint simplex[4];
};

// GJK on the cores of the two shapes (spheres are points here). booleanOnly: stop at the
// first direction that separates them by more than the touching band; stopAbove (m): stop at
// the first that separates them by more than that. Either way distance is then only an
// upper bound, lowerBound above the band or stopAbove (and `beyond` is set). start: the
// first direction (A to B) to try, instead of the line between the centres.
RGjkResult Gjk(RPairSupport& support, bool booleanOnly,
               RScalar stopAbove = std::numeric_limits<RScalar>::infinity(), const RVec3* start = nullptr);

// GJK's answer on a triangle of D, its direction recomputed from the triangle's plane. When
// the distance is small against the triangle (a box resting a micrometre above a dense hull's
// facets), the barycentric point v has an error of rounding times the triangle's size, so
// its direction is off by that over |v| and the support along it falls short of |v| by far
// more than rounding: the certificate fails though the triangle lies on a face of D. The
// plane's normal, a cross product of the edges, is exact to rounding whatever the distance.
// Returns g with that plane's distance, normal, witnesses and support bound when the
// origin projects inside the triangle; otherwise g unchanged.
RGjkResult RefineOnTrianglePlane(RPairSupport& support, const RGjkResult& g);

// Whether GJK's answer for separated cores is certain: its upper and lower bounds meet to a
// part in 1e9 of the distance (above rounding: 1e-14 of the pair's size). Relative, not
// the band: a pair 3 bands apart whose bounds differ by a band has its normal only to 45
// degrees (seen on a clang build, where GJK stopped one vertex earlier than on gcc's).
// GJK's "overlap" (a tetrahedron enclosing the origin, or |v| vanishing) is believed only
// where no support plane has separated the shapes by more than the band: a tetrahedron flat
// to rounding (from a needle of a hull) can pass its sign tests with the shapes 6.7 mm
// apart (found by fuzz_narrowphase).
inline bool CertainOverlap(const RGjkResult& g, RScalar band) { return g.overlap && g.lowerBound <= band; }

inline bool Certified(const RGjkResult& g, RScalar band) {
  return g.converged && !g.overlap &&
         g.distance - g.lowerBound <=
             RCollisionSolver::kTouchingTolerance * g.distance + RScalar(1e-5) * band;
}

struct REpaResult {
  // false: no verdict (the polytope could not be started or grown, or the iteration cap):
  // the caller answers another way.
  bool converged = false;
  RScalar depth = 0;               // m, >= 0
  RVec3 normal = RVec3::UnitX();   // from A to B
  RVec3 witnessA = RVec3::Zero();  // deepest points of A inside B and of B inside A
  RVec3 witnessB = RVec3::Zero();
  int iterations = 0;
  // The least overlap found along any normal EPA tried (the support of D there): moving B
  // by it along upperNormal separates the shapes, so it bounds the depth from above; with
  // its support points. Kept whether or not EPA converged (infinite when it never started).
  RScalar upperDepth = std::numeric_limits<RScalar>::infinity();
  RVec3 upperNormal = RVec3::UnitX();
  RVec3 upperA = RVec3::Zero(), upperB = RVec3::Zero();
};

// EPA stops when the support in the nearest face's normal is within this fraction of the
// face's distance (plus a floor relative to the pair's size, for depths near zero): the
// depth is then the minimum to that relative accuracy. For polyhedra it ends earlier, when
// the nearest face is a face of D and no support point lies beyond it.
constexpr RScalar kEpaRelativeGap = 1e-10;

// EPA from GJK's final simplex (which encloses the origin), to relativeGap.
REpaResult EpaPenetration(RPairSupport& support, const RGjkResult& gjk,
                          RScalar relativeGap = kEpaRelativeGap);

}  // namespace REngine
