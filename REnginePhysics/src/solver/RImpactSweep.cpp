// The impact phase's sweep along turning paths (RContactSolver::SweepImpact): once an impact
// has changed how a body turns, when within the rest of the step the pair it is in next
// closes, its rotation included. Box2D's time of impact (Catto, "Continuous Collision",
// GDC 2013) follows a separating axis between the bodies' sweeps and finds where the
// deepest points along it meet; this one does the same, and proves each stretch of the
// sweep free before it moves past it, since a body turning at krad/s can swing through a
// plate and out again between two looks at it.
#include "collision/RGjkEpa.h"
#include "collision/RMesh.h"
#include "shape/RCompound.h"
#include "solver/RContactSolver.h"
#include "solver/RImpactPath.h"
#include "solver/RSolverRows.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;

namespace {

// The pair's separation along the unit axis n (A to B, A's frame), B at pose X: how far
// apart their supports are along it (negative: their overlap along it). Any axis gives at
// most their distance (an axis along which they are apart separates them). A side that is a
// mesh is its contact's triangle (child).
RScalar AxisSeparation(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X, const RVec3& n,
                       std::uint32_t childA, std::uint32_t childB) {
  RPairSupport sup(a, b, X);
  RScalar highA = -std::numeric_limits<RScalar>::infinity(), lowB = std::numeric_limits<RScalar>::infinity();
  if (a.mesh) {
    for (int k = 0; k < 3; ++k) highA = std::max(highA, n.dot(a.mesh->Vertex(childA, k)));
  } else {
    highA = n.dot(sup.SupportA(n)) + a.radius;
  }
  if (b.mesh) {
    for (int k = 0; k < 3; ++k) lowB = std::min(lowB, n.dot(X.R_AB * b.mesh->Vertex(childB, k) + X.t_AB));
  } else {
    lowB = n.dot(sup.SupportB(-n)) - b.radius;
  }
  return lowB - highA;
}

// The least of s1 (1 - l) + s2 l - c l (1 - l) over l in [0, 1]: the lowest a function can
// be between two times where it is s1 and s2 when its second derivative is at least -2 c
// over the span squared.
RScalar LowestUnderChord(RScalar s1, RScalar s2, RScalar c) {
  if (!(c > 0)) return std::min(s1, s2);
  const RScalar l = std::clamp((c - (s2 - s1)) / (2 * c), RScalar(0), RScalar(1));
  return s1 + (s2 - s1 - c) * l + c * l * l;
}

int Deepest(const RContactManifold& m) {
  int d = 0;
  for (int k = 1; k < m.pointCount; ++k) d = m.points[k].separation < m.points[d].separation ? k : d;
  return d;
}

// A pair along its paths in the impact phase: where B is in A's frame at time t, their
// separation along an axis then, and the narrow phase's manifold then. A body that turns
// far within the step (TurnsFar) turns on the flow from its last impact (TurnedAt); any
// other keeps its orientation (turnQ, or the start's), as the impact geometry keeps it.
struct RPairPath {
  const RBodyCore &A, &B;
  const RSolverBody &sa, &sb;
  RConvexShape shapeA, shapeB;
  std::uint32_t childA, childB;
  RScalar halfDt;
  bool farA, farB;

  RPairPath(const RBodyCore& A_, const RBodyCore& B_, const RSolverBody& sa_, const RSolverBody& sb_,
            std::uint32_t childA_, std::uint32_t childB_, RScalar dt, RScalar slop)
      : A(A_), B(B_), sa(sa_), sb(sb_), shapeA(ShapeOf(Body(A_))), shapeB(ShapeOf(Body(B_))), childA(childA_),
        childB(childB_), halfDt(RScalar(0.5) * dt),
        farA(sa_.turns && TurnsFar(sa_, sa_.turnW_B.norm(), dt - sa_.turnTau, slop)),
        farB(sb_.turns && TurnsFar(sb_, sb_.turnW_B.norm(), dt - sb_.turnTau, slop)) {}

  // B's pose in A's frame at time t, and A's orientation then.
  void PoseAt(RScalar t, RRelativePose& X, RQuat& qA) const {
    RQuat qB = sb.turns ? sb.turnQ : B.m_q_WB;
    RVec3 w_B;
    qA = sa.turns ? sa.turnQ : A.m_q_WB;
    if (farA) TurnedAt(A, sa, t, qA, w_B);
    if (farB) TurnedAt(B, sb, t, qB, w_B);
    const RQuat qAW = qA.conjugate();
    X.R_AB = (qAW * qB).toRotationMatrix();
    X.t_AB = qAW * ((B.m_x_W - A.m_x_W) + (MovedAt(sb, t, halfDt) - MovedAt(sa, t, halfDt)));
  }
  // Their separation along world axis n at t.
  RScalar Separation(const RVec3& n, RScalar t) const {
    RRelativePose X;
    RQuat qA;
    PoseAt(t, X, qA);
    return AxisSeparation(shapeA, shapeB, X, qA.conjugate() * n, childA, childB);
  }
  // The narrow phase at t (the whole shapes; a mesh's contact triangle and those near it):
  // the manifold in A's frame, with the pose.
  RContactManifold ManifoldAt(RScalar t, RRelativePose& X, RQuat& qA) const {
    PoseAt(t, X, qA);
    return shapeA.mesh || shapeB.mesh ? MeshPartManifold(shapeA, shapeB, X, childA, childB)
                                      : RCollisionSolver::Manifold(shapeA, shapeB, X, std::numeric_limits<RScalar>::max());
  }
  RScalar Lead(RScalar t) const {
    RRelativePose X;
    RQuat qA;
    const RContactManifold m = ManifoldAt(t, X, qA);
    return m.pointCount == 0 ? RScalar(0) : m.points[Deepest(m)].separation;
  }
  // The moment of contact between ta (apart) and tb (touching or overlapping), to the
  // touching band of the narrow phase's deepest separation (Illinois' regula falsi): the
  // moment is the contact's, whatever bracket the sweep found it in.
  RScalar Touch(RScalar ta, RScalar tb, RScalar band) const {
    RScalar ga = Lead(ta), gb = Lead(tb);
    if (!(ga > band)) return ta;
    for (int k = 0, side = 0; k < 48 && gb < -band; ++k) {
      const RScalar t = ga - gb > 0 ? ta + (tb - ta) * (ga / (ga - gb)) : RScalar(0.5) * (ta + tb);
      const RScalar g = Lead(t);
      if (!(g == g)) break;
      if (g > band) {
        ta = t, ga = g;
        if (side == 1) gb *= RScalar(0.5);
        side = 1;
      } else {
        tb = t, gb = g;
        if (side == -1) ga *= RScalar(0.5);
        side = -1;
      }
    }
    return tb;
  }
};

// The features of a pair touching at a moment (within the slop of the deepest, over every
// child pair), as points of each body, and whether a contact found later is at one of them
// (the warm starts' match distance, on either body).
struct RTouched {
  static constexpr int kMost = 16;
  RVec3 onA[kMost], onB[kMost];
  int count = 0;
  RScalar same = 0;

  void Add(const RContactManifold& c, const RRelativePose& X, RScalar most) {
    for (int k = 0; k < c.pointCount && count < kMost; ++k) {
      if (c.points[k].separation > most) continue;
      onA[count] = c.points[k].position;
      onB[count++] = X.R_AB.transpose() * (c.points[k].position - X.t_AB);
    }
  }
  bool Holds(const RVec3& p, const RRelativePose& X) const {
    const RVec3 pB = X.R_AB.transpose() * (p - X.t_AB);
    for (int k = 0; k < count; ++k) {
      if ((p - onA[k]).norm() <= same || (pB - onB[k]).norm() <= same) return true;
    }
    return false;
  }
};

}  // namespace

// The sweep follows the separation s(t) of the pair along a fixed world axis n, first the
// normal of their contact at t0. While s > 0 they are apart. Every material point of a body
// moves along n with an acceleration of at most K: its centre's where the pair's
// n . (aB - aA) is positive (a convex parabola lies under its chords), and its turning's
// (TurnAcceleration times its bounding radius); a support, the most of such points, then
// lies at most K/2 (t - t1)(t2 - t) beyond its chord, and s at most that under its chord.
// So s measured at both ends of a stretch bounds it from below all along: a stretch whose
// bound stays above minus the slop is free (a point may sink the slop into the other
// unseen, what a resting contact may sink), and the sweep moves past it; one whose bound
// does not is halved. Each stretch is as long as the bound lets a flat chord at the last
// separation be free, so that a fast turn is looked at every few degrees, a slow one once
// for the rest of the step.
//
// A contact is where s comes down to the touch (zero, or the depth the pair overlaps at
// when the sweep starts), on a stretch short enough for the bound to be within half a slop
// of the chord: halved to there, the narrow phase says how far apart the bodies really are.
// Touching, that is the contact, at its moment (RPairPath::Touch); apart (B is no plane: the
// swinging tail passes beside it), the narrow phase's normal there is the new axis and the
// sweep goes on. A sweep that starts at a contact (the nose that hit) looks past it: until
// the supports have come half a slop apart, a contact is half a slop beyond where they
// started, what comes to touch while the start's contact goes on.
//
// A pair touching at t0 has that contact at t0, unless pastTouching. At the start of the
// step, what touches is what the contact rows were built at: a contact the sweep finds at
// those features is that contact's own motion, the rows' (a compound landing flat that its
// impact, through the centre of its face, set rocking onto one end), and the sweep stops
// there, as it stops past kSweepLooks separations and kSweepAxes axes. Later in the step the
// rows are the start's, and what touches then is swept like anything else.
RScalar RContactSolver::SweepImpact(const RBodyCore& A, const RBodyCore& B, const RSolverBody& sa,
                                    const RSolverBody& sb, RScalar t0, RScalar dt, std::uint32_t childA,
                                    std::uint32_t childB, bool pastTouching) const {
  constexpr RScalar kNone = std::numeric_limits<RScalar>::infinity();
  constexpr int kSweepLooks = 96, kSweepAxes = 4;
  const RPairPath path(A, B, sa, sb, childA, childB, dt, m_in->settings.penetrationSlop);
  if (path.shapeA.mesh && path.shapeB.mesh) return kNone;
  const RScalar slop = std::max(m_in->settings.penetrationSlop, Band(path.shapeA, path.shapeB));
  RRelativePose X;
  RQuat qA;
  RContactManifold m = path.ManifoldAt(t0, X, qA);
  if (m.pointCount == 0) return kNone;
  RScalar gap = m.points[Deepest(m)].separation;
  if (gap <= slop && !pastTouching) return t0;
  RTouched touched;
  touched.same = kWarmMatchDistance * std::min(A.m_boundingRadius, B.m_boundingRadius);
  if (gap <= slop && t0 == 0) {
    touched.Add(m, X, gap + slop);
    if (HasParts(path.shapeA) || HasParts(path.shapeB)) {
      ForEachChildManifold(path.shapeA, path.shapeB, X, gap + slop, [&](const RContactManifold& c) {
        if (c.childA != m.childA || c.childB != m.childB) touched.Add(c, X, gap + slop);
      });
    }
  }
  const RScalar turning = (path.farA ? TurnAcceleration(A, sa.turnW_B) * A.m_boundingRadius : 0) +
                          (path.farB ? TurnAcceleration(B, sb.turnW_B) * B.m_boundingRadius : 0);
  const RScalar band = RCollisionSolver::kTouchingTolerance * (A.m_boundingRadius + B.m_boundingRadius);
  RVec3 n = qA * m.normal;
  RScalar K = 0, t1 = t0, s1 = 0, floor = 0, level = 0;
  bool cleared = false;
  // The level of a contact: the touch once the supports have come half a slop apart, half a
  // slop beyond where they started before that.
  auto clear = [&](RScalar s) {
    cleared = cleared || s > floor + RScalar(0.5) * slop;
    level = cleared ? floor : floor - RScalar(0.5) * slop;
  };
  // A new axis at t: the bound along it, the separation there and the touch's level (apart:
  // taken where the pair is apart, whatever contact the sweep started in is left).
  auto takeAxis = [&](RScalar t, bool apart) {
    K = turning + std::max(RScalar(0), n.dot(sb.accel - sa.accel));
    t1 = t, s1 = path.Separation(n, t);
    floor = std::min(s1, RScalar(0));
    cleared = apart && s1 > 0, clear(s1);
  };
  // The longest stretch over which a chord at separation s above the floor stays free.
  auto stretch = [&](RScalar s) { return K > 0 ? std::sqrt(4 * (std::max(s - floor, RScalar(0)) + slop) / K) : dt; };
  takeAxis(t0, false);
  RScalar h = stretch(s1);
  for (int look = 0, axes = 1; look < kSweepLooks; ++look) {
    const RScalar t2 = std::min(t1 + h, dt);
    const RScalar span = t2 - t1;
    const RScalar s2 = path.Separation(n, t2);
    if (!(s2 == s2)) return kNone;  // not a number (bodies flung out of range): nothing to find
    const RScalar c = RScalar(0.5) * K * span * span;
    if (s2 > level && LowestUnderChord(s1, s2, c) >= floor - slop) {
      if (t2 >= dt) return kNone;
      t1 = t2, s1 = s2, h = stretch(s1);
      clear(s1);
      continue;
    }
    // Not proven free: shorter, unless the supports meet within half a slop of the chord
    // (c / 4 is the most s strays under it).
    if (s2 > level || c > 2 * slop) {
      h = RScalar(0.5) * span;
      continue;
    }
    // The crossing, halved until the separations at its ends are within half a slop (s can
    // lie far above the chord, where one support turns away and another comes in).
    RScalar ta = t1, sA = s1, tc = t2, sC = s2;
    for (int k = 0; k < kSweepLooks && sA - sC > RScalar(0.5) * slop; ++k) {
      const RScalar tm = RScalar(0.5) * (ta + tc), sm = path.Separation(n, tm);
      if (sm <= level) {
        tc = tm, sC = sm;
      } else {
        ta = tm, sA = sm;
      }
    }
    m = path.ManifoldAt(tc, X, qA);
    if (m.pointCount == 0) return kNone;
    const RContactPoint& p = m.points[Deepest(m)];
    gap = p.separation;
    if (cleared ? gap <= 0 : gap <= floor + slop) {
      if (touched.Holds(p.position, X)) return kNone;
      return cleared ? path.Touch(ta, tc, band) : tc;
    }
    if (++axes > kSweepAxes) return kNone;
    n = qA * m.normal;
    takeAxis(tc, true);
    h = stretch(s1);
  }
  return kNone;
}

}  // namespace REngine
