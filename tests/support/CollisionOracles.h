// Independent collision oracles for the narrow-phase tests and benchmarks: libccd 2.1
// (boolean GJK, GJK+EPA, MPR) and FCL 0.7 (collide with contacts, distance with nearest
// points), wrapped over convex hulls given as vertex lists in their own frames plus world
// poses. Nothing here shares code with REngine's GJK/EPA; the hull itself (vertices and the
// polygon faces FCL needs) comes from RConvexPolyhedron::Hull, so every oracle sees exactly
// the polytope the engine sees.
//
// Conventions, translated to REngine's (normal from A to B; translating B by +depth * normal
// separates penetrating shapes; see RCollision.h):
//  * libccd ccdGJKPenetration / ccdMPRPenetration: "if obj2 is translated by depth in
//    direction dir, the objects touch": dir is already REngine's A->B normal. `pos` is a
//    point between the shapes (EPA: mean of the polytope's nearest half; MPR: portal
//    centre), not a witness on either surface.
//  * libccd's epa_tolerance is not a length: EPA stops when (support - |w|) * |w| or the new
//    point's squared distance to the nearest triangle is below it (units m^2), so it is set
//    relative to scale^2. mpr_tolerance is a length. Both are scaled by the pair's size so the
//    oracles behave the same on a 1 cm pair and on a 100 m pair. libccd also compares
//    against absolute epsilons (DBL_EPSILON on squared lengths) that no setting scales.
//  * libccd's MPR depth is the distance to the portal that the ray from the interior point
//    towards the origin leaves through, not the minimum translation: a verdict oracle only.
//  * FCL collide: Contact::normal points from o1 to o2 (REngine's convention with o1 = A).
//    With GST_LIBCCD, FCL 0.7 runs libccd's MPR for convex pairs (so the depth is MPR's, not
//    the minimum); with GST_INDEP it runs its own GJK + EPA, and then (FCL 0.7 quirks,
//    corrected here) reports penetration_depth negated and the normal in o1's frame.
//  * FCL distance: min_distance >= 0 for separated shapes (-1 or <= 0 when they overlap,
//    unless signed distance is requested); nearest_points[0] on o1, [1] on o2, world frame.
//    The normal is (p1 - p0) / |p1 - p0|.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RConvexPolyhedron.h>
#include <ccd/ccd.h>

#include <algorithm>
#include <memory>
#include <vector>

namespace fcl {
template <typename S>
class Convex;
}

namespace REngine::test {

// Pose of a shape frame S in the world: p_W = q_WS * p_S + position_W.
struct OraclePose {
  RVec3 position_W = RVec3::Zero();
  RQuat q_WS = RQuat::Identity();  // unit: every oracle uses q_WS.toRotationMatrix() as is
  RVec3 ToWorld(const RVec3& p_S) const { return q_WS * p_S + position_W; }
};

// A convex hull, built once, in the forms the oracles want: the RConvexPolyhedron (local
// vertices, faces, edges) and FCL's Convex (its polygon face list [n, i0 .. in-1, n, ...]).
class OracleHull {
 public:
  explicit OracleHull(const std::vector<RVec3>& points_S);
  explicit OracleHull(RConvexPolyhedron polyhedron);

  const RConvexPolyhedron& Polyhedron() const { return m_polyhedron; }
  const fcl::Convex<double>& FclConvex() const { return *m_fcl; }
  // Largest vertex distance from the frame origin, m.
  RScalar Radius() const { return m_polyhedron.MaxRadius(); }

 private:
  RConvexPolyhedron m_polyhedron;
  std::shared_ptr<const fcl::Convex<double>> m_fcl;
};

// How far the hull, turned by q (q_WS), reaches along the world direction d: max over its
// vertices of d . (q v), m from the frame origin (to place a pair at a chosen gap).
inline RScalar SupportExtent(const OracleHull& h, const RQuat& q, const RVec3& d) {
  const RVec3 d_S = q.conjugate() * d;
  RScalar m = -1e300;
  for (const RVec3& v : h.Polyhedron().Vertices()) m = std::max(m, v.dot(d_S));
  return m;
}

// libccd's view of a posed hull: world-space vertices (so libccd's support is a plain loop
// over them, the cheapest support it could have) and an interior point for MPR.
struct CcdPosedHull {
  std::vector<RVec3> vertices_W;
  RVec3 center_W = RVec3::Zero();  // vertex mean: interior, as MPR requires
};
CcdPosedHull PoseForCcd(const OracleHull& hull, const OraclePose& X_WS);

// libccd configuration for a pair whose size (sum of the two bounding radii) is `scale`, m:
// GJK/MPR iteration cap 1000 (GJK on polytopes terminates in far fewer; the cap only
// guarantees termination), mpr_tolerance 1e-12 * scale, epa_tolerance 1e-14 * scale^2 (its
// m^2 units, see above). Tighter EPA tolerances buy no accuracy on the random suite (the
// median depth error is ~1e-15 relative either way) and make libccd's EPA loop: at
// 1e-18 * scale^2 it spent the support budget on 2 pairs in 300.
ccd_t MakeCcdConfig(RScalar scale);

// Result of a penetration oracle, in REngine's convention, world frame.
struct OraclePenetration {
  bool ok = true;                   // false: the oracle failed (libccd memory error, FCL exception)
  bool overlap = false;             // the oracle's verdict
  RScalar depth = 0;                // m, >= 0 when overlap
  RVec3 normal_W = RVec3::UnitX();  // unit, from A to B, when overlap
  RVec3 point_W = RVec3::Zero();    // the oracle's contact position (see the conventions)
};

// Every libccd call runs under a budget of 2000 support calls (libccd's EPA has no
// iteration cap and can loop at tight tolerances); spending it reports the oracle failed:
// -1 here, ok = false below.
// 1: intersect, 0: apart, -1: failed.
// Support calls each libccd query may make before it is stopped and reported as failed
// (its EPA has no iteration cap); <= 0 restores the default (2000). For tests of the guard.
void SetCcdSupportBudget(long budget);
int CcdGJKIntersect(const CcdPosedHull& a, const CcdPosedHull& b, const ccd_t& config);
OraclePenetration CcdGJKPenetration(const CcdPosedHull& a, const CcdPosedHull& b,
                                    const ccd_t& config);
OraclePenetration CcdMPRPenetration(const CcdPosedHull& a, const CcdPosedHull& b,
                                    const ccd_t& config);

enum class FclSolver { kLibccd, kIndep };  // fcl::GST_LIBCCD, fcl::GST_INDEP

// fcl::collide with enable_contact (one contact). `tolerance` is the request's gjk_tolerance
// (GST_INDEP also uses it as its EPA tolerance, a length); pass ~1e-12 * scale.
OraclePenetration FclCollide(const OracleHull& a, const OraclePose& X_WA, const OracleHull& b,
                             const OraclePose& X_WB, FclSolver solver, RScalar tolerance);

struct OracleDistance {
  bool ok = true;
  RScalar distance = 0;            // m; meaningful for separated shapes only
  RVec3 pointA_W = RVec3::Zero();  // nearest point on A, world
  RVec3 pointB_W = RVec3::Zero();  // nearest point on B, world
};
// fcl::distance with nearest points. `tolerance` is the request's distance_tolerance: the
// GJK stopping threshold on the change of distance between iterations, a length.
OracleDistance FclDistance(const OracleHull& a, const OraclePose& X_WA, const OracleHull& b,
                           const OraclePose& X_WB, FclSolver solver, RScalar tolerance);

// ---- Exact references by enumeration: slow, iteration-free, independent of GJK/EPA. ----
// Both polyhedra must be given in one common frame (RConvexPolyhedron::Transformed).

// The separating axis test over every candidate axis of the Minkowski difference
// D = A - B: the face normals of A, the negated face normals of B, and the cross products
// of edge pairs. The signed separation along an axis n (from A to B) is
// min_b n.b - max_a n.a; its maximum over all unit n is exactly the signed distance when
// the shapes overlap (minus the minimum penetration depth: the distance from the origin to
// the nearest facet of D, and every facet normal of D is a candidate), and a lower bound on
// the distance when they are apart (it is the distance when the closest features are
// face-vertex or edge-edge). Edge pairs: with `pruneEdges`, only those whose Gauss-map arcs
// cross (the pairs that form a facet of D, Gregorius 2013), evaluated at their edges in
// O(1); without it, every pair in both orientations with full support loops, O(E^2 V),
// which the tests use to validate the pruning.
struct SatResult {
  RScalar separation = 0;       // m: max over candidates (see above)
  RVec3 axis = RVec3::UnitX();  // unit, from A to B, attaining it
  // Every candidate axis within `tieTolerance` (m) of the maximum, one per direction (axes
  // closer than `tieAngle` rad merged): the axes a correct answer may pick. `unique` when
  // that is `axis` alone.
  std::vector<RVec3> nearOptimalAxes;
  bool unique = true;
  int faceCandidates = 0, edgeCandidates = 0;
};
SatResult SatSeparation(const RConvexPolyhedron& a, const RConvexPolyhedron& b,
                        RScalar tieTolerance, RScalar tieAngle, bool pruneEdges = true);

// Distance between separated polyhedra by enumeration of feature pairs: vertex-face (when
// the vertex projects inside the face), face-vertex and edge-edge (segment-segment, which
// also covers vertex-vertex and vertex-edge). Exact up to the rounding of one segment or
// plane computation. Meaningless (a positive number) for overlapping shapes.
struct BruteDistance {
  RScalar distance = 0;          // m
  RVec3 pointA = RVec3::Zero();  // on A, common frame
  RVec3 pointB = RVec3::Zero();  // on B
};
BruteDistance BruteForceDistance(const RConvexPolyhedron& a, const RConvexPolyhedron& b);

// Largest signed distance of p from the face planes of `p`'s polyhedron: 0 on the surface,
// < 0 inside, > 0 outside (a lower bound on the distance to the solid).
RScalar SurfaceOffset(const RConvexPolyhedron& poly, const RVec3& p);

}  // namespace REngine::test
