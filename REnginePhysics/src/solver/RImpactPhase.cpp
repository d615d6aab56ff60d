// The impact phase (RContactSolver::SolveIslandImpacts): impacts at their time within the step,
// restitution through one row per manifold.
#include "shape/RCompound.h"
#include "collision/RGjkEpa.h"
#include "pairs/RPairSweep.h"
#include "joints/RWeldGroups.h"
#include "solver/RContactSolver.h"
#include "solver/RImpactPath.h"
#include "world/RStepBodies.h"

#include "solver/RSolverRows.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;

namespace {

// Under gravity and constant forces a body's velocity through the step is v + a (t - dt/2),
// v its mean velocity (what the solver holds), a its acceleration: between impacts it moves
// on the parabola, and a pair's normal speed changes at the rate n . (aB - aA). Both are
// zero-cost where no body accelerates (space): then the motion is a line, as before.
RScalar NormalAcceleration(const RVec3& n, const RSolverBody& sa, const RSolverBody& sb) {
  return n.dot(sb.accel - sa.accel);
}

// How long a gap g >= 0 takes to close from an approach speed w (m/s, > 0 approaching) under
// an approach acceleration alpha (m/s^2): the first root of w t + alpha t^2 / 2 = g, or
// infinity if it never closes. The root is taken as 2 g / (w + sqrt(w^2 + 2 alpha g)), which
// cancels nothing; without acceleration it is g / w.
RScalar CloseTime(RScalar g, RScalar w, RScalar alpha) {
  constexpr RScalar kNoMeeting = std::numeric_limits<RScalar>::infinity();
  if (!(g < kNoMeeting)) return kNoMeeting;  // (a row joined into another has an infinite gap)
  if (alpha == 0) return w > 0 ? g / w : kNoMeeting;
  const RScalar disc = w * w + 2 * alpha * g;
  if (disc < 0) return kNoMeeting;  // slowing down, it stops short of the gap
  const RScalar root = w + std::sqrt(disc);
  if (root > 0) return 2 * g / root;
  // g = 0 and moving apart: back at 2 (-w)/alpha if pulled back.
  return alpha > 0 ? -2 * w / alpha : kNoMeeting;
}

// Moves a body along its path up to time t of the step (MovedAt): on the line of its
// velocity, or, accelerating, on its parabola.
void AdvanceTo(RSolverBody& s, RScalar t, RScalar halfDt) {
  if (t <= s.tau) return;
  s.moved = MovedAt(s, t, halfDt);
  s.tau = t;
}

// The normal impulse dn at arms rA, rB (dir: normal and tangents), then friction at the
// same point, within mu times this row's normal impulse so far. xA: A's centre at the start.
void ApplyImpact(RImpactRow& r, const RDirection* dir, const RVec3& rA, const RVec3& rB, RScalar dn, RSolverBody& sa,
                 RSolverBody& sb, const RVec3& xA) {
  r.lambdaN += dn;
  Push(dir[0], dn, sa, sb, sa.v, sa.w, sb.v, sb.w);
  const Eigen::Matrix<RScalar, 2, 1> step = TangentStep(dir[1], dir[2], Speed(dir[1], sa.v, sa.w, sb.v, sb.w),
                                                        Speed(dir[2], sa.v, sa.w, sb.v, sb.w), sa, sb);
  const RScalar lt1 = r.lambdaT1 + step.x(), lt2 = r.lambdaT2 + step.y();
  const RScalar limit = r.friction * r.lambdaN;
  const RScalar norm = std::sqrt(lt1 * lt1 + lt2 * lt2);
  const RScalar scale = norm > limit ? limit / norm : RScalar(1);
  const RScalar d1 = lt1 * scale - r.lambdaT1, d2 = lt2 * scale - r.lambdaT2;
  r.lambdaT1 += d1, r.lambdaT2 += d2;
  if (d1 != 0) Push(dir[1], d1, sa, sb, sa.v, sa.w, sb.v, sb.w);
  if (d2 != 0) Push(dir[2], d2, sa, sb, sa.v, sa.w, sb.v, sb.w);
  const RVec3 J = dn * dir[0].d + d1 * dir[1].d + d2 * dir[2].d;
  r.impulse += J, r.angularA += rA.cross(J), r.angularB += rB.cross(J);
  r.frictionImpulse += d1 * dir[1].d + d2 * dir[2].d;
  r.point_W = xA + sa.moved + rA, r.normal_W = dir[0].d;
}

// What an impact's geometry moves a body by before it is known to push: restored when it
// does not (a swept row's bodies also keep their time; the others keep where the geometry
// took them, as they always did, but not a turning body's spin and inertia there).
struct RKept {
  RVec3 moved, w;
  RMat3 invI;
  RScalar tau;
  explicit RKept(const RSolverBody& s) : moved(s.moved), w(s.w), invI(s.invI), tau(s.tau) {}
  void Restore(RSolverBody& s, bool path) const {
    if (s.turns) s.w = w, s.invI = invI;
    if (path) s.moved = moved, s.tau = tau;
  }
};

// After an impulse at time t on body s: where its turning goes on from, with its spin after
// the impulse: the orientation the geometry turned it to (qAt at atTau), or, not turning
// before (TurnsFar), the one it has had since turnTau. One that turns far neither before nor
// after keeps that orientation, its spin changed with the inertia there. At the start of the
// step the impulse is one of the start's, and the motion's path (the start's kick, then the
// flow) is the phase's; later, the motion turns it from there (turned).
void CommitTurn(RSolverBody& s, RScalar t, RScalar dt, RScalar slop) {
  ++s.impacts;
  if (!s.turns) return;
  if (!s.turning) s.qAt = s.turnQ, s.atTau = std::max(t, s.turnTau);
  const RVec3 w_B = s.qAt.conjugate() * s.w;
  if (!s.turning && !TurnsFar(s, w_B.norm(), dt - s.atTau, slop)) {
    s.turnW_B = s.turnQ.conjugate() * s.w;
    return;
  }
  s.turnQ = s.qAt, s.turnTau = s.atTau, s.turnW_B = w_B;
  if (s.turnTau > 0) s.turned = true;
}

}  // namespace

// The geometry of an impact within the step, at time t (updated): the narrow phase again at
// the poses the bodies have then (moved along their paths; a body that turns with a spin at
// its orientation then, TurnTo; the others at the start's), advanced until the leading
// points touch: t += gap / approach, which for two spheres converges to the exact moment,
// so an oblique collision gets the normal along the line of centres at contact, not at the
// start of the step. The impulse point is the centre of the leading points, the same for
// both bodies (lever arms from where their centres are at t), so angular momentum is
// exact. False if they do not meet this step. whole: a sweep's contact (SweepImpact), at its
// moment already: the geometry there, a compound meeting with whichever child pair is
// deepest, not with its contact's own.
bool RContactSolver::ImpactGeometry(const RBodyCore& A, const RBodyCore& B, RSolverBody& sa, RSolverBody& sb,
                                    RScalar& t, RScalar dt, RVec3& rA, RVec3& rB, RDirection* dir,
                                    std::uint32_t childA, std::uint32_t childB, bool whole) const {
  const RScalar halfDt = RScalar(0.5) * dt;
  const RConvexShape shapeA = ShapeOf(Body(A)), shapeB = ShapeOf(Body(B));
  // A compound's contact is one child pair's: the impact is that pair's.
  RShapeChild aloneA, aloneB;
  aloneA.shape = shapeA, aloneB.shape = shapeB;
  const bool children = HasParts(shapeA) || HasParts(shapeB);
  const RShapeChild& ca = shapeA.children ? shapeA.children[childA] : aloneA;
  const RShapeChild& cb = shapeB.children ? shapeB.children[childB] : aloneB;
  const RRelativePose X0 = RelativePose(Body(A), Body(B));
  const RMat3 R_WA0 = A.m_q_WB.toRotationMatrix();
  const bool turning = sa.turning || sb.turning || sa.turned || sb.turned;
  const RScalar tolerance = RCollisionSolver::kTouchingTolerance * (A.m_boundingRadius + B.m_boundingRadius);
  constexpr int kAdvances = 16;
  for (int k = 0; k < kAdvances; ++k) {
    AdvanceTo(sa, t, halfDt), AdvanceTo(sb, t, halfDt);
    RRelativePose X = X0;
    RMat3 R_WA = R_WA0;
    if (!turning) {
      X.t_AB += R_WA.transpose() * (sb.moved - sa.moved);
    } else {
      TurnTo(A, sa, t), TurnTo(B, sb, t);
      const RQuat qAW = (sa.turns ? sa.qAt : A.m_q_WB).conjugate();
      R_WA = qAW.conjugate().toRotationMatrix();
      X.R_AB = (qAW * (sb.turns ? sb.qAt : B.m_q_WB)).toRotationMatrix();
      X.t_AB = qAW * ((B.m_x_W - A.m_x_W) + (sb.moved - sa.moved));
    }
    RContactManifold m;
    if (shapeA.mesh || shapeB.mesh) {
      m = MeshPartManifold(shapeA, shapeB, X, childA, childB);
    } else if (children && !whole) {
      m = RCollisionSolver::Manifold(ca.shape, cb.shape, ChildPose(ca, cb, X), std::numeric_limits<RScalar>::max());
      ChildToBody(ca, childA, childB, m);
    } else {
      m = RCollisionSolver::Manifold(shapeA, shapeB, X, std::numeric_limits<RScalar>::max());
    }
    if (m.pointCount == 0) return false;
    RLeadingPoints leading = LeadingPoints(m);
    // No point within the slop of the deepest: the separations are not numbers (bodies
    // flung to 1e300 m/s overflow the pair's pose). No impact to find (found by fuzz_world).
    if (leading.count == 0) return false;
    const RScalar lead = m.points[leading.deepest].separation;
    if (children) {
      // A compound meets flat with several children at once (a ship's two hulls on a wall):
      // the leading points of every child pair facing the same way join this one's, so the
      // one impact goes through their centre, as a single body's face would.
      RVec3 sum = leading.centre * leading.count;
      int count = leading.count;
      ForEachChildManifold(shapeA, shapeB, X, lead + m_in->settings.penetrationSlop, [&](const RContactManifold& other) {
        if (other.childA == m.childA && other.childB == m.childB) return;
        if (other.normal.dot(m.normal) < kFaceContactCos) return;
        for (int q = 0; q < other.pointCount; ++q) {
          if (other.points[q].separation <= lead + m_in->settings.penetrationSlop) sum += other.points[q].position, ++count;
        }
      });
      leading.centre = sum / count;
    }
    const RVec3& centre_A = leading.centre;
    // World, relative to each body's centre of mass at t.
    const RVec3 n = R_WA * m.normal;
    const RVec3 p = R_WA * centre_A + sa.moved;  // from A's centre at the start
    rA = p - sa.moved;
    rB = p - (B.m_x_W - A.m_x_W) - sb.moved;
    RVec3 t1, t2;
    OrthonormalBasis(n, t1, t2);
    SetDirection(dir[0], n, rA, rB, sa, sb);
    SetDirection(dir[1], t1, rA, rB, sa, sb);
    SetDirection(dir[2], t2, rA, rB, sa, sb);
    // The normal speed at t (the mean speed, with acceleration the speed at t).
    const RScalar an = NormalAcceleration(n, sa, sb);
    const RScalar vn = an == 0 ? Speed(dir[0], sa.v, sa.w, sb.v, sb.w)
                               : Speed(dir[0], sa.v, sa.w, sb.v, sb.w) + an * (t - RScalar(0.5) * dt);
    // A sweep's contact is at its moment already (SweepImpact): its geometry there.
    if (whole) return true;
    if (lead <= tolerance) {
      // Touching and moving apart, but pulled back (a ball just bounced under gravity):
      // they meet again at t + 2 vn / (-an), if within the step.
      if (an < 0 && vn > 0 && t + 2 * vn / -an <= dt) {
        t += 2 * vn / -an;
        continue;
      }
      return true;
    }
    const RScalar close = CloseTime(lead, -vn, -an);
    if (close == std::numeric_limits<RScalar>::infinity()) return false;
    // Meeting after the step: not an impact of this step, unless the gap left is within
    // the slop (a row of balls a micrometre apart: the impulse goes down the row now).
    if (t + close > dt) return lead <= m_in->settings.penetrationSlop;
    t += close;
  }
  return true;  // close enough: the remaining gap shrinks every advance
}

// The impact phase: every manifold approaching faster than the restitution threshold, and
// reaching contact within the step, bounces through its impact row: the impulse that turns
// the approach speed vn into -e vn, then friction at the same point bounded by mu times
// that impulse. Passes repeat while some manifold still impacts, so an impulse travels
// along a chain of touching bodies the way it does in a Newton's cradle (the striker stops,
// the last ball leaves), instead of being shared out as a block. Each application changes
// the kinetic energy by (e^2 - 1) vn^2 / (2 k) <= 0, and friction only removes sliding, so
// no pass can add energy whatever the order.
//
// Impacts happen at their time within the step, not at its start: a contact that is gap
// away at approach speed vn hits at t = gap / -vn (never before an earlier impact of either
// body). Each body keeps the displacement it has travelled up to its last impact; the
// impulse acts where the contact then is (one point for both bodies, moved with the lighter
// one, so angular momentum is exact); and the body moves during the step with the
// velocity that gives the piecewise path (before the impact, then after it). The velocity
// it ends with is the one after its impacts: the difference is deferred to the end of the
// step. A missile at 2 km/s stops at the face of the plate it hits, not a step short of it.
//
// A body that turns (RSolverBody::turns) turns on its path as the motion turns it: the
// torque-free flow from the start, and from each impact that changes its spin, from its
// orientation and spin right after it (RImpactPath.h). An impact then acts at the
// orientation of its time, with the inverse inertia there: its kinetic energy, which
// depends on the orientation, changes by the impulse's (e^2 - 1) vn^2 / (2 k) and no more,
// and the free flow between impacts keeps it. Once an impact has changed how a body turns,
// where its surface goes is no longer what the start's geometry says (a rod hitting a plate
// nose first at 2.5 km/s turns at 1.3 krad/s, and its tail swings down through the plate
// within the step): each row of such a body is swept along the turning paths for the
// pair's next contact (SweepImpact), which bounces there like any other.
//
// Island by island (SolveIsland): an island's impact rows (one per manifold, its blocks'
// indices) move only its own bodies. A static or kinematic body, which islands share, is
// read and never written: its path is known (x + v t), so where it is at an impact's time
// is worked out on a copy, and its impacts with one body do not order those with another
// (only a movable body's impacts happen one after another).
void RContactSolver::SolveIslandImpacts(const RStepBodies& bodies, RScalar dt, std::size_t island,
                                        const RJointIslandView& jointView, RIslandScratch& sc) {
  const std::uint32_t* islandBodies = m_islandBodies.data() + m_islandBodyStart[island];
  const std::size_t bodyCount = m_islandBodyStart[island + 1] - m_islandBodyStart[island];
  for (std::size_t k = 0; k < bodyCount; ++k) {
    RSolverBody& s = m_solverBodies[islandBodies[k]];
    s.moved.setZero(), s.tau = 0;
    s.deferV.setZero();
    s.turned = false;
  }
  const auto [first, last] = m_blockIslands[island];
  const std::size_t count = m_islandImpacts[island] ? last - first : 0;
  const RScalar halfDt = RScalar(0.5) * dt;
  bool anyImpact = false;
  // With joints (RJointImpacts.cpp): each impact bounces through the joints' reaction
  // (their rows hold the relative velocities of before the impacts: begun before them).
  const bool joints = count > 0 && m_joints.IslandHasJoints(island);
  if (count > 0) BeginTurns(bodies, island, joints);
  if (joints) m_joints.BeginImpactJoints(jointView, sc);
  const int passes = std::max(1, m_in->settings.solverIterations);
  for (int pass = 0; pass < passes && count > 0; ++pass) {
    bool any = false;
    for (std::size_t ii = 0; ii < count; ++ii) {
      RImpactRow& r = m_impacts[first + ((pass % 2 == 0) ? ii : count - 1 - ii)];
      if (ImpactRow(bodies, r, dt, joints, jointView, sc)) any = anyImpact = true;
    }
    if (!any) break;
  }
  for (std::size_t k = 0; k < bodyCount; ++k) {
    RSolverBody& s = m_solverBodies[islandBodies[k]];
    s.vImpacts = s.v;
  }
  if (!anyImpact) {
    if (joints) m_joints.EndImpactJoints(jointView, sc, false);
    return;
  }
  // The velocity each body moves with this step gives its piecewise path; the rest of the
  // change waits for the end of the step. The contact phase works on the velocities after
  // the impacts, the bodies' real ones, so that its impulses, inelastic there, cannot add
  // energy; the difference is taken out of the motion only (ReportIsland).
  for (std::size_t k = 0; k < bodyCount; ++k) {
    RSolverBody& s = m_solverBodies[islandBodies[k]];
    if (s.tau <= 0 || s.invM == 0) continue;
    AdvanceTo(s, dt, halfDt);
    // A body that turns and turned at an impact within the step goes on turning from there
    // (turnQ at turnTau: the motion's Integrate), with the spin and inertia it has then,
    // which the contact phase works with. Any other body turns with its spin after its
    // impacts for the whole step: its geometry here kept the start's orientation, and moving
    // that along a piecewise spin and then handing it the deferred angular momentum would
    // change its kinetic energy (which depends on the orientation for unequal moments).
    s.deferV = s.v - s.moved / dt;
  }
  if (joints) m_joints.EndImpactJoints(jointView, sc, true);
}

// The bodies of an island with impact rows that turn on their paths (RSolverBody::turns):
// a dynamic body whose contacts move as it turns (not a sphere) and whose motion is the
// free flow (no angular locks or drag, not welded, no joints in the island, whose rows
// are worked out at the start's poses). Their turning starts at the start of the step with
// their spin after the start's kicks and warm starts.
void RContactSolver::BeginTurns(const RStepBodies& bodies, std::size_t island, bool joints) {
  for (std::uint32_t k = m_islandBodyStart[island]; k < m_islandBodyStart[island + 1]; ++k) {
    const std::uint32_t i = m_islandBodies[k];
    RSolverBody& s = m_solverBodies[i];
    const RBodyCore& b = bodies[i];
    s.impacts = 0;
    s.turns = !joints && s.armTurns && !b.m_angularLocked && b.m_angularDamping == 0 && !m_in->welds.Welded(i);
    if (!s.turns) continue;
    s.turnQ = s.qAt = b.m_q_WB;
    s.turnTau = s.atTau = 0;
    s.turnW_B = b.m_q_WB.conjugate() * s.w;
  }
}

// One impact row in a pass of the impact phase: when its bodies meet (judged from the start
// of the step, or, once an impact has changed how one of them turns, swept along their
// turning paths), then the impact there (ImpactAt). Returns whether it pushed.
bool RContactSolver::ImpactRow(const RStepBodies& bodies, RImpactRow& r, RScalar dt, bool joints,
                               const RJointIslandView& jointView, RIslandScratch& sc) {
  const RScalar halfDt = RScalar(0.5) * dt;
  RSolverBody* pa = &m_solverBodies[r.a];
  RSolverBody* pb = &m_solverBodies[r.b];
  // Swept: a body of the row turns differently since its last impact (a row joined into
  // another has the other's sweep; a weld's joined row its own point; nor is a pair swept
  // with a body whose turning the phase does not follow).
  const RScalar slop = m_in->settings.penetrationSlop;
  const bool swept = !r.joined && std::isfinite(r.gap) && (Spun(*pa, dt, slop) || Spun(*pb, dt, slop)) &&
                     !Unfollowed(bodies[r.a], *pa, dt, slop) && !Unfollowed(bodies[r.b], *pb, dt, slop);
  bool fromStart = true;
  RScalar an0 = 0, vn0 = 0;
  if (swept) {
    // Swept already since either body's last impulse: nothing new to find.
    if (r.sweptA == pa->impacts && r.sweptB == pb->impacts) return false;
    r.sweptA = pa->impacts, r.sweptB = pb->impacts;
  } else {
    vn0 = Speed(r.normal, pa->v, pa->w, pb->v, pb->w);
    // Accelerating, the normal speed runs from vn0 - an dt/2 at the start to vn0 + an dt/2
    // at the end; the gap closes when the parabola says.
    // After an impact of either body the gap at the start says nothing of when they meet
    // (a ball bounced once may land again within the step): the geometry at its time does.
    an0 = NormalAcceleration(r.normal.d, *pa, *pb);
    fromStart = an0 == 0 || std::max(pa->tau, pb->tau) == 0;
    if (an0 == 0) {
      if (vn0 >= -m_in->settings.restitutionThreshold || r.gap > -vn0 * dt) return false;
    } else {
      const RScalar vnStart = vn0 - an0 * halfDt;
      if (std::min(vnStart, vn0 + an0 * halfDt) >= -m_in->settings.restitutionThreshold) return false;
      if (fromStart && r.gap > 0 && CloseTime(r.gap, -vnStart, -an0) > dt) return false;
    }
  }
  // A static or kinematic body on a copy, at the start of its path (see above).
  RSolverBody copyA, copyB;
  if (pa->invM == 0) copyA = *pa, pa = &copyA;
  if (pb->invM == 0) copyB = *pb, pb = &copyB;
  // When: the gap closed at this approach, and no earlier than either body's last.
  RScalar t = std::max(pa->tau, pb->tau);
  if (!swept) {
    if (r.gap > 0 && fromStart) {
      t = std::max(t, an0 == 0 ? r.gap / -vn0 : CloseTime(r.gap, -(vn0 - an0 * halfDt), -an0));
    }
    if (t > dt) return false;
    return ImpactAt(bodies, r, *pa, *pb, t, dt, false, joints, jointView, sc);
  }
  // Swept: where the turning paths next close. First where the pair touches now, if it
  // does (a contact's own approach again, after friction at its impulse turned the body on
  // it, bounces as the passes always bounced it); then past that. One sweep follows the
  // pair through the rest of the step: the nose that hit, the tail it swings down, the nose
  // again, each bounced at its time, until they are apart to the end of the step (or a
  // contact there does not bounce: the tail that hit, sliding on as the nose swings down, is
  // swept past, a few times at most).
  const RContactManifold& manifold = m_in->sweep.Contacts()[r.contact].manifold;
  constexpr int kSweepsPast = 4, kSweptImpacts = 32;
  bool pushed = false, past = false;
  for (int impacts = 0, tries = 0; tries < kSweepsPast;) {
    t = SweepImpact(bodies[r.a], bodies[r.b], *pa, *pb, t, dt, manifold.childA, manifold.childB, past);
    if (t > dt) break;
    if (!ImpactAt(bodies, r, *pa, *pb, t, dt, true, joints, jointView, sc)) {
      past = true, ++tries;
      continue;
    }
    pushed = true, past = false, tries = 0;
    // Swept to here since the bodies' last impulse (another pass sweeps on from here if it
    // took more than this).
    r.sweptA = pa->impacts, r.sweptB = pb->impacts;
    if (++impacts == kSweptImpacts) {
      r.sweptA = r.sweptB = ~std::uint32_t{0};
      break;
    }
  }
  return pushed;
}

// Row r's impact at time t (updated to the moment of contact), if its bodies meet there
// approaching: the geometry, the bounce and friction, the joints' reaction, and where each
// body turns from. Otherwise the bodies are left as they were (a swept row's), or where the
// geometry moved them (the others', as they always were), and false.
bool RContactSolver::ImpactAt(const RStepBodies& bodies, RImpactRow& r, RSolverBody& sa, RSolverBody& sb, RScalar t,
                              RScalar dt, bool swept, bool joints, const RJointIslandView& jointView,
                              RIslandScratch& sc) {
  const RScalar halfDt = RScalar(0.5) * dt;
  const RContactManifold& manifold = m_in->sweep.Contacts()[r.contact].manifold;
  const RKept keptA(sa), keptB(sb);
  const RScalar slop = m_in->settings.penetrationSlop;
  for (RSolverBody* s : {&sa, &sb}) {
    s->turning = s->turns && TurnsFar(*s, s->turnW_B.norm(), dt - s->turnTau, slop);
    if (s->turns) s->qAt = s->turnQ, s->atTau = s->turnTau;  // (not turned yet)
  }
  AdvanceTo(sa, t, halfDt), AdvanceTo(sb, t, halfDt);
  RDirection dir[3];
  RVec3 rA, rB;
  if (!swept && (t == 0 || r.joined)) {
    // At the start: the manifold's own impact point and normal (a weld's joined
    // contacts: theirs, at any time, with the inertia a turning body has then).
    if (t > 0) TurnTo(bodies[r.a], sa, t), TurnTo(bodies[r.b], sb, t);
    rA = r.rA, rB = r.rB;
    SetDirection(dir[0], r.normal.d, rA, rB, sa, sb);
    SetDirection(dir[1], r.tangent[0], rA, rB, sa, sb);
    SetDirection(dir[2], r.tangent[1], rA, rB, sa, sb);
  } else if (!ImpactGeometry(bodies[r.a], bodies[r.b], sa, sb, t, dt, rA, rB, dir, manifold.childA, manifold.childB,
                             swept)) {
    if (!swept) r.miss = true;  // they pass each other, or meet only after the step
    keptA.Restore(sa, swept), keptB.Restore(sb, swept);
    return false;
  }
  // The approach at the moment of contact: under acceleration, the speed at t.
  const RScalar an = NormalAcceleration(dir[0].d, sa, sb);
  const RScalar vn = an == 0 ? Speed(dir[0], sa.v, sa.w, sb.v, sb.w)
                             : Speed(dir[0], sa.v, sa.w, sb.v, sb.w) + an * (t - halfDt);
  // (No effective mass: no impulse to find.) Accelerating, the speed at the moment of
  // contact is the one the threshold judges (a box resting on the ground under a stack a
  // falling box hits: its approach gains g t within the step, and stays a resting
  // contact's); swept, so it is (a tail settling slower than that is the contacts').
  if (vn >= 0 || !(dir[0].k > 0) || ((an != 0 || swept) && vn >= -m_in->settings.restitutionThreshold)) {
    keptA.Restore(sa, swept), keptB.Restore(sb, swept);
    return false;
  }
  // Pulled back onto each other (an < 0), a bounce of e vn returns after 2 e |vn| / |an|,
  // and all the bounces after it take 2 e |vn| / (|an| (1 - e)) (Zeno): if they end within
  // the step, the pair is at rest from now on, and bounces no more.
  const RScalar e = an < 0 && 2 * r.restitution * -vn <= -an * (1 - r.restitution) * (dt - t) ? 0 : r.restitution;
  RScalar dn = -(1 + e) * vn / dir[0].k;
  if (joints) {
    // The joints react within the impact: the approach changes per unit impulse by less
    // than the free bodies' k (a door turns about its hinge). That rate, measured by
    // the free bodies' impulse and the joints' answer to it (their response is linear),
    // gives the impulse that turns vn into -e vn through the joints; the rest of it and
    // friction, and the joints' answer again.
    const RScalar probe = dn;
    Push(dir[0], probe, sa, sb, sa.v, sa.w, sb.v, sb.w);
    r.lambdaN += probe;
    const RVec3 J = probe * dir[0].d;
    r.impulse += J, r.angularA += rA.cross(J), r.angularB += rB.cross(J);
    m_joints.ImpactJointsPass(jointView, t, sc);
    const RScalar k = (Speed(dir[0], sa.v, sa.w, sb.v, sb.w) - vn) / probe;
    dn = k > 0 ? std::max(-(1 + e) * vn / k - probe, -r.lambdaN) : 0;
  }
  ApplyImpact(r, dir, rA, rB, dn, sa, sb, bodies[r.a].m_x_W);
  if (joints) m_joints.ImpactJointsPass(jointView, t, sc);
  if (sa.invM != 0) CommitTurn(sa, t, dt, slop);
  if (sb.invM != 0) CommitTurn(sb, t, dt, slop);
  return true;
}

}  // namespace REngine
