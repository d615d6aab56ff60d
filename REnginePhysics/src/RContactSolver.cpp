// The contact solver (RWorldStep::FindImpulses): rows, warm starts, manifold blocks,
// friction patches and the end of the step; see RIntegrator.h.
#include "RWorldStep.h"

#include "RSolverRows.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;

// Sequential impulses (Catto 2005) over every contact point, with the velocities each body
// will move with during the step (its pending impulses and half the step's acceleration
// included: kick-drift-kick moves bodies with the mid-step velocity, so a resting contact
// that holds that velocity at zero does not sink at all). In phases: impacts (SolveImpacts),
// then the contacts: accumulated normal impulses clamped at zero (a contact pushes, never
// pulls: the separating-velocity guard), friction per manifold within the Coulomb disc of
// mu times the manifold's normal impulse (SolvePatch), every row starting from last step's
// impulses for the same features; small islands solved exactly; then the end of the step
// (all island by island: SolveContactIslands, RContactPasses.cpp). Penetration beyond a slop
// is removed by pseudo-velocities (split impulses), solved apart so that position
// correction never adds kinetic energy.
void RWorldStep::FindImpulses(const RStepBodies& bodies, RScalar dt) {
  const std::size_t n = bodies.size();
  // Warm-start memory is keyed by slot (and generation). A plain vector's slots are its
  // indices: when the game adds or removes bodies they shift, and another pair would
  // inherit a stranger's impulses.
  if (bodies.byIndex && n != m_warmBodyCount) m_warm.clear();
  m_warmBodyCount = bodies.byIndex ? n : 0;
  m_warmNext.clear();
  KeepSleepingWarmStarts(bodies);
  m_solverBodies.resize(n);
  const RScalar halfDt = RScalar(0.5) * dt;
  bool anyRow = false;
  for (const RContact& c : m_contacts) {
    const RRigidBody& a = bodies[c.a];
    const RRigidBody& b = bodies[c.b];
    anyRow = anyRow || (a.m_responds && b.m_responds && !(a.Immovable() && b.Immovable()) &&
                        c.manifold.pointCount > 0);
  }
  m_solved = anyRow;
  if (!anyRow) {
    m_rows.clear(), m_impacts.clear(), m_blocks.clear();
    std::swap(m_warm, m_warmNext);
    return;
  }
  // The rows, impact rows and friction patches of every contact, each contact's at places
  // counted beforehand (LayOutIslands: island by island), so that contacts are built as
  // tasks side by side.
  LayOutIslands(bodies);
  // Each body's solver state: the velocities it moves with this step (m_moveV, from
  // CollisionDetection's pre-pass), its world inverse inertia and masks (RBodyMotion.cpp);
  // only for the bodies in some row (most of a debris cloud's touch nothing).
  for (std::uint32_t i : m_rowBodies) InitSolverBody(m_solverBodies[i], bodies[i], m_moveV[i], halfDt, m_settings.gravity_W);
  if (m_warmTasks.size() < m_tasks) m_warmTasks.resize(m_tasks);
  const std::size_t rowTasks = ParallelRanges(m_jobs, m_contacts.size(), m_tasks, 32, [&](std::size_t c0, std::size_t c1, std::size_t task) {
    m_warmTasks[task] = 0;
    std::size_t warmFrom = 0;
    for (std::size_t ci = c0; ci < c1; ++ci) {
      if (m_contacts[ci].resolved) m_warmTasks[task] += BuildContactRows(bodies, static_cast<std::uint32_t>(ci), dt, warmFrom);
    }
  });
  for (std::size_t t = 0; t < rowTasks; ++t) m_pairStats.warmStarted += m_warmTasks[t];

  m_pairStats.contactPoints = m_rows.size();
  // Islands (bodies linked through dynamic bodies) from the rows alone: warm starting, the
  // passes and the direct solves then work island by island.
  BuildIslands();
  WarmStart(RPhase::kVelocity);
  SolveImpacts(bodies, dt);
  // A manifold whose impact the narrow phase, run again along the motion, found not to
  // happen within this step keeps no speculative rows: their linear prediction from the
  // start of the step (which said it would) would stop the bodies short, an inelastic
  // collision that never happened. Points already touching keep their rows.
  // (One impact row and one block per resolved contact: impact rows in the contacts' order,
  // blocks in the islands' (LayOutIslands), found through the contact.)
  for (const RImpactRow& impact : m_impacts) {
    if (!impact.miss || impact.lambdaN != 0) continue;
    const RBlock& blk = m_blocks[m_rowStart[impact.contact].block];
    for (int k = 0; k < blk.count; ++k) {
      RContactRow& r = m_rows[blk.first + k];
      if (r.gap > 0 && r.lambdaN == 0) r.target = kNever;
    }
  }
  // Bodies that impacted move with their piecewise path's velocity, deferV less than the
  // velocity after the impacts that the contact phase works on; the end of the step needs
  // the difference to predict which contacts are then closed.
  for (RContactRow& r : m_rows) {
    r.deferN = r.n.d.dot(m_solverBodies[r.b].deferV - m_solverBodies[r.a].deferV);
  }
  // The contact phase's impulses change the velocities after the impacts, and a body that
  // impacted moves with them on its post-impact path, which, run back to the start of the
  // step, passes through x - dt deferV, not through its centre x: the body gets their
  // moment about that point (the spin added with the deferred impulse below, which keeps
  // angular momentum exact). So they are solved with the lever arms they act with,
  // r + dt deferV. Solved with r, an impulse that only slows an approach also gave the
  // body a spin of dt deferV x J that no row had weighed, whatever its energy: a 0.4 m box
  // at 1.6 km/s glancing off a static sphere was still closing on it after the bounce, the
  // speculative row stopped that with its arm 2.2 m short, and the box left the step with
  // 2.2e8 J of spin from 1.2e7 J (the seed-3 world of broadphase_test reached 1e221 J in
  // 12 steps). The shift lies along the impacts' impulses, so a frictionless impact along
  // a row's normal (a box landing flat) leaves the row's angular terms as they were.
  // Position correction shares the rows' directions and sees the same arms (it moves
  // positions only: no energy).
  // A body with linear locks gets the moment of the shift only for the impulse's free part:
  // along a locked axis the lock's reaction cancels the impulse at the body's centre, which
  // moved with it, and the spin it is handed below is dt deferV x (its velocity change times
  // its mass), the free part alone. Solved with the whole impulse's moment, the rows weighed
  // a spin the body never got (a crate locked on x, squeezed by a kinematic paddle along x,
  // left a step at 515 rad/s where the solve had 20).
  auto shiftArms = [this, dt](RDirection& dir, const RVec3& rA, const RVec3& rB, std::uint32_t a, std::uint32_t b) {
    const RSolverBody& sa = m_solverBodies[a];
    const RSolverBody& sb = m_solverBodies[b];
    const RVec3& d = dir.d;
    const RVec3 shiftA = dt * sa.deferV, shiftB = dt * sb.deferV;
    dir.rAxd = sa.linLocked ? RVec3(rA.cross(d) + shiftA.cross(d.cwiseProduct(sa.linMask))) : RVec3((rA + shiftA).cross(d));
    dir.rBxd = sb.linLocked ? RVec3(rB.cross(d) + shiftB.cross(d.cwiseProduct(sb.linMask))) : RVec3((rB + shiftB).cross(d));
    SetEffectiveMass(dir, sa, sb);
  };
  auto deferred = [this](std::uint32_t i) { return !m_solverBodies[i].deferV.isZero(0); };
  for (RContactRow& r : m_rows) {
    if (!deferred(r.a) && !deferred(r.b)) continue;
    shiftArms(r.n, r.rA, r.rB, r.a, r.b);
    if (!(r.n.k > 0)) r.target = kNever, r.pseudoTarget = 0;  // as BuildContactRows
  }
  for (RBlock& blk : m_blocks) {
    const std::uint32_t a = m_rows[blk.first].a, b = m_rows[blk.first].b;
    if (!deferred(a) && !deferred(b)) continue;
    for (RDirection& t : blk.t) shiftArms(t, blk.rA, blk.rB, a, b);
  }
  const int iterations = std::max(1, m_settings.solverIterations);
  // Rows come grouped by contact. A manifold's normal rows are solved together: its points
  // share two bodies, and solving them one after another favours the first, leaving a
  // small torque that tilts stacked bodies step after step. The block's matrix is rank
  // deficient (four points of one face constrain three degrees of freedom), so the
  // minimum-norm least-squares inverse is precomputed once per step; when its answer
  // would pull at a point, that manifold falls back to one point at a time.

  SolveContactIslands(bodies, dt, iterations);

  // Accumulate on the bodies (applied by UpdateObjects), report, and remember.
  // Summed on the solver bodies (which start from the bodies' own impulses, and whose
  // inverse mass is 0 exactly when the body is static or kinematic), then written to the
  // bodies in one pass below: the same sums in the same order, without a visit per row to
  // bodies a kilobyte each.
  auto accumulate = [this](std::uint32_t a, std::uint32_t b, const RVec3& rA,
                           const RVec3& rB, const RVec3& J) {
    RSolverBody& A = m_solverBodies[a];
    RSolverBody& B = m_solverBodies[b];
    if (A.invM != 0) {
      A.impulse -= J;
      A.angularImpulse -= rA.cross(J);
    }
    if (B.invM != 0) {
      B.impulse += J;
      B.angularImpulse += rB.cross(J);
    }
  };
  // An impulse at the end of the step acts where the contact is then: the point moves with
  // the bodies, with the lighter one's displacement when one is much heavier (the ground's
  // contact with a sliding box moves with the box). The same point for both bodies keeps
  // angular momentum exact. Lever arms are about the centres at the start of the step;
  // UpdateObjects moves them to where the centres end.
  auto accumulateEnd = [&bodies, this, dt](std::uint32_t a, std::uint32_t b, const RVec3& rA,
                                           const RVec3& rB, const RVec3& J) {
    if (J.isZero(0)) return;
    RSolverBody& sa = m_solverBodies[a];
    RSolverBody& sb = m_solverBodies[b];
    const RVec3 moveA = (sa.vMid + sa.vp) * dt, moveB = (sb.vMid + sb.vp) * dt;
    const RVec3 shift = (sa.invM * moveA + sb.invM * moveB) / (sa.invM + sb.invM);
    if (!bodies[a].Immovable()) {
      sa.endLinear -= J;
      sa.endAngular -= (rA + shift).cross(J);
    }
    if (!bodies[b].Immovable()) {
      sb.endLinear += J;
      sb.endAngular += (rB + shift).cross(J);
    }
  };
  // Contact by contact, in their order (not the rows' island order): each body's impulses
  // add up in the order they always did, and next step's warm starts come out sorted.
  auto rowsOf = [this](std::uint32_t ci) {
    const RBlock& blk = m_blocks[m_rowStart[ci].block];
    return std::pair(m_rows.begin() + blk.first, m_rows.begin() + blk.first + blk.count);
  };
  for (std::uint32_t ci = 0; ci < m_contacts.size(); ++ci) {
   if (!m_contacts[ci].resolved) continue;
   for (auto [row, end] = rowsOf(ci); row != end; ++row) {
    const RContactRow& r = *row;
    accumulate(r.a, r.b, r.rA, r.rB, r.lambdaN * r.n.d);
    if (r.lambdaE != 0) accumulateEnd(r.a, r.b, r.rA, r.rB, r.lambdaE * r.n.d);
    m_contacts[r.contact].normalImpulse[r.point] = r.lambdaN + r.lambdaE;
    const RBlock& blk = m_blocks[r.block];
    const RContactPoint& p = m_contacts[r.contact].manifold.points[r.point];
    RWarmStart w;
    const RContact& c = m_contacts[r.contact];
    w.pair = PairKey(c.handleA.index, c.handleB.index);
    w.genA = c.handleA.generation, w.genB = c.handleB.generation;
    w.feature = p.featureId;
    w.point_A = m_rowPoint_A[static_cast<std::size_t>(&r - m_rows.data())];
    w.lambdaN = r.lambdaN;
    w.lambdaE = r.lambdaE;
    bool finite = std::isfinite(w.lambdaN) && std::isfinite(w.lambdaE) && AllFinite(w.point_A);
    for (int ph = 0; ph < 2; ++ph) {
      w.tangentImpulse[ph] = blk.lambdaT1[ph] * blk.t[0].d + blk.lambdaT2[ph] * blk.t[1].d;
      w.twistImpulse[ph] = blk.lambdaTwist[ph];
      finite = finite && AllFinite(w.tangentImpulse[ph]) && std::isfinite(w.twistImpulse[ph]);
    }
    // A step that overflowed must not seed the next one (its bodies are put back).
    if (finite) m_warmNext.push_back(w);
   }
  }
  for (std::uint32_t ci = 0; ci < m_contacts.size(); ++ci) {
    if (!m_contacts[ci].resolved) continue;
    const RBlock& blk = m_blocks[m_rowStart[ci].block];
    const RContactRow& r = m_rows[blk.first];
    accumulate(r.a, r.b, blk.rA, blk.rB, blk.lambdaT1[0] * blk.t[0].d + blk.lambdaT2[0] * blk.t[1].d);
    accumulateEnd(r.a, r.b, blk.rA, blk.rB, blk.lambdaT1[1] * blk.t[0].d + blk.lambdaT2[1] * blk.t[1].d);
    m_contacts[r.contact].frictionImpulse_W = (blk.lambdaT1[0] + blk.lambdaT1[1]) * blk.t[0].d +
                                              (blk.lambdaT2[0] + blk.lambdaT2[1]) * blk.t[1].d;
    // The twist: a pure torque about the normal.
    RSolverBody& sa = m_solverBodies[r.a];
    RSolverBody& sb = m_solverBodies[r.b];
    if (sa.invM != 0) {
      sa.angularImpulse -= blk.lambdaTwist[0] * blk.normal;
      sa.endAngular -= blk.lambdaTwist[1] * blk.normal;
    }
    if (sb.invM != 0) {
      sb.angularImpulse += blk.lambdaTwist[0] * blk.normal;
      sb.endAngular += blk.lambdaTwist[1] * blk.normal;
    }
  }
  // An impact's impulse is a one-off, not remembered: carried into the next step it would
  // push apart bodies that are already separating, energy from nowhere. It is reported at
  // the manifold's deepest point.
  for (const RImpactRow& r : m_impacts) {
    if (r.lambdaN == 0) continue;
    RSolverBody& A = m_solverBodies[r.a];
    RSolverBody& B = m_solverBodies[r.b];
    if (A.invM != 0) A.impulse -= r.impulse, A.angularImpulse -= r.angularA;
    if (B.invM != 0) B.impulse += r.impulse, B.angularImpulse += r.angularB;
    m_contacts[r.contact].normalImpulse[r.point] += r.lambdaN;
    m_contacts[r.contact].frictionImpulse_W += r.frictionImpulse;
  }
  // Impacts within the step: the bodies move with their piecewise path's velocity and get
  // the rest at the end (SolveImpacts).
  for (std::uint32_t i : m_rowBodies) {
    RSolverBody& s = m_solverBodies[i];
    if (s.invM == 0) continue;
    RRigidBody& b = bodies[i];
    if (!s.deferV.isZero(0)) {
    const RVec3 J = s.deferV / b.m_invMass;
    s.impulse -= J;
    s.deferredImpulse = J;
    // The contact phase's impulses act on the body at its start-of-step pose, but it then
    // moves deferV dt less than its final velocity would take it: the spin that keeps
    // angular momentum exact (the orbital term x x m v misses dt deferV x J_contact). It
    // is the moment of the lever arms' shift that the contact phase was solved with (see
    // the rows' directions after SolveImpacts), so it costs no energy the solve did not see.
    s.angularImpulse += dt * s.deferV.cross(s.contactDeltaV / b.m_invMass);
    }
    b.m_linearImpulse_W = s.impulse, b.m_angularImpulse_W = s.angularImpulse;
  }
  // Rows come in the pair sweep's order, which is slot order unless bodies were added or
  // removed (or it is a plain vector reordered): sorted already, most steps.
  auto before = [](const RWarmStart& x, const RWarmStart& y) {
    return x.pair < y.pair || (x.pair == y.pair && x.feature < y.feature);
  };
  if (!std::is_sorted(m_warmNext.begin(), m_warmNext.end(), before)) {
    std::sort(m_warmNext.begin(), m_warmNext.end(), before);
  }
  std::swap(m_warm, m_warmNext);
}


// One manifold's normal rows: the block's minimum-norm answer when it pushes at every point,
// else one point at a time. On the velocities (towards the rows' targets, impulses lambdaN)
// or on the pseudo-velocities of position correction (pseudoTarget, lambdaP).
RScalar RWorldStep::SolveNormalBlock(const RBlock& blk, RContactRow* rows, RPhase phase) {
  const bool pseudo = phase == RPhase::kPosition;
  RSolverBody& sa = m_solverBodies[rows[0].a];
  RSolverBody& sb = m_solverBodies[rows[0].b];
  RVec3& va = pseudo ? sa.vp : sa.v;
  RVec3& wa = pseudo ? sa.wp : sa.w;
  RVec3& vb = pseudo ? sb.vp : sb.v;
  RVec3& wb = pseudo ? sb.wp : sb.w;
  auto lambda = [phase](RContactRow& r) -> RScalar& { return Lambda(r, phase); };
  auto target = [phase](const RContactRow& r) { return Target(r, phase); };
  if (phase != RPhase::kVelocity) {
    // Most contacts need no position correction, and many are not in contact at the end of
    // the step: nothing to do unless some row does or did.
    bool active = false;
    for (int i = 0; i < blk.count; ++i) active = active || target(rows[i]) > 0 || lambda(rows[i]) > 0 || (phase == RPhase::kEnd && target(rows[i]) == 0);
    if (!active) return 0;
  }
  RScalar change = 0;
  bool allTargets = true;
  for (int i = 0; i < blk.count; ++i) allTargets = allTargets && target(rows[i]) != kNever;
  if (blk.useBlock && allTargets) {
    Eigen::Matrix<RScalar, 4, 1> rhs = Eigen::Matrix<RScalar, 4, 1>::Zero();
    for (int i = 0; i < blk.count; ++i) rhs[i] = target(rows[i]) - Speed(rows[i].n, va, wa, vb, wb);
    const Eigen::Matrix<RScalar, 4, 1> delta = blk.pinv * rhs;
    bool valid = true;
    for (int i = 0; i < blk.count; ++i) valid = valid && lambda(rows[i]) + delta[i] >= 0;
    if (valid) {
      for (int i = 0; i < blk.count; ++i) {
        lambda(rows[i]) += delta[i];
        if (delta[i] != 0) Push(rows[i].n, delta[i], sa, sb, va, wa, vb, wb);
        change = std::max(change, std::abs(delta[i]) * rows[i].n.k);
      }
      return change;
    }
  }
  for (int i = 0; i < blk.count; ++i) {
    RContactRow& r = rows[i];
    if (!(r.n.k > 0)) continue;  // no effective mass: see BuildContactRows
    const RScalar l = std::max(
        lambda(r) - (Speed(r.n, va, wa, vb, wb) - target(r)) / r.n.k, RScalar(0));
    const RScalar d = l - lambda(r);
    lambda(r) = l;
    if (d != 0) Push(r.n, d, sa, sb, va, wa, vb, wb);
    change = std::max(change, std::abs(d) * r.n.k);
  }
  return change;
}

}  // namespace REngine
