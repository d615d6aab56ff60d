// Exact signed distances for polyhedra by enumerating features. See RPolyhedronExact.h.
#include "collision/RPolyhedronExact.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

// Closest points of segments [p0, p1] and [q0, q1] (Ericson, Real-Time Collision
// Detection, 5.1.9): minimise |p(s) - q(t)| over s, t in [0, 1]. Edges of a valid polyhedron
// have non-zero length; a zero-length one is handled as a point all the same.
// Returns whether both closest points are interior to their segments (0 < s, t < 1).
bool ClosestOnSegments(const RVec3& p0, const RVec3& p1, const RVec3& q0, const RVec3& q1,
                       RVec3& onP, RVec3& onQ) {
  const RVec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const RScalar a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  RScalar s = 0, t = 0;
  if (!(a > 0) && !(e > 0)) {
    s = t = 0;
  } else if (!(a > 0)) {
    t = std::clamp(f / e, RScalar(0), RScalar(1));
  } else {
    const RScalar c = d1.dot(r);
    if (!(e > 0)) {
      s = std::clamp(-c / a, RScalar(0), RScalar(1));
    } else {
      const RScalar b = d1.dot(d2);
      const RScalar denom = a * e - b * b;  // >= 0; 0 for parallel segments
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, RScalar(0), RScalar(1)) : 0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0, s = std::clamp(-c / a, RScalar(0), RScalar(1));
      } else if (t > 1) {
        t = 1, s = std::clamp((b - c) / a, RScalar(0), RScalar(1));
      }
    }
  }
  onP = p0 + s * d1;
  onQ = q0 + t * d2;
  return s > 0 && s < 1 && t > 0 && t < 1;
}

namespace {



// Whether p's projection along the face's normal falls inside the face's polygon (loop
// counter-clockwise about the outward normal n).
bool ProjectsInsideFace(const RConvexPolyhedron& poly, const RFace& f, const RVec3& p) {
  const std::uint32_t* loop = &poly.LoopVertices()[f.firstVertex];
  const std::vector<RVec3>& v = poly.Vertices();
  for (std::uint32_t k = 0; k < f.vertexCount; ++k) {
    const RVec3& a = v[loop[k]];
    const RVec3& b = v[loop[(k + 1) % f.vertexCount]];
    if ((b - a).cross(p - a).dot(f.plane.normal) < 0) return false;
  }
  return true;
}

// The closest features of two separated polyhedra (B's vertices mapped into A's frame by
// toA, A's into B's by toB): vertex-face both ways where the vertex projects inside the face,
// and every pair of edges (which covers vertex-vertex and vertex-edge). The normal comes from
// the features (the face's normal, the edges' common perpendicular), not from the difference
// of the witnesses: at 1e3 m from A's centre two points 1e-10 m apart differ by rounding.
// The axis test said "apart", but maybe only by rounding: a vertex on or inside the other
// solid (every face plane's signed distance <= 0) is a touching point, distance 0.
template <class ToA, class ToB>
void ClosestFeatures(const RConvexPolyhedron& a, const RConvexPolyhedron& b, const RMat3& R_AB,
                     const ToA& toA, const ToB& toB, RDistanceResult& r) {
  RScalar bestD2 = kInf;
  // Vertex p (in P's frame) against polyhedron P's faces; `flip` maps P's face normals to
  // the A-to-B normal and p's side to the witnesses.
  auto vertexFaces = [&](const RConvexPolyhedron& poly, const RVec3& p, auto&& report) {
    RScalar most = -kInf;
    const RFace* mostFace = nullptr;
    for (const RFace& f : poly.Faces()) {
      const RScalar sd = f.plane.SignedDistance(p);
      if (sd > most) most = sd, mostFace = &f;
    }
    if (most <= 0) {  // on or inside the solid, to rounding: touching
      if (bestD2 > 0) bestD2 = 0, report(*mostFace, most);
      return;
    }
    for (const RFace& f : poly.Faces()) {
      const RScalar sd = f.plane.SignedDistance(p);
      if (sd > 0 && sd * sd < bestD2 && ProjectsInsideFace(poly, f, p)) {
        bestD2 = sd * sd, report(f, sd);
      }
    }
  };
  for (std::size_t j = 0; j < b.Vertices().size(); ++j) {
    const RVec3 p = toA(b.Vertices()[j]);
    vertexFaces(a, p, [&](const RFace& f, RScalar sd) {
      r.witnessA = p - sd * f.plane.normal, r.witnessB = p, r.normal = f.plane.normal;
    });
  }
  for (std::size_t i = 0; i < a.Vertices().size(); ++i) {
    const RVec3& pA = a.Vertices()[i];
    vertexFaces(b, toB(pA), [&](const RFace& f, RScalar sd) {
      r.normal = -(R_AB * f.plane.normal);
      r.witnessA = pA, r.witnessB = pA + sd * r.normal;
    });
  }
  for (const REdge& ea : a.Edges()) {
    const RVec3& a0 = a.Vertices()[ea.v0];
    const RVec3& a1 = a.Vertices()[ea.v1];
    for (const REdge& eb : b.Edges()) {
      const RVec3 b0 = toA(b.Vertices()[eb.v0]), b1 = toA(b.Vertices()[eb.v1]);
      RVec3 cA, cB;
      const bool interior = ClosestOnSegments(a0, a1, b0, b1, cA, cB);
      const RVec3 gap = cB - cA;
      const RScalar d2 = gap.squaredNorm();
      if (!(d2 < bestD2)) continue;
      bestD2 = d2, r.witnessA = cA, r.witnessB = cB;
      const RVec3 perpendicular = (a1 - a0).cross(b1 - b0);
      const RScalar len = perpendicular.norm();
      const bool crossing =
          interior && len > RScalar(1e-9) * (a1 - a0).norm() * (b1 - b0).norm();
      if (crossing) {
        r.normal = perpendicular / len;
        if (r.normal.dot(gap) < 0) r.normal = -r.normal;
      } else if (d2 > 0) {
        r.normal = gap / std::sqrt(d2);
      }  // else: the points coincide; the caller's axis stands
    }
  }
  r.separation = std::sqrt(bestD2);
}

}  // namespace

RDistanceResult ExactPolyhedra(const RConvexPolyhedron& a, const RConvexPolyhedron& b,
                               const RRelativePose& X_AB) {
  const RMat3& R = X_AB.R_AB;
  const RVec3& t = X_AB.t_AB;
  auto toA = [&](const RVec3& p_B) { return RVec3(R * p_B + t); };
  auto toB = [&](const RVec3& p_A) { return RVec3(R.transpose() * (p_A - t)); };
  const std::vector<RVec3>& vA = a.Vertices();
  const std::vector<RVec3>& vB = b.Vertices();

  // The separating axis test. Each candidate's separation is min over B of n.b minus max
  // over A of n.a, with n from A to B.
  enum class Kind { kFaceA, kFaceB, kEdges } kind = Kind::kFaceA;
  RScalar best = -kInf;
  RVec3 bestN = RVec3::UnitX();
  std::uint32_t bestA = 0, bestB = 0;  // supporting vertex, or edge indices
  bool edgesSupport = true;              // kEdges: the edges themselves support along bestN
  std::uint32_t supportB = 0;            // kEdges: B's supporting vertex
  for (const RFace& f : a.Faces()) {
    const RVec3& n = f.plane.normal;
    const RVec3 n_B = R.transpose() * n;
    const std::uint32_t j = b.Support(vB.data(), -n_B);
    const RScalar s = n_B.dot(vB[j]) + n.dot(t) - f.plane.offset;
    if (s > best) best = s, bestN = n, bestB = j, kind = Kind::kFaceA;
  }
  for (const RFace& g : b.Faces()) {
    const RVec3 n = -(R * g.plane.normal);
    const std::uint32_t i = a.Support(vA.data(), n);
    const RScalar s = n.dot(t) - g.plane.offset - n.dot(vA[i]);
    if (s > best) best = s, bestN = n, bestA = i, kind = Kind::kFaceB;
  }
  // Edge pairs whose arcs on the Gauss map cross: those, and only those, span a face of the
  // Minkowski difference (the pruning that makes the test O(E_a E_b) cheap tests). Arcs
  // (u1, u2) of A's edge and (-w1, -w2) of B's (B enters the difference negated) cross when
  // each arc's endpoints lie on either side of the other's great circle, on the same
  // hemisphere. Along such a normal both edges support, so their vertices give the
  // separation; a candidate that would beat the best is confirmed by the supports.
  const std::vector<RFace>& fA = a.Faces();
  const std::vector<RFace>& fB = b.Faces();
  for (std::uint32_t ia = 0; ia < a.Edges().size(); ++ia) {
    const REdge& ea = a.Edges()[ia];
    const RVec3& u1 = fA[ea.f0].plane.normal;
    const RVec3& u2 = fA[ea.f1].plane.normal;
    const RVec3 u2xu1 = u2.cross(u1);
    const RVec3 edgeA = vA[ea.v1] - vA[ea.v0];
    for (std::uint32_t ib = 0; ib < b.Edges().size(); ++ib) {
      const REdge& eb = b.Edges()[ib];
      const RVec3 w1 = -(R * fB[eb.f0].plane.normal);
      const RVec3 w2 = -(R * fB[eb.f1].plane.normal);
      const RScalar cba = w1.dot(u2xu1), dba = w2.dot(u2xu1);
      const RVec3 w2xw1 = w2.cross(w1);
      const RScalar adc = u1.dot(w2xw1), bdc = u2.dot(w2xw1);
      if (!(cba * dba < 0 && adc * bdc < 0 && cba * bdc > 0)) continue;
      const RVec3 edgeB = R * (vB[eb.v1] - vB[eb.v0]);
      RVec3 n = edgeA.cross(edgeB);
      const RScalar len = n.norm();
      // Parallel edges: their common faces' normals are already candidates.
      if (!(len > RScalar(1e-12) * edgeA.norm() * edgeB.norm())) continue;
      n /= len;
      // Outward from A (its frame's origin, the centre of mass, is inside it).
      if (n.dot(vA[ea.v0]) < 0) n = -n;
      const RScalar s = n.dot(toA(vB[eb.v0]) - vA[ea.v0]);
      if (!(s > best)) continue;
      // Along n the two edges are the supporting features when their arcs cross; on a
      // sliver of a hull whose face normals are nearly parallel the test is at the mercy of
      // rounding (fuzz_narrowphase: a 20 m needle's edge gave 0 where the shapes were 6.7 mm
      // apart along n). The supports decide.
      const std::uint32_t i = a.Support(vA.data(), n);
      const std::uint32_t j = b.Support(vB.data(), -(R.transpose() * n));
      const RScalar supported = n.dot(toA(vB[j]) - vA[i]);
      if (supported > best) {
        best = supported, bestN = n, bestA = ia, bestB = ib, kind = Kind::kEdges;
        edgesSupport = std::abs(supported - s) <= RScalar(1e-12) * (a.MaxRadius() + b.MaxRadius());
        supportB = j;
      }
    }
  }

  RDistanceResult r;
  if (best <= 0) {
    r.separation = best;
    r.normal = bestN;
    switch (kind) {
      case Kind::kFaceA:
        r.witnessB = toA(vB[bestB]);
        r.witnessA = r.witnessB - best * bestN;
        break;
      case Kind::kFaceB:
        r.witnessA = vA[bestA];
        r.witnessB = r.witnessA + best * bestN;
        break;
      case Kind::kEdges: {
        if (!edgesSupport) {  // the supporting vertex of B, and its projection onto A's
          r.witnessB = toA(vB[supportB]);
          r.witnessA = r.witnessB - best * bestN;
          break;
        }
        const REdge& ea = a.Edges()[bestA];
        const REdge& eb = b.Edges()[bestB];
        ClosestOnSegments(vA[ea.v0], vA[ea.v1], toA(vB[eb.v0]), toA(vB[eb.v1]), r.witnessA,
                          r.witnessB);
        break;
      }
    }
    return r;
  }
  // Apart: the axis test's answer is only a lower bound (the closest points may meet at an
  // edge or a vertex of the difference); the closest features give the distance.
  r.normal = bestN;
  ClosestFeatures(a, b, R, toA, toB, r);
  r.separation = std::max(r.separation, best);
  return r;
}

void ExactPointPolyhedron(const RConvexPolyhedron& p, const RVec3& c, RScalar& signedDistance,
                          RVec3& closest, RVec3& outward) {
  RScalar most = -kInf;
  for (const RFace& f : p.Faces()) {
    const RScalar s = f.plane.SignedDistance(c);
    if (s > most) most = s, outward = f.plane.normal;
  }
  if (most <= 0) {  // inside: the nearest face plane is the way out
    signedDistance = most;
    closest = c - most * outward;
    return;
  }
  RScalar bestD2 = kInf;
  for (const RFace& f : p.Faces()) {
    const RScalar s = f.plane.SignedDistance(c);
    if (s > 0 && s * s < bestD2 && ProjectsInsideFace(p, f, c)) {
      bestD2 = s * s, closest = c - s * f.plane.normal;
    }
  }
  for (const REdge& e : p.Edges()) {
    RVec3 onEdge, same;
    ClosestOnSegments(p.Vertices()[e.v0], p.Vertices()[e.v1], c, c, onEdge, same);
    const RScalar d2 = (c - onEdge).squaredNorm();
    if (d2 < bestD2) bestD2 = d2, closest = onEdge;
  }
  signedDistance = std::max(std::sqrt(bestD2), most);
  const RVec3 away = c - closest;
  const RScalar len = away.norm();
  if (len > 0 && std::isfinite(len)) outward = away / len;
}

}  // namespace REngine
