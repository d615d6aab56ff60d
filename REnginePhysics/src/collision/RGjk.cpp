// GJK over RConvexShape pairs, in A's frame (EPA: REpa.cpp). See RCollision.h for
// conventions.
//
// GJK finds the point v of the Minkowski difference D = A - B closest to the origin (the
// distance is |v|, the normal from A to B is -v/|v|); when the origin is inside D the
// shapes overlap and EPA expands GJK's final simplex into the face of D nearest the origin
// (depth = its distance, normal = its outward normal). Both keep, for every simplex or
// polytope vertex w = a - b, the points a and b, so witness points come from barycentric
// coordinates. No heap: every buffer is a fixed-size array on the stack.
#include "collision/RGjkEpa.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

namespace {


// GJK converges when the lower bound v.w is within this fraction of the upper bound v.v.
constexpr RScalar kGjkRelativeGap = 1e-12;

struct SimplexVertex {
  RVec3 w, a, b;
};

struct Simplex {
  SimplexVertex v[4];
  RScalar lambda[4];
  int n = 0;
};

// Closest point of the simplex to the origin; reduces the simplex to the smallest feature
// holding that point and fills its barycentric coordinates. Voronoi-region tests after
// Ericson, Real-Time Collision Detection, 5.1.2 and 5.1.5 (with P = origin). Returns false
// when the origin is inside a tetrahedron.
void ClosestOnSegment(Simplex& s, int i0, int i1) {
  const RVec3 a = s.v[i0].w, b = s.v[i1].w;
  const RVec3 ab = b - a;
  const RScalar t = -a.dot(ab);
  const RScalar denom = ab.squaredNorm();
  SimplexVertex va = s.v[i0], vb = s.v[i1];
  if (t <= 0 || denom <= 0) {
    s.v[0] = va, s.lambda[0] = 1, s.n = 1;
  } else if (t >= denom) {
    s.v[0] = vb, s.lambda[0] = 1, s.n = 1;
  } else {
    s.v[0] = va, s.v[1] = vb;
    s.lambda[1] = t / denom;
    s.lambda[0] = 1 - s.lambda[1];
    s.n = 2;
  }
}

void ClosestOnTriangle(Simplex& s, int i0, int i1, int i2) {
  const SimplexVertex A = s.v[i0], B = s.v[i1], C = s.v[i2];
  const RVec3 a = A.w, b = B.w, c = C.w;
  const RVec3 ab = b - a, ac = c - a, ap = -a;
  const RScalar d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) {
    s.v[0] = A, s.lambda[0] = 1, s.n = 1;
    return;
  }
  const RVec3 bp = -b;
  const RScalar d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) {
    s.v[0] = B, s.lambda[0] = 1, s.n = 1;
    return;
  }
  const RScalar vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const RScalar t = d1 / (d1 - d3);
    s.v[0] = A, s.v[1] = B, s.lambda[0] = 1 - t, s.lambda[1] = t, s.n = 2;
    return;
  }
  const RVec3 cp = -c;
  const RScalar d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) {
    s.v[0] = C, s.lambda[0] = 1, s.n = 1;
    return;
  }
  const RScalar vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const RScalar t = d2 / (d2 - d6);
    s.v[0] = A, s.v[1] = C, s.lambda[0] = 1 - t, s.lambda[1] = t, s.n = 2;
    return;
  }
  const RScalar va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const RScalar t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    s.v[0] = B, s.v[1] = C, s.lambda[0] = 1 - t, s.lambda[1] = t, s.n = 2;
    return;
  }
  const RScalar sum = va + vb + vc;
  if (!(sum > 0)) {  // degenerate (collinear) triangle: its best edge
    Simplex e1 = s, e2 = s, e3 = s;
    ClosestOnSegment(e1, i0, i1);
    ClosestOnSegment(e2, i0, i2);
    ClosestOnSegment(e3, i1, i2);
    auto point = [](const Simplex& x) {
      RVec3 p = RVec3::Zero();
      for (int i = 0; i < x.n; ++i) p += x.lambda[i] * x.v[i].w;
      return p.squaredNorm();
    };
    const RScalar p1 = point(e1), p2 = point(e2), p3 = point(e3);
    s = p1 <= p2 && p1 <= p3 ? e1 : (p2 <= p3 ? e2 : e3);
    return;
  }
  s.v[0] = A, s.v[1] = B, s.v[2] = C;
  s.lambda[1] = vb / sum;
  s.lambda[2] = vc / sum;
  s.lambda[0] = 1 - s.lambda[1] - s.lambda[2];
  s.n = 3;
}

// Returns true when the origin is inside (or on) the tetrahedron.
bool ClosestOnTetrahedron(Simplex& s) {
  const RVec3 p[4] = {s.v[0].w, s.v[1].w, s.v[2].w, s.v[3].w};
  // Face (i, j, k) with opposite vertex l: the origin is outside it when it lies on the
  // other side of the face's plane from l.
  static constexpr int kFaces[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {0, 2, 3, 1}, {1, 3, 2, 0}};
  bool outsideAny = false;
  RScalar best = kInf;
  Simplex bestS;
  for (const auto& f : kFaces) {
    const RVec3 n = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
    const RScalar sideOrigin = -n.dot(p[f[0]]);
    const RScalar sideOpp = n.dot(p[f[3]] - p[f[0]]);
    // Degenerate (flat) tetrahedron: sideOpp = 0, every face counts as "outside", and
    // the closest face point is the answer.
    if (sideOrigin * sideOpp < 0 || sideOpp == 0) {
      outsideAny = true;
      Simplex t = s;
      ClosestOnTriangle(t, f[0], f[1], f[2]);
      RVec3 q = RVec3::Zero();
      for (int i = 0; i < t.n; ++i) q += t.lambda[i] * t.v[i].w;
      const RScalar d = q.squaredNorm();
      if (d < best) best = d, bestS = t;
    }
  }
  if (!outsideAny) return true;
  s = bestS;
  return false;
}

RVec3 PointOf(const Simplex& s) {
  RVec3 p = RVec3::Zero();
  for (int i = 0; i < s.n; ++i) p += s.lambda[i] * s.v[i].w;
  return p;
}

void Witnesses(const Simplex& s, RVec3& a, RVec3& b) {
  a.setZero(), b.setZero();
  for (int i = 0; i < s.n; ++i) a += s.lambda[i] * s.v[i].a, b += s.lambda[i] * s.v[i].b;
}

}  // namespace

namespace {

// The support point of a compound's surface in direction d (its body frame): the farthest
// of its children's, each child's core support grown by its radius along d.
RVec3 CompoundSupport(const RConvexShape& s, const RVec3& d) {
  const RScalar len = d.norm();
  const RVec3 unit = len > 0 ? RVec3(d / len) : RVec3::UnitX();
  RVec3 best = RVec3::Zero();
  RScalar most = -std::numeric_limits<RScalar>::infinity();
  for (std::uint32_t i = 0; i < s.childCount; ++i) {
    const RShapeChild& c = s.children[i];
    const RVec3 dc = c.R_BC.transpose() * d;
    RVec3 p;
    if (c.shape.polyhedron) {
      const auto& v = c.shape.polyhedron->Vertices();
      p = v[c.shape.polyhedron->Support(v.data(), dc, 0)];
    } else if (c.shape.cylinderRadius > 0) {
      p = CylinderSupport(c.shape.cylinderRadius, c.shape.halfHeight, dc);
    } else {
      p = RVec3(0, c.shape.halfHeight == 0 ? 0 : dc.y() >= 0 ? c.shape.halfHeight : -c.shape.halfHeight, 0);
    }
    const RVec3 q = c.R_BC * p + c.p_BC + c.shape.radius * unit;
    if (q.dot(d) > most) most = q.dot(d), best = q;
  }
  return best;
}

}  // namespace

// The polyhedron first in both: the box and hull pairs' path is the one that must stay fast.
RVec3 RPairSupport::SupportA(const RVec3& d) {
  if (a.polyhedron) {
    const auto& v = a.polyhedron->Vertices();
    m_lastA = a.polyhedron->Support(v.data(), d, m_lastA);
    return v[m_lastA];
  }
  if (a.cylinderRadius > 0) return CylinderSupport(a.cylinderRadius, a.halfHeight, d);
  if (a.children) return CompoundSupport(a, d);
  return a.halfHeight == 0 ? RVec3::Zero() : RVec3(0, d.y() >= 0 ? a.halfHeight : -a.halfHeight, 0);
}

RVec3 RPairSupport::SupportB(const RVec3& d_A) {
  if (!b.polyhedron) {
    if (b.cylinderRadius > 0) {
      return X.R_AB * CylinderSupport(b.cylinderRadius, b.halfHeight, X.R_AB.transpose() * d_A) + X.t_AB;
    }
    if (b.children) return X.R_AB * CompoundSupport(b, X.R_AB.transpose() * d_A) + X.t_AB;
    if (b.halfHeight == 0) return X.t_AB;
    // The capsule's core end that is farthest along d: B's y axis is R_AB's second column.
    const RScalar h = X.R_AB.col(1).dot(d_A) >= 0 ? b.halfHeight : -b.halfHeight;
    return X.R_AB.col(1) * h + X.t_AB;
  }
  const RVec3 d_B = X.R_AB.transpose() * d_A;
  const auto& v = b.polyhedron->Vertices();
  m_lastB = b.polyhedron->Support(v.data(), d_B, m_lastB);
  return X.R_AB * v[m_lastB] + X.t_AB;
}

RGjkResult Gjk(RPairSupport& sup, bool booleanOnly, RScalar stopAbove, const RVec3* start) {
  RGjkResult r;
  const RScalar size = sup.a.boundingRadius + sup.b.boundingRadius;
  // Below this |v| the origin is on D's boundary to rounding: touching.
  const RScalar vanishing = 1e-14 * size;
  const RScalar band = RCollisionSolver::kTouchingTolerance * size;
  Simplex s;
  RVec3 d = start ? *start : sup.X.t_AB;  // first guess: the line between the centres
  if (d.squaredNorm() == 0) d = RVec3::UnitX();
  {
    const RVec3 a = sup.SupportA(-d), b = sup.SupportB(d);
    s.v[0] = {a - b, a, b};
    s.lambda[0] = 1;
    s.n = 1;
  }
  RVec3 v = s.v[0].w;
  for (r.iterations = 1; r.iterations <= RCollisionSolver::kMaxGjkIterations; ++r.iterations) {
    const RScalar vv = v.squaredNorm();
    if (vv <= vanishing * vanishing) {
      r.overlap = true;
      r.distance = 0;
      break;
    }
    const RVec3 a = sup.SupportA(-v), b = sup.SupportB(v);
    const RVec3 w = a - b;
    const RScalar vw = v.dot(w);
    const RScalar norm = std::sqrt(vv);
    if (vw / norm > r.lowerBound) r.lowerBound = vw / norm, r.lowerNormal = -v / norm;
    if ((booleanOnly && r.lowerBound > band) || r.lowerBound > stopAbove) {
      // The plane normal to v separates them by more than asked.
      r.overlap = false;
      r.distance = norm;  // an upper bound only
      r.converged = true;
      r.beyond = true;
      r.closest = v;
      return r;
    }
    bool duplicate = false;
    for (int i = 0; i < s.n; ++i) duplicate = duplicate || s.v[i].w == w;
    if (duplicate || vv - vw <= kGjkRelativeGap * vv) {
      r.converged = true;
      break;
    }
    const Simplex previous = s;
    s.v[s.n] = {w, a, b};
    s.n++;
    bool inside = false;
    switch (s.n) {
      case 2: ClosestOnSegment(s, 0, 1); break;
      case 3: ClosestOnTriangle(s, 0, 1, 2); break;
      case 4: inside = ClosestOnTetrahedron(s); break;
    }
    if (inside) {
      r.overlap = true;
      r.distance = 0;
      r.converged = true;
      break;
    }
    const RVec3 vNew = PointOf(s);
    // Rounding can stall the descent; no progress means v is as close as it gets.
    if (vNew.squaredNorm() >= vv) {
      s = previous;
      r.converged = true;
      break;
    }
    v = vNew;
  }
  if (r.iterations > RCollisionSolver::kMaxGjkIterations) {
    r.iterations = RCollisionSolver::kMaxGjkIterations;
    r.converged = false;
  }
  if (r.overlap) {
    r.converged = true;
    r.simplexSize = s.n;
    for (int i = 0; i < s.n; ++i) r.simplex[i] = {s.v[i].w, s.v[i].a, s.v[i].b};
    return r;
  }
  r.distance = std::sqrt(v.squaredNorm());
  Witnesses(s, r.witnessA, r.witnessB);
  r.closest = v;
  r.simplexSize = s.n;
  for (int i = 0; i < s.n; ++i) r.simplex[i] = {s.v[i].w, s.v[i].a, s.v[i].b};
  return r;
}

RGjkResult RefineOnTrianglePlane(RPairSupport& sup, const RGjkResult& g) {
  if (g.overlap || g.simplexSize != 3) return g;
  const RSimplexPoint* p = g.simplex;
  const RVec3 n = (p[1].w - p[0].w).cross(p[2].w - p[0].w);  // p0, p1, p2 counter-clockwise
  const RScalar nn = n.squaredNorm();
  if (!(nn > 0)) return g;
  // Outward: from the origin toward the triangle (D lies beyond its plane).
  RVec3 nHat = n / std::sqrt(nn);
  if (nHat.dot(p[0].w) < 0) nHat = -nHat;
  const RScalar dist = nHat.dot(p[0].w);
  // The origin on the plane: no direction to give (the caller's fallbacks decide).
  if (!(dist > 0)) return g;
  const RVec3 q = dist * nHat;  // the origin projected onto the plane
  // Barycentric coordinates of q: the sub-triangles' signed areas along n.
  RScalar lambda[3];
  for (int i = 0; i < 3; ++i) {
    const RVec3& u = p[(i + 1) % 3].w;
    const RVec3& v = p[(i + 2) % 3].w;
    lambda[i] = (u - q).cross(v - q).dot(n) / nn;
    if (!(lambda[i] > 0)) return g;  // q is not inside: the plane's distance bounds nothing
  }
  RGjkResult r = g;
  // q is a point of D (inside the triangle), so dist is an upper bound; the support plane
  // along nHat is a lower bound.
  const RVec3 w = sup.SupportA(-nHat) - sup.SupportB(nHat);
  r.distance = dist;
  r.lowerBound = std::max(g.lowerBound, nHat.dot(w));
  r.closest = q;
  const RScalar sum = lambda[0] + lambda[1] + lambda[2];
  r.witnessA.setZero(), r.witnessB.setZero();
  for (int i = 0; i < 3; ++i) {
    r.simplex[i] = p[i];
    r.witnessA += (lambda[i] / sum) * p[i].a;
    r.witnessB += (lambda[i] / sum) * p[i].b;
  }
  return r;
}

}  // namespace REngine
