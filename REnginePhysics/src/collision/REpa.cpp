// EPA over RConvexShape pairs, in A's frame, from GJK's final simplex (RGjk.cpp): when the
// origin is inside the Minkowski difference D = A - B, the simplex is expanded into the face
// of D nearest the origin (depth = its distance, normal = its outward normal); every polytope
// vertex keeps its points a and b, so witness points come from barycentric coordinates. No
// heap: every buffer is a fixed-size array on the stack. See RCollision.h for conventions.
#include "collision/RGjkEpa.h"
#include <REngineMath/RFunctions.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

namespace {

constexpr int kMaxEpaVertices = RCollisionSolver::kMaxEpaIterations + 8;
constexpr int kMaxEpaFaces = 2 * kMaxEpaVertices + 8;
constexpr RScalar kEpaAbsoluteGap = 1e-14;

struct EpaFace {
  int v[3];
  RVec3 n;
  RScalar d;
};

struct Epa {
  RSimplexPoint verts[kMaxEpaVertices];
  EpaFace faces[kMaxEpaFaces];
  int nv = 0, nf = 0;

  bool AddFace(int i, int j, int k) {
    if (nf >= kMaxEpaFaces) return false;
    EpaFace& f = faces[nf++];
    f.v[0] = i, f.v[1] = j, f.v[2] = k;
    const RVec3 n = (verts[j].w - verts[i].w).cross(verts[k].w - verts[i].w);
    const RScalar len = n.norm();
    if (len > 0) {
      f.n = n / len;
      f.d = f.n.dot(verts[i].w);
    } else {  // a sliver; kept for the topology, never chosen as nearest
      f.n = RVec3::UnitX();
      f.d = kInf;
    }
    return true;
  }
};

// Completes a simplex that encloses the origin to a tetrahedron of D: GJK may stop at a
// point, segment or triangle when the origin lies on it (touching, or exactly coincident
// shapes). Adds supports in directions that raise the dimension.
bool CompleteTetrahedron(RPairSupport& sup, RSimplexPoint* p, int& n, RScalar tol) {
  auto add = [&](const RVec3& d) {
    const RVec3 a = sup.SupportA(d), b = sup.SupportB(-d);
    p[n] = {a - b, a, b};
  };
  static const RVec3 kAxes[6] = {RVec3::UnitX(), -RVec3::UnitX(), RVec3::UnitY(),
                                 -RVec3::UnitY(), RVec3::UnitZ(), -RVec3::UnitZ()};
  if (n == 1) {
    for (const RVec3& d : kAxes) {
      add(d);
      if ((p[1].w - p[0].w).norm() > tol) {
        n = 2;
        break;
      }
    }
    if (n == 1) return false;
  }
  if (n == 2) {
    const RVec3 e = (p[1].w - p[0].w).normalized();
    RVec3 u, w;
    OrthonormalBasis(e, u, w);
    for (int k = 0; k < 6 && n == 2; ++k) {
      const RScalar t = kPi * k / 3;
      add(Cos(t) * u + Sin(t) * w);
      if ((p[2].w - p[0].w).cross(e).norm() > tol) n = 3;
    }
    if (n == 2) return false;
  }
  if (n == 3) {
    const RVec3 nrm = (p[1].w - p[0].w).cross(p[2].w - p[0].w).normalized();
    for (RScalar sgn : {1.0, -1.0}) {
      add(sgn * nrm);
      if (std::abs((p[3].w - p[0].w).dot(nrm)) > tol) {
        n = 4;
        break;
      }
    }
    if (n == 3) return false;
  }
  return true;
}

}  // namespace

REpaResult EpaPenetration(RPairSupport& sup, const RGjkResult& gjk, RScalar relativeGap) {
  REpaResult r;
  const RScalar size = sup.a.boundingRadius + sup.b.boundingRadius;
  Epa e;
  RSimplexPoint start[4];
  int n = gjk.simplexSize;
  for (int i = 0; i < n; ++i) start[i] = gjk.simplex[i];
  // No tetrahedron of D encloses the origin with room to spare: D is flat to rounding
  // around it, and no direction found here is the contact's normal (the line between the
  // centres, used once, was 25 degrees off for a box touching a wall): no verdict.
  if (n < 4 && !CompleteTetrahedron(sup, start, n, 1e-12 * size)) return r;
  for (int i = 0; i < 4; ++i) e.verts[i] = start[i];
  e.nv = 4;
  // Orient the tetrahedron's faces outward.
  const RVec3& p0 = e.verts[0].w;
  const RScalar orient = (e.verts[1].w - p0).cross(e.verts[2].w - p0).dot(e.verts[3].w - p0);
  if (orient < 0) {
    e.AddFace(0, 1, 2), e.AddFace(0, 3, 1), e.AddFace(0, 2, 3), e.AddFace(1, 3, 2);
  } else {
    e.AddFace(0, 2, 1), e.AddFace(0, 1, 3), e.AddFace(0, 3, 2), e.AddFace(1, 2, 3);
  }

  // A face sees a new point beyond its plane by more than this (0 for polyhedra, whose
  // supports are vertices of D; on a curved surface the faces near the answer are small and
  // their planes carry rounding, so a point grazing them is seen by chance).
  const RScalar visible = relativeGap > kEpaRelativeGap ? RScalar(1e-13) * size : RScalar(0);
  int horizon[kMaxEpaFaces * 3][2];
  // The faces array holds only the live polytope: each iteration's visibility pass also
  // compacts it and finds the nearest surviving face, so nothing scans dead faces.
  int nearest = -1;
  {
    RScalar best = kInf;
    for (int f = 0; f < e.nf; ++f) {
      if (e.faces[f].d < best) best = e.faces[f].d, nearest = f;
    }
  }
  for (r.iterations = 0; r.iterations < RCollisionSolver::kMaxEpaIterations; ++r.iterations) {
    if (nearest < 0) break;
    const EpaFace face = e.faces[nearest];
    const RVec3 a = sup.SupportA(face.n), b = sup.SupportB(-face.n);
    const RVec3 w = a - b;
    const RScalar dist = face.n.dot(w);
    if (dist < r.upperDepth) r.upperDepth = dist, r.upperNormal = face.n, r.upperA = a, r.upperB = b;
    const bool done = dist - face.d <= relativeGap * std::abs(face.d) + kEpaAbsoluteGap * size;
    if (done || e.nv >= kMaxEpaVertices) {
      r.converged = done;
      break;
    }
    const int wi = e.nv++;
    e.verts[wi] = {w, a, b};
    // Faces that see w go; the edges they share with faces that stay form the horizon.
    int nh = 0, out = 0;
    nearest = -1;
    RScalar best = kInf;
    for (int f = 0; f < e.nf; ++f) {
      const EpaFace& g = e.faces[f];
      if (g.n.dot(w - e.verts[g.v[0]].w) <= visible) {
        if (g.d < best) best = g.d, nearest = out;
        e.faces[out++] = g;
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        const int i = g.v[k], j = g.v[(k + 1) % 3];
        // An edge met in both directions is interior to the removed region.
        bool cancelled = false;
        for (int h = 0; h < nh; ++h) {
          if (horizon[h][0] == j && horizon[h][1] == i) {
            horizon[h][0] = horizon[nh - 1][0], horizon[h][1] = horizon[nh - 1][1];
            --nh;
            cancelled = true;
            break;
          }
        }
        if (!cancelled) horizon[nh][0] = i, horizon[nh][1] = j, ++nh;
      }
    }
    e.nf = out;
    bool ok = true;
    for (int h = 0; h < nh && ok; ++h) {
      ok = e.AddFace(horizon[h][0], horizon[h][1], wi);
      if (ok && e.faces[e.nf - 1].d < best) best = e.faces[e.nf - 1].d, nearest = e.nf - 1;
    }
    if (!ok) {
      nearest = -1;  // out of room: no verdict (reported as the iteration cap)
      break;
    }
  }
  if (nearest < 0) return r;
  const EpaFace& f = e.faces[nearest];
  r.depth = std::max(RScalar(0), f.d);
  r.normal = f.n;
  // Barycentric coordinates of the origin's projection d n onto the face.
  const RVec3 p = f.d * f.n;
  const RVec3 A = e.verts[f.v[0]].w, B = e.verts[f.v[1]].w, C = e.verts[f.v[2]].w;
  const RVec3 nABC = (B - A).cross(C - A);
  const RScalar area2 = nABC.squaredNorm();
  RScalar l0 = 1, l1 = 0, l2 = 0;
  if (area2 > 0) {
    l1 = (p - A).cross(C - A).dot(nABC) / area2;
    l2 = (B - A).cross(p - A).dot(nABC) / area2;
    l0 = 1 - l1 - l2;
  }
  r.witnessA = l0 * e.verts[f.v[0]].a + l1 * e.verts[f.v[1]].a + l2 * e.verts[f.v[2]].a;
  r.witnessB = l0 * e.verts[f.v[0]].b + l1 * e.verts[f.v[1]].b + l2 * e.verts[f.v[2]].b;
  return r;
}

}  // namespace REngine
