// libccd and FCL behind the plain interface of CollisionOracles.h. FCL's headers are
// included here only, so that the tests and benchmarks that use the oracles compile
// quickly and never see Eigen configured two ways.
#include "CollisionOracles.h"

#include <fcl/geometry/shape/convex.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

namespace REngine::test {

namespace {

ccd_vec3_t ToCcd(const RVec3& v) {
  ccd_vec3_t c;
  ccdVec3Set(&c, v.x(), v.y(), v.z());
  return c;
}
RVec3 FromCcd(const ccd_vec3_t& c) { return RVec3(ccdVec3X(&c), ccdVec3Y(&c), ccdVec3Z(&c)); }

// libccd's EPA has no iteration cap: with a tolerance near rounding it can expand a
// polytope forever on a flat Minkowski face. A budget of support calls guards every libccd
// call. When it runs out, every later support of both shapes is the origin: the Minkowski
// support is then 0, which libccd's EPA takes as "no expansion beyond the nearest face" and
// stops at once (and GJK and MPR are capped by max_iterations), so the call returns through
// its own clean-up and frees its polytope; the wrapper reports the oracle as failed. (It
// used to longjmp out of libccd, leaking the polytope.)
struct CcdGuard {
  long budget;
  bool spent = false;
};
thread_local CcdGuard* g_ccdGuard = nullptr;
// EPA on the random suite's hulls (up to 64 x 64 vertices) needs at most ~70 support calls
// (median 22) at the tolerance below; the budget is 30 times that.
constexpr long kCcdSupportBudget = 2000;
long g_ccdSupportBudget = kCcdSupportBudget;

// libccd support: the vertex maximising dot(v, dir), by a plain loop over world vertices.
void CcdSupport(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  if (g_ccdGuard != nullptr && (g_ccdGuard->spent || --g_ccdGuard->budget < 0)) {
    g_ccdGuard->spent = true;
    ccdVec3Set(out, 0, 0, 0);
    return;
  }
  const auto* hull = static_cast<const CcdPosedHull*>(obj);
  const RVec3 d = FromCcd(*dir);
  const RVec3* best = &hull->vertices_W[0];
  RScalar bestDot = best->dot(d);
  for (const RVec3& v : hull->vertices_W) {
    const RScalar dot = v.dot(d);
    if (dot > bestDot) {
      bestDot = dot;
      best = &v;
    }
  }
  *out = ToCcd(*best);
}

// Runs one libccd call under a fresh support budget: its return code, or kCcdBudgetSpent.
constexpr int kCcdBudgetSpent = -100;
template <typename Call>
int GuardedCcd(Call call) {
  CcdGuard guard;
  guard.budget = g_ccdSupportBudget;
  g_ccdGuard = &guard;
  const int rc = call();
  g_ccdGuard = nullptr;
  return guard.spent ? kCcdBudgetSpent : rc;
}

}  // namespace

void SetCcdSupportBudget(long budget) {
  g_ccdSupportBudget = budget > 0 ? budget : kCcdSupportBudget;
}

namespace {

void CcdCenter(const void* obj, ccd_vec3_t* center) {
  *center = ToCcd(static_cast<const CcdPosedHull*>(obj)->center_W);
}

fcl::Transform3d ToFcl(const OraclePose& X) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.linear() = X.q_WS.toRotationMatrix();
  tf.translation() = X.position_W;
  return tf;
}

std::shared_ptr<const fcl::Convex<double>> MakeFclConvex(const RConvexPolyhedron& p) {
  auto vertices =
      std::make_shared<std::vector<fcl::Vector3d>>(p.Vertices().begin(), p.Vertices().end());
  auto faces = std::make_shared<std::vector<int>>();
  for (const RFace& f : p.Faces()) {
    faces->push_back(static_cast<int>(f.vertexCount));
    for (std::uint32_t i = 0; i < f.vertexCount; ++i)
      faces->push_back(static_cast<int>(p.LoopVertices()[f.firstVertex + i]));
  }
  // throw_if_invalid: a hull FCL thinks is not watertight is a bug in this wrapper.
  return std::make_shared<const fcl::Convex<double>>(vertices, static_cast<int>(p.Faces().size()),
                                                     faces, /*throw_if_invalid=*/true);
}

fcl::GJKSolverType ToFcl(FclSolver s) {
  return s == FclSolver::kLibccd ? fcl::GST_LIBCCD : fcl::GST_INDEP;
}

}  // namespace

OracleHull::OracleHull(const std::vector<RVec3>& points_S)
    : OracleHull(RConvexPolyhedron::Hull(points_S)) {}

OracleHull::OracleHull(RConvexPolyhedron polyhedron)
    : m_polyhedron(std::move(polyhedron)), m_fcl(MakeFclConvex(m_polyhedron)) {}

CcdPosedHull PoseForCcd(const OracleHull& hull, const OraclePose& X_WS) {
  CcdPosedHull out;
  const RMat3 R = X_WS.q_WS.toRotationMatrix();
  RVec3 sum = RVec3::Zero();
  for (const RVec3& v : hull.Polyhedron().Vertices()) {
    out.vertices_W.push_back(R * v + X_WS.position_W);
    sum += v;
  }
  out.center_W = R * (sum / static_cast<RScalar>(out.vertices_W.size())) + X_WS.position_W;
  return out;
}

ccd_t MakeCcdConfig(RScalar scale) {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = CcdSupport;
  ccd.support2 = CcdSupport;
  ccd.center1 = CcdCenter;
  ccd.center2 = CcdCenter;
  ccd.max_iterations = 1000;
  ccd.mpr_tolerance = 1e-12 * scale;
  ccd.epa_tolerance = 1e-14 * scale * scale;
  ccd.dist_tolerance = 1e-12 * scale;
  return ccd;
}

int CcdGJKIntersect(const CcdPosedHull& a, const CcdPosedHull& b, const ccd_t& config) {
  const int rc = GuardedCcd([&] { return ccdGJKIntersect(&a, &b, &config); });
  return rc == kCcdBudgetSpent ? -1 : (rc != 0 ? 1 : 0);
}

namespace {
// libccd's two penetration queries share one signature and one result convention.
using CcdPenetrationFn = int (*)(const void*, const void*, const ccd_t*, ccd_real_t*,
                                 ccd_vec3_t*, ccd_vec3_t*);
OraclePenetration CcdPenetration(CcdPenetrationFn fn, const CcdPosedHull& a,
                                 const CcdPosedHull& b, const ccd_t& config) {
  OraclePenetration r;
  ccd_real_t depth = 0;
  ccd_vec3_t dir, pos;
  ccdVec3Set(&dir, 1, 0, 0);
  ccdVec3Set(&pos, 0, 0, 0);
  const int rc = GuardedCcd([&] { return fn(&a, &b, &config, &depth, &dir, &pos); });
  r.ok = rc == 0 || rc == -1;
  r.overlap = rc == 0;
  if (r.overlap) {
    r.depth = depth;
    r.normal_W = FromCcd(dir);
    r.point_W = FromCcd(pos);
  }
  return r;
}
}  // namespace

OraclePenetration CcdGJKPenetration(const CcdPosedHull& a, const CcdPosedHull& b,
                                    const ccd_t& config) {
  return CcdPenetration(ccdGJKPenetration, a, b, config);
}

OraclePenetration CcdMPRPenetration(const CcdPosedHull& a, const CcdPosedHull& b,
                                    const ccd_t& config) {
  return CcdPenetration(ccdMPRPenetration, a, b, config);
}

OraclePenetration FclCollide(const OracleHull& a, const OraclePose& X_WA, const OracleHull& b,
                             const OraclePose& X_WB, FclSolver solver, RScalar tolerance) {
  OraclePenetration r;
  try {
    fcl::CollisionRequestd request(/*num_max_contacts=*/1, /*enable_contact=*/true);
    request.gjk_solver_type = ToFcl(solver);
    request.gjk_tolerance = tolerance;
    fcl::CollisionResultd result;
    fcl::collide(&a.FclConvex(), ToFcl(X_WA), &b.FclConvex(), ToFcl(X_WB), request, result);
    r.overlap = result.isCollision();
    if (r.overlap && result.numContacts() > 0) {
      const fcl::Contactd& c = result.getContact(0);
      // FCL 0.7's GST_INDEP convex path reports the depth negated (its normal is A->B as
      // documented); GST_LIBCCD reports it positive. The magnitude is the depth.
      r.depth = std::abs(c.penetration_depth);
      // FCL 0.7's GST_INDEP path returns the normal in o1's frame, not the world's (its EPA
      // runs in o1's frame and the rotation back is missing; the contact point is
      // transformed). Measured on the random suite: rotated by R_WA it matches the exact
      // axis to 1e-16 rad; as returned, it is off by ~pi/2 on average.
      r.normal_W =
          solver == FclSolver::kIndep ? RVec3(ToFcl(X_WA).linear() * c.normal) : RVec3(c.normal);
      r.point_W = c.pos;
    }
  } catch (const std::exception&) {
    r.ok = false;
  }
  return r;
}

OracleDistance FclDistance(const OracleHull& a, const OraclePose& X_WA, const OracleHull& b,
                           const OraclePose& X_WB, FclSolver solver, RScalar tolerance) {
  OracleDistance r;
  try {
    fcl::DistanceRequestd request(/*enable_nearest_points=*/true);
    request.gjk_solver_type = ToFcl(solver);
    request.distance_tolerance = tolerance;
    fcl::DistanceResultd result;
    fcl::distance(&a.FclConvex(), ToFcl(X_WA), &b.FclConvex(), ToFcl(X_WB), request, result);
    r.distance = result.min_distance;
    r.pointA_W = result.nearest_points[0];
    r.pointB_W = result.nearest_points[1];
  } catch (const std::exception&) {
    r.ok = false;
  }
  return r;
}

namespace {

RScalar MaxDot(const RConvexPolyhedron& p, const RVec3& d) {
  RScalar m = -std::numeric_limits<RScalar>::infinity();
  for (const RVec3& v : p.Vertices()) m = std::max(m, v.dot(d));
  return m;
}
RScalar MinDot(const RConvexPolyhedron& p, const RVec3& d) { return -MaxDot(p, -d); }

// Closest points of segments [p1, q1] and [p2, q2] (Ericson, Real-Time Collision Detection,
// 5.1.9), with the degenerate (point) and parallel cases handled by clamping.
void ClosestSegmentSegment(const RVec3& p1, const RVec3& q1, const RVec3& p2, const RVec3& q2,
                           RVec3& c1, RVec3& c2) {
  const RVec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const RScalar a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  RScalar s = 0, t = 0;
  if (a == 0 && e == 0) {
    s = t = 0;
  } else if (a == 0) {
    t = std::clamp(f / e, RScalar(0), RScalar(1));
  } else {
    const RScalar c = d1.dot(r);
    if (e == 0) {
      s = std::clamp(-c / a, RScalar(0), RScalar(1));
    } else {
      const RScalar b = d1.dot(d2);
      const RScalar denom = a * e - b * b;  // >= 0; 0 for parallel segments
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, RScalar(0), RScalar(1)) : 0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, RScalar(0), RScalar(1));
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, RScalar(0), RScalar(1));
      }
    }
  }
  c1 = p1 + s * d1;
  c2 = p2 + t * d2;
}

// Vertices of `from` against the faces of `to`: the projection of a vertex onto a face's
// plane, when it falls inside the face's polygon. Updates `best` (distance, point on
// `from`, point on `to`).
void VertexFacePairs(const RConvexPolyhedron& from, const RConvexPolyhedron& to, RScalar& best,
                     RVec3& onFrom, RVec3& onTo) {
  for (const RFace& f : to.Faces()) {
    const RVec3& n = f.plane.normal;
    for (const RVec3& v : from.Vertices()) {
      const RScalar h = f.plane.SignedDistance(v);
      if (h < 0 || h >= best) continue;  // behind the face: not its closest feature
      const RVec3 proj = v - h * n;
      bool inside = true;
      for (std::uint32_t i = 0; i < f.vertexCount && inside; ++i) {
        const RVec3& e0 = to.Vertices()[to.LoopVertices()[f.firstVertex + i]];
        const RVec3& e1 = to.Vertices()[to.LoopVertices()[f.firstVertex + (i + 1) % f.vertexCount]];
        inside = (e1 - e0).cross(proj - e0).dot(n) >= 0;  // loops are CCW about n
      }
      if (inside) {
        best = h;
        onFrom = v;
        onTo = proj;
      }
    }
  }
}

}  // namespace

SatResult SatSeparation(const RConvexPolyhedron& a, const RConvexPolyhedron& b,
                        RScalar tieTolerance, RScalar tieAngle, bool pruneEdges) {
  struct Candidate {
    RScalar s;
    RVec3 n;
  };
  std::vector<Candidate> cands;
  SatResult r;
  // Separation along n, from A to B, by full support loops: a valid bound for any unit n.
  auto along = [&](const RVec3& n) { return MinDot(b, n) - MaxDot(a, n); };
  for (const RFace& f : a.Faces()) cands.push_back({along(f.plane.normal), f.plane.normal});
  for (const RFace& f : b.Faces()) cands.push_back({along(-f.plane.normal), -f.plane.normal});
  r.faceCandidates = static_cast<int>(cands.size());

  for (const REdge& ea : a.Edges()) {
    const RVec3& pa = a.Vertices()[ea.v0];
    const RVec3 da = a.Vertices()[ea.v1] - pa;
    const RVec3& na0 = a.Faces()[ea.f0].plane.normal;
    const RVec3& na1 = a.Faces()[ea.f1].plane.normal;
    const RVec3 na1_x_na0 = na1.cross(na0);
    for (const REdge& eb : b.Edges()) {
      const RVec3& pb = b.Vertices()[eb.v0];
      const RVec3 db = b.Vertices()[eb.v1] - pb;
      RVec3 n = da.cross(db);
      const RScalar len = n.norm();
      if (len == 0) continue;  // parallel edges: no facet of D, no axis
      if (pruneEdges) {
        // Gauss map of D = A + (-B): A's edge is the arc na0 -> na1, B's the arc -nb0 -> -nb1;
        // the pair forms a facet of D iff the arcs cross.
        const RVec3 nc = -b.Faces()[eb.f0].plane.normal;
        const RVec3 nd = -b.Faces()[eb.f1].plane.normal;
        const RVec3 nd_x_nc = nd.cross(nc);
        const RScalar cba = nc.dot(na1_x_na0), dba = nd.dot(na1_x_na0);
        const RScalar adc = na0.dot(nd_x_nc), bdc = na1.dot(nd_x_nc);
        if (!(cba * dba < 0 && adc * bdc < 0 && cba * bdc > 0)) continue;
        n /= len;
        if (n.dot(na0 + na1) < 0) n = -n;  // the facet normal lies on A's arc: outward of A
        // On the facet, A's edge supports n and B's edge supports -n: O(1). For nearly
        // parallel edges the axis carries a rounding error ~eps / sin(angle), and an axis off
        // by delta moves this value by ~delta * size; below sin = 1e-6 the full support loops
        // keep the candidate a valid bound instead (it can then only be too small, by at
        // most ~2e-10 of the size).
        const RScalar s = len > 1e-6 * da.norm() * db.norm() ? n.dot(pb - pa) : along(n);
        cands.push_back({s, n});
      } else {
        n /= len;
        cands.push_back({along(n), n});
        cands.push_back({along(-n), -n});
      }
    }
  }
  r.edgeCandidates = static_cast<int>(cands.size()) - r.faceCandidates;

  std::size_t best = 0;
  for (std::size_t i = 1; i < cands.size(); ++i)
    if (cands[i].s > cands[best].s) best = i;
  r.separation = cands[best].s;
  r.axis = cands[best].n;
  const RScalar cosTie = std::cos(tieAngle);
  r.nearOptimalAxes.push_back(r.axis);
  for (const Candidate& c : cands) {
    if (c.s < r.separation - tieTolerance) continue;
    bool known = false;
    for (const RVec3& n : r.nearOptimalAxes) known = known || c.n.dot(n) >= cosTie;
    if (!known) r.nearOptimalAxes.push_back(c.n);
  }
  r.unique = r.nearOptimalAxes.size() == 1;
  return r;
}

BruteDistance BruteForceDistance(const RConvexPolyhedron& a, const RConvexPolyhedron& b) {
  BruteDistance r;
  r.distance = std::numeric_limits<RScalar>::infinity();
  VertexFacePairs(a, b, r.distance, r.pointA, r.pointB);
  VertexFacePairs(b, a, r.distance, r.pointB, r.pointA);
  // Edge pairs: compare squared distances, take one square root at the end.
  RScalar best2 = r.distance * r.distance;
  RVec3 bestA = r.pointA, bestB = r.pointB;
  for (const REdge& ea : a.Edges()) {
    const RVec3& pa = a.Vertices()[ea.v0];
    const RVec3& qa = a.Vertices()[ea.v1];
    for (const REdge& eb : b.Edges()) {
      RVec3 ca, cb;
      ClosestSegmentSegment(pa, qa, b.Vertices()[eb.v0], b.Vertices()[eb.v1], ca, cb);
      const RScalar d2 = (cb - ca).squaredNorm();
      if (d2 < best2) {
        best2 = d2;
        bestA = ca;
        bestB = cb;
      }
    }
  }
  if (best2 < r.distance * r.distance) {
    r.distance = std::sqrt(best2);
    r.pointA = bestA;
    r.pointB = bestB;
  }
  return r;
}

RScalar SurfaceOffset(const RConvexPolyhedron& poly, const RVec3& p) {
  RScalar m = -std::numeric_limits<RScalar>::infinity();
  for (const RFace& f : poly.Faces()) m = std::max(m, f.plane.SignedDistance(p));
  return m;
}

}  // namespace REngine::test
